"""Clamped-free modes of a flexible link's own finite-element beam (modal reduction). Over its n elements
(`model.beam`'s integrals), node 1 clamped, the nodal mass and stiffness matrices are

    M_nn = Σ_e m ∫ N Nᵀ,    K_nn = Σ_e E I ∫ N'' N''ᵀ,

and the modes solve K φ = ω² M φ: Φ = [φ_1 … φ_k], mass-normalised (Φᵀ M Φ = 1, Φᵀ K Φ = diag ω²),
ascending ω, each signed so that its tip deflection is positive. The nodal vector is then d = Φ η."""
from __future__ import annotations

import numpy as np
import scipy.linalg as sla
import sympy as sp

from .beam import integrals


def nodal_matrices(length, mass_per_length, EI, elements: int) -> tuple[np.ndarray, np.ndarray]:
    """(M_nn, K_nn), 2n × 2n, of the nodes 2 … n+1 (deflection, slope of each)."""
    h = sp.sympify(length) / elements
    size = 2 * elements + 2
    M, K = np.zeros((size, size)), np.zeros((size, size))
    element = integrals(h)
    for e in range(elements):
        block = slice(2 * e, 2 * e + 4)
        M[block, block] += np.array(element["NN"], dtype=float)
        K[block, block] += np.array(element["K"], dtype=float)
    return float(mass_per_length) * M[2:, 2:], float(EI) * K[2:, 2:]


def clamped_modes(length, mass_per_length, EI, elements: int, k: int) -> tuple[np.ndarray, np.ndarray]:
    """(Φ, ω): the first k mass-normalised modes as the columns of Φ (2n × k), and their frequencies."""
    M, K = nodal_matrices(length, mass_per_length, EI, elements)
    omega2, Phi = sla.eigh(K, M, subset_by_index=(0, k - 1))
    return Phi * np.where(Phi[-2] < 0, -1.0, 1.0), np.sqrt(omega2)
