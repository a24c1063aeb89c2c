"""Joints of several axes: universal, planar, cylindrical, translation, and the helical joint."""

from __future__ import annotations

import sympy as sp

from ..errors import ModelError
from .joints import Joint, Several, complement, rotation_about, scalar, unit_axis, wrench_basis, zero
from .values import is_numeric

E = sp.eye(3)


class Universal(Several):
    """Two rotations, q₁ about `axis1` (joint axes), then q₂ about `axis2` (axes turned by q₁):
    R = R(a₁, q₁) R(a₂, q₂), as Pinocchio's JointModelUniversal. The axes must not be parallel."""

    def __init__(self, name: str, axis1=(1, 0, 0), axis2=(0, 1, 0), *, actuated: bool = True, armature=0):
        super().__init__(name, ("1", "2"), actuated=actuated, armature=armature)
        self.axis1, self.axis2 = unit_axis(axis1, self.name, "axis1"), unit_axis(axis2, self.name, "axis2")
        normal = self.axis1.cross(self.axis2)
        self.sine = sp.sqrt(sum(x**2 for x in normal))  # |a₁ × a₂|, constant: the angle between the axes
        if is_numeric(normal) and float(self.sine) < 1e-9:
            raise ModelError(
                f"joint '{self.name}': axis1 {tuple(self.axis1)} and axis2 {tuple(self.axis2)} are "
                "parallel; a universal joint needs two distinct axes (use a Revolute)"
            )

    def constants(self):
        return {
            **{f"axis1[{k}]": x for k, x in enumerate(self.axis1)},
            **{f"axis2[{k}]": x for k, x in enumerate(self.axis2)},
            "armature": self.armature,
        }

    def motion(self):
        q1, q2 = self._q
        return rotation_about(self.axis1, q1) * rotation_about(self.axis2, q2), zero()

    def subspace(self):
        """(0, R(a₂, q₂)ᵀ a₁), (0, a₂) in child axes."""
        return [(zero(), rotation_about(self.axis2, self._q[1]).T * self.axis1), (zero(), self.axis2)]

    def joint_frame_subspace(self):
        """(0, a₁), (0, R(a₁, q₁) a₂) in joint axes."""
        return [(zero(), self.axis1), (zero(), rotation_about(self.axis1, self._q[0]) * self.axis2)]

    def reaction_basis(self):
        (_, w1), (_, w2) = self.subspace()
        return wrench_basis(E, w1.cross(w2) / self.sine)

    def __repr__(self) -> str:
        return f"Universal({self.name!r}, axis1={tuple(self.axis1)}, axis2={tuple(self.axis2)})"


class Planar(Several):
    """Motion in the joint frame's xy plane: q = (x, y, θ), R = Rz(θ), and u = (v_x, v_y, ω_z), the
    child's twist in child axes (Pinocchio's JointModelPlanar, which stores cos θ, sin θ for θ):
    ẋ = cos θ v_x − sin θ v_y, ẏ = sin θ v_x + cos θ v_y, θ̇ = ω_z. Integrated on SE(2)."""

    group = "SE2"

    def __init__(self, name: str, *, actuated: bool = True, armature=0) -> None:
        super().__init__(
            name, ("x", "y", "theta"), ("vx", "vy", "wz"), actuated=actuated, armature=armature
        )

    def motion(self):
        x, y, theta = self._q
        return rotation_about(E[:, 2], theta), sp.Matrix([x, y, 0])

    def subspace(self):
        return [(E[:, 0], zero()), (E[:, 1], zero()), (zero(), E[:, 2])]

    def qdot(self):
        c, s = sp.cos(self._q[2]), sp.sin(self._q[2])
        vx, vy, w = self._u
        return [c * vx - s * vy, s * vx + c * vy, w]

    def hamel(self, u, p):
        """The planar Kirchhoff terms (−ω p_y, ω p_x, v_x p_y − v_y p_x)."""
        (vx, vy, w), (px, py, _) = u, p
        return [-w * py, w * px, vx * py - vy * px]

    def reaction_basis(self):
        return wrench_basis(E[:, 2], E[:, :2])


class Cylindrical(Several):
    """Translation d along `axis` and rotation θ about it: q = (d, θ), R = R(a, θ), t = d a
    (Pinocchio: a composite of PrismaticUnaligned and RevoluteUnaligned)."""

    def __init__(self, name: str, axis=(0, 0, 1), *, actuated: bool = True, armature=0) -> None:
        super().__init__(name, ("d", "theta"), actuated=actuated, armature=armature)
        self.axis = unit_axis(axis, self.name)

    def motion(self):
        d, theta = self._q
        return rotation_about(self.axis, theta), self.axis * d

    def subspace(self):
        return [(self.axis, zero()), (zero(), self.axis)]

    def joint_frame_subspace(self):
        return self.subspace()

    def reaction_basis(self):
        return wrench_basis(complement([self.axis]), complement([self.axis]))

    def __repr__(self) -> str:
        return f"Cylindrical({self.name!r}, axis={tuple(self.axis)})"


class Translation(Several):
    """Three translations along the joint axes: q = (x, y, z), t = q (JointModelTranslation)."""

    def __init__(self, name: str, *, actuated: bool = True, armature=0) -> None:
        super().__init__(name, ("x", "y", "z"), actuated=actuated, armature=armature)

    def motion(self):
        return sp.eye(3), sp.Matrix(self._q)

    def subspace(self):
        return [(E[:, k], zero()) for k in range(3)]

    def joint_frame_subspace(self):
        return self.subspace()

    def reaction_basis(self):
        return wrench_basis(sp.zeros(3, 0), E)


class Helical(Joint):
    """A screw: rotation q about `axis` and translation h q along it (h = `pitch`, length per radian),
    as Pinocchio's JointModelHelicalUnaligned; S = (h a, a)."""

    def __init__(self, name, axis=(0, 0, 1), pitch=0, *, actuated: bool = True, armature=0) -> None:
        super().__init__(name, axis, actuated=actuated, armature=armature)
        self.pitch = scalar(pitch, f"joint '{self.name}': pitch")

    def constants(self):
        return {**super().constants(), "pitch": self.pitch}

    def motion(self):
        return rotation_about(self.axis, self.q), self.axis * (self.pitch * self.q)

    def subspace(self):
        return [(self.pitch * self.axis, self.axis)]

    def joint_frame_subspace(self):
        return self.subspace()

    def reaction_basis(self):
        """Forces and torques across the axis, and the one screw along it that does no work,
        (a, −h a)/√(1 + h²)."""
        a, h, perp = self.axis, self.pitch, complement([self.axis])
        screw = a.col_join(-h * a) / sp.sqrt(1 + h**2)
        return wrench_basis(perp, perp).row_join(screw)

    def __repr__(self) -> str:
        return f"Helical({self.name!r}, axis={tuple(self.axis)}, pitch={self.pitch})"
