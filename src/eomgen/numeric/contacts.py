"""Contact dynamics, numerically (the inversions are never symbolic).

With M u̇ + b + g = Sᵀ τ + τ_loads + J_cᵀ F_c and the contacts held, J_c u̇ + J̇_c u = 0:

    F_c = −(J_c M⁻¹ J_cᵀ)⁻¹ (J_c M⁻¹ h + J̇_c u),   h = Sᵀ τ + τ_loads − b − g,
    u̇ = M⁻¹ (h + J_cᵀ F_c),
    N_c = 1 − M⁻¹ J_cᵀ (J_c M⁻¹ J_cᵀ)⁻¹ J_c,   J_c N_c = 0,   N_cᵀ (M u̇ + b + g) = N_cᵀ (Sᵀ τ + τ_loads).

F_c is the force the environment exerts on the robot (world-aligned axes). Everything goes through the
singular values σ of B = J_c L⁻ᵀ (M = L Lᵀ), so that J_c M⁻¹ J_cᵀ = B Bᵀ = U diag(s) Uᵀ, s = σ², is never
formed and its condition number κ = s_max / s_min is judged relative to its own scale (scaling all
masses leaves it unchanged):
- σ ≤ RANK_RTOL σ_max: rows that repeat other constraints; warned, naming them, and the minimum-norm
  (least-squares) forces are used (nothing along those directions);
- κ > COND_LIMIT: a near-singular contact set (e.g. an arm at a wrist singularity); warned with κ and the
  contact rows of the weak directions s < μ = s_max / COND_LIMIT, along which the forces are damped least
  squares, F = −s / (s² + μ²) (uᵀ r): each component of the constraint residual r is scaled by
  μ² / (s² + μ²) ≤ 1, so ‖J_c u̇ + J̇_c u‖ ≤ ‖J_c M⁻¹ h + J̇_c u‖ and ‖F‖ stays finite;
- otherwise the forces are the exact solution."""
from __future__ import annotations

import warnings
from dataclasses import dataclass

import numpy as np

from ..errors import ModelError

COND_LIMIT = 1e8  # κ beyond which a solve keeps fewer than half the digits (κ ε > √ε)
RANK_RTOL = 1e-10  # σ / σ_max below it (κ beyond 1e20): a row that repeats others


FLAT = float(np.sqrt(np.finfo(float).eps))  # s = ‖e × n‖ below which a rolling disk counts as lying flat


def refuse_flat(disks: list, s) -> None:
    """Refuse a state where a rolling disk lies (nearly) flat: s = ‖e × n‖ (the sine of its axle's angle to
    the ground normal, per disk; states along the first axes) below FLAT = √ε. Its contact point, the rim's
    lowest point c = ρ e × (e × n) / s, turns by δe / s for a change δe of the axle: it keeps fewer than
    half its digits there, and at s = 0 it is undefined."""
    low = np.min(np.reshape(np.asarray(s, dtype=float), (-1, len(disks))), axis=0)
    for disk, x in zip(disks, low):
        if not x >= FLAT:  # NaN too
            raise ModelError(f"rolling disk '{disk.name}' (body '{disk.body.name}') lies flat: "
                             f"{np.arcsin(min(abs(x), 1.0)):.1e} rad from flat (its axle's angle to the "
                             f"ground normal), below {FLAT:.1e} rad: the contact point, the rim's lowest "
                             "point, keeps fewer than half its digits there and is undefined on a flat disk")


def redundant_rows(A: np.ndarray, tol: float) -> list[int]:
    """Rows of a constraint matrix that are linear combinations of the rows before them (to `tol`)."""
    kept, redundant = np.zeros((0, A.shape[1])), []
    for i, row in enumerate(A):
        trial = np.vstack([kept, row])
        if np.linalg.matrix_rank(trial, tol=tol) > len(kept):
            kept = trial
        else:
            redundant.append(i)
    return redundant


