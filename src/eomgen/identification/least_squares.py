"""Identification by weighted least squares on the base parameters.

With A = W Y_b and c = W τ the weighted stacks (Nn rows: N states, n = nv joints, b base parameters,
W the per-joint weights of `weighting`), A = U S Vᵀ:

    β̂ = V S⁻¹ Uᵀ c,    r = c − A β̂,    σ² = ‖r‖² / (Nn − b),    Cov(β̂) = σ² (AᵀA)⁻¹ = σ² V S⁻² Vᵀ,

each β's standard deviation √Cov_kk, and cond(A) = s_max / s_min. The covariance holds for noise
independent between samples with the variance of each joint's rows proportional to 1/w_j²."""
from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from ..errors import ModelError
from . import weighting
from .base import BaseParameters, base_parameters
from .data import Regressor, rows, stack, states
from .model import resolve


@dataclass(frozen=True)
class Identification:
    """β̂ of the base parameters `base`, with its statistics."""

    base: BaseParameters
    beta: np.ndarray  # (b,) β̂
    std: np.ndarray  # (b,) each β̂'s standard deviation
    covariance: np.ndarray  # (b, b) σ² (AᵀA)⁻¹
    condition: float  # cond(A) of the weighted stacked base regressor
    weights: np.ndarray  # (nv,) w_j
    sigma: float  # σ, the weighted residual's standard deviation
    rms: np.ndarray  # (nv,) the unweighted residual's RMS per joint
    regressor: Regressor

    def predict(self, q, u, ud) -> np.ndarray:
        """τ̂ = Y_b(q, u, u̇) β̂, (N, nv)."""
        Y = stack(self.regressor, self.base.parameters, q, u, ud)
        return self.base.regressor(Y) @ self.beta


def identify(regressor, q, u, ud, tau, *, names: Sequence[str] | None = None, weights=None,
             base: BaseParameters | None = None) -> Identification:
    """β̂ from the measured torques τ (N, nv) at the states (q, u, u̇) (see the module's text); the
    regressor a System, EquationsOfMotion, `eg.regressor(...)` or a callable with column `names`.
    base: the base parameters (default: found from these states); weights: one per joint (default
    Gautier's 1/σ̂_j, `weighting`)."""
    regressor, names = resolve(regressor, names)
    q, u, ud = states(q, u, ud)
    tau = rows(tau, "tau", u.shape[1])
    if len(tau) != len(q):
        raise ModelError(f"argument 'tau' must have one row per state ({len(q)}), got {len(tau)}")
    base = base or base_parameters(regressor, q, u, ud, names=names)
    if base.parameters != names:
        raise ModelError("argument 'base' is of other parameters than 'names'")
    Yb = base.regressor(stack(regressor, names, q, u, ud))
    N, nv, b = Yb.shape
    if N * nv <= b:
        raise ModelError(f"identify: {N} states give {N * nv} rows for {b} base parameters; give more")
    w = weighting.gautier(Yb, tau) if weights is None else weighting.given(weights, nv)
    A, c = weighting.weighted(Yb, tau, w)
    U, s, Vt = np.linalg.svd(A, full_matrices=False)
    beta = Vt.T @ ((U.T @ c) / s)
    r = c - A @ beta
    sigma2 = r @ r / (N * nv - b)
    covariance = sigma2 * (Vt.T / s**2) @ Vt
    rms = np.sqrt(((tau - Yb @ beta) ** 2).mean(axis=0))
    return Identification(base=base, beta=beta, std=np.sqrt(np.diag(covariance)), covariance=covariance,
                          condition=float(s[0] / s[-1]), weights=w, sigma=float(np.sqrt(sigma2)), rms=rms,
                          regressor=regressor)
