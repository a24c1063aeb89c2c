"""Projected Newton-Euler: each body's momentum balance projected on the generalized directions.

    M = Σ_i J_Pᵢᵀ mᵢ J_Pᵢ + J_Rᵢᵀ Θᵢ J_Rᵢ
    b = Σ_i J_Pᵢᵀ mᵢ J̇_Pᵢ u + J_Rᵢᵀ (Θᵢ J̇_Rᵢ u + Ωᵢ × Θᵢ Ωᵢ)
    g = −Σ_i J_Pᵢᵀ mᵢ g⃗
    τ = Σ J_Pᵀ F + J_Rᵀ T   for every applied force F and torque T
(J_P of the centre of mass, Θ about it, all in world axes), plus each joint's armature on M's diagonal.
Only the requested quantities are formed; a body without mass and inertia is not visited, and for g
alone neither are the massless ones nor any rotation Jacobian."""
from __future__ import annotations

import sympy as sp

from ..eom import EquationsOfMotion
from ..kinematics import Kinematics
from ..linalg import cross, dot, matmul, scale
from ..model.loads import Point
from ..progress import progress
from .applied import add_armature, generalized_force, potential_energy


def derive(kin: Kinematics, quantities=("M", "b", "g")) -> EquationsOfMotion:
    system, sub, n = kin.system, kin.sub, kin.n
    u = sp.Matrix(kin.u)
    M, b, g = sp.zeros(n, n), sp.zeros(n, 1), sp.zeros(n, 1)
    inertial = {"M", "b"} & set(quantities)
    for body in progress(system.bodies, "projected Newton-Euler", unit="body"):
        if not kin.chain[body] or (body.mass == 0 and (not inertial or body.inertia.is_zero_matrix)):
            continue
        idx = sorted({i for k in kin.chain[body] for i, _, _ in kin.columns[k]})
        S = Point(body, body.com)
        J_P = kin.J_P(S)[:, idx]
        if "g" in quantities:
            _accumulate(g, idx, matmul(J_P.T, scale(-body.mass, system.gravity)))
        if not inertial:
            continue
        J_R = kin.J_R(body)[:, idx]
        Theta, Omega = kin.inertia_world(body), kin.omega(body)
        if "M" in quantities:
            ThetaJ_R = sub.add_matrix(matmul(Theta, J_R))
            _accumulate(M, idx, scale(body.mass, matmul(J_P.T, J_P)) + matmul(J_R.T, ThetaJ_R))
        if "b" in quantities:
            _accumulate(b, idx, matmul(J_P.T, scale(body.mass, kin.Jdot_u_P(S))) + matmul(J_R.T, (
                matmul(Theta, kin.Jdot_u_R(body)) + cross(Omega, sub.add_matrix(matmul(Theta, Omega))))))
    compact = {key: value for key, value in (("M", M), ("b", b), ("g", g)) if key in quantities}
    if "M" in quantities:
        add_armature(kin, M)
        compact["T"] = dot(u, matmul(M, u)) / 2
    compact["U"] = potential_energy(kin)
    for load in system.loads:
        compact[f"tau:{load.name}"] = generalized_force(kin, load)
    return EquationsOfMotion(kin, "projected_newton_euler", compact)


def _accumulate(total: sp.Matrix, idx: list[int], part: sp.Matrix) -> None:
    """total[idx, idx] += part (a body's contribution on the speeds of its chain), in place."""
    for a, i in enumerate(idx):
        for c in range(part.shape[1]):
            total[i, idx[c] if total.shape[1] > 1 else 0] += part[a, c]
