"""Newton-Euler with a free cut: every body cut free, the joint reactions as unknowns.

Body i gets from its parent, at its joint origin p_i, the wrench (F_i, T_i): a reaction in the
directions its joint blocks and the joint force τ_i along the direction it allows. Per body
(moments about the centre of mass S_i, world axes):

    m_i a_Si            = m_i g⃗ + F_ext,i + F_i − Σ_c F_c
    Θ_i α_i + Ω_i × Θ_i Ω_i = T_ext,i + T_i + (p_i − r_Si) × F_i − Σ_c (T_c + (p_c − r_Si) × F_c)

with a_S = J_P u̇ + J̇_P u and α = J_R u̇ + J̇_R u. Eliminating the reactions from the leaves to the
root gives each joint's wrench, moved to its origin:

    F_i = f_i + Σ_c F_c,    T_i = t_i + (r_Si − p_i) × f_i + Σ_c (T_c + (p_c − p_i) × F_c)

(f_i, t_i the body's own inertial minus applied force and moment), and the generalized equation
of speed k is the free component of the joint wrenches along the joint's motion subspace,
τ_k = Σ v_k · F_i + ω_k · T_i (ω_k · T for a revolute axis, v_k · F for a prismatic one; a mimic joint
adds its own to its driver's).
The terms multiplying u̇ give M, the bias terms b, gravity g, the loads τ."""
from __future__ import annotations

from dataclasses import dataclass
from typing import NamedTuple

import sympy as sp

from ..eom import EquationsOfMotion
from ..errors import ModelError
from ..constraint_rows import loop_rows
from ..kinematics import Kinematics
from ..linalg import cross, dot, half_quadratic_form, matmul, scale
from ..model.loads import Point
from ..subexpressions import samples
from ..symbols import Generated
from .cut_axes import WORLD, reactions
from .applied import add_armature, applied_wrenches, potential_energy

Wrench = tuple[sp.Matrix, sp.Matrix]


def derive(kin: Kinematics, quantities=("M", "b", "g")) -> EquationsOfMotion:
    """The elimination above; with only some of M, b, g requested, only their wrenches are propagated
    (and the joint wrenches and reactions, which need all three, are not formed)."""
    system, sub, n = kin.system, kin.sub, kin.n
    moving = [b for b in system.bodies if kin.chain[b]]
    zero = sp.zeros(3, 1)

    def inertial(body, J_P_col, J_R_col) -> Wrench:
        return scale(body.mass, J_P_col), matmul(kin.inertia_world(body), J_R_col)

    speeds = {b: {i for k in kin.chain[b] for i, _, _ in kin.columns[k]} for b in moving}
    columns = []  # M[:, j] from the wrenches of u̇ = e_j
    for j in range(n if "M" in quantities else 0):
        terms = {b: inertial(b, kin.J_P(Point(b, b.com))[:, j], kin.J_R(b)[:, j]) for b in moving if j in speeds[b]}
        columns.append(propagate(kin, terms))
    parts = {}  # the wrenches of b and g
    if "b" in quantities:
        parts["b"] = propagate(kin, {b: (scale(b.mass, kin.Jdot_u_P(Point(b, b.com))),
                                         matmul(kin.inertia_world(b), kin.Jdot_u_R(b))
                                         + cross(kin.omega(b), sub.add_matrix(matmul(kin.inertia_world(b), kin.omega(b)))))
                                     for b in moving})
    if "g" in quantities:
        parts["g"] = propagate(kin, {b: (scale(-b.mass, system.gravity), zero) for b in system.bodies if b.mass != 0})
    loads = {load.name: propagate(kin, external_terms(kin, [load], sign=-1)) for load in system.loads}

    u = sp.Matrix(kin.u)
    compact = {"U": potential_energy(kin)}
    if "M" in quantities:
        M = compact["M"] = sp.Matrix.hstack(*[free_components(kin, W) for W in columns])
        add_armature(kin, M)
        compact["T"] = half_quadratic_form(M, u)
    for key in ("b", "g"):
        if key in parts:
            compact[key] = free_components(kin, parts[key])
    for name, W in loads.items():
        compact[f"tau:{name}"] = -free_components(kin, W)
    if len(quantities) < 3:
        return EquationsOfMotion(kin, "free_cut", compact)

    ud = list(system.ud)
    wrenches, reactions = {}, {}
    for b in system.bodies:
        terms = [(W[b], ud[j]) for j, W in enumerate(columns)] + [(parts["b"][b], 1), (parts["g"][b], 1)]
        terms += [(W[b], 1) for W in loads.values()]
        F = sub.add_matrix(sum((scale(c, w[0]) for w, c in terms), zero))
        T = sub.add_matrix(sum((scale(c, w[1]) for w, c in terms), zero))
        wrenches[b.joint.name] = F.col_join(T)
        reactions[b.joint.name] = _without_free_component(kin, b, F, T)
    extras = {"joint_wrenches": wrenches, "reactions": reactions, "cut_equations": lambda: cut_equations(kin)}
    return EquationsOfMotion(kin, "free_cut", compact, extras)


