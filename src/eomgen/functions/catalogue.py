"""The catalogue of generated functions: every function a model offers, named once.

A `Function` is f(inputs) → an output of a fixed shape, whose expression is built from the equations'
intermediates on first request; a `Family` is one such function per item (a frame, load or joint). A
`Catalogue` holds a model's functions and families in the order the targets print them, and the reason
for each function the model does not offer (asking for one is a ModelError with that reason). Every
target (NumPy, the written module, the C extension, plain C) prints from it."""
from __future__ import annotations

from collections.abc import Callable, Iterator
from dataclasses import dataclass

import sympy as sp

from ..errors import ModelError
from ..subexpressions import Subexpressions

FORMS = ("matrix", "vector", "number")  # a call returns out, out[..., 0] or out[..., 0, 0]


@dataclass(frozen=True)
class Function:
    """One function: `key` (what targets store it by), its public `name`, what it is, its inputs (a
    subset of "q, u, ud"; the parameters p always), its output `shape` and `form`, whether it is
    symmetric (only the upper triangle computed), the names of its rows (constraints) and `build`, which
    returns its expression in the intermediates. `public`: a function users call in every target; the
    others are building blocks of the numeric algorithms. `item`: the frame, load or joint of a member
    of a family. A composite (no `build`) is computed by each target from its `parts`."""

    key: str
    name: str
    what: str
    inputs: str
    shape: tuple[int, int]
    build: Callable[[], sp.Basic] | None
    form: str = "matrix"
    symmetric: bool = False
    rows: tuple[str, ...] = ()
    public: bool = True
    item: str | None = None
    parts: tuple[str, ...] = ()  # a composite's: the functions it is computed from

    @property
    def composite(self) -> bool:
        """Whether each target computes it from other functions (no expression of its own)."""
        return self.build is None

    def expression(self) -> sp.Matrix:
        """The output in the intermediates, checked against the declared shape."""
        if self.composite:
            raise ModelError(f"catalogue: {self.key} is computed from other functions; it has no expression")
        expr = self.build()
        matrix = expr if isinstance(expr, sp.MatrixBase) else sp.Matrix([[expr]])
        if matrix.shape != self.shape:
            raise ModelError(f"catalogue: {self.key} has shape {matrix.shape}, declared {self.shape}")
        return matrix


@dataclass(frozen=True)
class Family:
    """One function per item: `prefix` (keys "<prefix>:<item>"), the kind of item ("frame", "load",
    "joint", "drive": a joint of prescribed motion), what it is ("{item}" stands for the item's name),
    the `items` a target prints by default, and `build(item)`; the rest as `Function`'s. An
    item outside `items` is refused by `known` (None: by `build` itself, e.g. any frame or body)."""

    prefix: str
    kind: str
    name: str
    what: str
    inputs: str
    shape: tuple[int, int]
    build: Callable[[str], sp.Basic]
    items: tuple[str, ...]
    form: str = "matrix"
    known: Callable[[str], None] | None = None

    def of(self, item: str) -> Function:
        """The function of one item."""
        if self.known is not None:
            self.known(item)
        return Function(f"{self.prefix}:{item}", self.name, self.what.format(item=item),
                        self.inputs, self.shape, lambda: self.build(item), self.form, item=item)


class Catalogue:
    """A model's functions and families, in printing order, and why the others are not offered."""

    def __init__(self, sub: Subexpressions, inputs: dict[str, list[sp.Symbol]], functions: list[Function],
                 families: list[Family], missing: dict[str, str], eager: list[str]) -> None:
        self.sub = sub  # the intermediates the expressions are written in
        self.inputs = inputs  # the symbols of q, u, ud and p (p[k]: the parameters sorted by name)
        self.functions = {f.key: f for f in functions}
        self.families = {f.prefix: f for f in families}
        self.missing = missing  # key: the reason it is not offered
        self.eager = eager  # the keys generated up front

    def __iter__(self) -> Iterator[Function]:
        return iter(self.functions.values())

    def __contains__(self, key: str) -> bool:
        prefix, _, item = key.partition(":")
        return key in self.functions or bool(item) and prefix in self.families

    def __getitem__(self, key: str) -> Function:
        if key in self.functions:
            return self.functions[key]
        prefix, _, item = key.partition(":")
        if item and prefix in self.families:
            return self.families[prefix].of(item)
        reason = self.missing.get(key) or self.missing.get(prefix) if item else self.missing.get(key)
        raise ModelError(reason or f"no function {key!r} in the catalogue")

    def family(self, prefix: str) -> Family:
        """The family `prefix`, or a ModelError with the reason the model has none."""
        if prefix not in self.families:
            raise ModelError(self.missing.get(prefix, f"no family {prefix!r} in the catalogue"))
        return self.families[prefix]

    def frames(self) -> list[str]:
        """The prefixes of the families per frame (J, J̇ u, [R | p])."""
        return [prefix for prefix, family in self.families.items() if family.kind == "frame"]

    def parts(self) -> set[str]:
        """The keys the composites are computed from."""
        return {key for fn in self if fn.composite for key in fn.parts}

    def printable(self, key: str) -> Function:
        """Function `key`, refused when it is a composite (which the numeric layer computes from its
        parts)."""
        fn = self[key]
        if fn.composite:
            raise ModelError(f"{key} is computed from other functions by the numeric layer; call {fn.name}")
        return fn

    def public(self) -> list[Function]:
        """The functions users call in every target."""
        return [f for f in self if f.public]
