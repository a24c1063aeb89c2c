"""The spherical (ball) joint: three rotations about the joint origin."""

from __future__ import annotations

import sympy as sp

from ..errors import ModelError
from .joints import Several, wrench_basis, zero
from .rotations import E, quaternion_rate, quaternion_rotation, zyx_axes, zyx_body_axes, zyx_rotation


class Spherical(Several):
    """A ball joint.

    parametrization "quaternion" (Pinocchio's JointModelSpherical): q = (qx, qy, qz, qw), a unit
    quaternion, and u = ω, the child's angular velocity in child axes; q̇ = ½ q ⊗ (ω, 0), integrated on
    SO(3). parametrization "zyx" (JointModelSphericalZYX): q = (ψ, θ, φ), R = Rz(ψ) Ry(θ) Rx(φ), u = q̇;
    singular at θ = ±90°."""

    def __init__(
        self, name: str, parametrization: str = "quaternion", *, actuated: bool = True, armature=0
    ) -> None:
        if parametrization not in ("quaternion", "zyx"):
            raise ModelError(
                f"joint '{name}': parametrization must be 'quaternion' or 'zyx', got {parametrization!r}"
            )
        self.parametrization = parametrization
        if parametrization == "quaternion":
            super().__init__(
                name, ("qx", "qy", "qz", "qw"), ("wx", "wy", "wz"), actuated=actuated, armature=armature
            )
            self.group = "SO3"
        else:
            super().__init__(name, ("yaw", "pitch", "roll"), actuated=actuated, armature=armature)
            self.pitch_index = 1

    def motion(self):
        R = (
            quaternion_rotation(*self._q)
            if self.parametrization == "quaternion"
            else zyx_rotation(*self._q)
        )
        return R, zero()

    def subspace(self):
        """Quaternion: S = (0, I). ZYX: the angle rates' axes in child axes."""
        axes = (
            [E[:, k] for k in range(3)]
            if self.parametrization == "quaternion"
            else zyx_body_axes(*self._q[1:])
        )
        return [(zero(), w) for w in axes]

    def joint_frame_subspace(self):
        return (
            None if self.parametrization == "quaternion" else [(zero(), w) for w in zyx_axes(*self._q[:2])]
        )

    def qdot(self):
        return self.speeds if self.parametrization == "zyx" else quaternion_rate(*self._q, self._u)

    def hamel(self, u, p):
        """Euler's term ω × p_ω of the angular velocity in child axes; none for angle rates."""
        if self.parametrization == "zyx":
            return None
        return list(sp.Matrix(u).cross(sp.Matrix(p)))

    def reaction_basis(self):
        return wrench_basis(sp.eye(3), sp.zeros(3, 0))

    def __repr__(self) -> str:
        return f"Spherical({self.name!r}, parametrization={self.parametrization!r})"
