"""Excitation trajectories: a finite Fourier series per joint (`fourier`) within the joints' position
and velocity limits, its coefficients chosen to minimise the condition number of the stacked base
regressor Y_b at `samples` times over one period (Swevers et al. 1997).

scipy's SLSQP minimises log cond(Y_b) (its gradient by finite differences) from `restarts` random
feasible starts (`random_fourier`); the limits, linear in the coefficients, are its constraints at the
sample times. Within `time_limit` seconds in all: the best feasible point seen is kept. For
joints with one coordinate per speed (revolute, prismatic: nq = nv)."""
from __future__ import annotations

import time
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from ..errors import ModelError
from .base import BaseParameters, base_parameters
from .data import Regressor, batch, stack
from .model import resolve
from .fourier import Fourier, limits, random_fourier


@dataclass(frozen=True)
class Excitation:
    """The optimised trajectory, sampled: q, u, u̇ (samples, n) at `times`."""

    fourier: Fourier
    condition: float  # cond(Y_b) at the samples
    start: float  # the best cond(Y_b) among the random starts
    base: BaseParameters
    times: np.ndarray
    q: np.ndarray
    u: np.ndarray
    ud: np.ndarray


class _Timeout(Exception):
    """The time limit has passed."""


def condition(regressor: Regressor, base: BaseParameters, q, u, ud) -> float:
    """cond(Y_b) of the stacked base regressor at the states (∞ where it loses rank)."""
    s = np.linalg.svd(base.regressor(stack(regressor, base.parameters, q, u, ud)).reshape(-1, base.rank),
                      compute_uv=False)
    return float(s[0] / s[-1]) if s[-1] > 0 else np.inf


def excite(regressor, lower, upper, velocity, *, names: Sequence[str] | None = None, harmonics: int = 5,
           period: float = 10.0, samples: int = 50, restarts: int = 3, iterations: int = 100,
           time_limit: float = 30.0,
           rng: np.random.Generator | None = None, base: BaseParameters | None = None) -> Excitation:
    """The excitation trajectory of the module's text: `harmonics` L, fundamental ω_f = 2π/`period`,
    at most `iterations` SLSQP iterations from each start; the regressor a System, EquationsOfMotion,
    `eg.regressor(...)` or a callable with column `names`."""
    regressor, names = resolve(regressor, names)
    lo, hi, v = limits(lower, upper, velocity)
    counts = {"harmonics": harmonics, "samples": samples, "restarts": restarts, "iterations": iterations}
    for name, value in counts.items():
        if not isinstance(value, int) or isinstance(value, bool) or value < 1 + (name == "samples"):
            raise ModelError(f"excite: argument '{name}' must be an integer ≥ {1 + (name == 'samples')}, "
                             f"got {value!r}")
    for name, value in {"period": period, "time_limit": time_limit}.items():
        if not value > 0:
            raise ModelError(f"excite: argument '{name}' must be positive, got {value!r}")
    rng = rng or np.random.default_rng()
    omega, n = 2 * np.pi / period, len(lo)
    times = np.linspace(0, period, samples, endpoint=False)
    randoms = [random_fourier(rng, lo, hi, v, harmonics, omega, times) for _ in range(restarts + 3)]
    sampled = tuple(map(np.concatenate, zip(*(f(times) for f in randoms))))
    regressor = batch(regressor, *sampled)
    base = base or base_parameters(regressor, *sampled, names=names)  # many more rows than parameters

    G, h = _limits_matrix(lambda x: _inside(Fourier.of(x, n, harmonics, omega), times, lo, hi, v),
                          n * (2 * harmonics + 1))
    best = {"x": None, "log": np.inf}  # the best feasible point the optimiser has seen

    def cost(x: np.ndarray) -> float:
        if time.monotonic() > deadline:
            raise _Timeout
        value = np.log(condition(regressor, base, *Fourier.of(x, n, harmonics, omega)(times)))
        if value < best["log"] and np.all(G @ x + h >= -1e-9):
            best.update(x=x.copy(), log=value)
        return value

    import scipy.optimize

    deadline, starts = time.monotonic() + time_limit, []
    for _ in range(restarts):
        x0 = random_fourier(rng, lo, hi, v, harmonics, omega, times).vector()
        try:
            starts.append(cost(x0))
            scipy.optimize.minimize(cost, x0, method="SLSQP", options={"maxiter": iterations}, constraints=[
                {"type": "ineq", "fun": lambda x: G @ x + h, "jac": lambda x: G}])
        except _Timeout:
            break
    if best["x"] is None:
        raise ModelError(f"excite: time_limit {time_limit} s passed before one trajectory was evaluated")
    fourier = Fourier.of(best["x"], n, harmonics, omega)
    return Excitation(fourier, float(np.exp(best["log"])), float(np.exp(min(starts))), base, times,
                      *fourier(times))


def _inside(f: Fourier, times, lo, hi, v) -> np.ndarray:
    """The limits' margins at the times: upper − q, q − lower, v − u, v + u (≥ 0 inside)."""
    q, u, _ = f(times)
    return np.concatenate([(hi - q).ravel(), (q - lo).ravel(), (v - u).ravel(), (v + u).ravel()])


def _limits_matrix(margins, size: int) -> tuple[np.ndarray, np.ndarray]:
    """(G, h) with margins(x) = G x + h (the margins are affine in the coefficients)."""
    h = margins(np.zeros(size))
    return np.column_stack([margins(e) - h for e in np.eye(size)]), h
