"""Finite Fourier series trajectories (Swevers, Ganseman, Tükel, De Schutter, Van Brussel 1997): joint i,

    q_i(t) = q_i0 + Σ_{l=1..L} a_il/(ω_f l) sin(ω_f l t) − b_il/(ω_f l) cos(ω_f l t),
    u_i(t) = Σ_l a_il cos(ω_f l t) + b_il sin(ω_f l t),
    u̇_i(t) = Σ_l ω_f l (−a_il sin(ω_f l t) + b_il cos(ω_f l t)),

periodic with period 2π/ω_f, so that measurements can be averaged over periods."""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..errors import ModelError


@dataclass(frozen=True)
class Fourier:
    """The coefficients: q0 (n,), a and b (n, L), the fundamental ω_f (rad/s)."""

    q0: np.ndarray
    a: np.ndarray
    b: np.ndarray
    omega: float

    @property
    def period(self) -> float:
        return 2 * np.pi / self.omega

    def __call__(self, t) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """(q, u, u̇) at the times t, each (len(t), n)."""
        t = np.atleast_1d(np.asarray(t, dtype=float))
        w = self.omega * np.arange(1, self.a.shape[1] + 1)  # (L,) ω_f l
        s, c = np.sin(t[:, None] * w), np.cos(t[:, None] * w)  # (T, L)
        q = self.q0 + s @ (self.a / w).T - c @ (self.b / w).T
        u = c @ self.a.T + s @ self.b.T
        ud = -s @ (self.a * w).T + c @ (self.b * w).T
        return q, u, ud

    def vector(self) -> np.ndarray:
        """q0, a, b as one vector (the optimiser's variables)."""
        return np.concatenate([self.q0, self.a.ravel(), self.b.ravel()])

    @classmethod
    def of(cls, x: np.ndarray, n: int, harmonics: int, omega: float) -> Fourier:
        """The inverse of `vector`."""
        L = harmonics
        return cls(x[:n], x[n: n + n * L].reshape(n, L), x[n + n * L:].reshape(n, L), omega)


def limits(lower, upper, velocity) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Joint limits as arrays of one length: lower < upper, velocity > 0, all finite."""
    lo, hi, v = (np.atleast_1d(np.asarray(x, dtype=float)) for x in (lower, upper, velocity))
    for name, x in (("lower", lo), ("upper", hi), ("velocity", v)):
        if x.ndim != 1 or len(x) != len(lo) or not np.isfinite(x).all():
            raise ModelError(f"argument '{name}' must be {len(lo)} finite numbers (one per joint), got {x}")
    if (lo >= hi).any() or (v <= 0).any():
        raise ModelError(f"joint limits need lower < upper and velocity > 0, got lower {lo}, upper {hi}, "
                         f"velocity {v}")
    return lo, hi, v


def random_fourier(rng: np.random.Generator, lower, upper, velocity, harmonics: int, omega: float,
                   times: np.ndarray, margin: float = 0.9) -> Fourier:
    """Random coefficients, scaled so that at the times the trajectory stays within `margin` of the
    limits: q0 at the middle, a and b normal, the scale the largest that keeps |q − q0| and |u| inside."""
    lo, hi, v = limits(lower, upper, velocity)
    n = len(lo)
    unit = Fourier(np.zeros(n), rng.normal(size=(n, harmonics)), rng.normal(size=(n, harmonics)), omega)
    q, u, _ = unit(times)
    reach = np.minimum(margin * (hi - lo) / 2 / np.abs(q).max(axis=0), margin * v / np.abs(u).max(axis=0))
    return Fourier((lo + hi) / 2, unit.a * reach[:, None], unit.b * reach[:, None], omega)
