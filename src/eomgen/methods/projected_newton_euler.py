"""Projected Newton-Euler: each body's momentum balance projected on the generalized directions.

    M = Σ_i J_Pᵢᵀ mᵢ J_Pᵢ + J_Rᵢᵀ Θᵢ J_Rᵢ
    b = Σ_i J_Pᵢᵀ mᵢ J̇_Pᵢ u + J_Rᵢᵀ (Θᵢ J̇_Rᵢ u + Ωᵢ × Θᵢ Ωᵢ)
    g = −Σ_i J_Pᵢᵀ mᵢ g⃗
    τ = Σ J_Pᵀ F + J_Rᵀ T   for every applied force F and torque T
(J_P of the centre of mass, Θ about it, all in world axes), plus each joint's armature on M's diagonal.
Only the requested quantities are formed; a body without mass and inertia is not visited, and for g
alone neither are the massless ones nor any rotation Jacobian."""
from __future__ import annotations

from collections.abc import Callable

import sympy as sp

from ..eom import EquationsOfMotion
from ..kinematics import Kinematics
from ..engine import vector
from ..linalg import add, apply, cross, dot, half_quadratic_form, mul, scale
from ..model.loads import Point
from ..progress import progress
from .applied import add_armature, generalized_force, potential_energy


def derive(kin: Kinematics, quantities=("M", "b", "g")) -> EquationsOfMotion:
    system, sub, n = kin.system, kin.sub, kin.n
    M, b, g = Sums(n, n), Sums(n, 1), Sums(n, 1)
    inertial = {"M", "b"} & set(quantities)
    for body in progress(system.bodies, "projected Newton-Euler", unit="body"):
        if not kin.chain[body] or (body.mass == 0 and (not inertial or body.inertia.is_zero_matrix)):
            continue
        idx = sorted({i for k in kin.chain[body] for i, _, _ in kin.columns[k]})
        S = Point(body, body.com)
        P = columns(kin.J_P(S), idx)
        if "g" in quantities:
            mg = scale(-body.mass, vector(system.gravity))
            g.add(idx, [dot(P_a, mg) for P_a in P])
        if not inertial:
            continue
        R = columns(kin.J_R(body), idx)
        Theta, Omega = vector(kin.inertia_world(body)), vector(kin.omega(body))
        if "M" in quantities:
            ThetaR = sub.add_matrix([dot(Theta[3 * i:3 * i + 3], R_c) for i in range(3) for R_c in R])
            ThetaR = [ThetaR[c::len(R)] for c in range(len(R))]  # Θ J_R, named row by row, by columns
            M.add_upper(idx, lambda a, c: mul(body.mass, dot(P[a], P[c])) + dot(R[a], ThetaR[c]))
        if "b" in quantities:
            ma = scale(body.mass, vector(kin.Jdot_u_P(S)))
            h = add(apply(Theta, vector(kin.Jdot_u_R(body))), cross(Omega, sub.add_matrix(apply(Theta, Omega))))
            b.add(idx, [dot(P_a, ma) + dot(R_a, h) for P_a, R_a in zip(P, R)])
    compact = {key: value.matrix() for key, value in (("M", M), ("b", b), ("g", g)) if key in quantities}
    if "M" in quantities:
        add_armature(kin, compact["M"])
        compact["T"] = half_quadratic_form(compact["M"], kin.u)
    compact["U"] = potential_energy(kin)
    for load in system.loads:
        compact[f"tau:{load.name}"] = generalized_force(kin, load)
    return EquationsOfMotion(kin, "projected_newton_euler", compact)


def columns(A: sp.Matrix, idx: list[int]) -> list[list[sp.Expr]]:
    """The columns idx of A as lists."""
    rows = A.tolist()
    return [[row[j] for row in rows] for j in idx]


class Sums:
    """A matrix of sums collected term by term and added once (adding to a growing sum one term at a
    time re-sorts it each time: quadratic in the number of bodies)."""

    def __init__(self, rows: int, cols: int) -> None:
        self.terms: list[list[list]] = [[[] for _ in range(cols)] for _ in range(rows)]
        self.cols, self.symmetric = cols, False

    def add(self, idx: list[int], part: list) -> None:
        """[idx] += part, a body's contribution on the speeds of its chain (a column)."""
        for i, x in zip(idx, part):
            self.terms[i][0].append(x)

    def add_upper(self, idx: list[int], entry: Callable[[int, int], sp.Expr]) -> None:
        """[idx, idx] += a symmetric part, given by its entries entry(a, c) for c >= a (M: half the work)."""
        self.symmetric = True
        for a, i in enumerate(idx):
            for c in range(a, len(idx)):
                self.terms[i][idx[c]].append(entry(a, c))

    def matrix(self) -> sp.Matrix:
        """The sums (a symmetric matrix: the upper triangle's, mirrored)."""
        sums = [[sp.Add(*cell) for cell in row] for row in self.terms]
        if self.symmetric:
            return sp.Matrix(len(sums), self.cols, lambda i, j: sums[min(i, j)][max(i, j)])
        return sp.Matrix(sums)
