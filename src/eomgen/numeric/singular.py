"""A singular mass matrix refused by naming what it cannot accelerate.

M u̇ = h has no unique u̇ where M v = 0 for some v ≠ 0: the motion along v moves no mass and no inertia
(the usual cause: a massless leaf body on its own joint). v is an eigenvector of the symmetric M whose
eigenvalue is zero relative to the largest; the joints with a part in v are named, with their bodies."""
from __future__ import annotations

import numpy as np

from ..errors import ModelError
from ..model import System

RTOL = 1e-12  # an eigenvalue below RTOL · max |eigenvalue| counts as zero


def singular_mass_matrix(system: System, M: np.ndarray, where: str) -> ModelError:
    """The error for a singular M (one state, or a batch: the most singular state is named)."""
    batch = np.asarray(M, dtype=float).reshape(-1, system.nv, system.nv)
    if not np.isfinite(batch).all():
        return ModelError(f"{where}: the mass matrix is not finite at this state (check q and params)")
    w, V = np.linalg.eigh(batch)
    scale = np.maximum(np.abs(w).max(axis=-1), np.finfo(float).tiny)
    k = int(np.argmin(w[:, 0] / scale))
    null = V[k][:, w[k] <= RTOL * scale[k]] if w[k, 0] <= RTOL * scale[k] else V[k][:, :1]
    speeds = set(np.flatnonzero(np.abs(null).max(axis=1) > 1e-8).tolist())
    names = [f"joint '{b.joint.name}' (body '{b.name}')" for b in system.bodies
             if b.index is not None and speeds & set(range(b.index, b.index + b.joint.dof))]
    state = f" at state {k} of the batch" if len(batch) > 1 else ""
    return ModelError(f"{where}: the mass matrix is singular{state}: no mass or inertia moves along the "
                      f"speeds of {', '.join(names)}; give the body moved by that joint (or one it carries) "
                      "a mass and an inertia along its motion, or make the joint Fixed")
