"""Joints and placements: how a body's frame sits on and moves against its parent's frame."""
from __future__ import annotations

from dataclasses import dataclass, field

import sympy as sp

from ..errors import ModelError
from ..symbols import Generated
from .values import is_numeric, matrix3, nonnegative, scalar, vector3


@dataclass(frozen=True)
class Placement:
    """Rigid transform of a frame relative to a parent frame: x_parent = rotation · x + translation."""

    rotation: sp.Matrix = field(default_factory=lambda: sp.eye(3))
    translation: sp.Matrix = field(default_factory=lambda: sp.zeros(3, 1))

    def __post_init__(self) -> None:
        R = matrix3(self.rotation, "placement.rotation")
        p = vector3(self.translation, "placement.translation")
        if is_numeric(R):
            Rn = sp.matrix2numpy(R, dtype=float)
            import numpy as np

            if not np.allclose(Rn.T @ Rn, np.eye(3), atol=1e-9) or np.linalg.det(Rn) < 0:
                raise ModelError(f"placement.rotation is not a proper rotation matrix: {R.tolist()}")
        object.__setattr__(self, "rotation", R)
        object.__setattr__(self, "translation", p)


def unit_axis(axis, joint: str) -> sp.Matrix:
    """The joint axis as a unit 3-vector (numeric axes are normalised; symbolic ones must be unit)."""
    a = vector3(axis, f"joint '{joint}': axis")
    if is_numeric(a):
        norm = sp.sqrt(sum(x**2 for x in a))
        if norm == 0 or float(norm) < 1e-12:
            raise ModelError(f"joint '{joint}': axis must not be zero")
        if norm != 1:
            a = a / norm
    return a


def rotation_about(a: sp.Matrix, angle: sp.Expr) -> sp.Matrix:
    """Rodrigues: R = I cos θ + sin θ [a]× + (1 − cos θ) a aᵀ, written out for principal axes."""
    c, s = sp.cos(angle), sp.sin(angle)
    return sp.eye(3) * c + s * skew(a) + (1 - c) * (a * a.T)


def skew(a: sp.Matrix) -> sp.Matrix:
    """[a]×, with [a]× b = a × b."""
    return sp.Matrix([[0, -a[2], a[1]], [a[2], 0, -a[0]], [-a[1], a[0], 0]])


class Joint:
    """A joint between a parent body and its child; `name` (str or Symbol) is also its coordinate q.
    `armature` is the rotor inertia seen at the joint (Pinocchio's armature): it adds to M_ii only."""

    dof = 1

    def __init__(self, name, axis=(0, 0, 1), *, actuated: bool = True, armature=0) -> None:
        if isinstance(name, sp.Symbol):
            self.name, self.q = name.name, name
        elif isinstance(name, str) and name.strip():
            self.name, self.q = name, sp.Symbol(name)
        else:
            raise ModelError(f"joint name must be a non-empty string or a sympy Symbol, got {name!r}")
        self.axis = unit_axis(axis, self.name)
        self.actuated = actuated
        self.armature = nonnegative(armature, f"joint '{self.name}': armature")  # adds to M_ii

    def motion(self) -> tuple[sp.Matrix, sp.Matrix]:
        """(R_j, t_j): the child frame in the joint frame as a function of q."""
        raise NotImplementedError

    def constants(self) -> dict[str, sp.Expr]:
        """The joint's constant fields by name (numbers or parameters)."""
        axis = {} if self.axis is None else {f"axis[{k}]": x for k, x in enumerate(self.axis)}
        return {**axis, "armature": self.armature}

    @property
    def coordinates(self) -> list[sp.Symbol]:
        """The joint's part of q."""
        return [] if self.q is None else [self.q]

    @property
    def speeds(self) -> list[sp.Symbol]:
        """The joint's part of u (u = q̇ for one-coordinate joints: 'phi' → 'phidot')."""
        return [speed_symbol(q) for q in self.coordinates]

    @property
    def accelerations(self) -> list[sp.Symbol]:
        """Symbols of the joint's part of u̇."""
        return [speed_symbol(q, "ddot") for q in self.coordinates]

    def qdot(self) -> list[sp.Expr]:
        """q̇ as a function of q and u (the kinematic differential equations)."""
        return self.speeds

    def __repr__(self) -> str:
        return f"{type(self).__name__}({self.name!r}, axis={tuple(self.axis)})"


