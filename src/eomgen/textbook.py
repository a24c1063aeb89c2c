"""Closed forms in textbook form, under a size and a time bound.

An entry is brought to a normal form in the sines and cosines of the coordinates (angles of sums
expanded, products multiplied out, cos² q → 1 − sin² q); two entries are equal exactly when their
difference has the normal form 0, which is how the methods are shown to agree. For display the
normal form goes through `fu`'s TR10i (products back to sums of angles: cos q₂ cos q₃ − sin q₂ sin q₃
→ cos(q₂ + q₃)) and is grouped by the bodies' masses with the common factors pulled out:
I₂ + m₂ l_c2 (l₁ cos q₂ + l_c2). Entries larger than `max_ops`, or met after `seconds` of work, are
left as they are; the document shows them in the shared form (see `shared`)."""

from __future__ import annotations

import itertools
import time

import sympy as sp
from sympy.polys.domains import QQ
from sympy.polys.orderings import lex
from sympy.polys.polyerrors import CoercionFailed, PolynomialError
from sympy.polys.rings import ring
from sympy.simplify.fu import TR10i

from .cse import cse
from .progress import progress
from .symbols import Generated

MAX_OPS = 6000  # closed-form entries larger than this are not simplified
SECONDS = 60.0  # simplification time for one solution


def trig_normal(expr: sp.Expr) -> sp.Expr:
    """sin/cos polynomial normal form: expand_trig, multiply out, cos²ᵏ q → (1 − sin² q)ᵏ.

    Polynomials go through sympy's sparse polynomial ring (division by cᵢ² + sᵢ² − 1, a Groebner basis:
    the remainder is unique), which is far faster than `expand` on large closed forms; anything else
    (roots, quotients) through expand and replace."""
    expr = sp.sympify(expr)
    if any(not f.args[0].is_Symbol for f in expr.atoms(sp.sin, sp.cos)):
        expr = sp.expand_trig(expr)
    angles = sorted({f.args[0] for f in expr.atoms(sp.sin, sp.cos)}, key=sp.default_sort_key)
    c = [sp.Dummy(f"c{k}") for k in range(len(angles))]
    s = [sp.Dummy(f"s{k}") for k in range(len(angles))]
    plain = expr.xreplace(
        {**{sp.cos(a): x for a, x in zip(angles, c)}, **{sp.sin(a): x for a, x in zip(angles, s)}}
    )
    others = sorted(plain.free_symbols - set(c) - set(s), key=sp.default_sort_key)
    try:
        R, *gens = ring(c + s + others, QQ, lex)  # cᵢ² leads cᵢ² + sᵢ² − 1
        p = R(plain)
    except (ValueError, TypeError, CoercionFailed, PolynomialError):
        return _trig_normal_expand(expr)
    n = len(angles)
    p = p.rem([gens[k] ** 2 + gens[n + k] ** 2 - 1 for k in range(n)])
    back = {**{x: sp.cos(a) for a, x in zip(angles, c)}, **{x: sp.sin(a) for a, x in zip(angles, s)}}
    return p.as_expr().xreplace(back)


def _trig_normal_expand(expr: sp.Expr) -> sp.Expr:
    expr = sp.expand(expr)
    expr = expr.replace(
        lambda x: x.is_Pow and isinstance(x.base, sp.cos) and x.exp.is_Integer and x.exp >= 2,
        lambda x: sp.cos(x.base.args[0]) ** (x.exp % 2) * (1 - sp.sin(x.base.args[0]) ** 2) ** (x.exp // 2),
    )
    return sp.expand(expr)


def is_zero(expr) -> bool:
    """Exactly zero as a trigonometric polynomial (every entry, for a matrix)."""
    entries = expr if isinstance(expr, sp.MatrixBase) else [expr]
    return all(trig_normal(e) == 0 for e in entries)


class Simplifier:
    """Textbook forms of closed-form entries, grouped by `groups` (the masses), within a budget."""

    def __init__(self, groups=(), max_ops: int = MAX_OPS, seconds: float = SECONDS) -> None:
        self.groups = [g for g in groups if isinstance(g, sp.Symbol)]
        self.max_ops, self.deadline = max_ops, time.perf_counter() + seconds
        self.left: int = 0  # entries left unsimplified
        self._known: dict[sp.Expr, sp.Expr] = {}  # normal form → textbook form (methods agree: once each)

    def entry(self, expr: sp.Expr) -> sp.Expr | None:
        """The textbook form, or None when the entry is over the size or time bound."""
        expr = sp.sympify(expr)
        if expr.is_Number or expr.is_Symbol:
            return expr
        if sp.count_ops(expr) > self.max_ops or time.perf_counter() > self.deadline:
            self.left += 1
            return None
        normal = trig_normal(expr)
        if normal not in self._known:
            self._known[normal] = self._grouped(TR10i(normal))
        form = self._known[normal]
        if expr.atoms(sp.Float):  # decimals went through exact rationals: decimals again
            form = form.xreplace({r: sp.Float(r, 15) for r in form.atoms(sp.Rational) if r.q > 1000})
        return form

    def _grouped(self, form: sp.Expr) -> sp.Expr:
        """The shorter of: terms collected by their angles (coefficients factored), or first by the
        masses and then by the angles (I₂ + m₂ l_c2 (l₁ cos q₂ + l_c2))."""
        candidates = [_by_angle(form)]
        if self.groups:
            parts = sp.collect(sp.expand(form), self.groups, evaluate=False)
            candidates.append(sp.Add(*[k * _by_angle(v) for k, v in parts.items()]))
        return min(candidates, key=sp.count_ops)

    def matrix(self, M: sp.Matrix) -> sp.Matrix:
        """Each entry in textbook form where it is within the bounds, else as it is."""
        entries = [self(e) for e in progress(list(M), "textbook form", unit="entry")]
        return sp.Matrix(M.rows, M.cols, entries)

    def __call__(self, expr: sp.Expr) -> sp.Expr:
        """The textbook form where within the bounds, else `expr` itself."""
        form = self.entry(expr)
        return expr if form is None else form


def _by_angle(expr: sp.Expr) -> sp.Expr:
    """Terms collected by their sines and cosines, each coefficient factored:
    2 l₁ l₂ q̇₁ q̇₂ sin q₂ + l₁ l₂ q̇₂² sin q₂ → l₁ l₂ q̇₂ (2 q̇₁ + q̇₂) sin q₂."""
    trig = sorted(expr.atoms(sp.sin, sp.cos), key=sp.default_sort_key)
    parts = sp.collect(sp.expand(expr), trig, evaluate=False) if trig else {sp.Integer(1): expr}
    return sp.Add(
        *[k * (sp.factor(v) if sp.count_ops(v) < 200 else sp.factor_terms(v)) for k, v in parts.items()]
    )


def operations(expr) -> int:
    """sympy's operation count, summed over the entries of a matrix."""
    return sum(map(sp.count_ops, expr)) if isinstance(expr, sp.MatrixBase) else sp.count_ops(expr)


def chi(k: int) -> Generated:
    """The shared definition χ_(k+1) of a printed solution."""
    return Generated(f"chi_{k + 1}", ("shared", k))


def shared(exprs: list[sp.Matrix]) -> tuple[list[tuple[sp.Symbol, sp.Expr]], list[sp.Matrix]]:
    """The matrices through common subexpressions χ_k (defined in the order returned)."""
    replacements, flat = cse([e for M in exprs for e in M], (chi(k) for k in itertools.count()))
    entries = iter(flat)
    return replacements, [sp.Matrix(M.rows, M.cols, [next(entries) for _ in M]) for M in exprs]