def propagate(kin: Kinematics, terms: dict) -> dict:
    """Joint wrenches (F_i, T_i at p_i) from the bodies' own (f_i, t_i about S_i), leaves to root."""
    sub, W = kin.sub, {}
    children = {b: [] for b in kin.system.bodies}
    for b in kin.system.bodies:
        if b.parent is not None:
            children[b.parent].append(b)
    for b in reversed(kin.system.bodies):  # every child comes after its parent
        f, t = terms.get(b, (sp.zeros(3, 1), sp.zeros(3, 1)))
        p = kin.p[b]
        F = f + sum((W[c][0] for c in children[b]), sp.zeros(3, 1))
        T = t + cross(kin.com(b) - p, f)
        for c in children[b]:
            T = T + W[c][1] + cross(kin.p[c] - p, W[c][0])
        W[b] = (sub.add_matrix(F), sub.add_matrix(T))
    return W


def external_terms(kin: Kinematics, loads, sign: int = 1) -> dict:
    """Per body, the applied force and its moment about the centre of mass (times sign)."""
    terms: dict = {}
    for load in loads:
        for point, F, T in applied_wrenches(kin, load):
            if point.body is None:
                continue
            f, t = terms.get(point.body, (sp.zeros(3, 1), sp.zeros(3, 1)))
            moment = cross(kin.position(point) - kin.com(point.body), F) + T
            terms[point.body] = (f + sign * F, t + sign * moment)
    return terms


def free_components(kin: Kinematics, W: dict) -> sp.Matrix:
    """The generalized forces of joint wrenches W (at each joint origin): per column (u_i, v, ω) of a
    body's joint, v · F + ω · T."""
    tau = sp.zeros(kin.n, 1)
    for body, cols in kin.columns.items():
        F, T = W[body]
        for i, v, w in cols:
            tau[i] += dot(v, F) + dot(w, T)
    return tau


def reaction_directions(kin: Kinematics, body) -> sp.Matrix:
    """The joint's reaction basis B (`Joint.reaction_basis`) in world axes, 6 × (6 − dof)."""
    B = body.joint.reaction_basis()
    R = kin.R[body]
    return matmul(R, B[:3, :]).col_join(matmul(R, B[3:, :]))


def _without_free_component(kin: Kinematics, body, F: sp.Matrix, T: sp.Matrix) -> sp.Matrix:
    """The reaction: the joint wrench's component in the directions the joint blocks, B Bᵀ (F; T)."""
    B = reaction_directions(kin, body)
    return matmul(B, matmul(B.T, F.col_join(T)))


class Balance(NamedTuple):
    """One row of a body's momentum balance: Newton m a_S,i = F_i or Euler (Θ α + Ω × Θ Ω)_i = T_i
    about the centre of mass, world axis `axis`, in the acceleration symbols a, α."""

    body: str
    law: str  # "Newton" or "Euler"
    axis: str
    lhs: sp.Expr
    rhs: sp.Expr


@dataclass(eq=False)
class CutEquations:
    """The cut-free system before elimination (closed forms, each expression = 0).

    `equations` hold Newton and Euler for every body with the accelerations written through the
    kinematics (a_S = J_P u̇ + J̇_P u); `unknowns` are the reaction components (world axes where the
    joint allows, see `cut_axes`) and u̇.
    `with_kinematics()` keeps a_S and α as unknowns and adds the kinematic relations.
    Planar systems keep 3 equations per body (the in-plane force and the normal moment)."""

    equations: list
    unknowns: list
    dynamic: list  # the same balances in the acceleration symbols
    kinematic: list  # a_S − (J_P u̇ + J̇_P u), α − (J_R u̇ + J̇_R u)
    accelerations: list
    planar_normal: int | None  # world axis (0, 1, 2) normal to the plane of motion, or None
    balances: list  # each body's Newton and Euler rows, lhs = rhs (`Balance`), in `dynamic`'s order
    body_axes: list  # the reaction unknowns in their child body's axes (the others: world axes)

    def with_kinematics(self) -> tuple[list, list]:
        """(equations, unknowns) with the accelerations of the bodies as extra unknowns."""
        reactions = [x for x in self.unknowns if x not in self.accelerations]
        return self.dynamic + self.kinematic, reactions + self.accelerations

    def __str__(self) -> str:
        eqs, unknowns = self.with_kinematics()
        return (f"{len(self.equations)} equations in {len(self.unknowns)} unknowns "
                f"({len(eqs)} in {len(unknowns)} with the kinematics)")


