"""URDF import through Pinocchio's parser: the same joint order, q layout and merged fixed links as
`pinocchio.buildModelFromUrdf`, converted into a `System` with numeric parameters."""
from __future__ import annotations

from pathlib import Path

import numpy as np
import sympy as sp

from ..errors import ModelError
from .free_flyer import FreeFlyer
from .joints import Fixed, Placement, Prismatic, Revolute
from .multi_axis import Planar
from .system import System
from .urdf_check import check_urdf

_AXES = {"X": (1, 0, 0), "Y": (0, 1, 0), "Z": (0, 0, 1)}


def number(x: float) -> sp.Expr:
    """A URDF number as sympy: exact 0 and ±1 where the float is within 1e-14 of them, else the
    float's exact binary value as a Rational (sympy multiplies Rationals several times faster than
    Floats; code generation prints them back as the nearest float)."""
    x = float(x)
    for exact in (0, 1, -1):
        if abs(x - exact) < 1e-14:
            return sp.Integer(exact)
    return sp.Rational(x)


def _matrix(a) -> list:
    return [[number(x) for x in row] for row in np.atleast_2d(np.asarray(a, float))]


def _axis(jmodel, angular: bool) -> tuple:
    """A one-dof joint's axis, read off its motion subspace S = [linear; angular] at q = 0 (the
    unbounded unaligned revolute does not expose its axis)."""
    data = jmodel.createData()
    jmodel.calc(data, np.array([1.0, 0.0]) if jmodel.nq == 2 else np.zeros(jmodel.nq))
    S = np.asarray(data.S).ravel()
    return tuple(number(x) for x in (S[3:] if angular else S[:3]))


def _joint(jmodel, name: str, armature: float, base: str = "quaternion"):
    """(eomgen joint, continuous) for one Pinocchio joint model; a clear error for the others."""
    kind = jmodel.shortname()
    rest = kind.removeprefix("JointModel")
    if rest in ("RX", "RY", "RZ", "RUBX", "RUBY", "RUBZ"):
        return Revolute(name, axis=_AXES[rest[-1]], armature=armature), rest.startswith("RUB")
    if rest in ("RevoluteUnaligned", "RevoluteUnboundedUnaligned"):
        unbounded = rest == "RevoluteUnboundedUnaligned"
        return Revolute(name, axis=_axis(jmodel, True), armature=armature), unbounded
    if rest in ("PX", "PY", "PZ"):
        return Prismatic(name, axis=_AXES[rest[-1]], armature=armature), False
    if rest == "FreeFlyer":
        return FreeFlyer(name, parametrization=base), False
    if rest == "PrismaticUnaligned":
        return Prismatic(name, axis=_axis(jmodel, False), armature=armature), False
    raise ModelError(f"joint '{name}': unsupported joint type {kind} (eomgen models revolute, continuous, "
                     "prismatic and fixed joints)")


def parse_urdf(path, floating_base: bool = False, srdf=None, mimic: str = "refuse"):
    """The Pinocchio model of a URDF file (armature from the SRDF's rotor parameters, if given)."""
    import pinocchio as pin

    path = Path(path)
    if not path.is_file():
        raise ModelError(f"URDF file not found: {path}")
    check_urdf(path, mimic)
    try:
        model = (pin.buildModelFromUrdf(str(path), pin.JointModelFreeFlyer()) if floating_base
                 else pin.buildModelFromUrdf(str(path)))
    except Exception as exc:  # Pinocchio raises ValueError / RuntimeError with the parser's message
        raise ModelError(f"cannot read URDF {path}: {exc}") from None
    if srdf is not None:
        srdf = Path(srdf)
        if not srdf.is_file():
            raise ModelError(f"SRDF file not found: {srdf}")
        try:
            pin.loadRotorParameters(model, str(srdf), False)
        except Exception as exc:
            raise ModelError(f"cannot read rotor parameters from SRDF {srdf}: {exc}") from None
        model.armature = np.multiply(model.rotorInertia, np.square(model.rotorGearRatio))
    return model


