"""Lagrange II from the energies, without Jacobians.

Velocities come from differentiating positions and rotations in time (chain rule, q̇ = u):
v_S = ṙ_S, Ω_B = vee(Rᵀ Ṙ). Then

    T = Σ ½ mᵢ v_Sᵢᵀ v_Sᵢ + ½ Ω_Bᵢᵀ Θᵢ Ω_Bᵢ,     p = ∂T/∂u,     M = ∂p/∂u
    b = d/dt p |_(u̇=0) − ∂T/∂q,                  g = ∂U_gravity/∂q,  U_gravity = −Σ mᵢ g⃗ · r_Sᵢ
    τ = F · ∂v/∂u + T · ∂Ω/∂u − ∂U_spring/∂q − ∂D/∂u
from the virtual power of the applied forces and torques (efforts held fixed) and the Rayleigh
function D of the dampers. A joint of prescribed motion θ(t) (`drive`): its θ, θ̇, θ̈ are named
intermediates with d/dt θ = θ̇, d/dt θ̇ = θ̈, and the effort it takes is Lagrange's equation along θ,
d/dt ∂T/∂θ̇ − ∂T/∂θ + ∂U/∂θ − τ_θ of the loads ("drive:<joint>"). Only the requested quantities are
formed: g alone needs no velocities.

Speeds that are not coordinate rates (a quaternion base's or a ball joint's body twist, a planar
joint's velocity in its own axes; q̇ = W(q) u) give Lagrange's equations in quasi-velocities (Hamel),

    b_k = d/dt p_k − X_k T + h_k(u, p),   g_k = X_k U,   X_k = Σ_i W_ik ∂/∂q_i,
with the joint's terms h (`Joint.hamel`: Euler's ω × p_ω for a ball joint; Kirchhoff's ω × p_v and
ω × p_ω + v × p_v for a free body); X_k T vanishes for a root joint (T does not depend on its pose).
For u = q̇, X_k = ∂/∂q_k and h = 0: the rows above."""
from __future__ import annotations

import sympy as sp

from ..eom import EquationsOfMotion
from ..kinematics import TIME, Kinematics
from ..linalg import dot
from ..model.loads import Actuator, Damper, Force, Point, Spring, Torque
from . import flexible
from ..model import FlexibleLink
from ..progress import progress
from .applied import armature, spring_potential, world


def derive(kin: Kinematics, quantities=("M", "b", "g")) -> EquationsOfMotion:
    system, sub, n = kin.system, kin.sub, kin.n
    kinetic = {"M", "b"} & set(quantities)
    u = kin.u
    du = [{uj: 1} for uj in u]
    directions, quasi = speed_directions(system)
    invariant = {i for b in quasi if b.parent is None for i in b.speed_indices}  # T does not depend on them

    def d_du(expr, j):
        return sub.derivative(expr, du[j], ("u", j))

    def d_dq(expr, j):
        """X_j expr = Σ_i W_ij ∂expr/∂q_i, the derivative along the motion of u_j (q̇ = W u)."""
        return sub.derivative(expr, directions[j], ("X", j))

    T_parts, U_gravity = [], sp.Integer(0)
    for body in system.bodies:
        r_S = kin.com(body)
        U_gravity += -body.mass * (system.gravity.T * r_S)[0]
        if not (kin.chain[body] or driven(body)) or not kinetic:
            continue
        v_S = kin.time_derivative(r_S)
        Omega_B = angular_velocity_body(kin, body)
        T_parts.append(sub.add(body.mass * (v_S.T * v_S)[0] / 2
                               + (Omega_B.T * body.inertia * Omega_B)[0] / 2))
    T_parts += [inertia * u[i] ** 2 / 2 for i, inertia in armature(kin)]  # rotors: ½ I_a u_i²
    T_parts += [j.armature * j.driven[1] ** 2 / 2 for j in system.prescribed if j.armature != 0]  # ½ I_a θ̇²
    U_elastic = []
    for body in system.bodies:
        if isinstance(body.joint, FlexibleLink):
            Omega = angular_velocity_body(kin, body) if body.joint.rotary_inertia is not None else None
            T_flex, U_flex, U_el = flexible.energies(kin, body, Omega)
            T_parts.append(T_flex)
            U_gravity += U_flex
            U_elastic.append(U_el)
    compact = {}
    if kinetic:
        T = compact["T"] = sp.Add(*T_parts)
        p = [sub.add(d_du(T, j)) for j in range(n)]
        if "M" in quantities:
            compact["M"] = sp.Matrix([[d_du(p[i], j) for j in range(n)]
                                      for i in progress(range(n), "Lagrange: M", unit="row")])
        if "b" in quantities:
            b = [sub.derivative(p[i], kin.time_seeds, TIME) - (0 if i in invariant else d_dq(T, i))
                 for i in range(n)]
            for body in quasi:  # Hamel's terms of the speeds that are not coordinate rates
                idx = body.speed_indices
                terms = body.joint.hamel([u[i] for i in idx], [p[i] for i in idx])
                for i, term in zip(idx, terms):
                    b[i] += term
            compact["b"] = sp.Matrix(b)
    if "g" in quantities:
        compact["g"] = sp.Matrix([d_dq(U_gravity, i) for i in range(n)])
    U = U_gravity
    drives = [(j.name, j.driven) for j in system.prescribed]  # ∂/∂θ and ∂/∂θ̇ along each prescribed motion
    along_q = [lambda e, j=j: d_dq(e, j) for j in range(n)] + [
        lambda e, name=name, theta=theta: sub.derivative(e, {theta: 1}, ("θ", name))
        for name, (theta, _, _) in drives]
    along_u = [lambda e, j=j: d_du(e, j) for j in range(n)] + [
        lambda e, name=name, rate=rate: sub.derivative(e, {rate: 1}, ("θ̇", name))
        for name, (_, rate, _) in drives]
    forces = {}  # per load: its generalized force along each u_j, then along each prescribed motion
    if U_elastic:  # bending: U_e enters like a spring, as a generalized force −∂U_e/∂q
        U_e = sub.add(sp.Add(*U_elastic))
        U += U_e
        forces["elastic"] = [-d(U_e) for d in along_q]
    for load in system.loads:
        if isinstance(load, Spring):
            U_s = sub.add(spring_potential(kin, load))
            U += U_s
            forces[load.name] = [-d(U_s) for d in along_q]
        elif isinstance(load, Damper):
            D = damper_dissipation(kin, load)
            forces[load.name] = [-d(D) for d in along_u]
        else:
            pairs = power(kin, load)
            forces[load.name] = [sum((dot(effort, flow.applyfunc(d)) for effort, flow in pairs),
                                     sp.Integer(0)) for d in along_u]
    for name, tau in forces.items():
        compact[f"tau:{name}"] = sp.Matrix(tau[:n])
    if kinetic and {"M", "b", "g"} <= set(quantities):
        for k, (name, _) in enumerate(drives):
            loads = sum((tau[n + k] for tau in forces.values()), sp.Integer(0))
            compact[f"drive:{name}"] = sp.Matrix([[drive(kin, T, U_gravity, along_q[n + k], along_u[n + k],
                                                         d_du) - loads]])
    compact["U"] = U
    return EquationsOfMotion(kin, "lagrange", compact)


