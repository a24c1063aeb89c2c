"""Jacobians of compact expressions by the chain rule through the named intermediates (forward mode).

A column of ∂f/∂y is the directional derivative of f along one seed, a map {symbol: rate}:

    (∂f/∂y) e_j = Σ_k ∂f/∂y_k · seed_j[y_k],

each intermediate's derivative a new intermediate (`Subexpressions.derivative`), so the columns share the
work of the expressions they differentiate and do not swell. Coordinates are differentiated in the tangent
space: seed j moves q along speed u_j, q̇ = Y(q) u gives seed_j = {q_k: Y_kj}; this is ∂/∂q at q ⊕ δ as in
Pinocchio (a quaternion free flyer: δ the body-frame twist; joints whose speeds are q̇: ∂/∂q itself)."""
from __future__ import annotations

from collections.abc import Hashable, Mapping, Sequence

import sympy as sp

from .model.system import System
from .subexpressions import Subexpressions


def tangent_seeds(system: System) -> list[dict]:
    """One seed per speed u_j: {q_k: ∂q̇_k/∂u_j} (q̇ = Y(q) u is linear in u)."""
    Y = system.qdot.jacobian(system.u)
    return [{q: Y[k, j] for k, q in enumerate(system.q) if Y[k, j] != 0} for j in range(len(system.u))]


def speed_seeds(system: System) -> list[dict]:
    """One seed per speed u_j: {u_j: 1}."""
    return [{u: 1} for u in system.u]


def jacobian(sub: Subexpressions, exprs: sp.Matrix, seeds: Sequence[Mapping], key: Hashable) -> sp.Matrix:
    """The matrix whose column j is the directional derivative of the column `exprs` along seeds[j]
    (memoized in `sub` under (key, j): the same key must always mean the same seeds)."""
    exprs = list(exprs)
    columns = [[sub.derivative(e, seed, (key, j)) for e in exprs] for j, seed in enumerate(seeds)]
    return sp.Matrix(len(exprs), len(seeds), lambda i, j: columns[j][i])
