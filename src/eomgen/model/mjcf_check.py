"""What an MJCF file must hold before Pinocchio's parser reads it: the content that parser would drop or
misread without a word, and the MuJoCo content eomgen's equations do not have, refused with the file,
element and name.

Found by experiment with Pinocchio 4.1's parser (`buildModelAndLegacyConstraintsFromMJCF`): it reads
the first `<body>` of `<worldbody>` only (the others vanish with their joints) and drops its pose when
it has no joint, skips `<frame>` and what is inside it, does not follow `<include>`, does not normalize
an axisangle's axis, reads an upper-case eulerseq as lower-case, ignores `<option gravity>` (read here
instead), keeps an equality with active="false", skips every equality but connect and weld, reads
"1 0" as the anchor 1 0 0, takes site2 of a connect between a body and a site as the world, and gives
an unknown site1 a joint index of 2⁶³. Passive forces (joint stiffness, gravity compensation, fluid
forces) are MuJoCo's and not part of M u̇ + b + g = τ; tendons neither. Actuators are not read: τ is
the generalized force."""
from __future__ import annotations

import xml.etree.ElementTree as ET
from dataclasses import dataclass
from pathlib import Path

from ..errors import ModelError
from .mjcf_defaults import Defaults, bodies as classed
from .mjcf_inertia import check_inertias
from .mjcf_names import body_names, check_names, site_names
from .mjcf_pose import pose as element_pose
from .xml_read import read_xml

_SKIPPED = ("include", "frame", "replicate", "attach", "composite", "flexcomp", "flex", "skin")
_EQUALITIES = ("connect", "weld")
NOT_MODELLED = ("is a MuJoCo force that is not part of eomgen's equations (remove it, or model it as an "
                "eomgen load after the import)")


@dataclass(frozen=True)
class Equality:
    """A connect ("point") or weld ("frame") equality of the file, between body1 (or site1) and body2
    (or site2; None: the world); `key` tells its constraint among Pinocchio's: (1 or 2, the translation of
    joint1_placement or joint2_placement, which is the file's anchor or relpose, or site1's name)."""

    name: str
    kind: str
    by: str  # "body" or "site"
    first: str
    second: str | None
    key: tuple


def numbers(element: ET.Element, name: str, count: int, owner: str) -> list[float] | None:
    """Attribute `name` as exactly `count` finite numbers (None if absent)."""
    text = element.get(name)
    if text is None:
        return None
    try:
        values = [float(x) for x in text.split()]
    except ValueError:
        raise ModelError(f"{owner}: {name}={text!r} is not {count} numbers") from None
    if len(values) != count or not all(abs(v) < float("inf") for v in values):
        raise ModelError(f"{owner}: {name}={text!r} must be {count} finite numbers (Pinocchio's parser "
                         "would fill missing ones with zeros)")
    return values


def _nonzero(element: ET.Element, name: str, count: int, owner: str) -> None:
    values = numbers(element, name, count, owner)
    if values is not None and any(values):
        raise ModelError(f"{owner}: {name}={element.get(name)!r} {NOT_MODELLED}")


def _read(path: Path) -> ET.Element:
    root = read_xml(path, "MJCF").root
    if root.tag != "mujoco":
        raise ModelError(f"MJCF {path.name}: the root element is <{root.tag}>, not <mujoco>")
    return root