def from_pinocchio(model, gravity=None, strict: bool = True, base: str = "quaternion") -> System:
    """A `System` equal to a Pinocchio model of revolute, continuous, prismatic and free-flyer joints
    (`strict=False`: impossible inertias warn instead of raising; `base="euler"`: the free flyer in
    ZYX Euler angles, for which Pinocchio has no counterpart)."""
    import pinocchio as pin

    system = System(gravity=tuple(number(x) for x in (model.gravity.linear if gravity is None else gravity)),
                    strict=strict)
    frames = list(model.frames)
    body_frame = {}  # joint index -> name of the link it moves
    for f in frames:
        if f.type == pin.FrameType.BODY and f.parentJoint not in body_frame:
            body_frame[f.parentJoint] = f.name
    floating = model.njoints > 1 and model.joints[1].shortname() == "JointModelFreeFlyer"
    root = body_frame.get(0, "world")
    bodies = {0: None if floating else system.add_body(root, joint=Fixed(f"{root}_fixed"))}
    continuous = []
    for i in range(1, model.njoints):
        name = model.names[i]
        joint, is_continuous = _joint(model.joints[i], name, number(model.armature[model.joints[i].idx_v]), base)
        inertia = model.inertias[i]
        M = model.jointPlacements[i]
        body_name = body_frame.get(i, f"{name}_body")
        bodies[i] = system.add_body(body_name, parent=bodies[model.parents[i]], joint=joint,
                                    mass=number(inertia.mass), com=[number(x) for x in inertia.lever],
                                    inertia=_matrix(inertia.inertia),
                                    placement=Placement(rotation=_matrix(M.rotation),
                                                        translation=[number(x) for x in M.translation]))
        continuous.append(is_continuous)
    taken = {b.name for b in system.bodies}
    for f in frames:
        if f.name in taken or f.name == "universe" or bodies[f.parentJoint] is None:
            continue
        taken.add(f.name)
        system.add_frame(f.name, bodies[f.parentJoint],
                         Placement(rotation=_matrix(f.placement.rotation),
                                   translation=[number(x) for x in f.placement.translation]))
    system.pinocchio_model = model if base == "quaternion" else None
    system.continuous = continuous
    return system


def from_urdf(path, floating_base: bool | str = False, srdf=None, strict: bool = True,
              mimic: str = "refuse") -> System:
    """Import a URDF file with numeric parameters; frames are the URDF links and fixed joints by name.
    A mimic joint is refused unless mimic="independent" (imported as an independent joint, warned).
    floating_base: False (fixed), True or "quaternion" (Pinocchio's free flyer), "euler" (ZYX angles).
    Armature comes from the SRDF's rotor parameters when `srdf` is given. With `strict=False` an
    inertia that is not physically possible is a warning, not an error."""
    if floating_base not in (False, True, "quaternion", "euler"):
        raise ModelError(f"floating_base must be False, True, 'quaternion' or 'euler', got {floating_base!r}")
    base = floating_base if isinstance(floating_base, str) else "quaternion"
    system = from_pinocchio(parse_urdf(path, bool(floating_base), srdf, mimic), strict=strict, base=base)
    system.source = str(path)
    return system


def pinocchio_configuration(system: System, q) -> np.ndarray:
    """Pinocchio's q from eomgen's: a continuous joint's angle θ becomes (cos θ, sin θ), as does a planar
    joint's; the quaternions of a free flyer and a ball joint are the same numbers in both."""
    q = np.asarray(q, float)
    parts, k = [], 0
    for joint, is_continuous in zip(system.joints, getattr(system, "continuous", [False] * len(system.joints))):
        n = len(joint.coordinates)
        parts += [q[..., k + i] for i in range(n - 1)] if isinstance(joint, Planar) else []
        angle = is_continuous or isinstance(joint, Planar)
        parts += [np.cos(q[..., k + n - 1]), np.sin(q[..., k + n - 1])] if angle else \
            [q[..., k + i] for i in range(n)]
        k += n
    return np.stack(parts, axis=-1)
