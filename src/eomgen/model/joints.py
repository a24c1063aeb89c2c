"""Joints and placements: how a body's frame sits on and moves against its parent's frame.

A joint moves its child frame in the joint frame by (R_q, t_q)(q) and is described, like Pinocchio's
joint models, by its motion subspace S(q): column k is the (linear, angular) velocity (v_k, ω_k) of
the child frame, in child axes, that the joint's speed u_k causes (v of the child origin relative to
the joint frame). The relative motion of the child when u̇ = 0 is its bias,

    α_rel = Σ_k ω̇_k u_k,    a_rel = ω × v + Σ_k v̇_k u_k     (child axes, v = Σ v_k u_k, ω = Σ ω_k u_k),

where ẋ = Σ_j ∂x/∂q_j q̇_j(q, u) is the rate of a column's components. Every method derives its
equations from R_q, t_q, S and the bias; a new joint type defines those, its coordinates, speeds and
q̇(q, u), and (for the free cut) the wrenches it transmits without work."""

from __future__ import annotations

from dataclasses import dataclass, field

import sympy as sp

from ..errors import ModelError
from ..symbols import Generated, t as time
from .values import is_numeric, matrix3, nonnegative, scalar, vector3

Column = tuple[sp.Matrix, sp.Matrix]  # (v, ω) of one speed


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


def unit_axis(axis, joint: str, what: str = "axis") -> sp.Matrix:
    """The joint axis as a unit 3-vector (numeric axes are normalised; symbolic ones must be unit)."""
    a = vector3(axis, f"joint '{joint}': {what}")
    if is_numeric(a):
        norm = sp.sqrt(sum(x**2 for x in a))
        if norm == 0 or float(norm) < 1e-12:
            raise ModelError(f"joint '{joint}': {what} must not be zero")
        if norm != 1:
            a = a / norm
    return a


def rotation_about(a: sp.Matrix, angle: sp.Expr) -> sp.Matrix:
    """Rodrigues: R = I cos θ + sin θ [a]× + (1 − cos θ) a aᵀ, written out for principal axes."""
    c, s = sp.cos(angle), sp.sin(angle)
    principal = {(1, 0, 0): 0, (0, 1, 0): 1, (0, 0, 1): 2}
    for sign in (1, -1):
        i = principal.get(tuple(sign * x for x in a))
        if i is not None:  # exact forms, no (1 − cos) terms; one matrix built (setting entries costs more)
            j, k = (i + 1) % 3, (i + 2) % 3
            R = [int(r == col) for r in range(3) for col in range(3)]
            R[4 * j], R[3 * j + k], R[3 * k + j], R[4 * k] = c, -sign * s, sign * s, c
            return sp.Matrix(3, 3, R)
    return sp.eye(3) * c + s * skew(a) + (1 - c) * (a * a.T)


def skew(a: sp.Matrix) -> sp.Matrix:
    """[a]×, with [a]× b = a × b."""
    return sp.Matrix([[0, -a[2], a[1]], [a[2], 0, -a[0]], [-a[1], a[0], 0]])


def joint_name(name, symbol_allowed: bool = True) -> tuple[str, sp.Symbol | None]:
    """(name, coordinate symbol) of a joint named by a string (or a Symbol, its coordinate)."""
    if symbol_allowed and isinstance(name, sp.Symbol):
        return name.name, name
    if isinstance(name, str) and name.strip():
        return name, sp.Symbol(name)
    raise ModelError(
        f"joint name must be a non-empty string{' or a sympy Symbol' * symbol_allowed}, got {name!r}"
    )


def components(name: str, labels) -> list[Generated]:
    """The coordinates (or speeds) of a joint with several, labelled `<name>_<label>`."""
    return [Generated(f"{name}_{c}", (name, c)) for c in labels]


def zero() -> sp.Matrix:
    return sp.zeros(3, 1)


