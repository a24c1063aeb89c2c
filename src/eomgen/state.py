"""Numeric states of a system: random valid states, q integrated with u on the configuration manifold
of each joint (`Joint.group`; unit quaternions stay unit quaternions), and the difference of two
configurations, the u that integrate carries from one to the other."""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .errors import ModelError
from .model import Cylindrical, FlexibleLink, Planar, Prismatic, System, Translation


SCALES = {"angle": np.pi, "pitch": 0.45 * np.pi, "length": 0.5, "position": 1.0, "deflection": 0.05}


@dataclass(frozen=True)
class Layout:
    """What `random_states` draws for a system: nq, nv, and q's columns as runs, each (start, stop, scales)
    of uniform columns (scales: their half-widths, a column vector) or (start, start + 4, None), a
    quaternion. Made once by `layout(system)`, so that many calls (a sweep's slices) pay it once."""

    nq: int
    nv: int
    runs: tuple

    def fill(self, n: int, rng, out: tuple | None = None) -> tuple[np.ndarray, ...]:
        """See `random_states`: q's runs drawn one after the other, each uniform run column by column."""
        q, *speeds = out if out is not None else (np.empty((n, self.nq)), np.empty((n, self.nv)),
                                                   np.empty((n, self.nv)))
        drawn = np.empty((self.nq, n))  # q transposed: each column's draws contiguous
        for start, stop, scales in self.runs:
            if scales is None:
                quat = rng.standard_normal(out=drawn[start:stop].reshape(n, 4))
                drawn[start:stop] = (quat / np.linalg.norm(quat, axis=1, keepdims=True)).T
            else:  # uniform(−1, 1) = 2 r − 1 in numpy's own operations, then scaled
                x = rng.random(out=drawn[start:stop])
                x *= 2
                x -= 1
                x *= scales
        q[...] = drawn.T
        for v in speeds:  # uniform(−2, 2) = 4 r − 2
            rng.random(out=v)
            v *= 4
            v -= 2
        return (q, *speeds)


def layout(system: System) -> Layout:
    """The `Layout` of a system's coordinates (`_scales` of each joint, a quaternion's 4 columns one run,
    runs of uniform columns merged)."""
    labels = [scale for j in system.joints for scale in _scales(j)
              for _ in range(4 if scale is None else 1)]  # None: a quaternion's column
    runs, k = [], 0
    while k < len(labels):
        if labels[k] is None:
            runs.append((k, k + 4, None))
            k += 4
            continue
        stop = next((i for i in range(k, len(labels)) if labels[i] is None), len(labels))
        runs.append((k, stop, np.array([[scale] for scale in labels[k:stop]])))
        k = stop
    return Layout(len(labels), system.nv, tuple(runs))


def random_states(system: System | Layout, n: int, rng, out: tuple | None = None) -> tuple[np.ndarray, ...]:
    """n states (q, u, u̇): angles in [−π, π] (ZYX pitch within ±0.45 π), lengths in [−0.5, 0.5] (a free
    flyer's and a planar joint's position in [−1, 1], a flexible link's nodes in [−0.05, 0.05], its modal
    amplitudes as `_scales` says), uniformly random unit quaternions, u and u̇ in [−2, 2]. With `out`,
    arrays (q,), (q, u) or (q, u, u̇) (C-contiguous float64, n rows) are filled and returned instead: the
    same values as the first arrays of a whole call with the same generator (the draws in the same order:
    q's column by column, then u, u̇). `system` may be its `layout(system)`, made once for many calls."""
    if not isinstance(n, int) or isinstance(n, bool) or n < 0:
        raise ModelError(f"random_states: n must be a non-negative integer, got {n!r}")
    if out is not None and not (isinstance(out, tuple) and 1 <= len(out) <= 3):
        raise ModelError(f"random_states: out must be a tuple (q,), (q, u) or (q, u, ud), got {out!r}")
    plan = system if isinstance(system, Layout) else layout(system)
    for name, x, width in zip(("q", "u", "ud"), out or (), (plan.nq, plan.nv, plan.nv)):
        if not isinstance(x, np.ndarray) or x.dtype != np.float64 or x.shape != (n, width) \
                or not x.flags.c_contiguous or not x.flags.writeable:
            raise ModelError(f"random_states: out's {name} must be a writeable C-contiguous float64 array of "
                             f"shape ({n}, {width}), got {getattr(x, 'shape', type(x).__name__)}")
    return plan.fill(n, rng, out)