def speed_symbol(q: sp.Symbol, suffix: str = "dot") -> sp.Symbol:
    """u for coordinate q: 'phi' → 'phidot' (φ̇), 'q_1' → 'qdot_1' (q̇₁)."""
    base, sep, sub = q.name.partition("_")
    return Generated(f"{base}{suffix}{sep}{sub}", (suffix, q))


class Revolute(Joint):
    """Rotation by q about `axis` (joint frame)."""

    def motion(self):
        return _axis_rotation(self.axis, self.q), sp.zeros(3, 1)


class Prismatic(Joint):
    """Translation by q along `axis` (joint frame)."""

    def motion(self):
        return sp.eye(3), self.axis * self.q


class FreeFlyer(Joint):
    """A free-flying base; only the root body of a tree may have it.

    parametrization "quaternion" (Pinocchio's layout): q = [x, y, z, qx, qy, qz, qw] (scalar last),
    u = [v, ω], the base twist in the base frame, q̇ = E(q) u with ṗ = R v and the quaternion rate
    ½ q ⊗ (ω, 0). parametrization "euler": q = [x, y, z, ψ, θ, φ] (ZYX: R = Rz(ψ) Ry(θ) Rx(φ)) and
    u = q̇; singular at pitch θ = ±90°, where ω no longer determines the angle rates."""

    dof = 6

    def __init__(self, name: str = "root_joint", parametrization: str = "quaternion") -> None:
        if not isinstance(name, str) or not name.strip():
            raise ModelError(f"joint name must be a non-empty string, got {name!r}")
        if parametrization not in ("quaternion", "euler"):
            raise ModelError(f"joint '{name}': parametrization must be 'quaternion' or 'euler', "
                             f"got {parametrization!r}")
        self.name, self.q, self.axis, self.actuated, self.armature = name, None, None, False, sp.Integer(0)
        self.parametrization = parametrization
        if parametrization == "quaternion":
            self._q = [Generated(f"{name}_{c}", (name, c)) for c in ("x", "y", "z", "qx", "qy", "qz", "qw")]
            self._u = [Generated(f"{name}_{c}", (name, c)) for c in ("vx", "vy", "vz", "wx", "wy", "wz")]
        else:
            self._q = [Generated(f"{name}_{c}", (name, c)) for c in ("x", "y", "z", "yaw", "pitch", "roll")]
            self._u = [speed_symbol(x) for x in self._q]

    @property
    def coordinates(self):
        return list(self._q)

    @property
    def speeds(self):
        return list(self._u)

    @property
    def accelerations(self):
        return [Generated(f"{s.name}dot", ("dot", s)) for s in self._u]

    def rotation(self) -> sp.Matrix:
        """R(q): for a unit quaternion as Pinocchio / Eigen compute it, or Rz(ψ) Ry(θ) Rx(φ)."""
        if self.parametrization == "euler":
            yaw, pitch, roll = self._q[3:]
            return (_axis_rotation(sp.Matrix([0, 0, 1]), yaw) * _axis_rotation(sp.Matrix([0, 1, 0]), pitch)
                    * _axis_rotation(sp.Matrix([1, 0, 0]), roll))
        x, y, z, w = self._q[3:]
        return sp.Matrix([[1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
                          [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
                          [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)]])

    def angular_axes(self) -> list[sp.Matrix]:
        """Euler: the world axes of ψ̇, θ̇, φ̇ (ω = ψ̇ e_z + θ̇ Rz e_y + φ̇ Rz Ry e_x)."""
        yaw, pitch = self._q[3:5]
        Rz = _axis_rotation(sp.Matrix([0, 0, 1]), yaw)
        return [sp.Matrix([0, 0, 1]), Rz[:, 1], (Rz * _axis_rotation(sp.Matrix([0, 1, 0]), pitch))[:, 0]]

    def motion(self):
        return self.rotation(), sp.Matrix(self._q[:3])

    def qdot(self) -> list[sp.Expr]:
        """Euler: q̇ = u. Quaternion: ṗ = R v, (ẋ, ẏ, ż, ẇ) of the quaternion = ½ q ⊗ (ω, 0)."""
        if self.parametrization == "euler":
            return self.speeds
        x, y, z, w = self._q[3:]
        v, (wx, wy, wz) = sp.Matrix(self._u[:3]), self._u[3:]
        p_dot = list(self.rotation() * v)
        half = sp.Rational(1, 2)
        return p_dot + [half * (w * wx - z * wy + y * wz), half * (z * wx + w * wy - x * wz),
                        half * (-y * wx + x * wy + w * wz), half * (-x * wx - y * wy - z * wz)]

    def __repr__(self) -> str:
        return f"FreeFlyer({self.name!r}, parametrization={self.parametrization!r})"


class FlexibleLink(Joint):
    """A planar flexible link on a revolute joint about its z axis: an Euler-Bernoulli beam of length L
    along the body's x axis, mass per length m and bending stiffness E I, deflecting along y, split
    into n elements with Hermite cubic shape functions. Coordinates: the joint angle θ, then the
    deflection and slope of nodes 2 … n+1 (node 1 is clamped to the joint). Children attach to the
    tip frame: translated by (L, w_tip) and turned by the tip slope. Lagrange II only."""

    def __init__(self, name, length, mass_per_length, EI, elements: int = 1, *, actuated: bool = True) -> None:
        super().__init__(name, axis=(0, 0, 1), actuated=actuated)
        if not isinstance(elements, int) or isinstance(elements, bool) or elements < 1:
            raise ModelError(f"joint '{self.name}': elements must be a positive integer, got {elements!r}")
        values = {"length": length, "mass_per_length": mass_per_length, "EI": EI}
        for label, value in values.items():
            values[label] = scalar(value, f"joint '{self.name}': {label}")
            if values[label].is_nonpositive:
                raise ModelError(f"joint '{self.name}': {label} must be positive, got {values[label]}")
        self.length, self.mass_per_length, self.EI = values.values()
        self.elements = elements
        self.nodal = [Generated(f"{kind}{k}_{self.name}", (self.name, kind, k))
                      for k in range(2, elements + 2)
                      for kind in ("w", "s")]

    @property
    def dof(self) -> int:
        """Number of speeds: the joint angle and the deflection and slope of each free node."""
        return 1 + len(self.nodal)

    def constants(self) -> dict[str, sp.Expr]:
        return {**super().constants(), "length": self.length, "mass_per_length": self.mass_per_length,
                "EI": self.EI}

    @property
    def coordinates(self):
        return [self.q, *self.nodal]

    def motion(self):
        return _axis_rotation(self.axis, self.q), sp.zeros(3, 1)

    def tip(self) -> tuple[sp.Matrix, sp.Matrix]:
        """(R, t) of the tip frame in the link frame: turned by the tip slope, at (L, w_tip)."""
        w, s = self.nodal[-2:]
        return _axis_rotation(self.axis, s), sp.Matrix([self.length, w, 0])


class Fixed(Joint):
    """No motion: the body is welded to its parent."""

    dof = 0

    def __init__(self, name: str = "fixed") -> None:
        self.name, self.q, self.axis, self.actuated, self.armature = str(name), None, None, False, sp.Integer(0)

    def motion(self):
        return sp.eye(3), sp.zeros(3, 1)

    def __repr__(self) -> str:
        return f"Fixed({self.name!r})"


def _axis_rotation(a: sp.Matrix, q: sp.Expr) -> sp.Matrix:
    c, s = sp.cos(q), sp.sin(q)
    principal = {(1, 0, 0): 0, (0, 1, 0): 1, (0, 0, 1): 2}
    for sign in (1, -1):
        if tuple(sign * a) in principal:  # exact forms, no (1 − cos) terms
            i = principal[tuple(sign * a)]
            j, k = (i + 1) % 3, (i + 2) % 3
            R = sp.eye(3)
            R[j, j], R[j, k], R[k, j], R[k, k] = c, -sign * s, sign * s, c
            return R
    return rotation_about(a, q)
