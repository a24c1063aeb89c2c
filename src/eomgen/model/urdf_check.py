"""What a URDF must hold before it becomes a model: every number urdfdom reads for the dynamics, in the
form and count urdfdom accepts.

urdfdom (Pinocchio's URDF parser) ignores a link it cannot read: it reports an unreadable `<inertial>`
on stderr and goes on with a massless link (or, when only the inertia is bad, with a zero inertia).
That would be wrong equations without a word, so the file is read here first (Python's XML parser: no
code is run) and refused with the file, link or joint, element, attribute and value named.

The rule urdfdom 6 applies (found by experiment with Pinocchio's parser, and in urdfdom's source:
`strToDouble`, `Vector3::init`, `parseInertial`), on the attribute text as tinyxml2 gives it (character
references decoded, literal tabs and newlines kept, CR LF read as LF):
- a number is C++ `istream >> double` in the C locale that must end exactly at the end of the text:
  leading whitespace (space, tab, LF, VT, FF, CR), an optional sign, decimal digits with at most one
  point and at least one digit, an optional exponent `e`/`E` with optional sign and digits; nothing
  after it (not even a space), no `inf`, `nan`, hexadecimal, `_` or `,`; a value overflowing a
  double is refused, one that underflows is read as 0 (or a subnormal), as Python reads it;
- a vector (`xyz`, `rpy`) is the text split at spaces only (a tab or newline does not separate), empty
  pieces skipped, exactly 3 pieces, each a number as above;
- `<inertial>` needs `<mass value>` (one number) and `<inertia>` with all of ixx, ixy, ixz, iyy, iyz,
  izz (one number each); its `<origin>` may omit xyz or rpy (zero). A link without `<inertial>` is a
  legitimate massless link.
Joint `<origin>` and `<axis>` and the `<mimic>` multiplier and offset are held to the same rule
(urdfdom would refuse the whole file, with a message naming neither the joint nor the value); `<axis>`
is read for the moving joint types only, and one without `xyz` would be the zero axis. `<limit>`,
`<dynamics>` and the rest do not enter M, b, g.

Pinocchio's parser (with mimic=True) stops with a terse message at a mimic it cannot follow and ignores
the `<mimic>` of a planar or floating joint; it ignores the axis of a planar joint. Those files are
refused here with the joints named (`_check_mimics`, `_check_joint`)."""
from __future__ import annotations

import math
import re
import warnings
import xml.etree.ElementTree as ET
from pathlib import Path

from ..errors import ModelError
from .xml_read import Document, read_xml

# C++ `istream >> double` in the classic locale, read to the end (urdfdom's strToDouble)
_NUMBER = re.compile(r"[ \t\n\v\f\r]*[+-]?(?:[0-9]+\.?[0-9]*|\.[0-9]+)(?:[eE][+-]?[0-9]+)?")
_INERTIA = ("ixx", "ixy", "ixz", "iyy", "iyz", "izz")
_AXIS_READ = ("revolute", "continuous", "prismatic", "planar")  # urdfdom ignores the axis of the others
_ATTRIBUTE = re.compile(r"""([^\s=/>]+)\s*=\s*(?:"([^"]*)"|'([^']*)')""")
_START_TAG = re.compile(rb"""<(?:[^"'>]|"[^"]*"|'[^']*')*>""")  # to the first '>' outside quotes
_REFERENCE = re.compile(r"&(#x[0-9a-fA-F]+|#[0-9]+|lt|gt|amp|quot|apos);")
_NAMED = {"lt": "<", "gt": ">", "amp": "&", "quot": '"', "apos": "'"}


def _tinyxml(raw: str) -> str:
    """An attribute's text as tinyxml2 gives it: newlines normalized, references decoded, the
    rest (tabs and newlines included) kept."""
    raw = raw.replace("\r\n", "\n").replace("\r", "\n")

    def decode(match: re.Match) -> str:
        ref = match.group(1)
        if ref.startswith("#x"):
            return chr(int(ref[2:], 16))
        return chr(int(ref[1:])) if ref.startswith("#") else _NAMED[ref]
    return _REFERENCE.sub(decode, raw)


