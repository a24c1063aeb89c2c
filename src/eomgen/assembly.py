"""Consistent states of a system with loop closures and rolling disks: q on the closure r(q) = 0
(`assemble`), and (q, u) projected onto the constraint manifold (`project`). Numeric throughout: the
generated r(q), J_c(q), M(q) of `eg.codegen` (NumPy or C)."""
from __future__ import annotations

from collections.abc import Iterable

import numpy as np
import sympy as sp

from .codegen import NumericEoM, codegen
from .eom import EquationsOfMotion
from .errors import ModelError
from .methods import derive
from .model import System
from .state import integrate, unit_quaternions

HALVINGS = 30  # step halvings before a Gauss–Newton step counts as stalled (a least-squares minimum)


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
            whole = " (a quaternion's component: name a speed)" if str(name) in map(str, system.q) else ""
            raise ModelError(f"{what}: unknown coordinate or speed {x!r}{whole}; coordinates are "
                             f"{[q.name for q in system.q]}, speeds {[u.name for u in system.u]}")
        if lookup[name] in out:
            raise ModelError(f"{what}: {name!r} names speed '{system.u[lookup[name]]}' a second time")
        out.append(lookup[name])
    return out


def assemble(system_or_f, q_guess, fixed=(), params=None, tol: float = 1e-12,
             max_iter: int = 50) -> np.ndarray:
    """q near q_guess with the closures r(q) = 0 (`closure_rows`: loops, rolling disks' heights), the
    `fixed` coordinates (or speeds) held. Gauss–Newton in the free speeds: with J_r the rows of J_c that
    carry r (`closure_index`, ṙ = J_r u) and its free columns, Δu = −J_r⁺ r (the minimum-norm step when
    there are more free speeds than rows), q ← q ⊕ Δu (`eg.integrate`: quaternions stay unit), the step
    halved while ‖r‖ grows. Until ‖r‖ ≤ tol; else ModelError with ‖r‖ and the worst row."""
    f = numeric(system_or_f, "assemble")
    system = f.eom.system
    if not f.closure_rows:
        raise ModelError("assemble: the system has no loops or rolling disks (nothing to close)")
    q = np.array(q_guess, dtype=float)
    if q.shape != (f.nq,):
        raise ModelError(f"assemble: q_guess must have shape ({f.nq},), got {q.shape}")
    q = unit_quaternions(system, q)  # R(q) is a rotation only for unit quaternions
    held = speed_indices(system, fixed, "assemble: fixed")
    free = [i for i in range(f.nv) if i not in held]
    r = f.closure_residual(q, params)
    for _ in range(max_iter):
        if np.linalg.norm(r) <= tol:
            return q
        J = f.contact_jacobian(q, params)[f.closure_index][:, free]
        du = np.zeros(f.nv)
        du[free] = -np.linalg.lstsq(J, r, rcond=1e-12)[0]
        for _ in range(HALVINGS):
            trial = integrate(system, q, du, 1.0)
            r_trial = f.closure_residual(trial, params)
            if np.linalg.norm(r_trial) < np.linalg.norm(r):
                break
            du /= 2
        else:
            break  # no step reduces ‖r‖: a minimum of ‖r‖ that is not a closure
        q, r = trial, r_trial
    if np.linalg.norm(r) <= tol:
        return q
    worst = int(np.argmax(np.abs(r)))
    holding = f" with {[str(system.u[i]) for i in held]} held" if held else ""
    raise ModelError(f"assemble: the closures cannot be satisfied{holding}: "
                     f"‖r‖ = {np.linalg.norm(r):.3e} > tol = {tol:.0e} after Gauss–Newton; worst row "
                     f"'{f.closure_rows[worst]}' = {r[worst]:.3e}")


def project(system_or_f, q, u, params=None, tol: float = 1e-12) -> tuple[np.ndarray, np.ndarray]:
    """(q, u) on the constraint manifold: unit quaternions, q assembled (`assemble`) with nothing held
    (the minimum-norm correction), then u ← N_c u = u − M⁻¹ J_cᵀ (J_c M⁻¹ J_cᵀ)⁺ J_c u, the speeds with
    J_c u = 0 (every row: contacts, loops, no-slip) nearest to u in kinetic energy,
    min (u' − u)ᵀ M (u' − u)."""
    f = numeric(system_or_f, "project")
    q = unit_quaternions(f.eom.system, q)
    q = assemble(f, q, params=params, tol=tol) if f.closure_rows else q
    return q, f.support_projector(q, params) @ np.asarray(u, dtype=float)
