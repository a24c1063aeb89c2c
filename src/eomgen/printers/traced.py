"""The traced targets, JAX and CasADi: a catalogue function printed in Python (`TRACED`: the NumPy syntax
with And and Or as calls) and run once on symbolic inputs, JAX's tracers or CasADi's SX, with the target's
math as `m`; the outputs `out[i, j]` it writes become the target's matrix. What the function computes is
the printed text, the same as every other target's.

    JAX:     jax_function(source, shape)(q, u, ud, p) → a jax array of `shape` (jit, vmap, grad)
    CasADi:  casadi_expression(source, shape, symbols) → an SX matrix of `shape` in the given symbols

A Piecewise is printed as `where` (JAX: both branches evaluated, the one taken returned: its derivative
is NaN where the other branch is NaN), so the JAX target refuses functions with a Piecewise
(`refuse_branches`), naming the function."""
from __future__ import annotations

from dataclasses import replace

import sympy as sp

from ..errors import ModelError
from ..subexpressions import Subexpressions
from .python import compile_function
from .syntax import PYTHON

TRACED = replace(PYTHON, logic=("m.logical_and({a}, {b})", "m.logical_or({a}, {b})", "m.logical_not({c})"))


class Cells:
    """The outputs a traced function writes: out[i, j] = value (read back for a symmetric mirror)."""

    def __init__(self) -> None:
        self.values: dict = {}

    def __setitem__(self, ij, value) -> None:
        self.values[ij] = value

    def __getitem__(self, ij):
        return self.values[ij]


def jax_function(source: str, shape: tuple[int, int], label: str):
    """The printed function as a JAX function of one state, (q, u, ud, p) → array of `shape`."""
    import jax.numpy as jnp

    f, (rows, cols) = compile_function(source, label), shape

    def evaluate(q, u, ud, p):
        cells = f(q, u, ud, p, Cells(), jnp.sin, jnp.cos, jnp.sqrt, jnp).values
        zero = jnp.zeros((), q.dtype)
        return jnp.stack([jnp.stack([jnp.asarray(cells.get((i, j), zero), q.dtype) for j in range(cols)])
                          for i in range(rows)])
    return evaluate


class CasadiMath:
    """The functions of printed code in CasADi (numpy's names)."""

    def __getattr__(self, name: str):
        import casadi as ca

        special = {"arcsin": ca.asin, "arccos": ca.acos, "arctan": ca.atan, "arctan2": ca.atan2,
                   "power": lambda b, e: b ** e, "nan": float("nan"), "where": ca.if_else,
                   "logical_and": ca.logic_and, "logical_or": ca.logic_or, "logical_not": ca.logic_not,
                   "heaviside": lambda x, h: ca.if_else(x > 0, 1.0, ca.if_else(x < 0, 0.0, h))}
        return special[name] if name in special else getattr(ca, name)


def casadi_expression(source: str, shape: tuple[int, int], label: str, q, u, ud, p):
    """The printed function evaluated on CasADi symbols (or numbers) q, u, ud, p: an SX of `shape`."""
    import casadi as ca

    return compile_function(source, label)(q, u, ud, p, ca.SX.zeros(*shape), ca.sin, ca.cos, ca.sqrt,
                                           CasadiMath())


def refuse_branches(sub: Subexpressions, expr: sp.Basic, key: str, target: str) -> None:
    """A ModelError naming `key` when its expression or an intermediate it reads holds a Piecewise."""
    exprs = list(expr) if isinstance(expr, sp.MatrixBase) else [sp.sympify(expr)]
    if any(e.has(sp.Piecewise) for e in (*exprs, *(sub.definitions[s] for s in sub.dependencies(exprs)))):
        raise ModelError(f"{target}: {key} holds a Piecewise, whose untaken branch would make its "
                         "derivatives NaN in this target; evaluate it with the NumPy or C backend")