def _raw_attributes(document: Document) -> dict[int, dict[str, str]]:
    """id(element) → its attributes as tinyxml2 reads them (Python's parser turns literal tabs and
    newlines into spaces, which would hide values urdfdom cannot read)."""
    data, raw = document.data, {}
    for element, start in zip(document.root.iter(), document.starts):
        tag = _START_TAG.match(data, start).group().decode("utf-8", errors="replace")
        raw[id(element)] = {m.group(1): _tinyxml(m.group(2) if m.group(2) is not None else m.group(3))
                            for m in _ATTRIBUTE.finditer(tag)}
    return raw


class _Reader:
    """Reads numbers off elements with urdfdom's rule; refusals name owner, element, attribute, value."""

    def __init__(self, raw: dict[int, dict[str, str]]):
        self.raw = raw

    def text(self, element: ET.Element, name: str) -> str | None:
        return self.raw.get(id(element), element.attrib).get(name)

    def numbers(self, element: ET.Element, name: str, count: int | None, owner: str,
                where: str, required: bool = False) -> list[float] | None:
        """The values of attribute `name`: one number if count is None, else a vector of `count`."""
        text = self.text(element, name)
        if text is None:
            if required:
                raise ModelError(f"{owner}: {where} has no {name} attribute (urdfdom would drop the "
                                 "link's inertial data and go on with zeros)")
            return None
        pieces = [text] if count is None else [p for p in text.split(" ") if p != ""]
        if count is not None and len(pieces) != count:
            raise ModelError(f"{owner}: {where} {name}={text!r} has {len(pieces)} numbers, {count} expected")
        values = []
        for piece in pieces:
            which = "" if count is None else f" ({piece!r})"
            if piece.strip().lower().lstrip("+-") in ("inf", "infinity", "nan"):
                raise ModelError(f"{owner}: {where} {name}={text!r}{which} must be finite")
            if not _NUMBER.fullmatch(piece):
                raise ModelError(f"{owner}: {where} {name}={text!r}{which} is not a number urdfdom reads "
                                 "(decimal digits, point, exponent, leading blanks only; no inf, nan, "
                                 "hexadecimal, '_', ',' or trailing blank)")
            value = float(piece)
            if not math.isfinite(value):
                raise ModelError(f"{owner}: {where} {name}={text!r}{which} must be finite (it overflows "
                                 "a double)")
            values.append(value)
        return values


def _check_link(link: ET.Element, read: _Reader, owner: str) -> None:
    for inertial in link.findall("inertial"):
        for origin in inertial.findall("origin"):
            for name in ("xyz", "rpy"):
                read.numbers(origin, name, 3, owner, "inertial/origin")
        masses, inertias = inertial.findall("mass"), inertial.findall("inertia")
        if not masses:
            raise ModelError(f"{owner}: <inertial> has no <mass> (urdfdom would drop the inertial and "
                             "go on with a massless link; leave out <inertial> for a massless link)")
        if not inertias:
            raise ModelError(f"{owner}: <inertial> has no <inertia> (urdfdom would go on with a zero "
                             "inertia)")
        for mass in masses:
            value = read.numbers(mass, "value", None, owner, "inertial/mass", required=True)[0]
            if value < 0:
                raise ModelError(f"{owner}: mass must be non-negative, got {value}")
        for inertia in inertias:
            for name in _INERTIA:
                read.numbers(inertia, name, None, owner, "inertial/inertia", required=True)


