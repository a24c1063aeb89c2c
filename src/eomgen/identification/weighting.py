"""Weighted least squares over stacked joint torques, and the per-joint weights of Gautier's method.

Rows of joint j are multiplied by w_j. By default w_j = 1/σ̂_j, σ̂_j the standard deviation of joint
j's residual in an unweighted fit (Gautier 1997), corrected for the b fitted parameters:
σ̂_j² = ‖r_j‖² / (N − b/nv) over the N states; this is done once (one reweighting, not iterated to
convergence). σ̂_j is floored at 1e-12 of the largest; all zero (an exact fit): equal weights."""
from __future__ import annotations

import numpy as np

from ..errors import ModelError


def given(weights, nv: int) -> np.ndarray:
    """Weights given by the user: nv positive finite numbers."""
    w = np.asarray(weights, dtype=float)
    if w.shape != (nv,) or not np.isfinite(w).all() or (w <= 0).any():
        raise ModelError(f"argument 'weights' must be {nv} positive finite numbers (one per joint), got "
                         f"{np.asarray(weights).tolist()}")
    return w


def weighted(Y: np.ndarray, tau: np.ndarray, w: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(A, c): the rows of Y (N, nv, b) and τ (N, nv) scaled by their joint's weight and stacked."""
    return (Y * w[None, :, None]).reshape(-1, Y.shape[2]), (tau * w).reshape(-1)


def gautier(Y: np.ndarray, tau: np.ndarray) -> np.ndarray:
    """w_j = 1/σ̂_j from the residuals of the unweighted fit (see the module's text)."""
    N, nv, b = Y.shape
    A, c = weighted(Y, tau, np.ones(nv))
    beta = np.linalg.lstsq(A, c, rcond=None)[0]
    r = (tau - Y @ beta).reshape(N, nv)
    dof = N - b / nv
    if dof <= 0:
        raise ModelError(f"identify: {N} states are too few for {b} base parameters and {nv} joints")
    sigma = np.sqrt((r**2).sum(axis=0) / dof)
    if sigma.max() == 0:
        return np.ones(nv)
    return 1.0 / np.maximum(sigma, 1e-12 * sigma.max())