class Joint:
    """A joint between a parent body and its child (see the module). `armature` is the rotor inertia
    seen at each of its speeds (Pinocchio's armature): it adds to those diagonal entries of M."""

    group = "vector"  # configuration space for integration: "vector", "SO3", "SE2" or "SE3"
    pitch_index: int | None = None  # ZYX angles: position of the pitch in the joint's q (singular at ±90°)
    mimic: "Mimic | None" = None  # a joint that follows another's coordinate (`OneAxis`)
    prescribed: sp.Expr | None = None  # a joint driven as a given function of time (`OneAxis`)
    driven: tuple = ()  # then its variable, rate and acceleration as named intermediates (`drive`)

    def __init__(self, name, axis=(0, 0, 1), *, actuated: bool = True, armature=0) -> None:
        self.name, self.q = joint_name(name)
        self.axis = unit_axis(axis, self.name)
        self.actuated = actuated
        self.armature = nonnegative(armature, f"joint '{self.name}': armature")

    @property
    def dof(self) -> int:
        """Number of the joint's own speeds."""
        return len(self.speeds)

    @property
    def efforts(self) -> int:
        """How many of its speeds (the first ones) an actuator drives: all of them."""
        return self.dof

    def motion(self) -> tuple[sp.Matrix, sp.Matrix]:
        """(R_q, t_q): the child frame in the joint frame as a function of q."""
        raise NotImplementedError

    def subspace(self) -> list[Column]:
        """S: per speed, (v, ω) of the child frame in child axes."""
        raise NotImplementedError

    def joint_frame_subspace(self) -> list[Column] | None:
        """S in joint axes where that is simpler (an axis the motion leaves in place, R_q a = a; Euler
        angle rates), else None; its bias is then the plain rate Σ_k Ṡ_k u_k, in joint axes."""
        return None

    def bias(self) -> tuple[sp.Matrix, sp.Matrix]:
        """(a_rel, α_rel) in child axes, the joint's relative acceleration when u̇ = 0 (module)."""
        S, u = self.subspace(), self.speeds
        v = sum((vk * uk for (vk, _), uk in zip(S, u)), zero())
        w = sum((wk * uk for (_, wk), uk in zip(S, u)), zero())
        a, alpha = self._rates(S)
        return w.cross(v) + a, alpha

    def joint_frame_bias(self) -> tuple[sp.Matrix, sp.Matrix]:
        """(a_rel, α_rel) in joint axes for `joint_frame_subspace`: Σ_k Ṡ_k u_k (the joint frame does
        not turn with the joint)."""
        return self._rates(self.joint_frame_subspace())

    def _rates(self, S: list[Column]) -> tuple[sp.Matrix, sp.Matrix]:
        """(Σ_k v̇_k u_k, Σ_k ω̇_k u_k) of columns S over the joint's own speeds."""
        u = self.speeds
        return (sum((self.rate(vk) * uk for (vk, _), uk in zip(S, u)), zero()),
                sum((self.rate(wk) * uk for (_, wk), uk in zip(S, u)), zero()))

    def rate(self, x: sp.Matrix) -> sp.Matrix:
        """ẋ = Σ_j ∂x/∂q_j q̇_j(q, u) for an expression in the joint's coordinates."""
        return sum((x.diff(q) * qd for q, qd in zip(self.coordinates, self.qdot())), sp.zeros(*x.shape))

    def reaction_basis(self) -> sp.Matrix:
        """6 × (6 − dof), orthonormal columns: the wrenches (F; T) at the child origin, child axes,
        that the joint transmits without work (Bᵀ S = 0), the directions of its reactions."""
        raise NotImplementedError

    def hamel(self, u: list, p: list) -> list | None:
        """For speeds that are not coordinate rates (a body twist), the terms that Lagrange's
        equations in these quasi-velocities add to b_k, given u and p = ∂T/∂u of this joint."""
        return None

    def constants(self) -> dict[str, sp.Expr]:
        """The joint's constant fields by name (numbers or parameters)."""
        axis = {} if self.axis is None else {f"axis[{k}]": x for k, x in enumerate(self.axis)}
        motion = {} if self.prescribed is None else {"motion": self.prescribed}
        return {**axis, "armature": self.armature, **motion}

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
        """Symbols of the joint's part of u̇: q̈ where u = q̇ ('phi' → 'phiddot'), else u̇ ('wx' →
        'wxdot')."""
        if self.speeds == [speed_symbol(q) for q in self.coordinates]:
            return [speed_symbol(q, "ddot") for q in self.coordinates]
        return [Generated(f"{s.name}dot", ("dot", s)) for s in self.speeds]

    def qdot(self) -> list[sp.Expr]:
        """q̇ as a function of q and u (the kinematic differential equations)."""
        return self.speeds

    def __repr__(self) -> str:
        return f"{type(self).__name__}({self.name!r}, axis={tuple(self.axis)})"