def _check_joint(joint: ET.Element, read: _Reader, owner: str) -> None:
    for origin in joint.findall("origin"):
        for name in ("xyz", "rpy"):
            read.numbers(origin, name, 3, owner, "origin")
    kind = read.text(joint, "type")
    axis = [1.0, 0.0, 0.0]  # urdfdom's default
    if kind in _AXIS_READ:
        for element in joint.findall("axis"):
            if read.text(element, "xyz") is None:
                raise ModelError(f"{owner}: <axis> has no xyz attribute (urdfdom reads it as the zero "
                                 "axis; leave out <axis> for the default 1 0 0)")
            axis = read.numbers(element, "xyz", 3, owner, "axis")
    if kind == "planar" and not (axis[2] > 0 and math.hypot(*axis[:2]) <= 1e-14 * axis[2]):
        raise ModelError(f"{owner}: a planar joint moves in the plane normal to its axis, here "
                         f"{' '.join(map(repr, axis))} (1 0 0 without <axis>), but Pinocchio's parser "
                         "always takes the joint frame's xy plane: give <axis xyz=\"0 0 1\"/> and turn the "
                         "joint's <origin> so that its z axis is the plane's normal")
    follows = joint.find("mimic")  # urdfdom reads the first, on every joint type
    if follows is not None:
        if read.text(follows, "joint") is None:
            raise ModelError(f"{owner}: <mimic> has no joint attribute (urdfdom refuses the file)")
        for name in ("multiplier", "offset"):
            read.numbers(follows, name, None, owner, "mimic")


MIMIC = ("mimic", "independent", "refuse")
MAX_CHAIN = 1000  # joints from the root link (see _check_depth)
_FOLLOWED = ("revolute", "prismatic")  # the types Pinocchio's parser makes mimic joints of, and follows


def _parse_order(root: ET.Element, read: _Reader) -> list[tuple[str, str | None, int]]:
    """(joint, its child link, its depth: 1 below the root link) in the order Pinocchio's parser adds
    joints: depth first from the root link, the child joints of a link by name (urdfdom keeps them in
    a std::map). Walked with a stack: urdfdom recurses, eomgen must not."""
    children: dict[str | None, list[tuple[str, str | None]]] = {}
    for joint in root.findall("joint"):
        parent, child = joint.find("parent"), joint.find("child")
        if parent is not None and child is not None:
            children.setdefault(read.text(parent, "link"), []).append((read.text(joint, "name") or "",
                                                                      read.text(child, "link")))
    child_links = {link for joints in children.values() for _, link in joints}
    links = [read.text(link, "name") for link in root.findall("link")]
    roots = [link for link in links if link not in child_links]

    def below(link, depth):  # reversed: the stack pops the first name first
        return [(name, child, depth) for name, child in sorted(children.get(link, []), reverse=True,
                                                                key=lambda joint: joint[0])]

    order: list[tuple[str, str | None, int]] = []
    stack, seen = below(roots[0], 1) if len(roots) == 1 else [], set(roots)
    while stack:
        order.append(stack.pop())
        name, link, depth = order[-1]
        if link not in seen:  # a link below two joints (urdfdom refuses the file) is walked once
            seen.add(link)
            stack += below(link, depth + 1)
    return order


def _check_depth(path: Path, order: list[tuple[str, str | None, int]]) -> None:
    """Refuse a chain of more than MAX_CHAIN joints: Pinocchio's URDF parser recurses once per joint
    (Pinocchio 4.1, measured on 2 cores: 1000 joints 0.15 s and 35 MB, 2000 joints 0.5 s; near 4000 it
    overflows an 8 MB stack and kills the process)."""
    if order and (deepest := max(order, key=lambda joint: joint[2]))[2] > MAX_CHAIN:
        raise ModelError(f"URDF {path.name}: joint '{deepest[0]}' is {deepest[2]} joints below the root "
                         f"link, more than the {MAX_CHAIN} eomgen reads (Pinocchio's parser recurses once "
                         "per joint and crashes near 4000)")


