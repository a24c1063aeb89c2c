"""Consistent states of a system with loop closures and rolling disks: q on the closure r(q) = 0
(`assemble`), and (q, u) projected onto the constraint manifold (`project`). Numeric throughout: the
generated r(q), J_c(q), M(q) of `eg.codegen` (NumPy or C)."""
from __future__ import annotations

from collections.abc import Iterable

import numpy as np
import sympy as sp

from ..arguments import count, finite_array, positive
from ..eom import EquationsOfMotion
from ..errors import ModelError
from ..methods import derive
from ..model import System
from ..state import integrate, unit_quaternions
from .codegen import codegen
from .equations import NumericEoM

HALVINGS = 30  # step halvings before a Gauss–Newton step counts as stalled
TOL = 1e-12  # closure tolerance, and smallest singular value of J_r kept, per unit of the problem's `size`
STEP = 1.0  # largest change of one speed's coordinate per Gauss–Newton step (rad or length unit)
STATIONARY = 1e-6  # ‖J_r J_r⁺ r‖ / ‖r‖ at or below: a least-squares minimum of ‖r‖ (r ⟂ range J_r)
EPS = np.finfo(float).eps


def numeric(system_or_f, entry: str) -> NumericEoM:
    """The numeric functions of a System (derived with method "recursive"), of an EquationsOfMotion, or
    the functions themselves (`eg.codegen`, NumPy or C: give these for repeated calls)."""
    if isinstance(system_or_f, NumericEoM):
        return system_or_f
    if isinstance(system_or_f, EquationsOfMotion):
        return codegen(system_or_f)
    if isinstance(system_or_f, System):
        return codegen(derive(system_or_f, method="recursive"))
    raise ModelError(f"{entry}: expected a System, EquationsOfMotion or its eg.codegen functions, got "
                     f"{type(system_or_f).__name__}")


def speed_indices(system: System, names: Iterable, what: str) -> list[int]:
    """The speeds named by coordinates (those whose rate is one speed: q̇_k = u_i) or by speeds
    (names or symbols), in the given order; unknown and repeated names refused."""
    lookup = {s.name: i for i, s in enumerate(system.u)}
    speeds = list(system.u)
    lookup.update({q.name: speeds.index(qd) for q, qd in zip(system.q, system.qdot) if qd in speeds})
    names = [names] if isinstance(names, (str, sp.Symbol)) else list(names)
    out = []
    for x in names:
        name = x.name if isinstance(x, sp.Symbol) else x
        if not isinstance(name, str) or name not in lookup:
            raise ModelError(f"{what}: unknown coordinate or speed {x!r}{_not_a_rate(system, name)}; "
                             f"coordinates are {[q.name for q in system.q]}, speeds "
                             f"{[u.name for u in system.u]}")
        if lookup[name] in out:
            raise ModelError(f"{what}: {name!r} names speed '{system.u[lookup[name]]}' a second time")
        out.append(lookup[name])
    return out


def _not_a_rate(system: System, name) -> str:
    """For a coordinate whose rate is no single speed (a free flyer's or planar joint's position, a
    quaternion's component): its joint and the speeds to name instead."""
    for b in system.bodies:
        if str(name) in map(str, b.joint.coordinates):
            return (f" (a coordinate of {type(b.joint).__name__} joint '{b.joint.name}' whose rate is no "
                    f"one speed: name its speeds {[u.name for u in b.joint.speeds]})")
    return ""


def size(f: NumericEoM, q, params=None) -> float:
    """max(1, the largest world coordinate ‖p‖_∞ of the loop frames and rolling disks' centres at q) in the
    system's length unit: r's position rows are differences of such p, so round-off leaves ~ε ‖p‖_∞ in them
    (and in J_r) however small the mechanism is; 1 keeps an absolute floor near the origin."""
    return max(1.0, float(np.abs(f.call("closure_frames", q, params=params)).max()))


