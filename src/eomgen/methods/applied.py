"""The applied forces of a load: which force F and torque T act where (world axes), action and
reaction included. Projected Newton-Euler projects them with Jacobians, the free cut puts them in the
body balances; Lagrange II works from energy and power instead."""
from __future__ import annotations

import sympy as sp

from ..errors import ModelError
from ..kinematics import Kinematics
from ..linalg import dot, matmul, mul
from ..model.loads import Actuator, Damper, Force, Point, Spring, Torque
from ..subexpressions import samples


def world(kin: Kinematics, vector: sp.Matrix, body, in_body_frame: bool) -> sp.Matrix:
    """A vector given in world axes, or in the body's axes when in_body_frame."""
    return matmul(kin.R[body], vector) if in_body_frame and body is not None else vector


def applied_wrenches(kin: Kinematics, load) -> list[tuple[Point, sp.Matrix, sp.Matrix]]:
    """[(point, F, T)]: force F at point and pure torque T on the point's body (world axes)."""
    zero = sp.zeros(3, 1)
    if isinstance(load, Force):
        return [(load.point, world(kin, load.force, load.point.body, load.in_body_frame), zero)]
    if isinstance(load, Torque):
        return [(Point(load.body, zero), zero, world(kin, load.torque, load.body, load.in_body_frame))]
    a, b = load.a, load.b
    d = kin.sub.add_matrix(kin.position(a) - kin.position(b))
    length = kin.sub.add(sp.sqrt((d.T * d)[0]))
    zero_length_spring = isinstance(load, Spring) and load.rest_length.is_zero  # F = −k d: no direction
    if not zero_length_spring and getattr(load, "force", True) is not None:
        _check_line(kin, load.name, d)
    if isinstance(load, Actuator):
        T = zero if load.torque is None else world(kin, load.torque, a.body, load.in_body_frame)
        F = zero if load.force is None else load.force * d / length
    elif isinstance(load, Spring):
        F = -load.stiffness * (d if load.rest_length.is_zero else (length - load.rest_length) / length * d)
        T = zero
    elif isinstance(load, Damper):
        n_ab = kin.sub.add_matrix(d / length)
        l_dot = kin.sub.add((n_ab.T * (kin.velocity(a) - kin.velocity(b)))[0])
        F, T = -load.damping * l_dot * n_ab, zero
    else:
        raise TypeError(f"unknown load type {type(load).__name__}")
    return [(a, F, T), (b, -F, -T)]


def _check_line(kin: Kinematics, name: str, d: sp.Matrix) -> None:
    """Refuse a load along the line between two points that coincide at every state (d/|d| = 0/0),
    judged at random states (`subexpressions.samples`)."""
    for values in samples(kin.q, kin.system.parameters, 3):
        if any(abs(x) > 1e-12 for x in kin.sub.evaluate(list(d), values)):
            return
    raise ModelError(f"load '{name}': its two points coincide at every state, so the line it acts along is "
                     "undefined; attach its ends at distinct points")


def spring_potential(kin: Kinematics, spring: Spring) -> sp.Expr:
    """U = ½ k (‖r_a − r_b‖ − l0)²."""
    d = kin.position(spring.a) - kin.position(spring.b)
    if spring.rest_length.is_zero:
        return spring.stiffness * (d.T * d)[0] / 2
    return spring.stiffness * (sp.sqrt((d.T * d)[0]) - spring.rest_length) ** 2 / 2


def spring_energies(kin: Kinematics) -> list[sp.Expr]:
    """½ k (‖r_a − r_b‖ − l0)² of each spring."""
    return [spring_potential(kin, s) for s in kin.system.loads if isinstance(s, Spring)]


def potential_energy(kin: Kinematics) -> sp.Expr:
    """U = −Σ mᵢ g⃗ · r_Sᵢ + Σ ½ k (‖r_a − r_b‖ − l0)² (gravity and springs)."""
    return sp.Add(*[-mul(body.mass, dot(kin.system.gravity, kin.com(body))) for body in kin.system.bodies],
                  *spring_energies(kin))


def armature(kin: Kinematics) -> list[tuple[int, sp.Expr]]:
    """(i, I_a) per speed u_i that turns a rotor: the joint's armature on each of its speeds, k² times
    a mimic's on its driver's (the rotor turns at k u_driver)."""
    terms = []
    for body in kin.system.bodies:
        joint = body.joint
        mimic = joint.mimic
        k = 1 if mimic is None else mimic.multiplier
        if joint.armature != 0:
            terms += [(i, mul(k**2, joint.armature)) for i in body.speed_indices]
    return terms


def add_armature(kin: Kinematics, M: sp.Matrix) -> None:
    """M_ii += armature_i (rotor inertia reflected through the gear), in place."""
    for i, inertia in armature(kin):
        M[i, i] += inertia


def generalized_force(kin: Kinematics, load) -> sp.Matrix:
    """τ = Σ J_Pᵀ F + J_Rᵀ T over the forces and torques of one load (action and reaction); F and T named
    first, as every τ_i reads them (and so do their derivatives)."""
    tau = sp.zeros(kin.n, 1)
    for point, F, T in applied_wrenches(kin, load):
        F, T = kin.sub.add_matrix(F), kin.sub.add_matrix(T)
        tau += matmul(kin.J_P(point).T, F) + matmul(kin.J_R(point.body).T, T)
    return tau
