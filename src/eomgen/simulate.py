"""Simulation of a system with contacts, loops and rolling disks that keeps their constraints.

The state x = [q, u] moves by q̇ = q̇(q, u) (`System.qdot`) and the constrained dynamics u̇ of
`constrained_dynamics` (J_c u̇ + J̇_c u = 0, forces by the contact machinery), on SciPy's integrators.
Integration holds the constraint's second derivative only, so r(q) and J_c u drift; `stabilization`:
- "projection": after each accepted step (q, u) ← eg.project(q, u) (q back on r = 0 by Gauss–Newton,
  u ← u − M⁻¹ J_cᵀ (J_c M⁻¹ J_cᵀ)⁺ J_c u); explicit Runge–Kutta methods, whose state is (t, x, ẋ);
- "baumgarte": J_c u̇ + J̇_c u = −2 α J_c u − β² r (r on the rows that have a position residual);
- None: the drift left as it grows."""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.integrate import DOP853, RK23, RK45, solve_ivp

from .assembly import numeric, project
from .errors import ModelError

STABILIZATIONS = ("projection", "baumgarte", None)
METHODS = ("RK45", "RK23", "DOP853", "Radau", "BDF", "LSODA")  # solve_ivp's
PROJECTING = {"RK23": RK23, "RK45": RK45, "DOP853": DOP853}  # explicit: (t, x, ẋ) is their whole state


@dataclass
class Simulation:
    """States at the times t (N,): q (N, nq), u (N, nv); the drifts ‖r(q)‖ (None without loops or rolling
    disks) and ‖J_c u‖; the energy T + U when no load acts (None otherwise)."""

    t: np.ndarray
    q: np.ndarray
    u: np.ndarray
    closure_drift: np.ndarray | None
    velocity_drift: np.ndarray
    energy: np.ndarray | None


def simulate(f, x0, t_span, tau_a=None, stabilization: str | None = "projection",
             baumgarte: tuple[float, float] = (10.0, 10.0), params=None, method: str = "DOP853",
             t_eval=None, rtol: float = 1e-10, atol: float = 1e-10, max_step: float = np.inf,
             tol: float | None = None) -> Simulation:
    """Integrate from x0 = (q0, u0) (or [q0, u0]) over t_span = (t0, t1) with actuator torques tau_a (None,
    values, or a function (t, q, u) → values) and the module's `stabilization` ((α, β) = `baumgarte`:
    critically damped at α = β); t1 < t0 runs backward. With projection (`tol`: `eg.project`'s), x0 is
    projected first and the states are those after each accepted step (or at t_eval, interpolated in the
    step and projected); else solve_ivp's. t_eval within t_span, in the direction of time."""
    f = numeric(f, "simulate")
    if stabilization not in STABILIZATIONS:
        raise ModelError(f"simulate: stabilization must be one of {STABILIZATIONS}, got {stabilization!r}")
    if stabilization == "projection" and method not in PROJECTING:
        raise ModelError(f"simulate: projection needs an explicit Runge–Kutta method {list(PROJECTING)}, "
                         f"got {method!r}")
    if method not in METHODS:
        raise ModelError(f"simulate: method must be one of {list(METHODS)}, got {method!r}")
    t_eval = _times(t_span, t_eval)
    y0 = np.concatenate([np.ravel(x) for x in x0]) if isinstance(x0, tuple) else np.asarray(x0, dtype=float)
    if y0.shape != (f.nq + f.nv,):
        raise ModelError(f"simulate: x0 must be (q0, u0) with {f.nq} + {f.nv} values, got {y0.shape[0]}")
    torque = tau_a if callable(tau_a) else (lambda t, q, u: tau_a)
    gains = baumgarte if stabilization == "baumgarte" else None

    def rhs(t, y):
        q, u = y[:f.nq], y[f.nq:]
        return np.concatenate([f.qdot(q, u, params),
                               f.constrained_dynamics(q, u, torque(t, q, u), params, gains)[0]])

    options = dict(rtol=rtol, atol=atol, max_step=max_step)
    if stabilization == "projection":
        t, y = _projected(f, rhs, y0, t_span, PROJECTING[method], t_eval, params, options, tol)
    else:
        sol = solve_ivp(rhs, t_span, y0, method=method, t_eval=t_eval, **options)
        if sol.status < 0:
            raise ModelError(f"simulate: the integrator failed at t = {sol.t[-1]}: {sol.message}")
        t, y = sol.t, sol.y.T
    return _report(f, t, y, params, loads=tau_a is not None or bool(f.eom.load_names))


def _times(t_span, t_eval) -> np.ndarray | None:
    """t_eval as an array, refused outside t_span = (t0, t1) or out of the order from t0 to t1."""
    if t_eval is None:
        return None
    t0, t1 = (float(t) for t in t_span)
    t_eval = np.atleast_1d(np.asarray(t_eval, dtype=float))
    outside = t_eval[(t_eval < min(t0, t1)) | (t_eval > max(t0, t1))]
    if outside.size:
        raise ModelError(f"simulate: t_eval {outside.tolist()} outside t_span ({t0}, {t1})")
    if np.any(np.diff(t_eval) * np.sign(t1 - t0) < 0):
        raise ModelError(f"simulate: t_eval must run from t0 = {t0} to t1 = {t1} in order")
    return t_eval


def _projected(f, rhs, y0, t_span, method, t_eval, params, options, tol) -> tuple[np.ndarray, np.ndarray]:
    """Step `method` and project (q, u) after each accepted step (its x and ẋ reset); the t_eval
    between the step's ends (in the direction of time) from its dense output, projected."""

    def projected(y):
        return np.concatenate(project(f, y[:f.nq], y[f.nq:], params, tol))

    solver = method(rhs, t_span[0], projected(y0), t_span[1], **options)
    ts, ys = ([], []) if t_eval is not None else ([solver.t], [solver.y])
    if t_eval is not None and t_eval.size and t_eval[0] == solver.t:
        ts, ys = [solver.t], [solver.y]
    while solver.status == "running":
        message = solver.step()
        if solver.status == "failed":
            raise ModelError(f"simulate: the integrator failed at t = {solver.t}: {message}")
        if t_eval is not None:
            after = (t_eval - solver.t_old) * solver.direction
            inside = t_eval[(after > 0) & ((t_eval - solver.t) * solver.direction <= 0)]
            if inside.size:
                dense = solver.dense_output()
                ts.extend(inside)
                ys.extend(projected(dense(t)) for t in inside)
        solver.y = projected(solver.y)
        solver.f = solver.fun(solver.t, solver.y)
        if t_eval is None:
            ts.append(solver.t)
            ys.append(solver.y)
    return np.array(ts), np.array(ys)


def _report(f, t, y, params, loads: bool) -> Simulation:
    """The states with their drifts ‖r‖, ‖J_c u‖ and (no loads) the energy T + U."""
    q, u = y[:, :f.nq], y[:, f.nq:]
    closure = np.linalg.norm(f.closure_residual(q, params), axis=-1) if f.closure_rows else None
    velocity = np.linalg.norm(np.einsum("nij,nj->ni", f.contact_jacobian(q, params), u), axis=-1)
    energy = None
    if not loads and "T" in f.eom.compact and "U" in f.eom.compact:
        energy = f.T(q, u, params) + f.U(q, params)
    return Simulation(t, q, u, closure, velocity, energy)
