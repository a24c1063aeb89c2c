"""The pieces of a linearization (M, h, J_c, ... in the named intermediates) at one point, with their
Jacobians along the tangent directions δ (`derivatives.tangent_seeds`), the speeds u, Kane's speeds w
and the chosen parameters p (`derivatives.jacobian`: the chain rule through the intermediates):

    d piece = ∂piece/∂δ dδ + ∂piece/∂u du + ∂piece/∂w dw + ∂piece/∂p dp,

each value and Jacobian a generated NumPy function of (q, u, w, p), written on first use; or, at a
symbolic point, the intermediates substituted one after another (closed forms, refused beyond
`SYMBOLIC_OPS` operations)."""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field

import numpy as np
import sympy as sp

from ..numeric.parameters import Parameters
from ..printers.python import compile_function
from ..printers.runtime import runtime_namespace
from ..printers.walker import FunctionWriter, Generated
from ..derivatives import jacobian, speed_seeds, tangent_seeds
from ..errors import ModelError
from ..subexpressions import Subexpressions
from .dual import Algebra, Dual

_call = runtime_namespace()["_call"]
SYMBOLIC_OPS = 50_000  # operations of the closed forms at a symbolic point beyond which it is refused


@dataclass
class Point:
    """Where the pieces are evaluated: q (nq), the parameter values {symbol: value}, the `chosen`
    parameters p (a family of directions), the tangents {"q": dδ, "p": dp} (n × seeds), n directions;
    at a symbolic point the values of the intermediates found so far and their operation count."""

    q: np.ndarray
    values: dict
    chosen: list
    tangents: dict
    n: int
    algebra: Algebra
    known: dict = field(default_factory=dict)
    ops: int = 0


class Pieces:
    """Named matrices `exprs` {name: (matrix, arguments ⊂ {"u", "w"})} of one set of intermediates, in the
    system's q, u, Kane's speeds `w` (none for equations of motion) and the `parameters`."""

    def __init__(self, sub: Subexpressions, system, exprs: dict, parameters: Parameters, w: list) -> None:
        self.sub, self.exprs, self.parameters = sub, exprs, parameters
        self.nq, self.n = len(system.q), len(system.u)
        self.seeds = {"q": tangent_seeds(system), "u": speed_seeds(system), "w": [{x: 1} for x in w]}
        self.inputs = {"q": list(system.q), "u": list(system.u), "w": list(w)}
        self.writer = FunctionWriter(
            sub,
            {"q": self.inputs["q"], "u": self.inputs["u"], "ud": self.inputs["w"], "p": parameters.symbols},
        )
        self.functions: dict[tuple, Generated] = {}

    def parameters_used(self) -> list[int]:
        """The indices of the parameters any piece needs (through its intermediates)."""
        exprs = [x for matrix, _ in self.exprs.values() for x in sp.Matrix(matrix)]
        needed = set().union(*(sp.sympify(x).free_symbols for x in exprs),
                             *(self.sub.definitions[s].free_symbols for s in self.sub.dependencies(exprs)))
        return [k for k, p in enumerate(self.parameters.symbols) if p in needed]

    def _matrix(self, name: str, family: str | None, chosen: list) -> sp.Matrix:
        """The piece (family None), or its Jacobian (r c × seeds, rows of the piece row by row)."""
        expr = sp.Matrix(self.exprs[name][0])
        if family is None:
            return expr
        column = expr.reshape(expr.rows * expr.cols, 1)
        if family != "p":
            return jacobian(self.sub, column, self.seeds[family], ("linearize", family))
        return sp.Matrix.hstack(
            *(jacobian(self.sub, column, [{p: 1}], ("linearize", "p", p)) for p in chosen),
            sp.zeros(column.rows, 0),
        )

    def evaluate(self, name: str, family: str | None, point: Point, u=None, w=None) -> np.ndarray:
        """The piece (family None) or its Jacobian along a family at the point (u, w: the speeds' values)."""
        return (self._closed if point.algebra.symbolic else self._numbers)(name, family, point, u, w)

    def _numbers(self, name: str, family: str | None, point: Point, u, w) -> np.ndarray:
        key = (name, family, tuple(point.chosen) if family == "p" else ())
        if key not in self.functions:
            source, shape, ops = self.writer.source("f", self._matrix(name, family, point.chosen))
            self.functions[key] = Generated(
                source, shape, ops, compile_function(source, f"linearize {name}")
            )
        f = self.functions[key]
        p = self.parameters.vector(point.values, f.params_used)
        return _call(f.function, f.shape, self.nq, self.n, point.q, u, w, p)

    def _closed(self, name: str, family: str | None, point: Point, u, w) -> np.ndarray:
        """The closed form at a symbolic point: each intermediate's definition with the values so far."""
        matrix = self._matrix(name, family, point.chosen)
        known = point.known
        known.update(point.values)
        known.update(
            {
                s: v
                for arg, x in (("q", point.q), ("u", u), ("w", w))
                if x is not None
                for s, v in zip(self.inputs[arg], x)
            }
        )
        for s in self.sub.dependencies(list(matrix)):
            if s not in known:
                known[s] = self.sub.definitions[s].xreplace(known)
                point.ops += sp.count_ops(known[s])
                if point.ops > SYMBOLIC_OPS:
                    raise ModelError(
                        f"linearize: the closed forms at this operating point exceed {SYMBOLIC_OPS} "
                        f"operations (at {name}): the system is too large for symbolic=True; "
                        "linearize numerically (symbolic=False)"
                    )
        return np.array(matrix.xreplace(known).tolist(), dtype=object).reshape(matrix.shape)

    def dual(self, name: str, point: Point, u: Dual | None = None, w: Dual | None = None) -> Dual:
        """The piece at `point` (with the speeds u, w where it takes them) and its derivatives along the
        point's directions."""
        uv, wv = (None if x is None else x.value[:, 0] for x in (u, w))
        value = self.evaluate(name, None, point, uv, wv)
        tangent = None
        directions = {"q": point.tangents["q"], "u": _flat(u), "w": _flat(w), "p": point.tangents.get("p")}
        for family, d in directions.items():
            if d is not None and d.shape[1] and self._takes(name, family):
                t = (d @ self.evaluate(name, family, point, uv, wv).T).reshape((point.n,) + value.shape)
                tangent = t if tangent is None else tangent + t
        return Dual(value, tangent)

    def _takes(self, name: str, family: str) -> bool:
        """Whether the piece depends on a family's symbols: q and p always, u and w where declared."""
        return family in ("q", "p") or family in self.exprs[name][1] and bool(self.seeds[family])


def _flat(x: Dual | None) -> np.ndarray | None:
    """The tangent of a column (n × r × 1) as n × r."""
    return None if x is None or x.tangent is None else x.tangent[:, :, 0]


def values(parameters: Parameters, params: Mapping | None, symbolic: bool) -> dict:
    """{symbol: value} of the given parameters by name or symbol (numbers; or sympy values, symbolic)."""
    if params is not None and not isinstance(params, Mapping):
        raise ModelError(f"params: expected a mapping {{name: value}}, got {type(params).__name__}")
    out = {}
    for key, value in (params or {}).items():
        k = parameters.index.get(key, parameters.index.get(str(key)))
        if k is None:
            raise ModelError(
                f"params: unknown parameter {key!r}; the parameters are {list(parameters.names)}"
            )
        out[parameters.symbols[k]] = sp.sympify(value) if symbolic else value
    return out
