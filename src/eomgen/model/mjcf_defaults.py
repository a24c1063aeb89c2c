"""MuJoCo's default classes: an element's attribute is its own, else that of its class's `<default>`
for its tag, else of the enclosing defaults up to the top one ("main"). The class is the element's
`class`, else the `childclass` of the nearest enclosing body, else "main"."""
from __future__ import annotations

import xml.etree.ElementTree as ET
from collections.abc import Iterator


class Defaults:
    """The `<default>` tree of a file, by class name."""

    def __init__(self, root: ET.Element) -> None:
        self.element: dict[str, ET.Element] = {}
        self.parent: dict[str, str | None] = {}
        for top in root.findall("default"):
            self._add(top, top.get("class", "main"), None)

    def _add(self, element: ET.Element, name: str, parent: str | None) -> None:
        self.element[name], self.parent[name] = element, parent
        for child in element.findall("default"):
            self._add(child, child.get("class", ""), name)

    def get(self, element: ET.Element, attribute: str, cls: str) -> str | None:
        """The attribute as MuJoCo reads it for `element` of class `cls` (None: MuJoCo's own default)."""
        if attribute in element.attrib:
            return element.get(attribute)
        name: str | None = element.get("class", cls)
        while name is not None and name in self.element:
            for given in self.element[name].findall(element.tag):
                if attribute in given.attrib:
                    return given.get(attribute)
            name = self.parent[name]
        return None


def bodies(body: ET.Element, cls: str = "main", parent: ET.Element | None = None
           ) -> Iterator[tuple[ET.Element, str, ET.Element | None]]:
    """(body, the class of its elements, its parent body) of a tree, parents first."""
    cls = body.get("childclass", cls)
    yield body, cls, parent
    for child in body.findall("body"):
        yield from bodies(child, cls, body)
