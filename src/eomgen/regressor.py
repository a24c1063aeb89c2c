"""The joint-torque regressor: τ_ID = Y(q, u, u̇) π, the equations of motion linear in the parameters.

π per link (a moving body with the fixed bodies welded to it; Pinocchio's bodies), in its frame, about its
origin: [m, m c_x, m c_y, m c_z, I_xx, I_xy, I_yy, I_xz, I_yz, I_zz] of (m, h = m c, I_O = I_c + m (cᵀc 1 −
c cᵀ)) (Pinocchio's `computeJointTorqueRegressor`); then per joint speed its armature (column u̇_i) and
friction (viscous u_i, Coulomb sign(u_i), offset 1; π: 0, eomgen's inverse dynamics has no friction).

Link j's wrench about its origin, in its axes, is linear in π_j (a_O with −g⃗, `Recursion.motions`):
    f = m a_O + α × h + ω × (ω × h),   n = I_O α + ω × (I_O ω) + h × a_O,
and carried up the tree like the recursive Newton-Euler's backward pass, τ_k += v_kᵀ f + ω_kᵀ n.
The energies are linear in π too (v, ω of the origin in the link's axes; R, p its placement):
    T = ½ m vᵀv + h · (v × ω) + ½ ωᵀ I_O ω + Σ ½ I_a,i u_i²,   U = −m g⃗ · p − (Rᵀ g⃗) · h
(Pinocchio's energy regressors; bodies welded to the world are left out of U, a constant)."""
from __future__ import annotations

import weakref
from dataclasses import dataclass

import sympy as sp

from .eom import EquationsOfMotion
from .errors import ModelError
from .engine import vector
from .linalg import IDENTITY, ZERO, add, apply, cross, dot, matmul
from .methods import derive
from .methods.applied import armature
from .methods.recursive import Recursion, about_origin, moved
from .model import FlexibleLink, FreeFlyer, Point, System

INERTIAL = ("m", "mx", "my", "mz", "I_xx", "I_xy", "I_yy", "I_xz", "I_yz", "I_zz")
FRICTION = {"viscous": "Fv", "coulomb": "Fc", "offset": "Fo"}
UNIT = [(0, 0), (0, 1), (1, 1), (0, 2), (1, 2), (2, 2)]  # the entries of I_O, Pinocchio's order
_full: weakref.WeakKeyDictionary = weakref.WeakKeyDictionary()


@dataclass(frozen=True, eq=False)
class Regressor:
    """τ_ID = Y π (Y: nv × p in q, u, u̇ and the equations' intermediates), T = T π and U = U π (1 × p);
    `names` of π's entries, the `columns` these are of the full regressor `f.regressor` prints, and the
    `equations` it is of."""

    Y: sp.Matrix
    pi: sp.Matrix
    names: tuple[str, ...]
    T: sp.Matrix
    U: sp.Matrix
    columns: tuple[int, ...]
    equations: EquationsOfMotion


def regressor(system_or_eom, friction=tuple(FRICTION), armature: bool = True) -> Regressor:
    """The regressor of a System (derived with "recursive") or of its EquationsOfMotion, with the
    friction kinds `friction` (a subset of "viscous", "coulomb", "offset", in that order per joint) and
    the armature columns if `armature`."""
    eom = derive(system_or_eom, quantities=()) if isinstance(system_or_eom, System) else system_or_eom
    if not isinstance(eom, EquationsOfMotion):
        raise ModelError(f"regressor: expected a System or EquationsOfMotion, got {type(eom).__name__}")
    kinds = (friction,) if isinstance(friction, str) else friction
    known = isinstance(kinds, (tuple, list)) and all(isinstance(k, str) and k in FRICTION for k in kinds)
    if not known or len(set(kinds)) < len(kinds):
        raise ModelError(f"regressor: friction must be a subset of {tuple(FRICTION)}, got {friction!r}")
    if not isinstance(armature, bool):
        raise ModelError(f"regressor: armature must be True or False, got {armature!r}")
    full = full_regressor(eom)
    left_out = {"Ia", *FRICTION.values()} - {FRICTION[k] for k in kinds} - ({"Ia"} if armature else set())
    columns = tuple(i for i, name in enumerate(full.names) if name.split("_")[0] not in left_out)
    return Regressor(full.Y[:, columns], full.pi[columns, :], tuple(full.names[i] for i in columns),
                     full.T[:, columns], full.U[:, columns], columns, eom)


