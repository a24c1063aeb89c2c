"""Contact dynamics, numerically (the inversions are never symbolic).

With M u̇ + b + g = Sᵀ τ + τ_loads + J_cᵀ F_c and the contacts held, J_c u̇ + J̇_c u = 0:

    F_c = −(J_c M⁻¹ J_cᵀ)⁻¹ (J_c M⁻¹ h + J̇_c u),   h = Sᵀ τ + τ_loads − b − g,
    u̇ = M⁻¹ (h + J_cᵀ F_c),
    N_c = 1 − M⁻¹ J_cᵀ (J_c M⁻¹ J_cᵀ)⁻¹ J_c,   J_c N_c = 0,   N_cᵀ (M u̇ + b + g) = N_cᵀ (Sᵀ τ + τ_loads).

F_c is the force the environment exerts on the robot (world-aligned axes). A rank-deficient contact set
(redundant constraints) gets the least-squares (minimum-norm) solution and a warning naming the rows
that add nothing."""
from __future__ import annotations

import warnings

import numpy as np


def row_names(contacts) -> list[str]:
    names = []
    for c in contacts:
        names += [f"{c.frame}.{axis}" for axis in ("x", "y", "z", "rx", "ry", "rz")[:c.rows]]
    return names


def redundant_rows(A: np.ndarray, tol: float = 1e-10) -> list[int]:
    """Rows of a constraint matrix that are linear combinations of the rows before them."""
    kept, redundant = np.zeros((0, A.shape[1])), []
    scale = max(1.0, np.abs(A).max())
    for i, row in enumerate(A):
        trial = np.vstack([kept, row])
        if np.linalg.matrix_rank(trial, tol=tol * scale) > len(kept):
            kept = trial
        else:
            redundant.append(i)
    return redundant


def inverse(A: np.ndarray, J: np.ndarray, names: list[str]) -> np.ndarray:
    """A⁻¹ for A = J M⁻¹ Jᵀ, or its pseudo-inverse with a warning when the contacts are redundant."""
    redundant = redundant_rows(J)
    if not redundant:
        return np.linalg.inv(A)
    warnings.warn(f"rank-deficient contact set: {[names[i] for i in redundant]} repeat other constraints; "
                  "using the minimum-norm (least-squares) contact forces", stacklevel=3)
    return np.linalg.pinv(A, rcond=1e-12, hermitian=True)


def contact_dynamics(M, h, J, Jdot_u, names) -> tuple[np.ndarray, np.ndarray]:
    """(u̇, F_c) of the constrained system."""
    Minv_JT = np.linalg.solve(M, J.T)
    Minv_h = np.linalg.solve(M, h)
    F = -inverse(J @ Minv_JT, J, names) @ (J @ Minv_h + Jdot_u)
    return Minv_h + Minv_JT @ F, F


def support_projector(M, J, names) -> np.ndarray:
    """N_c = 1 − M⁻¹ J_cᵀ (J_c M⁻¹ J_cᵀ)⁻¹ J_c."""
    Minv_JT = np.linalg.solve(M, J.T)
    return np.eye(M.shape[0]) - Minv_JT @ inverse(J @ Minv_JT, J, names) @ J
