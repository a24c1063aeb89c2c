"""Euler-Bernoulli beam elements with Hermite cubic shape functions: the shape functions, their
coefficients in ξ, and their integrals over one element, exact (the integrands are polynomials), made
once in the element's own symbols ξ and h (its length) and then given values.

On an element, y(x) = Σ_k N_k(ξ) d_k with ξ = x − x₀ (x₀ where it starts) and d its nodal deflections
and slopes; the integrals are "NN" = ∫ N_k N_l (mass), "K" = ∫ N_k'' N_l'' (bending), "G" = ∫ N_k' N_l'
(foreshortening: −½ ∫ y'² = −½ dᵀ G d). The twist φ of a 3D link is linear on an element (its values at
the two ends): "NN" = ∫ L_k L_l = (h/6)[[2, 1], [1, 2]], "K" = ∫ L_k' L_l' = (1/h)[[1, −1], [−1, 1]]
(`twist_integrals`)."""
from __future__ import annotations

from functools import cache

import sympy as sp

from ..symbols import Generated

_xi, _h = (Generated(x, ("element", x), positive=True) for x in ("xi", "h"))


def shape_functions(h=_h, xi=_xi) -> list[sp.Expr]:
    """Hermite cubics: deflection and slope at ξ = 0, then at ξ = h."""
    s = xi / h
    return [1 - 3 * s**2 + 2 * s**3, h * (s - 2 * s**2 + s**3), 3 * s**2 - 2 * s**3, h * (-s**2 + s**3)]


@cache
def _symbolic() -> dict:
    N = shape_functions()
    dN, ddN = [n.diff(_xi) for n in N], [n.diff(_xi, 2) for n in N]

    def pairs(a, b):
        return [[sp.expand(sp.integrate(sp.expand(p * r), (_xi, 0, _h))) for r in b] for p in a]
    return {"NN": pairs(N, N), "K": pairs(ddN, ddN), "G": pairs(dN, dN)}


def twist_integrals(h) -> dict:
    """The twist's element integrals (module doc) of an element of length h."""
    return {"NN": [[h / 3, h / 6], [h / 6, h / 3]], "K": [[1 / h, -1 / h], [-1 / h, 1 / h]]}


@cache
def _coefficients() -> list[list[sp.Expr]]:
    N = shape_functions()
    return [[sp.Poly(n, _xi).coeff_monomial(_xi**p) for p in range(4)] for n in N]


def coefficients(h) -> list[list[sp.Expr]]:
    """c[k][p]: N_k(ξ) = Σ_p c[k][p] ξ^p on an element of length h."""
    return [[c.xreplace({_h: h}) for c in row] for row in _coefficients()]


def integrals(h) -> dict:
    """The element integrals (module doc) of an element of length h."""
    values = {_h: h}

    def given(e):
        return [given(a) for a in e] if isinstance(e, list) else sp.sympify(e).xreplace(values)
    return {key: given(e) for key, e in _symbolic().items()}


def quadratic(matrix, a, b) -> sp.Expr:
    """aᵀ matrix b for an element matrix (lists) and nodal vectors a, b, expanded (modal nodes Φ η:
    a quadratic form in η, k (k + 1)/2 terms, not 16 products of sums)."""
    return sp.expand(sp.Add(*[matrix[k][l] * a[k] * b[l] for k in range(len(a)) for l in range(len(b))]))
