"""Centre of mass and centroidal momentum, from the bodies' kinematics (world axes):

    m = Σ m_i,   c = Σ m_i r_Si / m,   J_com = Σ m_i J_P(S_i) / m,
    A_G = [Σ m_i J_P(S_i);  Σ Θ_i J_R,i + m_i (r_Si − c) × J_P(S_i)],   h_G = A_G u

(h_G: the linear momentum and the angular momentum about the centre of mass, Pinocchio's `ccrba`). The sums
run over the bodies that move: a body fixed to the world is part of the world (as in Pinocchio)."""
from __future__ import annotations

import sympy as sp

from .errors import ModelError
from .linalg import cross, matmul, scale
from .model import FlexibleLink
from .model.loads import Point


def moving(kin) -> list:
    """The bodies with mass or inertia that some joint moves."""
    return [b for b in kin.system.bodies if kin.chain[b] and (b.mass != 0 or not b.inertia.is_zero_matrix)]


def total_mass(kin) -> sp.Expr:
    """m = Σ m_i over the moving bodies; refused when zero, or with a flexible link (its distributed mass
    is not a body's)."""
    if any(isinstance(j, FlexibleLink) for j in kin.system.joints):
        raise ModelError("centre of mass and centroidal momentum: flexible links are not supported")
    m = sum((b.mass for b in moving(kin)), sp.Integer(0))
    if m.is_zero:
        raise ModelError("the moving bodies have no mass: the centre of mass is undefined")
    return m


def com(kin) -> sp.Matrix:
    """c = Σ m_i r_Si / m."""
    total = sum((scale(b.mass, kin.com(b)) for b in moving(kin)), sp.zeros(3, 1))
    return kin.sub.add_matrix(total / total_mass(kin))


def com_jacobian(kin) -> sp.Matrix:
    """J_com = Σ m_i J_P(S_i) / m (3 × n)."""
    J = sum((scale(b.mass, kin.J_P(Point(b, b.com))) for b in moving(kin)), sp.zeros(3, kin.n))
    return J / total_mass(kin)


def centroidal_momentum_matrix(kin) -> sp.Matrix:
    """A_G (6 × n): rows [linear momentum; angular momentum about c] per unit speed."""
    c = com(kin)
    A = sp.zeros(6, kin.n)
    for b in moving(kin):
        J_P, J_R = kin.J_P(Point(b, b.com)), kin.J_R(b)
        arm = kin.sub.add_matrix(kin.com(b) - c)
        Theta = kin.inertia_world(b)
        for j in range(kin.n):
            p = scale(b.mass, J_P[:, j])
            A[:3, j] += p
            A[3:, j] += matmul(Theta, J_R[:, j]) + cross(arm, p)
    return A