def assemble(system_or_f, q_guess, fixed=(), params=None, tol: float | None = None,
             max_iter: int = 50) -> np.ndarray:
    """q near q_guess with the closures r(q) = 0 (`closure_rows`: loops, rolling disks' heights), the
    `fixed` coordinates (or speeds) held. Gauss–Newton in the free speeds: with J_r the rows of J_c that
    carry r (`closure_index`, ṙ = J_r u) and its free columns, Δu = −J_r⁺ r (the minimum-norm step when
    there are more free speeds than rows; singular values below 1e-12 s of the largest dropped: round-off),
    scaled to ‖Δu‖_∞ ≤ 1 (rad or length unit: a trust region), q ← q ⊕ Δu (`eg.integrate`: quaternions
    stay unit), the step halved while ‖r‖ grows. Until ‖r‖ ≤ tol, by default 1e-12 s with s = `size` at
    q_guess (max(1, the largest ‖p‖_∞ of the loop frames): the residual's round-off scale). Else ModelError:
    the closures cannot be satisfied when Gauss–Newton stopped at a least-squares minimum ‖r‖ > 0 (r ⟂ the
    range of J_r), no closure found from this guess otherwise; with ‖r‖ and the worst row."""
    f = numeric(system_or_f, "assemble")
    system = f.eom.system
    if not f.closure_rows:
        raise ModelError("assemble: the system has no loops or rolling disks (nothing to close)")
    q = finite_array(q_guess, (f.nq,), "assemble: q_guess")
    q = unit_quaternions(system, q)  # R(q) is a rotation only for unit quaternions
    held = speed_indices(system, fixed, "assemble: fixed")
    free = [i for i in range(f.nv) if i not in held]
    max_iter = count(max_iter, "assemble: max_iter", least=0)
    s = size(f, q, params)
    tol = TOL * s if tol is None else positive(tol, "assemble: tol")
    r = f.closure_residual(q, params)
    for _ in range(max_iter):
        if np.linalg.norm(r) <= tol:
            return q
        du = np.zeros(f.nv)
        du[free] = -_gauss_newton(f, q, r, free, s, params)[1]
        du *= min(1.0, STEP / max(np.abs(du).max(), EPS))
        for _ in range(HALVINGS):
            trial = integrate(system, q, du, 1.0)
            r_trial = f.closure_residual(trial, params)
            if np.linalg.norm(r_trial) < np.linalg.norm(r):
                break
            du /= 2
        else:
            break  # no step reduces ‖r‖
        q, r = trial, r_trial
    if np.linalg.norm(r) <= tol:
        return q
    raise _no_closure(f, q, r, free, held, tol, s, params)


def _gauss_newton(f: NumericEoM, q, r, free, s: float, params) -> tuple[np.ndarray, np.ndarray]:
    """(J_r, J_r⁺ r): the closure rows' free columns at q and the minimum-norm solution of J_r x = r,
    singular values below 1e-12 s of the largest dropped."""
    J = f.contact_jacobian(q, params)[f.closure_index][:, free]
    return J, np.linalg.lstsq(J, r, rcond=TOL * s)[0]


def _no_closure(f: NumericEoM, q, r, free, held, tol: float, s: float, params) -> ModelError:
    """The closures cannot be satisfied when r ⟂ range J_r (‖J_r J_r⁺ r‖ ≤ 1e-6 ‖r‖: no first-order
    motion of the free speeds reduces ‖r‖, a least-squares minimum); else no closure found from here."""
    J, x = _gauss_newton(f, q, r, free, s, params)
    reach = np.linalg.norm(J @ x) / np.linalg.norm(r)
    worst = int(np.argmax(np.abs(r)))
    holding = f" with {[str(f.eom.system.u[i]) for i in held]} held" if held else ""
    where = (f"‖r‖ = {np.linalg.norm(r):.3e} > tol = {tol:.1e}; worst row '{f.closure_rows[worst]}' = "
             f"{r[worst]:.3e}")
    if reach <= STATIONARY:
        return ModelError(f"assemble: the closures cannot be satisfied{holding}: they fail by {where} at a "
                          "least-squares minimum of ‖r‖ (no motion of the free coordinates reduces it)")
    return ModelError(f"assemble: no closure found from this guess{holding} ({where}): try a guess nearer "
                      "a closure")


def project(system_or_f, q, u, params=None, tol: float | None = None) -> tuple[np.ndarray, np.ndarray]:
    """(q, u) on the constraint manifold: unit quaternions, q assembled (`assemble`, `tol` its tolerance:
    by default relative to the problem's `size`) with nothing held (the minimum-norm correction), then
    u ← N_c u = u − M⁻¹ J_cᵀ (J_c M⁻¹ J_cᵀ)⁺ J_c u, the speeds with J_c u = 0 (every row: contacts, loops,
    no-slip) nearest to u in kinetic energy, min (u' − u)ᵀ M (u' − u)."""
    f = numeric(system_or_f, "project")
    q = finite_array(q, (f.nq,), "project: q")
    u = finite_array(u, (f.nv,), f"project: u (the {f.nv} speeds {[str(x) for x in f.eom.u]})")
    q = assemble(f, q, params=params, tol=tol) if f.closure_rows else unit_quaternions(f.eom.system, q)
    return q, f.support_projector(q, params) @ u