@dataclass
class ContactSet:
    """M = L Lᵀ and the SVD J_c L⁻ᵀ = U diag(σ) Vᵀ; `weight` w with (J_c M⁻¹ J_cᵀ)⁺ ≈ U diag(w) Uᵀ
    (1/s exact, s/(s² + μ²) on the weak directions, 0 on the redundant ones) and `rank`."""

    L: np.ndarray
    U: np.ndarray
    Vt: np.ndarray
    weight: np.ndarray
    rank: int

    def Minv(self, x: np.ndarray) -> np.ndarray:
        """M⁻¹ x = L⁻ᵀ L⁻¹ x (NumPy's solvers: SciPy's bring a second BLAS thread pool, ten times slower
        here under load)."""
        return np.linalg.solve(self.L.T, np.linalg.solve(self.L, x))


def contact_set(M, J, names: list[str], damped: str) -> ContactSet:
    """The contact set's spectrum, with the warnings for redundant and near-singular sets (`damped`: what
    is done along the weak directions)."""
    try:
        L = np.linalg.cholesky(M)
    except np.linalg.LinAlgError:
        raise ModelError("the mass matrix is not positive definite at this state; contact forces are "
                         "undefined") from None
    B = np.linalg.solve(L, J.T).T
    U, sigma, Vt = np.linalg.svd(B, full_matrices=False)
    tol = RANK_RTOL * sigma[0]
    rank = int((sigma > tol).sum())
    if rank < len(names):
        redundant = [names[i] for i in redundant_rows(B, tol)]
        warnings.warn(f"rank-deficient contact set: {redundant} repeat other constraints; "
                      "using the minimum-norm (least-squares) contact forces", stacklevel=4)
    s = sigma[:rank] ** 2
    mu = s[0] / COND_LIMIT if rank else 0.0
    weak = s < mu  # some exactly when cond = s_max / s_min > COND_LIMIT
    weight = np.zeros(len(sigma))
    weight[:rank] = np.where(weak, s / (s ** 2 + mu ** 2), 1 / s)
    if weak.any():
        cond = s[0] / s[-1]
        share = (U[:, :rank][:, weak] ** 2).sum(axis=1)  # each row's part in the weak directions
        rows = [f"{names[i]} ({share[i]:.2f})" for i in np.argsort(-share) if share[i] >= 0.01]
        frames = sorted({names[i].rsplit(".", 1)[0] for i in np.flatnonzero(share >= 0.01)})
        warnings.warn(f"near-singular contact set: cond(J_c M⁻¹ J_cᵀ) = {cond:.2e} > {COND_LIMIT:.0e} at "
                      f"contacts {frames}; rows in the weak directions (s < μ = s_max / {COND_LIMIT:.0e} = "
                      f"{mu:.2e}): {', '.join(rows)}; {damped}", stacklevel=4)
    return ContactSet(L, U, Vt, weight, rank)


def contact_dynamics(M, h, J, Jdot_u, names) -> tuple[np.ndarray, np.ndarray]:
    """(u̇, F_c) of the constrained system: F_c = −U diag(w) Uᵀ (J_c M⁻¹ h + J̇_c u),
    u̇ = M⁻¹ (h + J_cᵀ F_c)."""
    c = contact_set(M, J, names, "their forces are damped least squares with damping μ, "
                                 "F = −s / (s² + μ²) uᵀ r: the contacts are not held exactly there "
                                 "(residual ≤ ‖J_c M⁻¹ h + J̇_c u‖)")
    Minv_h = c.Minv(h)
    F = -c.U @ (c.weight * (c.U.T @ (J @ Minv_h + Jdot_u)))
    return Minv_h + c.Minv(J.T @ F), F


def support_projector(M, J, names) -> np.ndarray:
    """N_c = 1 − M⁻¹ J_cᵀ (J_c M⁻¹ J_cᵀ)⁺ J_c = L⁻ᵀ (1 − V_r V_rᵀ) Lᵀ (V_r: the rank's right singular
    vectors), a projector even near a singularity."""
    c = contact_set(M, J, names, "N_c removes them exactly, but they turn fast with q (by about √κ times "
                                 "a relative change of J_c)")
    V = c.Vt[:c.rank].T
    P = np.eye(M.shape[0]) - V @ V.T
    return np.linalg.solve(c.L.T, P @ c.L.T)
