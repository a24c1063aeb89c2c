"""A body's pseudo-inertia (Wensing, Kim, Slotine 2017): its ten parameters, in Pinocchio's order
π = [m, h_x, h_y, h_z, I_xx, I_xy, I_yy, I_xz, I_yz, I_zz] (h = m c, I about the body frame's origin),
as the second moments of its mass distribution,

    J = [[Σ, h], [hᵀ, m]],    Σ = ∫ x xᵀ dm = ½ tr(I) 1 − I.

A mass distribution with these parameters exists (they are realisable) if and only if J ⪰ 0."""
from __future__ import annotations

import numpy as np

from ..errors import ModelError

PER_BODY = 10


def inertia(pi: np.ndarray):
    """I about the origin, symmetric 3 × 3, from a body's ten parameters (numbers or cvxpy terms)."""
    _, _, _, _, xx, xy, yy, xz, yz, zz = (pi[k] for k in range(PER_BODY))
    return [[xx, xy, xz], [xy, yy, yz], [xz, yz, zz]]


def pseudo_inertia(pi) -> np.ndarray:
    """J (4 × 4) of a body's ten parameters."""
    pi = np.asarray(pi, dtype=float)
    if pi.shape != (PER_BODY,):
        raise ModelError(f"pseudo_inertia: a body has {PER_BODY} parameters, got shape {pi.shape}")
    inner = np.array(inertia(pi))
    J = np.empty((4, 4))
    J[:3, :3] = 0.5 * np.trace(inner) * np.eye(3) - inner
    J[:3, 3] = J[3, :3] = pi[1:4]
    J[3, 3] = pi[0]
    return J


def smallest_eigenvalues(pi, bodies: int) -> np.ndarray:
    """The smallest eigenvalue of each of the first `bodies` bodies' J (≥ 0: realisable)."""
    pi = np.asarray(pi, dtype=float)
    if bodies < 0 or pi.ndim != 1 or len(pi) < PER_BODY * bodies:
        raise ModelError(f"argument 'bodies' ({bodies}) needs {PER_BODY * bodies} parameters, got "
                         f"shape {pi.shape}")
    return np.array([np.linalg.eigvalsh(pseudo_inertia(pi[PER_BODY * k: PER_BODY * (k + 1)]))[0]
                     for k in range(bodies)])
