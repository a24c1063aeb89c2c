"""The coordinates of a linearization: one tangent direction δ_j per speed u_j, q = q0 ⊕ δ (`eg.integrate`,
the directional derivatives along `derivatives.tangent_seeds`).

A coordinate whose rate is a speed, q̇_k = u_j, is its own direction: δ_j = q_k − q0_k and δ̇_j = u_j.
A free flyer, ball or planar joint with quaternion or planar coordinates moves as q = q0 exp(δ) in its
group (body twist u): exp(δ)⁻¹ d/dt exp(δ) = u gives δ̇ = J_r(δ)⁻¹ u = u + ½ ad(δ) u + O(δ²), linearized
about δ = 0 and the joint's speeds u0

    δ̇ = u − ½ ad(u0) δ,   ad(v, ω) = [[ω]×, [v]×; 0, [ω]×] (SE3),   ad(ω) = [ω]× (SO3),
    ad(v_x, v_y, ω) = [[0, −ω, v_y], [ω, 0, −v_x], [0, 0, 0]] (SE2)."""

from __future__ import annotations

import numpy as np
import sympy as sp

from ..model.system import System
from .dual import Algebra

GROUPS = ("SO3", "SE3", "SE2")


def _skew(w, algebra: Algebra) -> np.ndarray:
    S = algebra.zeros(3, 3)
    S[0, 1], S[0, 2], S[1, 2] = -w[2], w[1], -w[0]
    S[1, 0], S[2, 0], S[2, 1] = w[2], -w[1], w[0]
    return S


def adjoint(group: str, u, algebra: Algebra) -> np.ndarray:
    """ad(u) of a body twist u of the joint's group (speeds in the joint's order)."""
    if group == "SO3":
        return _skew(u, algebra)
    if group == "SE2":
        vx, vy, w = u
        ad = algebra.zeros(3, 3)
        ad[0, 1], ad[0, 2], ad[1, 0], ad[1, 2] = -w, vy, w, -vx
        return ad
    ad = algebra.zeros(6, 6)
    ad[:3, :3] = ad[3:, 3:] = _skew(u[3:], algebra)
    ad[:3, 3:] = _skew(u[:3], algebra)
    return ad


class Chart:
    """The tangent directions of a system: `names` (the coordinate's name where q̇_k = u_j, else
    `delta_<speed>`), `coordinate` {direction: q_k}, and the joints moving in a group."""

    def __init__(self, system: System) -> None:
        u = list(system.u)
        self.coordinate = {u.index(rate): q for q, rate in zip(system.q, system.qdot) if rate in u}
        self.names = [
            str(self.coordinate[j]) if j in self.coordinate else f"delta_{u[j]}" for j in range(len(u))
        ]
        self.groups = [
            (b.joint.group, b.index, b.joint.dof)
            for b in system.bodies
            if b.index is not None and b.joint.group in GROUPS
        ]

    def direction(self, coordinate: sp.Symbol) -> int | None:
        """The direction j of a coordinate with q̇_k = u_j (None for a quaternion's or planar joint's)."""
        return next((j for j, q in self.coordinate.items() if q == coordinate), None)

    def drift(self, u0: np.ndarray, algebra: Algebra) -> np.ndarray:
        """∂δ̇/∂δ at the speeds u0: the blocks −½ ad(u0) of the joints moving in a group, 0 elsewhere."""
        D = algebra.zeros(len(self.names), len(self.names))
        for group, i, dof in self.groups:
            D[i : i + dof, i : i + dof] = -adjoint(group, list(u0[i : i + dof]), algebra) / 2
        return D
