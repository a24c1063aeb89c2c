"""What a URDF must hold before it becomes a model: every number urdfdom reads for the dynamics, in the
form and count urdfdom accepts.

urdfdom (Pinocchio's URDF parser) ignores a link it cannot read: it reports an unreadable `<inertial>`
on stderr and goes on with a massless link (or, when only the inertia is bad, with a zero inertia); a
mimic joint becomes an independent joint. Both would be wrong equations without a word, so the file
is read here first (Python's XML parser: no code is run) and refused with the file, link or joint,
element, attribute and value named.

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
Joint `<origin>` and `<axis>` are held to the same rule (urdfdom would refuse the whole file, with a
message naming neither the joint nor the value); `<axis>` is read for the moving joint types only, and
one without `xyz` would be the zero axis. `<limit>`, `<dynamics>` and the rest do not enter M, b, g."""
from __future__ import annotations

import math
import re
import warnings
import xml.etree.ElementTree as ET
from pathlib import Path
from xml.parsers import expat

from ..errors import ModelError

# C++ `istream >> double` in the classic locale, read to the end (urdfdom's strToDouble)
_NUMBER = re.compile(r"[ \t\n\v\f\r]*[+-]?(?:[0-9]+\.?[0-9]*|\.[0-9]+)(?:[eE][+-]?[0-9]+)?")
_INERTIA = ("ixx", "ixy", "ixz", "iyy", "iyz", "izz")
_AXIS_READ = ("revolute", "continuous", "prismatic", "planar")  # urdfdom ignores the axis of the others
_ATTRIBUTE = re.compile(r"""([^\s=/>]+)\s*=\s*(?:"([^"]*)"|'([^']*)')""")
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


def _raw_attributes(data: bytes, root: ET.Element) -> dict[int, dict[str, str]]:
    """id(element) → its attributes as tinyxml2 reads them (Python's parser turns literal tabs and
    newlines into spaces, which would hide values urdfdom cannot read)."""
    starts: list[int] = []
    parser = expat.ParserCreate()
    parser.StartElementHandler = lambda name, attrs: starts.append(parser.CurrentByteIndex)
    parser.Parse(data, True)
    elements = list(root.iter())
    if len(starts) != len(elements):  # cannot happen for a file both parsers read; keep ET's values
        return {}
    raw = {}
    for element, start in zip(elements, starts):
        end, quote = start, None
        while end < len(data):  # the start tag ends at the first '>' outside quotes
            c = data[end:end + 1]
            if quote:
                quote = None if c == quote else quote
            elif c in (b'"', b"'"):
                quote = c
            elif c == b">":
                break
            end += 1
        tag = data[start:end].decode("utf-8", errors="replace")
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
    if read.text(joint, "type") in _AXIS_READ:
        for axis in joint.findall("axis"):
            if read.text(axis, "xyz") is None:
                raise ModelError(f"{owner}: <axis> has no xyz attribute (urdfdom reads it as the zero "
                                 "axis; leave out <axis> for the default 1 0 0)")
            read.numbers(axis, "xyz", 3, owner, "axis")


MIMIC = ("refuse", "independent")


def check_urdf(path: Path, mimic: str = "refuse") -> None:
    """Refuse any inertial number, origin or axis urdfdom would not read (or would drop), an
    `<inertial>` without mass or inertia, a negative mass; mimic joints are refused, or with
    mimic="independent" imported as independent joints (as Pinocchio's default model has them)
    with a warning naming them."""
    if mimic not in MIMIC:
        raise ModelError(f"mimic must be one of {MIMIC}, got {mimic!r}")
    path = Path(path)
    try:
        data = path.read_bytes()
        root = ET.fromstring(data)
        raw = _raw_attributes(data, root)
    except (ET.ParseError, expat.ExpatError) as exc:
        raise ModelError(f"cannot read URDF {path}: {exc}") from None
    read = _Reader(raw)
    for link in root.findall("link"):  # urdfdom reads the top level only
        if read.text(link, "name") is None:
            raise ModelError(f"URDF {path.name}: a <link> has no name attribute")
        _check_link(link, read, f"URDF {path.name}: link '{link.get('name')}'")
    mimics = []
    for joint in root.findall("joint"):
        owner = f"URDF {path.name}: joint '{joint.get('name')}'"
        _check_joint(joint, read, owner)
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
