"""What a URDF must hold before it becomes a model: finite numbers where urdfdom would silently drop them.

urdfdom (Pinocchio's URDF parser) reports an unreadable inertial element on stderr and goes on with a
massless link; a mimic joint becomes an independent joint. Both would be wrong equations without a
word, so the file is read here first (Python's XML parser: no code is run) and refused with the
link, joint and field named."""
from __future__ import annotations

import math
import xml.etree.ElementTree as ET
import warnings
from pathlib import Path

from ..errors import ModelError

_NUMBERS = {  # element path → attributes that hold numbers
    "inertial/mass": ("value",),
    "inertial/origin": ("xyz", "rpy"),
    "inertial/inertia": ("ixx", "ixy", "ixz", "iyy", "iyz", "izz"),
}
_JOINT_NUMBERS = {"origin": ("xyz", "rpy"), "axis": ("xyz",)}


def _numbers(element, attributes, owner: str, path: str) -> None:
    for name in attributes:
        text = element.get(name)
        if text is None:
            continue
        try:
            values = [float(x) for x in text.split()]
        except ValueError:
            raise ModelError(f"{owner}: {path} {name}={text!r} is not a number") from None
        if not all(math.isfinite(v) for v in values):
            raise ModelError(f"{owner}: {path} {name}={text!r} must be finite")
        if path == "inertial/mass" and values and values[0] < 0:
            raise ModelError(f"{owner}: mass must be non-negative, got {values[0]}")


MIMIC = ("refuse", "independent")


def check_urdf(path: Path, mimic: str = "refuse") -> None:
    """Refuse non-finite or unreadable inertial numbers, origins and axes; mimic joints are refused, or
    with mimic="independent" imported as independent joints (as Pinocchio's default model has them)
    with a warning naming them."""
    if mimic not in MIMIC:
        raise ModelError(f"mimic must be one of {MIMIC}, got {mimic!r}")
    try:
        root = ET.parse(path).getroot()
    except ET.ParseError as exc:
        raise ModelError(f"cannot read URDF {path}: {exc}") from None
    for link in root.iter("link"):
        owner = f"URDF {path.name}: link '{link.get('name')}'"
        for element_path, attributes in _NUMBERS.items():
            for element in link.findall(element_path):
                _numbers(element, attributes, owner, element_path)
        for inertial in link.findall("inertial"):
            if inertial.find("mass") is not None and inertial.find("mass").get("value") is None:
                raise ModelError(f"{owner}: inertial/mass has no value")
    mimics = []
    for joint in root.iter("joint"):
        owner = f"URDF {path.name}: joint '{joint.get('name')}'"
        for element_path, attributes in _JOINT_NUMBERS.items():
            for element in joint.findall(element_path):
                _numbers(element, attributes, owner, element_path)
        follows = joint.find("mimic")
        if follows is not None and mimic == "refuse":
            raise ModelError(f"{owner} mimics joint '{follows.get('joint')}'; eomgen does not model mimic "
                             "joints yet: from_urdf(..., mimic='independent') imports it as an independent "
                             "joint")
        if follows is not None:
            mimics.append(joint.get("name"))
    if mimics:
        warnings.warn(f"URDF {path.name}: mimic joints {mimics} imported as independent joints "
                      "(mimic='independent'), as in Pinocchio's default model", stacklevel=4)
