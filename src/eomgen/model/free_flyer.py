"""A free-flying joint: six degrees of freedom, for the base of a floating robot."""

from __future__ import annotations

import sympy as sp

from ..errors import ModelError
from ..linalg import cross
from ..symbols import Generated
from .joints import Several, zero
from .rotations import E, quaternion_rate, quaternion_rotation, zyx_axes, zyx_body_axes, zyx_rotation


class FreeFlyer(Several):
    """A free-flying joint (the root body of a floating robot).

    parametrization "quaternion" (Pinocchio's layout): q = [x, y, z, qx, qy, qz, qw] (scalar last),
    u = [v, ω], the twist of the child in its own axes, q̇ = E(q) u with ṗ = R v and the quaternion rate
    ½ q ⊗ (ω, 0). parametrization "euler": q = [x, y, z, ψ, θ, φ] (ZYX: R = Rz(ψ) Ry(θ) Rx(φ)) and
    u = q̇; singular at pitch θ = ±90°, where ω no longer determines the angle rates."""

    def __init__(self, name: str = "root_joint", parametrization: str = "quaternion") -> None:
        if parametrization not in ("quaternion", "euler"):
            raise ModelError(
                f"joint '{name}': parametrization must be 'quaternion' or 'euler', got {parametrization!r}"
            )
        self.parametrization = parametrization
        if parametrization == "quaternion":
            super().__init__(
                name,
                ("x", "y", "z", "qx", "qy", "qz", "qw"),
                ("vx", "vy", "vz", "wx", "wy", "wz"),
                actuated=False,
            )
            self.group = "SE3"
        else:
            super().__init__(name, ("x", "y", "z", "yaw", "pitch", "roll"), actuated=False)
            self.pitch_index = 4

    @property
    def accelerations(self):
        return [Generated(f"{s.name}dot", ("dot", s)) for s in self._u]

    def rotation(self) -> sp.Matrix:
        """R(q): of the unit quaternion, or Rz(ψ) Ry(θ) Rx(φ)."""
        if self.parametrization == "euler":
            return zyx_rotation(*self._q[3:])
        return quaternion_rotation(*self._q[3:])

    def motion(self):
        return self.rotation(), sp.Matrix(self._q[:3])

    def subspace(self):
        """Quaternion: the identity (u is the child's twist). Euler: translation rates along the joint
        axes, Rᵀ e_k in child axes, and the angle rates' axes."""
        if self.parametrization == "quaternion":
            return [(E[:, k], zero()) for k in range(3)] + [(zero(), E[:, k]) for k in range(3)]
        R = self.rotation()
        return [(R.T[:, k], zero()) for k in range(3)] + [(zero(), w) for w in zyx_body_axes(*self._q[4:])]

    def joint_frame_subspace(self):
        if self.parametrization == "quaternion":
            return None
        return [(E[:, k], zero()) for k in range(3)] + [(zero(), w) for w in zyx_axes(*self._q[3:5])]

    def reaction_basis(self):
        return sp.zeros(6, 0)

    def hamel(self, u, p):
        """Kirchhoff's terms of a body twist: (ω × p_v, ω × p_ω + v × p_v); none for Euler rates."""
        if self.parametrization == "euler":
            return None
        v, w, p_v, p_w = (sp.Matrix(x[a : a + 3]) for x, a in ((u, 0), (u, 3), (p, 0), (p, 3)))
        return list(cross(w, p_v).col_join(cross(w, p_w) + cross(v, p_v)))

    def qdot(self) -> list[sp.Expr]:
        """Euler: q̇ = u. Quaternion: ṗ = R v, (ẋ, ẏ, ż, ẇ) of the quaternion = ½ q ⊗ (ω, 0)."""
        if self.parametrization == "euler":
            return self.speeds
        v = sp.Matrix(self._u[:3])
        return list(self.rotation() * v) + quaternion_rate(*self._q[3:], self._u[3:])

    def __repr__(self) -> str:
        return f"FreeFlyer({self.name!r}, parametrization={self.parametrization!r})"
