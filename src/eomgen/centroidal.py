"""Centre of mass and centroidal momentum, from the bodies' kinematics (world axes):

    m = Σ m_i,   c = Σ m_i r_Si / m,   J_com = Σ m_i J_P(S_i) / m,
    A_G = [Σ m_i J_P(S_i);  Σ Θ_i J_R,i + m_i (r_Si − c) × J_P(S_i)],   h_G = A_G u

(h_G: the linear momentum and the angular momentum about the centre of mass, Pinocchio's `ccrba`). The sums
run over the bodies that move: a body fixed to the world is part of the world (as in Pinocchio)."""
from __future__ import annotations

import sympy as sp

from .errors import ModelError
from . import linalg
from .engine import vector
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
    return sp.Matrix(_com(kin))


def _com(kin) -> tuple:
    m, total = total_mass(kin), linalg.total(linalg.scale(b.mass, vector(kin.com(b))) for b in moving(kin))
    return kin.sub.add_matrix(tuple(x / m for x in total))


def com_jacobian(kin) -> sp.Matrix:
    """J_com = Σ m_i J_P(S_i) / m (3 × n)."""
    m, n = total_mass(kin), kin.n
    J = linalg.total((linalg.scale(b.mass, vector(kin.J_P(Point(b, b.com)))) for b in moving(kin)),
                     (0,) * (3 * n))
    return sp.Matrix(3, n, [x / m for x in J])


def centroidal_momentum_matrix(kin) -> sp.Matrix:
    """A_G (6 × n): rows [linear momentum; angular momentum about c] per unit speed; column j of a body's
    part is [m_i J_P,j;  Θ_i J_R,j + (r_Si − c) × m_i J_P,j]."""
    c, n = _com(kin), kin.n

    def columns(b) -> tuple:  # the body's part, column by column
        J_P, J_R = vector(kin.J_P(Point(b, b.com))), vector(kin.J_R(b))
        arm = kin.sub.add_matrix(linalg.subtract(vector(kin.com(b)), c))
        Theta, part = vector(kin.inertia_world(b)), []
        for j in range(n):
            p = linalg.scale(b.mass, J_P[j::n])
            part += p + linalg.add(linalg.apply(Theta, J_R[j::n]), linalg.cross(arm, p))
        return tuple(part)

    A = linalg.total(map(columns, moving(kin)), (0,) * (6 * n))  # column by column
    return sp.Matrix(n, 6, A).T