def _scales(joint) -> list[float | None]:
    """The half-width of each coordinate's draws, `SCALES` of its kind (a quaternion: None). A flexible link's
    modal amplitude η_k (mass-normalised: η = 1 deflects the tip by about 2/√(m L)) gets 0.05 / max_i |Φ_ik|,
    so that its mode alone moves no node's deflection or slope by more than a nodal coordinate's 0.05."""
    scales = [None if kind == "quaternion" else SCALES[kind] for kind in _kinds(joint)]
    if isinstance(joint, FlexibleLink) and joint.shapes is not None:
        scales[-len(joint.nodal):] = SCALES["deflection"] / np.abs(joint.shapes).max(axis=0)
    return scales


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
        return ["angle"] * (joint.q is not None) + ["deflection"] * len(joint.nodal)
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


def _log_so3(quat: np.ndarray) -> np.ndarray:
    """The rotation vector ω of a quaternion (x, y, z, w) on the shorter path (w ≥ 0):
    ω = 2 atan2(|v|, w) v/|v|, accurate near the identity (→ 2 v/w) and near a half turn (w → 0)."""
    v, w = (quat[:3], quat[3]) if quat[3] >= 0 else (-quat[:3], -quat[3])
    s = np.linalg.norm(v)
    return (2 * np.arctan2(s, w) / s if s > 0 else 2 / w) * v


def _inverse_left_jacobian(w: np.ndarray) -> np.ndarray:
    """V(ω)⁻¹ = 1 − ½ [ω]× + (1 − (θ/2) cot(θ/2))/θ² [ω]×² for |ω| = θ ≤ π (series where it cancels)."""
    t2 = w @ w
    W = _skew(w)
    if t2 < 1e-4:
        c = 1 / 12 + t2 / 720 + t2**2 / 30240
    else:
        half = np.sqrt(t2) / 2
        c = (1 - half * np.cos(half) / np.sin(half)) / t2
    return np.eye(3) - W / 2 + c * W @ W


def difference(system: System, q0, q1) -> np.ndarray:
    """q1 ⊖ q0, the u with integrate(system, q0, u, 1) = q1, as pinocchio.difference (one state):
    vector joints q1 − q0; a ball joint ω = log(R0ᵀ R1); a free flyer Pinocchio's log6 of M0⁻¹ M1,
    ω = log(R0ᵀ R1), v = V(ω)⁻¹ R0ᵀ (p1 − p0); a planar joint the same in the plane with the angle
    θ1 − θ0 taken within ±π (integrate then returns q1's pose, its angle up to 2π), as the rotations take
    the shorter path (q1's quaternion up to sign)."""
    if not isinstance(system, System):
        raise ModelError(f"difference: expected a System, got {type(system).__name__}")
    q0, q1 = (_configuration(system, q, name) for q, name in ((q0, "q0"), (q1, "q1")))
    u = np.zeros(system.nv)
    for b in system.bodies:
        if b.index is None:
            continue
        j, k, i = b.joint, b.q_index, b.index
        if j.group in ("SO3", "SE3"):
            r = k + 3 * (j.group == "SE3")
            quat = _turn(q0[r:r + 4] * [-1, -1, -1, 1], q1[r:r + 4])  # q0⁻¹ ⊗ q1
            w = _log_so3(quat)
            if j.group == "SE3":
                R0 = _quaternion_rotation(*q0[r:r + 4])
                u[i:i + 3] = _inverse_left_jacobian(w) @ R0.T @ (q1[k:k + 3] - q0[k:k + 3])
                i += 3
            u[i:i + 3] = w
        elif j.group == "SE2":
            w = q1[k + 2] - q0[k + 2]
            w -= 2 * np.pi * np.round(w / (2 * np.pi))
            c, s = np.cos(q0[k + 2]), np.sin(q0[k + 2])
            d = np.array([[c, s], [-s, c]]) @ (q1[k:k + 2] - q0[k:k + 2])
            u[i:i + 3] = np.r_[_inverse_left_jacobian(np.r_[0.0, 0.0, w])[:2, :2] @ d, w]
        else:
            u[i:i + j.dof] = q1[k:k + j.dof] - q0[k:k + j.dof]
    return u


def _configuration(system: System, q, name: str) -> np.ndarray:
    """One configuration (nq,) of finite numbers, its quaternions made unit."""
    try:
        q = np.asarray(q, dtype=float)
    except (TypeError, ValueError):
        raise ModelError(f"difference: {name} must be an array of numbers, got {type(q).__name__}") from None
    if q.shape != (system.nq,):
        raise ModelError(f"difference: {name} must have shape ({system.nq},) (one configuration), "
                         f"got {q.shape}")
    with np.errstate(invalid="ignore", divide="ignore"):
        q = unit_quaternions(system, q)
    if not np.isfinite(q).all():
        raise ModelError(f"difference: {name} has non-finite entries or a zero quaternion")
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
