"""The usual mistakes in an entry of M, b, g, τ, found by trying their corrections: the first candidate
whose corrected entry equals the derived one (at the checker's random states) is the likely cause.

    sign            −s = t            factor ½ / 2         2 s = t,  s / 2 = t
    sin for cos     s with sin(a) ↔ cos(a) = t  (each sine or cosine of s, then all at once)
    parallel axis   s ± m_i d² = t    (m_i a body's mass, d its com distance or a placement's length)
    Coriolis        s + c u_j u_k = t (c u_j u_k a term of t, j ≠ k; centrifugal for j = k)
    inertia axis    s with I_a → I_b = t (a, b entries of one body's inertia)
    sign of a term  s − 2 s_k = t     (s_k a term of s, as written or multiplied out)"""

from __future__ import annotations

from typing import Callable, Iterator

import numpy as np
import sympy as sp


def plain_text(expr) -> str:
    """An expression as plain text: l^2*m_p."""
    return sp.sstr(expr).replace("**", "^")


def likely_cause(student: sp.Expr, truth: sp.Expr, values: Callable, same: Callable, system) -> str | None:
    """The first usual mistake whose correction turns `student` into `truth`; `values(expr)` gives an
    expression at the states, `same(x, y)` compares such values."""
    s, t = values(student), values(truth)
    for candidate, cause in _candidates(student, truth, s, values, system):
        if same(candidate, t):
            return cause
    return None


def _candidates(student, truth, s, values, system) -> Iterator[tuple[np.ndarray, str]]:
    yield -s, "sign"
    yield 2 * s, "a factor ½ (the entry is half the right one)"
    yield s / 2, "a factor 2 (the entry is twice the right one)"
    trig = sorted(student.atoms(sp.sin, sp.cos), key=sp.default_sort_key)
    for f in trig:
        cause = f"{plain_text(f)} where {plain_text(_swapped(f))} belongs"
        yield values(student.xreplace({f: _swapped(f)})), cause
    if len(trig) > 1:
        yield values(student.xreplace({f: _swapped(f) for f in trig})), "sin for cos and cos for sin"
    for term in _parallel_axis_terms(system):
        d = values(term)
        yield s + d, f"missing parallel-axis term {plain_text(term)}"
        yield s - d, f"extra parallel-axis term {plain_text(term)}"
    u = list(system.u)
    if truth.free_symbols & set(u):
        for monomial, c in sp.Poly(sp.expand(truth), *u).terms():
            if sum(monomial) == 2:
                term = c * sp.Mul(*[ui**k for ui, k in zip(u, monomial)])
                kind = "centrifugal" if max(monomial) == 2 else "Coriolis"
                yield s + values(term), f"missing {kind} term {plain_text(term)}"
    for body in system.bodies:
        axes = sorted(body.inertia.free_symbols & system.parameters, key=str)
        for a in set(axes) & student.free_symbols:
            for b in axes:
                if b != a:
                    yield values(student.xreplace({a: b})), f"wrong axis of inertia: {a} where {b} belongs"
    for term in dict.fromkeys(sp.Add.make_args(student) + sp.Add.make_args(sp.expand(student))):
        yield s - 2 * values(term), f"sign of the term {plain_text(term)}"


def _swapped(f: sp.Expr) -> sp.Expr:
    return (sp.cos if isinstance(f, sp.sin) else sp.sin)(f.args[0])


def _parallel_axis_terms(system) -> list[sp.Expr]:
    """m_i d² for each body's mass m_i and each squared distance d² of a com or a joint placement."""
    distances = {sp.expand((v.T * v)[0]) for b in system.bodies for v in (b.com, b.placement.translation)}
    masses = [b.mass for b in system.bodies if b.mass != 0]
    return [m * d for m in dict.fromkeys(masses) for d in sorted(distances - {0}, key=sp.default_sort_key)]
