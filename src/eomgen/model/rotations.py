"""Rotations of the joints with several angles: unit quaternions (Pinocchio's and Eigen's layout,
(x, y, z, w), scalar last) and ZYX Euler angles R = Rz(ψ) Ry(θ) Rx(φ)."""

from __future__ import annotations

import sympy as sp

from .joints import rotation_about

E = sp.eye(3)


def quaternion_rotation(x, y, z, w) -> sp.Matrix:
    """R(q) of a unit quaternion as Eigen computes it."""
    return sp.Matrix(
        [
            [1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
            [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
            [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)],
        ]
    )


def quaternion_rate(x, y, z, w, omega) -> list[sp.Expr]:
    """(ẋ, ẏ, ż, ẇ) = ½ q ⊗ (ω, 0), ω in the rotated (body) axes."""
    wx, wy, wz = omega
    half = sp.Rational(1, 2)
    return [
        half * (w * wx - z * wy + y * wz),
        half * (z * wx + w * wy - x * wz),
        half * (-y * wx + x * wy + w * wz),
        half * (-x * wx - y * wy - z * wz),
    ]


def zyx_rotation(yaw, pitch, roll) -> sp.Matrix:
    """Rz(ψ) Ry(θ) Rx(φ)."""
    return rotation_about(E[:, 2], yaw) * rotation_about(E[:, 1], pitch) * rotation_about(E[:, 0], roll)


def zyx_axes(yaw, pitch) -> list[sp.Matrix]:
    """Axes of ψ̇, θ̇, φ̇ in the unrotated frame: ω = ψ̇ e_z + θ̇ Rz e_y + φ̇ Rz Ry e_x."""
    Rz = rotation_about(E[:, 2], yaw)
    return [E[:, 2], Rz[:, 1], (Rz * rotation_about(E[:, 1], pitch))[:, 0]]


def zyx_body_axes(pitch, roll) -> list[sp.Matrix]:
    """The same axes in the rotated frame (Pinocchio's S of JointModelSphericalZYX):
    (Rx Ry)ᵀ e_z, Rxᵀ e_y, e_x."""
    Rx, Ry = rotation_about(E[:, 0], roll), rotation_about(E[:, 1], pitch)
    return [(Rx.T * Ry.T)[:, 2], Rx.T[:, 1], E[:, 0]]