def _planar_normal(kin: Kinematics) -> int | None:
    """The world axis the system moves perpendicular to, if all motion stays in one plane."""
    def zero(e):
        return sp.expand(kin.sub.inline(e)) == 0
    for axis in range(3):
        others = [i for i in range(3) if i != axis]
        if kin.system.gravity[axis] != 0:
            continue
        if all(zero(kin.J_R(b)[i, j]) for b in kin.system.bodies for i in others for j in range(kin.n)) and \
                all(zero(kin.J_P(Point(b, b.com))[axis, j]) for b in kin.system.bodies for j in range(kin.n)) and \
                all(zero(F[axis]) and all(zero(T[i]) for i in others)
                    for load in kin.system.loads for _, F, T in applied_wrenches(kin, load)):
            return axis
    return None


def _efforts(kin: Kinematics, body, F: sp.Matrix, T: sp.Matrix) -> tuple[sp.Matrix, sp.Matrix]:
    """The joint's efforts τ_k as a wrench in its motion subspace, S G⁻¹ τ with G = SᵀS constant
    (Sᵀ of it gives back τ)."""
    joint, sub = body.joint, kin.sub
    S = sp.Matrix.hstack(*[v.col_join(w) for v, w in joint.subspace()])
    G = _constant(S.T * S, joint.coordinates)
    if G is None:
        raise ModelError(f"joint '{joint.name}': the angles between its motion axes change with q (angle "
                         "rates); the cut-free balances are written for joints whose motion axes keep them")
    tau = sp.Matrix(effort_symbols(joint))
    wrench = S * (G.inv() * tau)  # a constant Gram matrix of at most 6 × 6 numbers or parameters
    R = sub.inline(kin.R[body])  # S is in child axes
    return F + R * wrench[:3, 0], T + R * wrench[3:, 0]


def effort_symbols(joint) -> list[Generated]:
    """τ_<joint> of a one-speed joint, τ_<joint>_k of a joint with several speeds."""
    names = [joint.name] if joint.dof == 1 else [f"{joint.name}_{k}" for k in range(joint.dof)]
    return [Generated(f"tau_{x}", ("tau", x)) for x in names]


def _constant(G: sp.Matrix, q: list) -> sp.Matrix | None:
    """G at q = 0 if it does not depend on q (judged at random states, `samples`: cos² + sin² = 1 of a
    turned axis stays unproven in floats), else None."""
    if not G.free_symbols & set(q):
        return G
    G0 = G.xreplace({x: 0 for x in q})
    for point in samples(q, (G.free_symbols - set(q)), 3):
        at, at0 = (sp.Matrix(M).xreplace(point) for M in (G, G0))
        if any(abs(complex(a - b)) > 1e-12 for a, b in zip(at, at0)):
            return None
    return G0


