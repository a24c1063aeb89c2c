"""Simulation of any system on SciPy's integrators, with its energy balance.

The state x = [q, u] (with DC motors [q, u, i]; Kane's equations [q, w_ind]) moves by the functions'
`rhs` (`codegen.rhs`), and the work W of the actuators and of the non-conservative loads by Ẇ = `power`
alongside it, so that E(t) − E(t0) − W(t) = 0 (E = T + U, `energy`) up to the integration error. With
contacts, loops and rolling disks the constrained dynamics hold only the constraints' second derivative,
so r(q) and J_c u drift; `stabilization`:
- "projection": after each accepted step (q, u) ← eg.project(q, u) (q back on r = 0 by Gauss–Newton,
  u ← u − M⁻¹ J_cᵀ (J_c M⁻¹ J_cᵀ)⁺ J_c u); explicit Runge–Kutta methods, whose state is (t, x, ẋ);
- "baumgarte": J_c u̇ + J̇_c u = −2 α J_c u − β² r (r on the rows that have a position residual);
- None: the drift left as it grows."""
from __future__ import annotations

import re
import warnings
from contextlib import contextmanager
from dataclasses import dataclass, field

import numpy as np

from .arguments import finite_array
from .numeric import NumericEoM, NumericKane, codegen, project
from .numeric.assembly import numeric
from .numeric.state_equations import efforts
from .eom import EquationsOfMotion
from .errors import ModelError
from .methods.kane import KaneEquations
from .model import System

STABILIZATIONS = ("projection", "baumgarte", None)
METHODS = ("RK45", "RK23", "DOP853", "Radau", "BDF", "LSODA")  # solve_ivp's
PROJECTING = ("RK23", "RK45", "DOP853")  # explicit: (t, x, ẋ) is their whole state


@dataclass
class Simulation:
    """The motion at the times t (N,): q (N, nq), u (N, nv) (Kane's: w_ind), the motor currents (N, motors;
    None without motors) and the actuator efforts τ_a at these states (N, actuated; None without them);
    the energy E = T + U (+ ½ Σ L i²) and the work W of the actuators and non-conservative loads since t0,
    so that `balance` = E − E(t0) − W vanishes but for the integration error; the drifts ‖r(q)‖ of the
    loops, rolling disks (Kane's: holonomic constraints) and ‖J_c u‖ (None where there are none); the
    `functions` that ran, with their `params`."""

    t: np.ndarray
    q: np.ndarray
    u: np.ndarray
    currents: np.ndarray | None
    tau: np.ndarray | None
    energy: np.ndarray
    work: np.ndarray
    closure_drift: np.ndarray | None
    velocity_drift: np.ndarray | None
    functions: NumericEoM | NumericKane = field(repr=False)
    params: dict | None = field(default=None, repr=False)

    @property
    def balance(self) -> np.ndarray:
        """E(t) − E(t0) − W(t): zero for exact integration (not offered where a prescribed motion does
        work, which W does not count)."""
        if self.functions.system.prescribed:
            raise ModelError(f"balance: the work of joint '{self.functions.system.prescribed[0].name}''s "
                             "prescribed motion is not in W; compare E with ∫ driving_effort · θ̇ dt")
        return self.energy - self.energy[0] - self.work


def functions(source, entry: str) -> NumericEoM | NumericKane:
    """The numeric functions of a System (derived with method "recursive"), an EquationsOfMotion, a
    KaneEquations, or the `eg.codegen` functions themselves (give these for repeated runs)."""
    if isinstance(source, (NumericEoM, NumericKane)):
        return source
    if isinstance(source, KaneEquations):
        return codegen(source)
    if not isinstance(source, (System, EquationsOfMotion)):
        raise ModelError(f"{entry}: expected a System, EquationsOfMotion, KaneEquations or their eg.codegen "
                         f"functions, got {type(source).__name__}")
    return numeric(source, entry)