def _check_tree(root: ET.Element, owner: str) -> ET.Element:
    """The one body below `<worldbody>` (refusing what Pinocchio's parser skips or eomgen does not model)."""
    for element in root.iter():
        if element.tag in _SKIPPED:
            raise ModelError(f"{owner}: <{element.tag}> is not read by Pinocchio's MJCF parser (write its "
                             "content out in the file)")
        turn = numbers(element, "axisangle", 4, f"{owner}: <{element.tag} name={element.get('name', '')!r}>")
        if turn is not None and abs(sum(x * x for x in turn[:3]) - 1) > 1e-9:
            raise ModelError(f"{owner}: <{element.tag} name={element.get('name', '')!r}> axisangle="
                             f"{element.get('axisangle')!r}: give a unit axis (Pinocchio's parser does not "
                             "normalize it and would make a matrix that is no rotation)")
        if element.tag == "joint" or element.tag == "default":
            for joint in [element] if element.tag == "joint" else element.findall("joint"):
                _nonzero(joint, "stiffness", 1, f"{owner}: joint '{joint.get('name', '(default)')}'")
                _nonzero(joint, "springdamper", 2, f"{owner}: joint '{joint.get('name', '(default)')}'")
            for joint in element.findall("joint") if element.tag == "default" else []:
                if any(numbers(joint, "pos", 3, f"{owner}: <default>") or []):
                    raise ModelError(f"{owner}: <default class={element.get('class', 'main')!r}>: a joint "
                                     "pos in a default class is not read by Pinocchio's parser (give it on "
                                     "each joint)")
    for compiler in root.findall("compiler"):
        if compiler.get("eulerseq", "").lower() != compiler.get("eulerseq", ""):
            raise ModelError(f"{owner}: <compiler eulerseq={compiler.get('eulerseq')!r}>: Pinocchio's "
                             "parser takes upper case (axes fixed) as lower case (axes rotating with the "
                             "frame): give the angles for a lower-case sequence")
    for tendon in root.findall("tendon"):
        if len(tendon):
            raise ModelError(f"{owner}: <tendon> {tendon[0].tag} '{tendon[0].get('name', '')}': tendons are "
                             "not part of eomgen's equations")
    for option in root.findall("option"):
        for name, count in (("density", 1), ("viscosity", 1), ("wind", 3)):
            _nonzero(option, name, count, f"{owner}: <option>")
    world = root.findall("worldbody")
    bodies = [b for w in world for b in w.findall("body")]
    if len(bodies) != 1:
        names = [b.get("name", "(unnamed)") for b in bodies]
        raise ModelError(f"{owner}: <worldbody> holds {len(bodies)} bodies {names}; Pinocchio's MJCF parser "
                         "reads one tree (the first body and what is below it): put them below one body")
    pose = [a for a in ("pos", "quat", "euler", "axisangle", "xyaxes", "zaxis") if a in bodies[0].attrib]
    if pose and not _joints(bodies[0]):
        raise ModelError(f"{owner}: body '{bodies[0].get('name', '(unnamed)')}' is fixed to the world and "
                         f"has {' and '.join(pose)}, which Pinocchio's parser drops: leave the root body at "
                         "the world origin, unrotated (its children carry the offsets)")
    for body in bodies[0].iter("body"):
        where = f"{owner}: body '{body.get('name', '(unnamed)')}'"
        for free in [j for j in _joints(body) if j.tag == "freejoint" or j.get("type") == "free"]:
            if any(numbers(free, "pos", 3, where) or []):
                raise ModelError(f"{where}: free joint pos={free.get('pos')!r}; MuJoCo ignores it, "
                                 "Pinocchio's parser moves the body by it: remove it")
        _nonzero(body, "gravcomp", 1, where)
        joints = _joints(body)
        if len(joints) > 1:
            raise ModelError(f"{where} has {len(joints)} joints {[j.get('name', '') for j in joints]}; "
                             "eomgen takes one joint per body (put each joint on a body of its own)")
    return bodies[0]