def speed_symbol(q: sp.Symbol, suffix: str = "dot") -> sp.Symbol:
    """u for coordinate q: 'phi' → 'phidot' (φ̇), 'q_1' → 'qdot_1' (q̇₁)."""
    base, sep, sub = q.name.partition("_")
    return Generated(f"{base}{suffix}{sep}{sub}", (suffix, q))


def complement(vectors: list[sp.Matrix]) -> sp.Matrix:
    """An orthonormal basis (3 × (3 − k)) of the directions perpendicular to k orthonormal vectors."""
    if not vectors:
        return sp.eye(3)
    if len(vectors) == 3:
        return sp.zeros(3, 0)
    if len(vectors) == 2:
        n = vectors[0].cross(vectors[1])
        return n / sp.sqrt(sum(x**2 for x in n))
    a = vectors[0]
    for k in range(3):
        if all(a[i] == 0 for i in range(3) if i != k):
            return sp.eye(3)[:, [i for i in range(3) if i != k]]
    m = min(range(3), key=lambda i: abs(float(a[i])) if a[i].is_number else 1)
    n1 = a.cross(sp.eye(3)[:, m])
    n1 = n1 / sp.sqrt((n1.T * n1)[0])
    return n1.row_join(a.cross(n1))


def wrench_basis(forces: sp.Matrix, torques: sp.Matrix) -> sp.Matrix:
    """6 × k: the force directions (torque 0) beside the torque directions (force 0)."""
    return (
        sp.diag(forces, torques)
        if forces.cols and torques.cols
        else (
            forces.col_join(sp.zeros(3, forces.cols))
            if forces.cols
            else sp.zeros(3, torques.cols).col_join(torques)
        )
    )


class Several(Joint):
    """A joint with several coordinates, labelled `<name>_<label>`; its speeds are labelled likewise when
    they are a twist in its own axes (`speeds`), else they are the coordinates' rates."""

    def __init__(self, name: str, coordinates, speeds=None, *, actuated: bool = True, armature=0) -> None:
        self.name, _ = joint_name(name, symbol_allowed=False)
        self.q, self.axis, self.actuated = None, None, actuated
        self.armature = nonnegative(armature, f"joint '{self.name}': armature")
        self._q = components(self.name, coordinates)
        self._u = [speed_symbol(x) for x in self._q] if speeds is None else components(self.name, speeds)

    @property
    def coordinates(self):
        return list(self._q)

    @property
    def speeds(self):
        return list(self._u)

    def __repr__(self) -> str:
        return f"{type(self).__name__}({self.name!r})"


class Mimic:
    """q = k q_driver + o: a one-coordinate joint that follows another joint's coordinate (URDF
    `<mimic>`, Pinocchio's JointModelMimic); its speed is k u_driver and its effort reaches the driver
    multiplied by k. Bound to the driver when its body is added to a System."""

    def __init__(self, joint: Joint, mimic) -> None:
        if not (isinstance(mimic, tuple) and len(mimic) == 3):
            raise ModelError(
                f"joint '{joint.name}': mimic must be (joint name, multiplier, offset), got {mimic!r}"
            )
        other, k, o = mimic
        if not isinstance(other, str) or not other:
            raise ModelError(
                f"joint '{joint.name}': mimic needs the name of the joint it follows, got {other!r}"
            )
        if other == joint.name:
            raise ModelError(f"joint '{joint.name}' cannot mimic itself")
        self.driver_name = other
        self.multiplier = scalar(k, f"joint '{joint.name}': mimic multiplier")
        if self.multiplier.is_zero:
            raise ModelError(f"joint '{joint.name}': mimic multiplier 0 would not move the joint; use Fixed")
        self.offset = scalar(o, f"joint '{joint.name}': mimic offset")
        self.driver: Joint | None = None


