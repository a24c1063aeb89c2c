"""Clamped-free modes of a flexible link's own finite-element beam (modal reduction). Over its n elements
(`model.beam`'s integrals), node 1 clamped, the nodal mass and stiffness matrices are

    M_nn = Σ_e m ∫ N Nᵀ,    K_nn = Σ_e E I ∫ N'' N''ᵀ,

and the modes solve K φ = ω² M φ: Φ = [φ_1 … φ_k], mass-normalised (Φᵀ M Φ = 1, Φᵀ K Φ = diag ω²),
ascending ω, each signed so that its tip deflection (or twist) is positive. The nodal vector is then d = Φ η.
The twist of a 3D link the same way from its linear elements (ρI_x, GJ)."""
from __future__ import annotations

import numpy as np
import sympy as sp

from .beam import integrals, twist_integrals


def nodal_matrices(length, inertia, stiffness, elements: int, dofs: int = 2,
                   rotary=0.0) -> tuple[np.ndarray, np.ndarray]:
    """(M_nn, K_nn) of the nodes 2 … n+1: bending (dofs = 2, deflection and slope of each node; inertia
    m, stiffness E I, and the sections' rotary inertia ρI about the bending axis: M_nn gains ρI ∫ N' N'ᵀ)
    or twist (dofs = 1, linear elements; inertia ρI_x, stiffness GJ)."""
    h = sp.sympify(length) / elements
    element = integrals(h) if dofs == 2 else twist_integrals(h)
    size = dofs * (elements + 1)
    M, K = np.zeros((size, size)), np.zeros((size, size))
    for e in range(elements):
        block = slice(dofs * e, dofs * e + 2 * dofs)
        M[block, block] += float(inertia) * np.array(element["NN"], dtype=float)
        if float(rotary):
            M[block, block] += float(rotary) * np.array(element["G"], dtype=float)
        K[block, block] += np.array(element["K"], dtype=float)
    return M[dofs:, dofs:], float(stiffness) * K[dofs:, dofs:]


def clamped_modes(length, inertia, stiffness, elements: int, k: int, dofs: int = 2,
                  rotary=0.0) -> tuple[np.ndarray, np.ndarray]:
    """(Φ, ω): the first k mass-normalised modes as the columns of Φ (dofs · n × k), and their frequencies."""
    M, K = nodal_matrices(length, inertia, stiffness, elements, dofs, rotary)
    import scipy.linalg

    omega2, Phi = scipy.linalg.eigh(K, M, subset_by_index=(0, k - 1))
    return Phi * np.where(Phi[-dofs] < 0, -1.0, 1.0), np.sqrt(omega2)
