"""Numeric states of a system: random valid states, and q integrated with u on the configuration
manifold of each joint (`Joint.group`): unit quaternions stay unit quaternions."""
from __future__ import annotations

import numpy as np

from .errors import ModelError
from .model import Cylindrical, FlexibleLink, Planar, Prismatic, System, Translation


def random_states(system: System, n: int, rng) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """n states (q, u, u̇): angles in [−π, π] (ZYX pitch within ±0.45 π), lengths in [−0.5, 0.5] (a free
    flyer's and a planar joint's position in [−1, 1], a flexible link's nodes in [−0.05, 0.05]),
    uniformly random unit quaternions, u and u̇ in [−2, 2]."""
    if not isinstance(n, int) or isinstance(n, bool) or n < 0:
        raise ModelError(f"random_states: n must be a non-negative integer, got {n!r}")
    parts = []
    for j in system.joints:
        for label in _kinds(j):
            if label == "quaternion":
                quat = rng.normal(size=(n, 4))
                parts.append(quat / np.linalg.norm(quat, axis=1, keepdims=True))
            else:
                scale = {"angle": np.pi, "pitch": 0.45 * np.pi, "length": 0.5, "position": 1.0,
                         "deflection": 0.05}[label]
                parts.append(rng.uniform(-1, 1, (n, 1)) * scale)
    q = np.concatenate(parts, axis=1) if parts else np.zeros((n, 0))
    return q, rng.uniform(-2, 2, (n, system.nv)), rng.uniform(-2, 2, (n, system.nv))


def _kinds(joint) -> list[str]:
    """What each coordinate of a joint is: "angle", "pitch", "length", "position", "deflection" (a
    flexible link's node, and its slope) or (4 of them) "quaternion"."""
    if joint.group in ("SO3", "SE3"):
        return ["position"] * 3 * (joint.group == "SE3") + ["quaternion"]
    if joint.pitch_index is not None:  # ZYX angles, after the free flyer's position
        return ["position"] * (joint.pitch_index - 1) + ["angle", "pitch", "angle"]
    if isinstance(joint, Planar):
        return ["position", "position", "angle"]
    if isinstance(joint, (Prismatic, Translation)):
        return ["length"] * len(joint.coordinates)
    if isinstance(joint, Cylindrical):
        return ["length", "angle"]
    if isinstance(joint, FlexibleLink):
        return ["angle"] + ["deflection"] * (len(joint.coordinates) - 1)
    return ["angle"] * len(joint.coordinates)  # revolute, helical, universal


def _skew(w: np.ndarray) -> np.ndarray:
    return np.array([[0, -w[2], w[1]], [w[2], 0, -w[0]], [-w[1], w[0], 0]])


def _quaternion_rotation(x, y, z, w) -> np.ndarray:
    return np.array([[1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
                     [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
                     [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)]])


def _exp_so3(w: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(V, half-angle quaternion) of a rotation vector w: exp([w]×) = q(w), and
    V = 1 + (1 − cos θ)/θ² [w]× + (θ − sin θ)/θ³ [w]×², the left Jacobian that carries a body velocity."""
    theta = np.linalg.norm(w)
    W = _skew(w)
    if theta < 1e-8:
        return np.eye(3) + W / 2, np.r_[w / 2, 1.0]
    a = 2 * np.sin(theta / 2) ** 2 / theta**2  # (1 − cos θ)/θ² without cancellation
    t2 = theta**2  # (θ − sin θ)/θ³ by its series where the difference cancels
    c = (1 / 6 - t2 / 120 + t2**2 / 5040) if theta < 1e-2 else (theta - np.sin(theta)) / theta**3
    return np.eye(3) + a * W + c * W @ W, np.r_[np.sin(theta / 2) * w / theta, np.cos(theta / 2)]


def _turn(quat: np.ndarray, half: np.ndarray) -> np.ndarray:
    """The quaternion product quat ⊗ half (scalar last)."""
    a, s, c, d = quat[:3], quat[3], half[:3], half[3]
    return np.r_[s * c + d * a + np.cross(a, c), s * d - a @ c]


def integrate(system: System, q, u, dt: float) -> np.ndarray:
    """q ⊕ u dt, as pinocchio.integrate: vector joints q + u dt; a body twist (free flyer, ball joint,
    planar joint) moves along its exponential, p ← p + R V(ω dt) v dt and R ← R exp(ω dt)."""
    q, u = np.asarray(q, float).copy(), np.asarray(u, float)
    for b in system.bodies:
        if b.index is None:
            continue
        j, k, i = b.joint, b.q_index, b.index
        if j.group == "SE3":
            V, half = _exp_so3(u[i + 3:i + 6] * dt)
            q[k:k + 3] += _quaternion_rotation(*q[k + 3:k + 7]) @ V @ (u[i:i + 3] * dt)
            q[k + 3:k + 7] = _turn(q[k + 3:k + 7], half)
        elif j.group == "SO3":
            q[k:k + 4] = _turn(q[k:k + 4], _exp_so3(u[i:i + 3] * dt)[1])
        elif j.group == "SE2":
            V, _ = _exp_so3(np.r_[0.0, 0.0, u[i + 2] * dt])
            c, s = np.cos(q[k + 2]), np.sin(q[k + 2])
            q[k:k + 2] += (np.array([[c, -s], [s, c]]) @ V[:2, :2] @ (u[i:i + 2] * dt))
            q[k + 2] += u[i + 2] * dt
        else:
            q[k:k + j.dof] += u[i:i + j.dof] * dt
    return q


def unit_quaternions(system: System, q) -> np.ndarray:
    """q (one state, or states along the last axis) with each quaternion (free flyer, ball joint) divided
    by its norm: R(q) is a rotation only for unit quaternions."""
    q = np.array(q, dtype=float)
    for b in system.bodies:
        if b.index is not None and b.joint.group in ("SO3", "SE3"):
            k = b.q_index + 3 * (b.joint.group == "SE3")
            q[..., k:k + 4] /= np.linalg.norm(q[..., k:k + 4], axis=-1, keepdims=True)
    return q
