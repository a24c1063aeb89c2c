"""A robot file (URDF, MJCF) read once, and refused where Pinocchio's parser would read other elements or
fail on its size.

eomgen checks a file with expat before Pinocchio parses it again with its own parser (tinyxml2 for URDF,
rapidxml for MJCF). The parsers agree on plain XML, not on a DTD: an entity whose text holds `>` (URDF)
or `]>` (MJCF) makes them read different elements, so the checks would pass one model and the equations
use another. As defusedxml does, a file is refused, naming it and what was found, at
- a DOCTYPE (with or without an internal subset), so ENTITY declarations (which only a DOCTYPE holds)
  and entity references besides the five predefined ones (&lt; &gt; &amp; &quot; &apos;) and
  character references (&#…;), which expat refuses as undefined without a DTD;
- a processing instruction (the XML declaration `<?xml …?>` is none);
- elements nested deeper than MAX_DEPTH. Pinocchio 4.1 recurses per level: a 10,000-deep MJCF chain
  kills the process (segmentation fault), and its MJCF parser grows as the cube of the depth (measured
  on 2 cores: 200 bodies 0.3 s and 0.26 GB, 247 bodies — depth 250 with <mujoco>, <worldbody> and a
  geom — 0.8 s and 0.5 GB, 300 bodies 1.7 s and 0.85 GB, 400 bodies 4.4 s and 2 GB); tinyxml2 refuses
  500 levels with a message that names nothing. A URDF's chain of joints is flat XML (see urdf_check).
The check runs in expat's callbacks while it streams (no recursion: a 10,000-deep file is refused at
level 251 in milliseconds), and the same pass builds the tree, without namespace processing: the C++
parsers know no namespaces (`<robot xmlns="…">` is `robot` to them, not `{…}robot`)."""
from __future__ import annotations

import xml.etree.ElementTree as ET
from dataclasses import dataclass
from pathlib import Path
from xml.parsers import expat

from ..errors import ModelError

MAX_DEPTH = 250  # elements nested, the root's level 1


@dataclass(frozen=True)
class Document:
    """A file's bytes, its element tree, and the byte offset of each start tag in document order (the
    order of `root.iter()`)."""

    data: bytes
    root: ET.Element
    starts: list[int]


class _Stream:
    """expat's callbacks: refuse (see the module) and build the tree while the parser streams."""

    def __init__(self, owner: str):
        self.owner, self.depth, self.starts = owner, 0, []
        self.parser, self.builder = expat.ParserCreate(), ET.TreeBuilder()
        self.parser.StartDoctypeDeclHandler = self.doctype
        self.parser.ProcessingInstructionHandler = self.instruction
        self.parser.StartElementHandler, self.parser.EndElementHandler = self.start, self.end
        self.parser.CharacterDataHandler = self.builder.data

    def where(self) -> str:
        return f"{self.owner}, line {self.parser.CurrentLineNumber}"

    def doctype(self, name: str, *_) -> None:
        raise ModelError(f"{self.where()}: <!DOCTYPE {name} …>: DTDs and entities are refused in robot "
                         "files (Pinocchio's parser would read other elements than eomgen's checks); "
                         "write the values out")

    def instruction(self, target: str, _) -> None:
        raise ModelError(f"{self.where()}: processing instruction <?{target} …?>: remove it")

    def start(self, tag: str, attributes: dict) -> None:
        self.depth += 1
        if self.depth > MAX_DEPTH:
            raise ModelError(f"{self.where()}: <{tag}> is nested deeper than {MAX_DEPTH} elements, the "
                             "most eomgen reads (Pinocchio's parser recurses per level: 10,000 levels crash "
                             "it, a 400-deep MJCF chain takes 4 s and 2 GB)")
        self.starts.append(self.parser.CurrentByteIndex)
        self.builder.start(tag, attributes)

    def end(self, tag: str) -> None:
        self.depth -= 1
        self.builder.end(tag)


def read_xml(path: Path, kind: str) -> Document:
    """The file at `path` (kind: "URDF" or "MJCF", for the messages) read and checked (see the module)."""
    path = Path(path)
    if not path.is_file():
        raise ModelError(f"{kind} file not found: {path}")
    try:
        data = path.read_bytes()
    except OSError as exc:
        raise ModelError(f"cannot read {kind} {path}: {exc}") from None
    try:
        data.decode("utf-8")
    except UnicodeDecodeError as exc:
        raise ModelError(f"{kind} {path.name}: byte {exc.start} is not UTF-8; robot files are read as UTF-8 "
                         "(the C++ parsers read no other encoding alike)") from None
    stream = _Stream(f"{kind} {path.name}")
    try:
        stream.parser.Parse(data, True)
    except expat.ExpatError as exc:
        undefined = exc.code == expat.errors.codes[expat.errors.XML_ERROR_UNDEFINED_ENTITY]
        hint = (" (entities are refused in robot files: only &lt; &gt; &amp; &quot; &apos; and character "
                "references &#…; are read alike by eomgen and Pinocchio)") if undefined else ""
        raise ModelError(f"cannot read {kind} {path}: {expat.errors.messages[exc.code]}: line {exc.lineno}, "
                         f"column {exc.offset + 1}{hint}") from None
    return Document(data, stream.builder.close(), stream.starts)