class OneAxis(Joint):
    """A one-coordinate joint along or about `axis` (joint axes), optionally a mimic of another, or
    driven by a prescribed `motion`: its variable a given expression of the time `eg.t` (and of
    parameters), so it has no coordinate, no speed and no actuator of its own (`prescribed`)."""

    def __init__(self, name, axis=(0, 0, 1), *, actuated: bool = True, armature=0, mimic=None,
                 motion=None) -> None:
        super().__init__(name, axis, actuated=actuated, armature=armature)
        self.mimic = None if mimic is None else Mimic(self, mimic)
        if motion is not None:
            drive(self, motion)
        if self.mimic is not None and self.prescribed is not None:
            raise ModelError(f"joint '{self.name}': give mimic or motion, not both")
        if self.mimic is not None or self.prescribed is not None:
            self.q = None  # no coordinate of its own

    def bind(self, driver: Joint) -> None:
        """Follow `driver` (a mimic's driving joint, found by the System)."""
        self.mimic.driver = driver

    @property
    def value(self) -> sp.Expr:
        """The joint variable: q, k q_driver + o for a mimic, or (the name of) its prescribed motion θ(t)."""
        if self.prescribed is not None:
            return self.driven[0]
        if self.mimic is None:
            return self.q
        if self.mimic.driver is None:
            raise ModelError(f"joint '{self.name}': a mimic joint moves only once its body is in a System")
        return self.mimic.multiplier * self.mimic.driver.q + self.mimic.offset

    def joint_frame_subspace(self):
        return self.subspace()

    def bias(self) -> tuple[sp.Matrix, sp.Matrix]:
        """(0, 0): its one column (v, ω) is constant and along or about one axis, so ω × v = 0 and Ṡ = 0."""
        return zero(), zero()

    def joint_frame_bias(self) -> tuple[sp.Matrix, sp.Matrix]:
        return self.bias()

    def scale(self) -> sp.Expr:
        """The factor of the driver's speed in this joint's motion (1 for an ordinary joint)."""
        return sp.Integer(1) if self.mimic is None else self.mimic.multiplier

    def constants(self) -> dict[str, sp.Expr]:
        extra = (
            {}
            if self.mimic is None
            else {"mimic multiplier": self.mimic.multiplier, "mimic offset": self.mimic.offset}
        )
        return {**super().constants(), **extra}

    def reaction_basis(self) -> sp.Matrix:
        v, w = self.subspace()[0]
        return wrench_basis(
            complement([v / self.scale()] if v != zero() else []),
            complement([w / self.scale()] if w != zero() else []),
        )

    def __repr__(self) -> str:
        mimic = (
            ""
            if self.mimic is None
            else f", mimic=({self.mimic.driver_name!r}, {self.mimic.multiplier}, {self.mimic.offset})"
        )
        motion = "" if self.prescribed is None else f", motion={self.prescribed}"
        return f"{type(self).__name__}({self.name!r}, axis={tuple(self.axis)}{mimic}{motion})"


def drive(joint: Joint, motion) -> None:
    """Give `joint` a prescribed motion: a real expression θ in the time `eg.t` and parameters (a number:
    a joint held still), twice differentiable in t. It has no coordinate then; θ, θ̇, θ̈ are named by
    `joint.driven`, which the kinematics define as intermediates (so that the equations can be
    differentiated along the motion, for the effort that drives it)."""
    expr = scalar(motion, f"joint '{joint.name}': motion")
    others = [s for s in expr.free_symbols if s.name == time.name and s != time]
    if others:
        raise ModelError(f"joint '{joint.name}': motion uses {sp.srepr(others[0])}, not the time eg.t "
                         f"({sp.srepr(time)}); write the motion in eg.t")
    variable = Generated(f"_θ_{joint.name}", ("motion", joint.name))
    joint.prescribed, joint.q = expr, None
    joint.driven = (variable, speed_symbol(variable), speed_symbol(variable, "ddot"))


class Revolute(OneAxis):
    """Rotation by q about `axis` (joint axes); S = (0, a)."""

    def motion(self):
        return rotation_about(self.axis, self.value), zero()

    def subspace(self):
        return [(zero(), self.scale() * self.axis)]


class Prismatic(OneAxis):
    """Translation by q along `axis` (joint axes); S = (a, 0)."""

    def motion(self):
        return sp.eye(3), self.axis * self.value

    def subspace(self):
        return [(self.scale() * self.axis, zero())]


class Fixed(Joint):
    """No motion: the body is welded to its parent."""

    def __init__(self, name: str = "fixed") -> None:
        self.name, self.q, self.axis, self.actuated, self.armature = (
            str(name),
            None,
            None,
            False,
            sp.Integer(0),
        )

    def motion(self):
        return sp.eye(3), zero()

    def subspace(self):
        return []

    def reaction_basis(self):
        return sp.eye(6)

    def __repr__(self) -> str:
        return f"Fixed({self.name!r})"
