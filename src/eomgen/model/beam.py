"""Euler-Bernoulli beam elements with Hermite cubic shape functions: the shape functions and their
integrals over one element, exact (the integrands are polynomials), made once in the element's own
symbols x₀ (where it starts along the link) and h (its length) and then given values.

On an element, y(x) = Σ_k N_k(ξ) d_k with ξ = x − x₀ and d its nodal deflections and slopes; with
s = x₀ + ξ the integrals are

    "1", "x", "xx":   ∫ 1, ∫ s, ∫ s²                       "N", "xN":  ∫ N_k, ∫ s N_k
    "NN":             ∫ N_k N_l                             "K":        ∫ N_k'' N_l''   (bending)
    "G", "xG", "xxG": ∫ N_k' N_l', ∫ s N_k' N_l', ∫ s² N_k' N_l'   (foreshortening: −½ ∫ y'²)"""
from __future__ import annotations

from functools import cache

import sympy as sp

from ..symbols import Generated

_xi, _h, _x0 = (Generated(x, ("element", x), positive=True) for x in ("xi", "h", "x0"))


def shape_functions(h=_h, xi=_xi) -> list[sp.Expr]:
    """Hermite cubics: deflection and slope at ξ = 0, then at ξ = h."""
    s = xi / h
    return [1 - 3 * s**2 + 2 * s**3, h * (s - 2 * s**2 + s**3), 3 * s**2 - 2 * s**3, h * (-s**2 + s**3)]


@cache
def _symbolic() -> dict:
    N, x = shape_functions(), _x0 + _xi
    dN, ddN = [n.diff(_xi) for n in N], [n.diff(_xi, 2) for n in N]

    def integral(e):
        return sp.expand(sp.integrate(sp.expand(e), (_xi, 0, _h)))

    def pairs(a, b, weight=1):
        return [[integral(weight * p * r) for r in b] for p in a]
    return {"1": integral(1), "x": integral(x), "xx": integral(x * x), "N": [integral(n) for n in N],
            "xN": [integral(x * n) for n in N], "NN": pairs(N, N), "K": pairs(ddN, ddN),
            "G": pairs(dN, dN), "xG": pairs(dN, dN, x), "xxG": pairs(dN, dN, x * x)}


def integrals(x0, h) -> dict:
    """The element integrals (module doc) of the element that starts at x0 and has length h."""
    values = {_x0: x0, _h: h}

    def given(e):
        return [given(a) for a in e] if isinstance(e, list) else sp.sympify(e).xreplace(values)
    return {key: given(e) for key, e in _symbolic().items()}


def quadratic(matrix, a, b) -> sp.Expr:
    """aᵀ matrix b for a 4 × 4 element matrix (lists) and nodal vectors a, b, expanded (modal nodes Φ η:
    a quadratic form in η, k (k + 1)/2 terms, not 16 products of sums)."""
    return sp.expand(sp.Add(*[matrix[k][l] * a[k] * b[l] for k in range(4) for l in range(4)]))