def full_regressor(eom: EquationsOfMotion) -> Regressor:
    """Every column: 10 per link, armature and the three friction kinds per joint speed (built once)."""
    if eom not in _full:
        _full[eom] = _derive(eom)
    return Regressor(*_full[eom], eom)


def links(system: System) -> dict:
    """Per moving body, the bodies welded to it through fixed joints (itself first); bodies welded to the
    world carry no column."""
    out: dict = {}
    for b in system.bodies:
        carrier = b if b.speed_indices else up_to_link(b, sp.eye(3), sp.zeros(3, 1))[0]
        if carrier is not None:
            out.setdefault(carrier, []).append(b)
    return out


def up_to_link(body, R: sp.Matrix, t: sp.Matrix) -> tuple:
    """(the link carrying `body`'s parent or None for the world, R, t): x_parent = R x + t carried up
    through the fixed joints above to that link's axes (x_link = R' x + t')."""
    parent = body.parent
    while parent is not None and not parent.speed_indices:
        P = parent.placement
        R_q, t_q = parent.joint.motion()
        R_p = matmul(P.rotation, R_q)
        R, t = matmul(R_p, R), matmul(R_p, t) + P.translation + matmul(P.rotation, t_q)
        parent = parent.parent
    return parent, R, t


def ten(m, h, I_O) -> list:
    """A link's ten parameters in Pinocchio's order from (m, h, I_O)."""
    return [m, *h, *(I_O[3 * j + k] for j, k in UNIT)]


def speeds(system: System) -> list[tuple[int, str]]:
    """(i, name) of each joint speed that gets armature and friction columns: every speed but a floating
    base's, named by its joint (with the speed's name where the joint has several)."""
    out = []
    for b in system.bodies:
        if b.joint.dof and not isinstance(b.joint, FreeFlyer):
            out += [(i, b.joint.name if b.joint.dof == 1 else str(system.u[i])) for i in b.speed_indices]
    return out


def missing_reason(system: System) -> str | None:
    """Why the system has no regressor (a flexible link, whose bending is no rigid body's 10 parameters),
    or None."""
    flexible = [j.name for j in system.joints if isinstance(j, FlexibleLink)]
    if flexible:
        return f"regressor: flexible link {flexible[0]!r} is not a rigid body with 10 parameters"
    moving = [j.name for j in system.prescribed]
    if moving:
        return (f"regressor: joint {moving[0]!r} has a prescribed motion, which the regressor's recursion "
                "leaves out")
    return None