def _equality(element: ET.Element, bodies: set, sites: set, owner: str) -> Equality:
    kind = element.tag
    where = f"{owner}: <{kind}{' name=' + repr(element.get('name')) if element.get('name') else ''}>"
    if kind not in _EQUALITIES:
        raise ModelError(f"{where}: a {kind} equality is not handled (eomgen takes connect and weld "
                         "equalities as loops)")
    if element.get("active", "true") != "true":
        raise ModelError(f"{where}: active={element.get('active')!r}; Pinocchio's parser would hold it "
                         "anyway (remove it)")
    by = "site" if element.get("site1") is not None or element.get("site2") is not None else "body"
    first, second = element.get(f"{by}1"), element.get(f"{by}2")
    other = "body" if by == "site" else "site"
    if first is None or element.get(f"{other}1") is not None or element.get(f"{other}2") is not None \
            or by == "site" and second is None:
        raise ModelError(f"{where}: give body1 (and body2, the world if absent) or site1 and site2, not a "
                         "mixture (Pinocchio's parser would take the world for what it does not read)")
    names = bodies if by == "body" else sites
    for which, name in (("1", first), ("2", second)):
        if name is not None and name not in names:
            hint = " (leave out body2 for the world)" if name == "world" else ""
            raise ModelError(f"{where}: {by}{which} '{name}' is not a {by} of the file's tree{hint}")
    anchor = numbers(element, "anchor", 3, where) or [0.0, 0.0, 0.0]
    relpose = numbers(element, "relpose", 7, where)
    if by == "site":
        key = (1, first)  # the site's placement, looked up in the model
    elif kind == "connect":
        key = (1, tuple(anchor))
    elif relpose is not None and any(relpose[3:]):
        key = (1, tuple(relpose[:3]))
    else:
        key = (2, tuple(anchor))
    name = element.get("name") or f"{first}-{second or 'world'}"
    return Equality(name, "point" if kind == "connect" else "frame", by, first, second, key)


def _welded_sites(root: ET.Element, tree: ET.Element, names: dict, defaults: Defaults, owner: str) -> list:
    """(name, on the root body, R, p) of the sites Pinocchio's parser drops: those of `<worldbody>` and of
    a root body welded to the world (at the world's origin, unrotated: checked)."""
    compiler = {k: v for c in root.findall("compiler") for k, v in c.attrib.items()}
    welded = []
    for body in [w for w in root.findall("worldbody")] + ([] if _joints(tree) else [tree]):
        cls = body.get("childclass", "main")
        for site, name in zip(body.findall("site"), site_names(body, names)):
            welded.append((name, body is tree, *element_pose(lambda a: defaults.get(site, a, cls), compiler,
                                                      f"{owner}: site '{name}'")))
    return welded


def _joints(body: ET.Element) -> list[ET.Element]:
    return body.findall("joint") + body.findall("freejoint")


def _gravity(root: ET.Element, owner: str) -> list[float] | None:
    """`<option gravity>` (None if not given), zero where `<option><flag gravity="disable">`."""
    if any(f.get("gravity") == "disable" for o in root.findall("option") for f in o.findall("flag")):
        return [0.0, 0.0, 0.0]
    gravity = [numbers(o, "gravity", 3, f"{owner}: <option>") for o in root.findall("option")]
    return next((g for g in reversed(gravity) if g is not None), None)


def check_mjcf(path) -> tuple[list[float] | None, list[Equality], list]:
    """Refuse what Pinocchio's MJCF parser would drop or misread and what eomgen does not model (see the
    module); the gravity of `<option>` (None if not given), the file's equalities and the sites welded to
    the world that the parser drops (`_welded_sites`)."""
    path = Path(path)
    root = _read(path)
    owner = f"MJCF {path.name}"
    tree = _check_tree(root, owner)
    defaults = Defaults(root)
    names = {w: "world" for w in root.findall("worldbody")} | body_names(tree, owner)
    moved = {j for b in names for j in b.findall("joint") if any(numbers(j, "pos", 3, owner) or [])}
    check_names(names, moved, owner)
    check_inertias(root, [(b, cls, names[b]) for b, cls, _ in classed(tree)], defaults, owner)
    bodies = {b.get("name") for b in tree.iter("body")}
    sites = {s.get("name") for s in tree.iter("site")}
    equalities = [_equality(e, bodies, sites, owner) for group in root.findall("equality") for e in group]
    named = [e.name for e in equalities]
    for name in named:
        if named.count(name) > 1:
            raise ModelError(f"{owner}: two equalities are named '{name}' (an unnamed one is named after "
                             "its bodies or sites), and Pinocchio's parser keeps one per name: name each of "
                             "them")
    return _gravity(root, owner), equalities, _welded_sites(root, tree, names, defaults, owner)
