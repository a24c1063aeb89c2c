"""Sphinx directives of eomgen's documentation, reading the package at build time.

``eomgen-quantities``
    A table of the quantities the numeric functions of ``eg.codegen`` evaluate, one row per entry of
    ``eomgen.functions.QUANTITIES``: the call, the shape of its result for one state (measured on a small
    model) and the description from the source.

``toctree-if-any``
    A ``toctree`` that is left out while its glob patterns match no document (Sphinx warns on an
    empty glob, and the notebooks folder may be empty).

Both write reStructuredText: use them inside an ``{eval-rst}`` block of a MyST page."""
from __future__ import annotations

import inspect

from docutils import nodes
from docutils.statemachine import StringList
from sphinx.directives.other import TocTree
from sphinx.util import docname_join
from sphinx.util.docutils import SphinxDirective
from sphinx.util.matching import patfilter


def _parse(directive: SphinxDirective, text: str) -> list[nodes.Node]:
    container = nodes.container()
    directive.state.nested_parse(StringList(text.splitlines(), source="<eomgen_docs>"),
                                 directive.content_offset, container)
    return container.children


def _shape_text(shape: tuple) -> str:
    """The shape of a result on the two-speed sample model, with the sizes named."""
    if shape == ():
        return "scalar"
    return "(" + ", ".join("nv" if n == 2 else str(n) for n in shape) + (",)" if len(shape) == 1 else ")")


class Quantities(SphinxDirective):
    """The table of ``QUANTITIES`` (see the module doc)."""

    has_content = False

    def run(self) -> list[nodes.Node]:
        import sympy as sp

        import eomgen as eg
        from eomgen.functions import QUANTITIES
        from eomgen.numeric import NumericEoM

        for obj in (NumericEoM, NumericEoM.M):  # the class, and the module of its evaluations
            self.env.note_dependency(inspect.getfile(obj))
        m = sp.Symbol("m", positive=True)
        system = eg.System(gravity=(0, -9.81, 0))
        cart = system.add_body("cart", joint=eg.Prismatic("x", axis=(1, 0, 0)), mass=1)
        system.add_body("pendulum", parent=cart, joint=eg.Revolute("phi"), mass=m, com=(0, -1, 0))
        f = eg.codegen(eg.derive(system, method="recursive"))
        rows = []
        for key, what in QUANTITIES.items():
            method = getattr(NumericEoM, key)
            parameters = [p for p in inspect.signature(method).parameters.values() if p.name != "self"]
            values = {"q": [0.1, 0.2], "u": [0.3, 0.4], "params": {"m": 0.5}, "out": None}
            shape = _shape_text(tuple(getattr(f, key)(*[values[p.name] for p in parameters]).shape))
            call = f"``f.{key}({', '.join(map(str, parameters))})``"
            rows.append(f"   * - {call}\n     - {shape}\n     - {what.replace('*', chr(92) + '*')}")
        table = ("\n.. list-table::\n   :header-rows: 1\n   :widths: 25 12 63\n\n"
                 "   * - call\n     - result (one state)\n     - what it is\n" + "\n".join(rows) + "\n")
        return _parse(self, table)


class TocTreeIfAny(TocTree):
    """A globbing ``toctree``, left out while no document matches (see the module doc)."""

    def run(self) -> list[nodes.Node]:
        current = self.env.docname
        documents = sorted(self.env.found_docs - {current})
        patterns = [docname_join(current, entry.strip()) for entry in self.content if entry.strip()]
        if not any(patfilter(documents, pattern) for pattern in patterns):
            self.env.glob_toctrees.add(current)  # read again when documents are added
            return []
        return super().run()


def setup(app):
    app.add_directive("eomgen-quantities", Quantities)
    app.add_directive("toctree-if-any", TocTreeIfAny)
    return {"parallel_read_safe": True, "parallel_write_safe": True}
