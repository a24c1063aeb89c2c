"""The names of an MJCF file's bodies, joints and sites as Pinocchio's parser gives them, and the clashes
refused. MuJoCo keeps three namespaces; eomgen has one name per frame (bodies and sites, and the joint
of a body whose joint has a `pos`: that eomgen body sits at the joint). Bodies must have names; the
parser names an unnamed joint "<body>Joint_0" (a freejoint "<body>_free") and the k-th site of a body
"<body>Site_<k>"; two elements of one name would be one frame (or one body) for it."""
from __future__ import annotations

import xml.etree.ElementTree as ET
from collections import Counter

from ..errors import ModelError


def body_names(root_body: ET.Element, owner: str) -> dict[ET.Element, str]:
    """Every body of the tree by name; an unnamed one refused (Pinocchio's parser drops an unnamed root
    body and one without attributes, with their joints, and names two unnamed siblings alike)."""
    if not root_body.get("name"):
        raise ModelError(f"{owner}: the root body below <worldbody> has no name: give it one")
    names = {root_body: root_body.get("name")}
    for parent in root_body.iter("body"):
        for k, body in enumerate(parent.findall("body")):
            if not body.get("name"):
                raise ModelError(f"{owner}: body {k + 1} inside body '{names[parent]}' has no name: give it "
                                 "one (Pinocchio's parser drops or merges unnamed bodies)")
            names[body] = body.get("name")
    return names


def joint_name(body: ET.Element, joint: ET.Element, names: dict) -> str:
    return joint.get("name") or names[body] + ("_free" if joint.tag == "freejoint" else "Joint_0")


def site_names(body: ET.Element, names: dict) -> list[str]:
    return [s.get("name") or f"{names[body]}Site_{k}" for k, s in enumerate(body.findall("site"))]


def check_names(names: dict[ET.Element, str], moved: set[ET.Element], owner: str) -> None:
    """Refuse two bodies, joints or sites of one name, a site named like a body or joint, and a joint
    with a `pos` (`moved`: its element) named like a body."""
    joints = [(joint_name(b, j, names), j) for b in names
              for j in b.findall("joint") + b.findall("freejoint")]
    sites = [s for b in names for s in site_names(b, names)]
    every = {"bodies": list(names.values()), "joints": [n for n, _ in joints], "sites": sites}
    for kind, listed in every.items():
        twice = [n for n, k in Counter(listed).items() if k > 1]
        if twice:
            raise ModelError(f"{owner}: two {kind} are named '{twice[0]}' (Pinocchio's parser names an "
                             "unnamed joint '<body>Joint_0', site '<body>Site_<k>') and would keep one: "
                             "name each of them")
    for site in sites:
        if site in dict(joints) or site in names.values():
            what = "joint" if site in dict(joints) else "body"
            raise ModelError(f"{owner}: site '{site}' has the name of a {what}; MuJoCo keeps them apart, "
                             "eomgen's frames have one namespace: rename the site")
    for name, joint in joints:
        if joint in moved and name in names.values():
            raise ModelError(f"{owner}: joint '{name}' has a pos and the name of a body; eomgen names the "
                             "body that moves about the joint's point after the joint (its origin is the "
                             "frame of the body's name): rename the joint")
