"""The rows J_c u = 0 of contacts, loop closures and rolling disks, with J̇_c u and position residuals.

Loop between frames a and b (world axes, J = J_a − J_b in the constrained directions)::

    point:    r = p_a − p_b,                          J = J_P,a − J_P,b
    frame:    + r_R = 2 vee(E − Eᵀ) / (1 + tr E),    J = J_R,a − J_R,b   (ṙ_R = ω_a − ω_b at closure)
              E = R_a R_bᵀ: r_R = 2 tan(θ/2) e for a turn θ about e (zero only at θ = 0, not at a half turn)
    revolute: + r_i = 2 t_iᵀ (n_b × n_a) / (1 + n_a · n_b), i = 1, 2,     J = t_iᵀ (J_R,a − J_R,b),
              n = R axis, t_i = R_a n_i (⟂ axis);    J̇u = t_iᵀ (α_a − α_b) + (ω_a × t_i)ᵀ (ω_a − ω_b)

Rolling disk (centre p, axle e = R axis, ground normal n and tangents t1, t2, height h = n · p_ground)::

    c = ρ d / s,  d = e × (e × n) = (e · n) e − n (toward the ground in the disk's plane),
    s = ‖e × n‖ = ‖d‖ (the sine of the axle's angle to the normal),  r = n · (p + c) − h = n · p − ρ s − h,
    v = v_p + ω × c (the disk's material point at the contact), J = [t1; t2; n] (J_P + J_R × c),
    J̇u = [t1; t2; n] (a_p + α × c + ω × ċ), ċ = ∂c/∂q q̇.

d and s are written with cross products, not as (e · n) e − n and √(1 − (e · n)²): near lying flat
(e · n → ±1) those lose the digits of 1 − (e · n)² (1e-5 relative at 1e-6 rad), the products do not."""
from __future__ import annotations

from dataclasses import dataclass

import sympy as sp

from .linalg import cross, dot, matmul
from .model.constraints import Loop, Rolling
from .model.loads import Point


@dataclass
class Rows:
    """Rows of a constraint: position residual (0 rows for a contact), J (k × n), J̇ u (k × 1)."""

    residual: sp.Matrix
    J: sp.Matrix
    Jdot_u: sp.Matrix


def vee(A: sp.Matrix) -> sp.Matrix:
    """The vector of a skew matrix: A = [a]× → a."""
    return sp.Matrix([A[2, 1], A[0, 2], A[1, 0]])


def loop_rows(kin, loop: Loop) -> Rows:
    """The loop's residual, J and J̇ u (module formulas)."""
    (R_a, p_a), (R_b, p_b) = kin.frame_placement(loop.frame_a), kin.frame_placement(loop.frame_b)
    J = kin.jacobian(loop.frame_a) - kin.jacobian(loop.frame_b)
    Jdot_u = kin.jacobian_dot_u(loop.frame_a) - kin.jacobian_dot_u(loop.frame_b)
    residual = p_a - p_b
    if loop.kind in ("point", "spherical"):
        return Rows(residual, J[:3, :], Jdot_u[:3, :])
    if loop.kind == "frame":
        E = matmul(R_a, R_b.T)
        return Rows(residual.col_join(vee(E - E.T) * (2 / (1 + E.trace()))), J, Jdot_u)
    n_a, n_b = matmul(R_a, loop.axis), kin.sub.add_matrix(matmul(R_b, loop.axis))
    w_a, w_b = (kin.omega(kin._frame(f).body) for f in (loop.frame_a, loop.frame_b))
    for n_i in loop.normals:
        t = kin.sub.add_matrix(matmul(R_a, n_i))
        residual = residual.col_join(sp.Matrix([2 * dot(t, cross(n_b, n_a)) / (1 + dot(n_a, n_b))]))
        J = J.col_join(t.T * J[3:6, :])
        Jdot_u = Jdot_u.col_join(sp.Matrix([dot(t, Jdot_u[3:6, 0]) + dot(cross(w_a, t), w_a - w_b)]))
    return Rows(residual, J[[0, 1, 2, 6, 7], :], Jdot_u[[0, 1, 2, 6, 7], :])


def tilt(kin, disk: Rolling) -> tuple[sp.Matrix, sp.Matrix, sp.Expr]:
    """(e, e × n, s): the disk's axle e = R axis (world axes), and s = ‖e × n‖, the sine of its angle to
    the ground normal n (0: lying flat, no contact point)."""
    e = kin.sub.add_matrix(matmul(kin.R[disk.body], disk.axis))
    w = kin.sub.add_matrix(cross(e, disk.ground.rotation[:, 2]))
    return e, w, kin.sub.add(sp.sqrt(dot(w, w)))


def tilts(kin) -> sp.Matrix:
    """s = ‖e × n‖ of every rolling disk (a column, `tilt`)."""
    return sp.Matrix([tilt(kin, disk)[2] for disk in kin.system.rolling])


def rolling_rows(kin, disk: Rolling) -> Rows:
    """The disk's height residual (1 row) and its three velocity rows (module formulas)."""
    body, sub = disk.body, kin.sub
    G = disk.ground.rotation
    n, tangents = G[:, 2], [G[:, 0], G[:, 1]]
    e, w, s = tilt(kin, disk)
    c = sub.add_matrix(cross(e, w) * (disk.radius / s))
    origin = Point(body, sp.zeros(3, 1))
    residual = sp.Matrix([dot(n, kin.p[body]) - disk.radius * s - dot(n, disk.ground.translation)])
    J_P, J_R = kin.J_P(origin), kin.J_R(body)
    v = sp.Matrix.hstack(*(J_P[:, j] + cross(J_R[:, j], c) for j in range(kin.n)))
    a = kin.Jdot_u_P(origin) + cross(kin.Jdot_u_R(body), c) + cross(kin.omega(body), kin.time_derivative(c))
    T = sp.Matrix.vstack(*(x.T for x in (*tangents, n)))
    return Rows(residual, T * v, sub.add_matrix(T * a))


def constraint_rows(kin) -> Rows:
    """Every constraint's rows stacked (contacts, loops, rolling: `System.constraint_rows`) and the
    closures' residuals stacked (loops, rolling heights: `System.closure_rows`)."""
    system = kin.system
    J, Jdot_u, residual = sp.zeros(0, kin.n), sp.zeros(0, 1), sp.zeros(0, 1)
    for c in system.contacts:
        J = J.col_join(kin.jacobian(c.frame)[:c.rows, :])
        Jdot_u = Jdot_u.col_join(kin.jacobian_dot_u(c.frame)[:c.rows, :])
    for rows in [loop_rows(kin, x) for x in system.loops] + [rolling_rows(kin, x) for x in system.rolling]:
        J, Jdot_u = J.col_join(rows.J), Jdot_u.col_join(rows.Jdot_u)
        residual = residual.col_join(rows.residual)
    return Rows(residual, J, Jdot_u)
