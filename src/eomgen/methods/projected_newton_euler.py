"""Projected Newton-Euler: each body's momentum balance projected on the generalized directions.

    M = Σ_i J_Pᵢᵀ mᵢ J_Pᵢ + J_Rᵢᵀ Θᵢ J_Rᵢ
    b = Σ_i J_Pᵢᵀ mᵢ J̇_Pᵢ u + J_Rᵢᵀ (Θᵢ J̇_Rᵢ u + Ωᵢ × Θᵢ Ωᵢ)
    g = −Σ_i J_Pᵢᵀ mᵢ g⃗
    τ = Σ J_Pᵀ F + J_Rᵀ T   for every applied force F and torque T
(J_P of the centre of mass, Θ about it, all in world axes), plus each joint's armature on M's diagonal."""
from __future__ import annotations

import sympy as sp

from ..eom import EquationsOfMotion
from ..kinematics import Kinematics
from ..linalg import cross, dot, matmul, scale
from ..model.loads import Point
from .applied import add_armature, generalized_force, potential_energy


def derive(kin: Kinematics) -> EquationsOfMotion:
    system, sub, n = kin.system, kin.sub, kin.n
    u = sp.Matrix(kin.u)
    M, b, g = sp.zeros(n, n), sp.zeros(n, 1), sp.zeros(n, 1)
    for body in system.bodies:
        if not kin.chain[body]:
            continue
        idx = [i for k in kin.chain[body] for i, _, _ in kin.columns[k]]
        S = Point(body, body.com)
        J_P, J_R = kin.J_P(S)[:, idx], kin.J_R(body)[:, idx]
        Theta, Omega = kin.inertia_world(body), kin.omega(body)
        ThetaJ_R = sub.add_matrix(matmul(Theta, J_R))
        M_i = scale(body.mass, matmul(J_P.T, J_P)) + matmul(J_R.T, ThetaJ_R)
        b_i = matmul(J_P.T, scale(body.mass, kin.Jdot_u_P(S))) + matmul(J_R.T, (
            matmul(Theta, kin.Jdot_u_R(body)) + cross(Omega, sub.add_matrix(matmul(Theta, Omega)))))
        g_i = matmul(J_P.T, scale(-body.mass, system.gravity))
        for a, i in enumerate(idx):
            b[i] += b_i[a]
            g[i] += g_i[a]
            for c, j in enumerate(idx):
                M[i, j] += M_i[a, c]
    add_armature(kin, M)
    compact = {"M": M, "b": b, "g": g, "T": dot(u, matmul(M, u)) / 2, "U": potential_energy(kin)}
    for load in system.loads:
        compact[f"tau:{load.name}"] = generalized_force(kin, load)
    return EquationsOfMotion(kin, "projected_newton_euler", compact)