def cut_equations(kin: Kinematics) -> CutEquations:
    """Newton and Euler of every body cut free, with the joint reactions as unknowns (mimic joints,
    which couple two joints through a mechanism that is not a body, are not written out)."""
    system, sub = kin.system, kin.sub
    mimics = [b.joint.name for b in system.bodies if b.joint.mimic is not None]
    if mimics:
        raise ModelError(f"the cut-free balances are not written for mimic joints ({mimics}); derive "
                         "the equations (eg.derive) to include them")
    ud = sp.Matrix(list(system.ud))
    normal = _planar_normal(kin)
    keep_F = [i for i in range(3) if i != normal]
    keep_T = [normal] if normal is not None else [0, 1, 2]
    W, reaction_unknowns, body_axes = {}, [], []
    for b in system.bodies:
        F, T = sp.zeros(3, 1), sp.zeros(3, 1)
        for r in reactions(kin, b):
            if normal is not None and (sp.expand(r.force[normal]) != 0 or any(sp.expand(r.torque[i]) != 0
                                                                                 for i in keep_F)):
                continue  # out of the plane: decoupled, not part of the planar system
            reaction_unknowns.append(r.symbol)
            body_axes += [r.symbol] if r.axes != WORLD else []
            F, T = F + r.force * r.symbol, T + r.torque * r.symbol
        if b.joint.actuated and b.joint.dof:
            F, T = _efforts(kin, b, F, T)
        W[b] = (F, T)
    ext = external_terms(kin, system.loads)
    loop_loads, loop_unknowns, closing = _loop_cuts(kin, normal)
    for b, (f, t) in loop_loads.items():
        f0, t0 = ext.get(b, (sp.zeros(3, 1), sp.zeros(3, 1)))
        ext[b] = (f0 + f, t0 + t)
    balances, kinematic, accelerations, substituted = [], [], [], []
    for b in system.bodies:
        a = sp.Matrix([Generated(f"a_{b.name}_{c}", ("a", b.name, c)) for c in "xyz"])
        alpha = sp.Matrix([Generated(f"alpha_{b.name}_{c}", ("alpha", b.name, c)) for c in "xyz"])
        S = Point(b, b.com)
        a_of_ud = sub.inline(kin.J_P(S) * ud + kin.Jdot_u_P(S))
        alpha_of_ud = sub.inline(kin.J_R(b) * ud + kin.Jdot_u_R(b))
        r_S, p = sub.inline(kin.com(b)), sub.inline(kin.p[b])
        Theta, Omega = sub.inline(kin.inertia_world(b)), sub.inline(kin.omega(b))
        f_ext, t_ext = (sub.inline(x) for x in ext.get(b, (sp.zeros(3, 1), sp.zeros(3, 1))))
        F, T = W[b]
        children = [c for c in system.bodies if c.parent is b]
        newton_F = F - sum((W[c][0] for c in children), sp.zeros(3, 1)) + b.mass * system.gravity + f_ext
        euler_T = T + (p - r_S).cross(F) + t_ext - sum(
            (W[c][1] + (sub.inline(kin.p[c]) - r_S).cross(W[c][0]) for c in children), sp.zeros(3, 1))
        gyro = Omega.cross(Theta * Omega)
        for i in keep_F:
            balances.append(Balance(b.name, "Newton", "xyz"[i], b.mass * a[i], newton_F[i]))
            substituted.append(b.mass * a_of_ud[i] - newton_F[i])
            kinematic.append(a[i] - a_of_ud[i])
            accelerations.append(a[i])
        for i in keep_T:
            balances.append(Balance(b.name, "Euler", "xyz"[i], (Theta * alpha)[i] + gyro[i], euler_T[i]))
            substituted.append((Theta * alpha_of_ud)[i] + gyro[i] - euler_T[i])
            kinematic.append(alpha[i] - alpha_of_ud[i])
            accelerations.append(alpha[i])
    unknowns = reaction_unknowns + loop_unknowns + list(ud)
    dynamic = [x.lhs - x.rhs for x in balances]
    return CutEquations(substituted + closing, unknowns, dynamic + closing, kinematic, accelerations, normal,
                        balances, body_axes)


def _loop_cuts(kin: Kinematics, normal: int | None) -> tuple[dict, list, list]:
    """Each loop cut open: its force components λ_k along the rows' directions d_k (force rows along world
    x, y, z; torque rows along x, y, z or t_1, t_2) act on frame_a's body at frame_a's origin, −λ_k on
    frame_b's; the closing equations are the rows' J u̇ + J̇ u = 0. Returns (per body the force and
    its moment about the centre of mass, the unknowns, the equations); planar systems keep the in-plane
    rows."""
    sub, ud = kin.sub, sp.Matrix(list(kin.system.ud))
    loads, unknowns, equations = {}, [], []
    for loop in kin.system.loops:
        rows = loop_rows(kin, loop)
        J, Jdot_u = sub.inline(rows.J), sub.inline(rows.Jdot_u)
        R_a = kin.frame_placement(loop.frame_a)[0]
        axes = [sp.eye(3)[:, k % 3] for k in range(J.rows)] if loop.kind != "revolute" else \
            [sp.eye(3)[:, k] for k in range(3)] + [sub.inline(matmul(R_a, n)) for n in loop.normals]
        for k, (d, label) in enumerate(zip(axes, loop.row_names)):
            torque = k >= 3
            if normal is not None and (sp.expand(d[normal]) != 0) != torque:
                continue  # out of the plane of motion
            lam = Generated(f"F_{label}", ("F", loop.name, label))
            unknowns.append(lam)
            equations.append((J[k, :] * ud)[0] + Jdot_u[k])
            for frame, sign in ((loop.frame_a, 1), (loop.frame_b, -1)):
                body = kin._frame(frame).body
                if body is None:
                    continue
                F, T = (sp.zeros(3, 1), d * sign * lam) if torque else (d * sign * lam, sp.zeros(3, 1))
                arm = sub.inline(kin.frame_placement(frame)[1] - kin.com(body))
                f0, t0 = loads.get(body, (sp.zeros(3, 1), sp.zeros(3, 1)))
                loads[body] = (f0 + F, t0 + T + arm.cross(F))
    return loads, unknowns, equations
