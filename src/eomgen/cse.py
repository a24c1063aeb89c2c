"""Common-subexpression elimination: symengine's `cse` (C++) where symengine is installed, else sympy's,
with sympy objects in and out.

For symengine the expressions are rewritten over Add, Mul, Pow, integers, rationals and the elementary
functions of `FUNCTIONS`; every other part (a symbol, a float, π, a Piecewise ...) enters as an opaque
placeholder `_a<k>`, numbered in the order a walk over the expressions first meets it, and is put back
unchanged: the result does not depend on Python's hash order, symbol assumptions and float precision
survive, and symengine's names for its intermediates cannot meet a name of the input."""
from __future__ import annotations

from collections.abc import Iterator

import sympy as sp

try:
    import symengine as se
except ImportError:  # the optional extra eomgen[symengine]: sympy's cse
    se = None

FUNCTIONS = (sp.sin, sp.cos, sp.tan, sp.exp, sp.log)


def cse(exprs: list[sp.Expr], symbols: Iterator[sp.Symbol]) -> tuple[list[tuple[sp.Symbol, sp.Expr]],
                                                                     list[sp.Expr]]:
    """(replacements x_k = e_k in the order defined, the expressions over them), as sympy's `cse`;
    the intermediates named by `symbols` in turn."""
    if se is None:
        return sp.cse(exprs, symbols=symbols)
    atoms: dict[sp.Basic, object] = {}
    memo: dict[sp.Basic, object] = {}
    replacements, reduced = se.cse([_to_symengine(e, memo, atoms) for e in exprs])
    back = {f"_a{k}": atom for k, atom in enumerate(atoms)}
    back.update({str(x): next(symbols) for x, _ in replacements})
    memo = {}
    return ([(back[str(x)], _to_sympy(e, back, memo)) for x, e in replacements],
            [_to_sympy(e, back, memo) for e in reduced])


def _to_symengine(e: sp.Basic, memo: dict, atoms: dict):
    """`e` in symengine, each part it cannot take as a placeholder `_a<k>` (`atoms`: part → k)."""
    if e in memo:
        return memo[e]
    if e.is_Rational:
        out = se.Rational(int(e.p), int(e.q))
    elif e.is_Add or e.is_Mul or e.is_Pow or type(e) in FUNCTIONS:
        args = [_to_symengine(a, memo, atoms) for a in e.args]
        out = (se.Add if e.is_Add else se.Mul if e.is_Mul else se.Pow if e.is_Pow
               else getattr(se, type(e).__name__))(*args)
    else:
        out = se.Symbol(f"_a{atoms.setdefault(e, len(atoms))}")
    memo[e] = out
    return out


def _to_sympy(e, names: dict[str, sp.Basic], memo: dict) -> sp.Expr:
    """`e` (symengine) in sympy, a symbol by its name in `names`."""
    if e in memo:
        return memo[e]
    kind = type(e).__name__
    if kind == "Symbol":
        out = names[e.name]
    elif not e.args:  # a number or a constant (e: exp(x) is e**x there)
        out = sp.sympify(e)
    else:
        args = [_to_sympy(a, names, memo) for a in e.args]
        out = (sp.Add if kind == "Add" else sp.Mul if kind == "Mul" else sp.Pow if kind == "Pow"
               else getattr(sp, kind))(*args)
    memo[e] = out
    return out
