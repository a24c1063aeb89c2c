"""Projected Newton-Euler: each body's momentum balance projected on the generalized directions.

    M = Σ_i J_Pᵢᵀ mᵢ J_Pᵢ + J_Rᵢᵀ Θᵢ J_Rᵢ
    b = Σ_i J_Pᵢᵀ mᵢ J̇_Pᵢ u + J_Rᵢᵀ (Θᵢ J̇_Rᵢ u + Ωᵢ × Θᵢ Ωᵢ)
    g = −Σ_i J_Pᵢᵀ mᵢ g⃗
    τ = Σ J_Pᵀ F + J_Rᵀ T   for every applied force F and torque T
(J_P of the centre of mass, Θ about it, all in world axes)."""
from __future__ import annotations

import sympy as sp

from ..eom import EquationsOfMotion
from ..kinematics import Kinematics
from ..model.loads import Actuator, Damper, Force, Point, Spring, Torque


def derive(kin: Kinematics) -> EquationsOfMotion:
    system, sub, n = kin.system, kin.sub, kin.n
    u = sp.Matrix(kin.u)
    M, b, g = sp.zeros(n, n), sp.zeros(n, 1), sp.zeros(n, 1)
    U = sp.Integer(0)
    for body in system.bodies:
        if not kin.chain[body]:
            U += _gravity_potential(kin, body)
            continue
        idx = [k.index for k in kin.chain[body]]
        S = Point(body, body.com)
        J_P, J_R = kin.J_P(S)[:, idx], kin.J_R(body)[:, idx]
        Theta, Omega = kin.inertia_world(body), kin.omega(body)
        ThetaJ_R = sub.add_matrix(Theta * J_R)
        M_i = body.mass * J_P.T * J_P + J_R.T * ThetaJ_R
        b_i = J_P.T * (body.mass * kin.Jdot_u_P(S)) + J_R.T * (
            Theta * kin.Jdot_u_R(body) + Omega.cross(sub.add_matrix(Theta * Omega)))
        g_i = -J_P.T * (body.mass * system.gravity)
        for a, i in enumerate(idx):
            b[i] += b_i[a]
            g[i] += g_i[a]
            for c, j in enumerate(idx):
                M[i, j] += M_i[a, c]
        U += _gravity_potential(kin, body)
    compact = {"M": M, "b": b, "g": g, "T": (u.T * M * u)[0] / 2}
    for load in system.loads:
        compact[f"tau:{load.name}"] = generalized_force(kin, load)
        if isinstance(load, Spring):
            U += spring_potential(kin, load)
    compact["U"] = U
    return EquationsOfMotion(kin, "projected_newton_euler", compact)


def _gravity_potential(kin: Kinematics, body) -> sp.Expr:
    """U = −m g⃗ · r_S."""
    return -body.mass * (kin.system.gravity.T * kin.com(body))[0]


def spring_potential(kin: Kinematics, spring: Spring) -> sp.Expr:
    """U = ½ k (‖r_a − r_b‖ − l0)²."""
    d = kin.position(spring.a) - kin.position(spring.b)
    if spring.rest_length == 0:
        return spring.stiffness * (d.T * d)[0] / 2
    return spring.stiffness * (sp.sqrt((d.T * d)[0]) - spring.rest_length) ** 2 / 2


def _world(kin: Kinematics, vector: sp.Matrix, body, in_body_frame: bool) -> sp.Matrix:
    return kin.R[body] * vector if in_body_frame and body is not None else vector


def generalized_force(kin: Kinematics, load) -> sp.Matrix:
    """τ = Σ J_Pᵀ F + J_Rᵀ T of one load, with the action and reaction of two-point loads."""
    if isinstance(load, Force):
        return kin.J_P(load.point).T * _world(kin, load.force, load.point.body, load.in_body_frame)
    if isinstance(load, Torque):
        return kin.J_R(load.body).T * _world(kin, load.torque, load.body, load.in_body_frame)
    a, b = load.a, load.b
    J_ab = kin.J_P(a) - kin.J_P(b)
    d = kin.sub.add_matrix(kin.position(a) - kin.position(b))
    length = sp.sqrt((d.T * d)[0])
    if isinstance(load, Actuator):
        tau = sp.zeros(kin.n, 1)
        if load.torque is not None:
            T = _world(kin, load.torque, a.body, load.in_body_frame)
            tau += (kin.J_R(a.body) - kin.J_R(b.body)).T * T
        if load.force is not None:
            tau += J_ab.T * (load.force * d / length)
        return tau
    if isinstance(load, Spring):
        if load.rest_length == 0:
            return J_ab.T * (-load.stiffness * d)
        return J_ab.T * (-load.stiffness * (length - load.rest_length) / length * d)
    if isinstance(load, Damper):
        n_ab = d / length
        l_dot = (n_ab.T * (kin.velocity(a) - kin.velocity(b)))[0]
        return J_ab.T * (-load.damping * l_dot * n_ab)
    raise TypeError(f"unknown load type {type(load).__name__}")