def _derive(eom: EquationsOfMotion) -> tuple:
    """(Y, π, names, T, U, columns) of every column (module formulas)."""
    system, kin = eom.system, eom.kinematics
    if missing_reason(system):
        raise ModelError(missing_reason(system))
    rec, n, sub = Recursion(kin), kin.n, kin.sub
    motion = rec.motions(kin.u, list(system.ud), system.gravity)
    Y, T, U, pi, names = [], [], [], [], []
    for link, welded in links(system).items():
        w, al, a = (vector(sub.matrix(x)) for x in motion[link])
        for wrench in _wrenches(w, al, a):
            Y.append(_torques(rec, link, *wrench))
        R = kin.R[link]
        v = sub.add_matrix(matmul(R.T, kin.velocity(Point(link, sp.zeros(3, 1)))))
        omega = sub.add_matrix(matmul(R.T, kin.omega(link)))
        T += [dot(v, v) / 2, *cross(v, omega), *(_quadratic(omega, j, k) for j, k in UNIT)]
        g_link = sub.add_matrix(matmul(R.T, system.gravity))
        U += [-dot(system.gravity, kin.p[link]), *(-g_link), *[0] * 6]
        pi += _parameters(link, welded)
        names += [f"{p}_{link.name}" for p in INERTIAL]
    rotor = dict.fromkeys(range(n), sp.Integer(0))
    for i, inertia in armature(kin):
        rotor[i] += inertia
    joint_speeds = speeds(system)
    flying = [i for i in rotor if rotor[i] != 0 and i not in dict(joint_speeds)]
    if flying:
        raise ModelError(f"regressor: the floating base's speed {system.u[flying[0]]} has armature, "
                         "which has no column")
    for i, name in joint_speeds:
        Y.append(_at(n, i, system.ud[i]))
        T.append(kin.u[i] ** 2 / 2)
        U.append(0)
        pi.append(rotor[i])
        names.append(f"Ia_{name}")
    for i, name in joint_speeds:
        for column, prefix in zip((kin.u[i], sp.sign(kin.u[i]), sp.Integer(1)), FRICTION.values()):
            Y.append(_at(n, i, column))
            names.append(f"{prefix}_{name}")
        T, U, pi = T + [0] * 3, U + [0] * 3, pi + [0] * 3
    columns = [vector(y) for y in Y]
    full = sp.Matrix(n, len(Y), [column[i] for i in range(n) for column in columns])
    return full, sp.Matrix(pi), tuple(names), sp.Matrix([T]), sp.Matrix([U]), tuple(range(len(pi)))


def _wrenches(w: tuple, al: tuple, a: tuple) -> list[tuple[tuple, tuple]]:
    """(f, n) per unit parameter of [m, h_x, h_y, h_z, I_xx, I_xy, I_yy, I_xz, I_yz, I_zz] (module
    formulas)."""
    out = [(a, ZERO)]
    for k in range(3):
        e = IDENTITY[3 * k:3 * k + 3]
        out.append((add(cross(al, e), cross(w, cross(w, e))), cross(e, a)))
    for j, k in UNIT:
        E = tuple(int((r, c) in ((j, k), (k, j))) for r in range(3) for c in range(3))
        out.append((ZERO, add(apply(E, al), cross(w, apply(E, w)))))
    return out


def _torques(rec: Recursion, link, f: tuple, n: tuple) -> sp.Matrix:
    """τ of a wrench (f, n) on `link` (its axes, at its origin): τ_k = v_k · f + ω_k · n on every joint
    from the link to the root, the wrench carried to each parent (`Recursion.up`)."""
    tau, body = [0] * rec.n, link
    f, n = (rec.sub.add_matrix(rec.sub.vector(x)) for x in (f, n))
    while body is not None:
        for i, v, w in rec.S[body]:
            tau[i] += dot(v, f) + dot(w, n)
        if body.parent is None:
            break
        f, n = rec.up(body, f, n)
        body = body.parent
    return rec.sub.matrix(tau)


def _parameters(link, welded: list) -> list[sp.Expr]:
    """π of a link: its own (m, h, I_O) plus each welded body's moved into its frame, in the user's
    symbols (placements of the fixed joints, no intermediates)."""
    m, h, I_O = about_origin(link)
    for body in welded[1:]:  # x_link = R x_body + t through the fixed joints
        R_q, t_q = body.joint.motion()
        P = body.placement
        _, R, t = up_to_link(body, matmul(P.rotation, R_q), P.translation + matmul(P.rotation, t_q))
        m_b, h_b, I_b = moved(about_origin(body), R, t)
        m, h, I_O = m + m_b, add(h, h_b), add(I_O, I_b)
    return ten(m, h, I_O)


def _quadratic(w: sp.Matrix, j: int, k: int) -> sp.Expr:
    """The coefficient of I_jk in ½ ωᵀ I ω: ½ ω_j² on the diagonal, ω_j ω_k off it."""
    return w[j] ** 2 / 2 if j == k else w[j] * w[k]


def _at(n: int, i: int, value) -> sp.Matrix:
    column = sp.zeros(n, 1)
    column[i] = value
    return column