def driven(body) -> bool:
    """Whether a joint of prescribed motion moves the body (its energy is then needed for that effort)."""
    while body is not None:
        if body.joint.prescribed is not None:
            return True
        body = body.parent
    return False


def drive(kin: Kinematics, T, U_gravity, d_theta, d_rate, d_du) -> sp.Expr:
    """The effort a prescribed motion θ(t) takes besides the loads: Lagrange's equation along θ,
    d/dt ∂T/∂θ̇ − ∂T/∂θ + ∂U_g/∂θ, with d/dt ∂T/∂θ̇ = Σ_j ∂(∂T/∂θ̇)/∂u_j u̇_j + its rate along q, θ, θ̇."""
    sub, ud = kin.sub, kin.system.ud
    p = sub.add(d_rate(T))
    rate = sub.derivative(p, kin.time_seeds, TIME) + sum((d_du(p, j) * ud[j] for j in range(kin.n)),
                                                         sp.Integer(0))
    return sub.add(rate - d_theta(T) + d_theta(U_gravity))


def speed_directions(system) -> tuple[list[dict], list]:
    """Per speed u_j, its direction in q (the column j of W in q̇ = W(q) u, as {q_i: W_ij}); and the
    bodies whose joint's speeds are quasi-velocities (`Joint.hamel`)."""
    directions, quasi = [], []
    for body in system.bodies:
        joint = body.joint
        if body.index is None:
            continue
        rates = joint.qdot()
        for s in joint.speeds:
            directions.append({q: W for q, W in ((q, sp.diff(r, s)) for q, r in zip(joint.coordinates, rates))
                               if W != 0})
        if joint.hamel(joint.speeds, [0] * joint.dof) is not None:
            quasi.append(body)
    return directions, quasi


def angular_velocity_body(kin: Kinematics, body) -> sp.Matrix:
    """Ω in body axes from [Ω]× = Rᵀ Ṙ."""
    R = kin.R[body]
    W = R.T * kin.time_derivative(R)
    return kin.sub.add_matrix(sp.Matrix([W[2, 1], W[0, 2], W[1, 0]]))


def _angular_velocity_world(kin: Kinematics, body) -> sp.Matrix:
    return sp.zeros(3, 1) if body is None else kin.R[body] * angular_velocity_body(kin, body)


def _velocity(kin: Kinematics, point: Point) -> sp.Matrix:
    return kin.time_derivative(kin.position(point))


def _length(kin: Kinematics, a: Point, b: Point) -> sp.Expr:
    d = kin.position(a) - kin.position(b)
    return kin.sub.add(sp.sqrt((d.T * d)[0]))


def power(kin: Kinematics, load) -> list[tuple[sp.Matrix, sp.Matrix]]:
    """The virtual power P = F · v + T · Ω as (effort, flow) pairs, flows linear in u (actuator:
    T · (Ω_a − Ω_b) + f ℓ̇). τ_j = Σ effort · ∂flow/∂u_j with the efforts held fixed, so forces that
    depend on the speeds (a motor's friction) count once."""
    if isinstance(load, Force):
        return [(world(kin, load.force, load.point.body, load.in_body_frame), _velocity(kin, load.point))]
    if isinstance(load, Torque):
        return [(world(kin, load.torque, load.body, load.in_body_frame), _angular_velocity_world(kin, load.body))]
    if isinstance(load, Actuator):
        pairs = []
        if load.torque is not None:
            T = world(kin, load.torque, load.a.body, load.in_body_frame)
            pairs.append((T, _angular_velocity_world(kin, load.a.body) - _angular_velocity_world(kin, load.b.body)))
        if load.force is not None:
            pairs.append((sp.Matrix([load.force]),
                          kin.time_derivative(sp.Matrix([_length(kin, load.a, load.b)]))))
        return pairs
    raise TypeError(f"unknown load type {type(load).__name__}")


def damper_dissipation(kin: Kinematics, damper: Damper) -> sp.Expr:
    """Rayleigh D = ½ c ℓ̇², ℓ = ‖r_a − r_b‖."""
    l_dot = kin.time_derivative(sp.Matrix([_length(kin, damper.a, damper.b)]))[0]
    return damper.damping * l_dot**2 / 2