def _check_mimics(path: Path, root: ET.Element, read: _Reader, mimic: str,
                  order: list[tuple[str, str | None, int]]) -> None:
    """Refuse a mimic of an unknown joint, of itself, a loop of mimics; per `mimic` (see check_urdf),
    the mimic joints, or (mode "mimic") what Pinocchio's parser and eomgen do not follow: a mimic of a
    mimic, of a joint neither revolute nor prismatic, a mimic that is not revolute or prismatic, or one
    met before its driver."""
    types = {read.text(j, "name"): read.text(j, "type") for j in root.findall("joint")}
    follows = {read.text(j, "name"): read.text(j.find("mimic"), "joint") for j in root.findall("joint")
               if j.find("mimic") is not None and read.text(j, "type") != "fixed"}  # fixed: no motion
    for name, driver in follows.items():
        owner = f"URDF {path.name}: joint '{name}'"
        if driver == name:
            raise ModelError(f"{owner} mimics itself")
        if driver not in types:
            raise ModelError(f"{owner} mimics the unknown joint '{driver}'")
        loop = [name]
        while loop[-1] in follows and follows[loop[-1]] not in loop:
            loop.append(follows[loop[-1]])
        if loop[-1] in follows:
            loop = loop[loop.index(follows[loop[-1]]):]
            raise ModelError(f"URDF {path.name}: joints {loop} mimic each other in a loop: "
                             f"{' → '.join(repr(j) for j in loop + loop[:1])}")
    if follows and mimic == "refuse":
        name, driver = next(iter(follows.items()))
        raise ModelError(f"URDF {path.name}: joint '{name}' mimics joint '{driver}': from_urdf(..., "
                         "mimic='mimic') follows it, mimic='independent' imports it as an independent joint")
    if follows and mimic == "independent":
        warnings.warn(f"URDF {path.name}: mimic joints {list(follows)} imported as independent joints "
                      "(mimic='independent'), as in Pinocchio's default model", stacklevel=5)
    if mimic != "mimic":
        return
    place = {name: i for i, (name, _, _) in reversed(list(enumerate(order)))}  # a name's first place
    for name, driver in follows.items():
        owner = f"URDF {path.name}: joint '{name}'"
        if types[name] not in _FOLLOWED:
            raise ModelError(f"{owner}, a {types[name]} joint, mimics '{driver}': Pinocchio's parser makes "
                             "mimic joints of revolute and prismatic joints only; use mimic='independent'")
        if driver in follows:
            raise ModelError(f"{owner} mimics '{driver}', which mimics '{follows[driver]}': a mimic of a "
                             f"mimic is followed by neither Pinocchio nor eomgen; let '{name}' mimic "
                             f"'{follows[driver]}' with the product of the multipliers")
        if types[driver] not in _FOLLOWED:
            raise ModelError(f"{owner} mimics '{driver}', a {types[driver]} joint: a mimic joint follows a "
                             "revolute or prismatic joint")
        if place.get(driver, -1) > place.get(name, -1):
            raise ModelError(f"{owner} mimics '{driver}', which Pinocchio's parser adds after it (depth "
                             "first from the root link, the joints of a link by name); rename or rearrange "
                             f"the joints so that '{driver}' comes first, or use mimic='independent'")


def check_urdf(path: Path, mimic: str = "mimic") -> None:
    """Refuse what `read_xml` refuses (DTDs, entities, deep nesting), a chain deeper than MAX_CHAIN
    joints, any inertial number, origin, axis or mimic number urdfdom would not read (or would drop),
    an `<inertial>` without mass or inertia, a negative mass, a planar joint whose plane is not the
    joint frame's xy plane, and mimic joints that cannot be followed (`_check_mimics`);
    mimic="independent" imports them as independent joints (as Pinocchio's default model has them)
    with a warning naming them, mimic="refuse" refuses them. A fixed joint's `<mimic>` moves nothing."""
    if mimic not in MIMIC:
        raise ModelError(f"mimic must be one of {MIMIC}, got {mimic!r}")
    path = Path(path)
    document = read_xml(path, "URDF")
    root, read = document.root, _Reader(_raw_attributes(document))
    for link in root.findall("link"):  # urdfdom reads the top level only
        if read.text(link, "name") is None:
            raise ModelError(f"URDF {path.name}: a <link> has no name attribute")
        _check_link(link, read, f"URDF {path.name}: link '{link.get('name')}'")
    for joint in root.findall("joint"):
        _check_joint(joint, read, f"URDF {path.name}: joint '{joint.get('name')}'")
    order = _parse_order(root, read)
    _check_depth(path, order)
    _check_mimics(path, root, read, mimic, order)