def simulate(system_or_functions, x0, t_span, controller=None, tau=None, params=None,
             stabilization: str | None = "projection", baumgarte: tuple[float, float] = (10.0, 10.0),
             method: str = "DOP853", t_eval=None, rtol: float = 1e-10, atol: float = 1e-10,
             max_step: float = np.inf, tol: float | None = None) -> Simulation:
    """Integrate from x0 = (q0, u0) (with motors (q0, u0, i0); Kane's (q0, w0); or one array) over
    t_span = (t0, t1) (t1 < t0 runs backward) with the actuator efforts of `controller`, a function
    (t, q, u) → τ_a, or `tau` (values, or such a function; not both). With contacts, loops or rolling
    disks, `stabilization` ((α, β) = `baumgarte`, critically damped at α = β); with projection (`tol`:
    `eg.project`'s) x0 is projected first and the states are those after each accepted step (or at
    t_eval, interpolated in the step and projected); else solve_ivp's. t_eval within t_span, in the
    direction of time."""
    f = functions(system_or_functions, "simulate")
    if stabilization not in STABILIZATIONS:
        raise ModelError(f"simulate: stabilization must be one of {STABILIZATIONS}, got {stabilization!r}")
    if method not in METHODS:
        raise ModelError(f"simulate: method must be one of {list(METHODS)}, got {method!r}")
    constrained = isinstance(f, NumericEoM) and bool(f.constraint_rows)
    projecting = constrained and stabilization == "projection"
    if projecting and method not in PROJECTING:
        raise ModelError(f"simulate: projection needs an explicit Runge–Kutta method {list(PROJECTING)}, "
                         f"got {method!r}")
    if controller is not None and tau is not None:
        raise ModelError("simulate: give the actuator efforts by controller or by tau, not both")
    if controller is not None and not callable(controller):
        raise ModelError(f"simulate: controller must be a function (t, q, u) → τ_a, got "
                         f"{type(controller).__name__}")
    source = tau if controller is None else controller
    t_span = tuple(finite_array(t_span, (2,), "simulate: t_span"))
    t_eval = _times(t_span, t_eval)
    gains = {}
    if constrained and stabilization == "baumgarte":
        gains = {"baumgarte": tuple(finite_array(baumgarte, (2,), "simulate: baumgarte"))}
    options = dict(rtol=rtol, atol=atol, max_step=max_step)
    n_efforts = len(f.S)

    def rates(t, y):
        x = y[:-1]
        tau_a = _efforts(source, t, x[:f.nq], x[f.nq:f.nq + f.nv], n_efforts)
        return np.append(f.rhs(t, x, tau_a, params, **gains), f.power(t, x, tau_a, params))

    import scipy.integrate

    y0 = np.append(_initial(f, x0), 0.0)
    with _once():
        if projecting:
            stepper = getattr(scipy.integrate, method)
            t, y = _projected(f, rates, y0, t_span, stepper, t_eval, params, options, tol)
        else:
            sol = scipy.integrate.solve_ivp(rates, t_span, y0, method=method, t_eval=t_eval, **options)
            if sol.status < 0:
                raise ModelError(f"simulate: the integrator failed at t = {sol.t[-1]}: {sol.message}")
            t, y = sol.t, sol.y.T
        return _report(f, t, y, params, source)


def _efforts(source, t, q, u, n: int) -> np.ndarray | None:
    """τ_a at (t, q, u): `tau`'s values or the controller's, which gets copies of q and u (the integrator's
    state is not its to change); n finite numbers (not None, not booleans), else a ModelError naming it."""
    if source is None:
        return None
    what = "simulate: the controller's efforts τ_a" if callable(source) else "simulate: tau"
    return finite_array(efforts(source, t, q.copy(), u.copy()), (n,), what)


@contextmanager
def _once():
    """The warnings of one simulation, each kind (its text less the numbers) issued once at its end, with
    how often it came: a redundant loop warns at every evaluation of the dynamics."""
    kinds: dict = {}
    try:
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            try:
                yield
            finally:
                for w in caught:
                    kind = re.sub(r"[-+]?\d[\d.e+-]*", "#", str(w.message))
                    kinds.setdefault((w.category, kind), []).append(w.message)
    finally:
        for (category, _), seen in kinds.items():
            times = f" ({len(seen)} times in this simulation)" if len(seen) > 1 else ""
            warnings.warn(f"{seen[0]}{times}", category, stacklevel=4)


def _initial(f, x0) -> np.ndarray:
    """x0 from a tuple of parts or one array, of f.nx values."""
    x = np.concatenate([np.ravel(p) for p in x0]) if isinstance(x0, tuple) else np.asarray(x0, dtype=float)
    if x.shape != (f.nx,):
        parts = "q0, w0" if isinstance(f, NumericKane) else "q0, u0, i0" if f.nx > f.nq + f.nv else "q0, u0"
        raise ModelError(f"simulate: x0 must be ({parts}) with {f.nx} values in all, got shape {x.shape}")
    return x


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


def _projected(f, rates, y0, t_span, method, t_eval, params, options, tol) -> tuple[np.ndarray, np.ndarray]:
    """Step `method` and project (q, u) after each accepted step (its y and ẏ reset); the t_eval
    between the step's ends (in the direction of time) from its dense output, projected."""
    n = f.nq + f.nv

    def projected(y):
        return np.concatenate([*project(f, y[:f.nq], y[f.nq:n], params, tol), y[n:]])

    solver = method(rates, t_span[0], projected(y0), t_span[1], **options)
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


def _report(f, t, y, params, source) -> Simulation:
    """The states with their energy, work, efforts and drifts."""
    x, n = y[:, :-1], f.nq + f.nv
    q, u = x[:, :f.nq], x[:, f.nq:n]
    tau = None
    if source is not None:
        tau = np.array([_efforts(source, tk, qk, uk, len(f.S)) for tk, qk, uk in zip(t, q, u)])
    closure = velocity = None
    if isinstance(f, NumericKane):
        if f.kane.dependent_coordinates:
            closure = np.linalg.norm(f.holonomic_residual(q, params), axis=-1)
    elif f.constraint_rows:
        closure = np.linalg.norm(f.closure_residual(q, params), axis=-1) if f.closure_rows else None
        velocity = np.linalg.norm(np.einsum("nij,nj->ni", f.contact_jacobian(q, params), u), axis=-1)
    currents = x[:, n:] if x.shape[1] > n else None
    if "t" in f.parameters.names:  # T and U at each state's time (the drive's work is not in y[:, -1])
        energy = np.array([f.energy(xk, {**(params or {}), "t": tk}) for tk, xk in zip(t, x)])
    else:
        energy = f.energy(x, params)
    return Simulation(t, q, u, currents, tau, energy, y[:, -1], closure, velocity, f, params)
