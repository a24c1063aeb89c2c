"""Numeric states of a system: random valid states, and q integrated with u on the configuration
manifold (the quaternion of a free-flyer base stays a unit quaternion)."""
from __future__ import annotations

import numpy as np

from .errors import ModelError
from .model import FreeFlyer, Revolute, System


def random_states(system: System, n: int, rng) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """n states (q, u, u̇): revolute angles in [−π, π], prismatic in [−0.5, 0.5], a free-flyer base in
    [−1, 1]³ with a uniformly random orientation (Euler base: pitch within ±0.45 π), u and u̇ in [−2, 2]."""
    if not isinstance(n, int) or isinstance(n, bool) or n < 0:
        raise ModelError(f"random_states: n must be a non-negative integer, got {n!r}")
    parts = []
    for j in system.joints:
        if isinstance(j, FreeFlyer) and j.parametrization == "euler":
            parts += [rng.uniform(-1, 1, (n, 3)), rng.uniform(-np.pi, np.pi, (n, 3)) * [1, 0.45, 1]]
        elif isinstance(j, FreeFlyer):
            quat = rng.normal(size=(n, 4))
            parts += [rng.uniform(-1, 1, (n, 3)), quat / np.linalg.norm(quat, axis=1, keepdims=True)]
        else:
            parts.append(rng.uniform(-1, 1, (n, 1)) * (np.pi if isinstance(j, Revolute) else 0.5))
    q = np.concatenate(parts, axis=1)
    return q, rng.uniform(-2, 2, (n, system.nv)), rng.uniform(-2, 2, (n, system.nv))


def _skew(w: np.ndarray) -> np.ndarray:
    return np.array([[0, -w[2], w[1]], [w[2], 0, -w[0]], [-w[1], w[0], 0]])


def _quaternion_rotation(x, y, z, w) -> np.ndarray:
    return np.array([[1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
                     [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
                     [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)]])


def integrate(system: System, q, u, dt: float) -> np.ndarray:
    """q ⊕ u dt: joints q + u dt; a quaternion base moves along the exponential of its body twist,
    p ← p + R V(ω dt) v dt and q ← q ⊗ exp(ω dt / 2), with V = 1 + (1 − cos θ)/θ² [w]× + (θ − sin θ)/θ³ [w]×²."""
    q, u = np.asarray(q, float).copy(), np.asarray(u, float)
    for b in system.bodies:
        if b.index is None:
            continue
        j, k, i = b.joint, b.q_index, b.index
        if isinstance(j, FreeFlyer) and j.parametrization == "quaternion":
            v, w = u[i:i + 3] * dt, u[i + 3:i + 6] * dt
            theta = np.linalg.norm(w)
            W = _skew(w)
            if theta < 1e-8:
                V, half = np.eye(3) + W / 2, np.r_[w / 2, 1.0]
            else:
                V = np.eye(3) + (1 - np.cos(theta)) / theta**2 * W + (theta - np.sin(theta)) / theta**3 * W @ W
                half = np.r_[np.sin(theta / 2) * w / theta, np.cos(theta / 2)]
            x, y, z, s = q[k + 3:k + 7]
            q[k:k + 3] += _quaternion_rotation(x, y, z, s) @ V @ v
            a, c = np.array([x, y, z]), half[:3]  # quaternion product (a, s) ⊗ (c, d)
            q[k + 3:k + 7] = np.r_[s * c + half[3] * a + np.cross(a, c), s * half[3] - a @ c]
        else:
            q[k:k + j.dof] += u[i:i + j.dof] * dt
    return q
