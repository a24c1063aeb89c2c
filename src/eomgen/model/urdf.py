"""URDF import through Pinocchio's parser: the same joint order, q layout and merged fixed links as
`pinocchio.buildModelFromUrdf`, converted into a `System` with numeric parameters."""
from __future__ import annotations

import re
from pathlib import Path

import numpy as np
import sympy as sp

from ..errors import ModelError
from .free_flyer import FreeFlyer
from .joints import Fixed, OneAxis, Placement, Prismatic, Revolute
from .multi_axis import Cylindrical, Helical, Planar, Translation, Universal
from .spherical import Spherical
from .system import System
from .urdf_check import check_urdf

_AXES = {"X": (1, 0, 0), "Y": (0, 1, 0), "Z": (0, 0, 1)}
_SLIDE = {"PX", "PY", "PZ", "PrismaticUnaligned"}  # the bounded one-axis joints, which a mimic can be
_TURN = {"RX", "RY", "RZ", "RevoluteUnaligned"}


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


def placement(M) -> Placement:
    """A Pinocchio SE3 as an eomgen Placement with numbers as in `number`."""
    return Placement(rotation=_matrix(M.rotation), translation=_vector(M.translation))


def _axis(jmodel, angular: bool) -> tuple:
    """A one-dof joint's axis, read off its motion subspace S = [linear; angular] at q = 0 (the
    unbounded unaligned revolute does not expose its axis)."""
    data = jmodel.createData()
    jmodel.calc(data, np.array([1.0, 0.0]) if jmodel.nq == 2 else np.zeros(jmodel.nq))
    S = np.asarray(data.S).ravel()
    return _vector(S[3:] if angular else S[:3])


def _vector(v) -> tuple:
    return tuple(number(x) for x in v)


def _cylinder_axis(composite) -> tuple | None:
    """The axis of a composite joint that is a cylindrical one (a prismatic, then a revolute joint on
    the same axis, nothing between them), else None."""
    parts = [j.shortname().removeprefix("JointModel") for j in composite.joints]
    if len(parts) != 2 or parts[0] not in _SLIDE or parts[1] not in _TURN \
            or not all(M.isIdentity() for M in composite.jointPlacements):
        return None
    axes = _axis(composite.joints[0], False), _axis(composite.joints[1], True)
    return axes[0] if axes[0] == axes[1] else None


def _mimic(model, i: int) -> OneAxis:
    """Pinocchio's mimic joint i as a Revolute or Prismatic following its driver; its own type is in
    the mimic's description (Pinocchio 4.1 crashes computing a helical one), its axis in
    S = multiplier · S_own."""
    import pinocchio as pin

    jmodel, name = model.joints[i], model.names[i]
    driver = model.names[model.mimicked_joints[list(model.mimicking_joints).index(i)]]
    mimic = jmodel.extract()
    own = re.search(r"Mimicking joint type: JointModel(\w+)", repr(mimic))
    own = own.group(1) if own else "joint of unknown type"
    kind = Revolute if own in _TURN else Prismatic if own in _SLIDE else None
    if kind is None:
        raise ModelError(f"joint '{name}' mimics '{driver}' as a {own}; eomgen's mimic joints are revolute "
                         "or prismatic")
    if number(mimic.scaling) == 0:
        raise ModelError(f"joint '{name}' mimics '{driver}' with multiplier {mimic.scaling:g}, 0 to 1e-14: "
                         "it does not move (make it a fixed joint)")
    data = jmodel.createData()
    jmodel.calc(data, pin.neutral(model))
    S = np.asarray(data.S).ravel() / mimic.scaling
    return kind(name, axis=_vector(S[3:] if kind is Revolute else S[:3]),
                mimic=(driver, number(mimic.scaling), number(mimic.offset)))


def _joint(model, i: int, base: str = "quaternion"):
    """(eomgen joint, continuous) for Pinocchio's joint i; a clear error for the others."""
    jmodel, name = model.joints[i], model.names[i]
    kind = jmodel.shortname()
    rest = kind.removeprefix("JointModel")
    if rest == "Mimic":
        return _mimic(model, i), False
    armatures = model.armature[jmodel.idx_v:jmodel.idx_v + jmodel.nv]
    if np.ptp(armatures) > 0 or rest == "FreeFlyer" and armatures.any():
        raise ModelError(f"joint '{name}': armature {armatures.tolist()} (eomgen gives a joint one armature "
                         "for all of its speeds, a free flyer none)")
    armature = number(armatures[0])
    joint = jmodel.extract()
    if rest in ("RX", "RY", "RZ", "RUBX", "RUBY", "RUBZ"):
        return Revolute(name, axis=_AXES[rest[-1]], armature=armature), rest.startswith("RUB")
    if rest in ("RevoluteUnaligned", "RevoluteUnboundedUnaligned"):
        unbounded = rest == "RevoluteUnboundedUnaligned"
        return Revolute(name, axis=_axis(jmodel, True), armature=armature), unbounded
    if rest in ("PX", "PY", "PZ"):
        return Prismatic(name, axis=_AXES[rest[-1]], armature=armature), False
    if rest == "PrismaticUnaligned":
        return Prismatic(name, axis=_axis(jmodel, False), armature=armature), False
    if rest in ("HX", "HY", "HZ", "HelicalUnaligned"):
        axis = _AXES[rest[-1]] if len(rest) == 2 else _vector(joint.axis)
        return Helical(name, axis=axis, pitch=number(joint.pitch), armature=armature), False
    if rest == "FreeFlyer":
        return FreeFlyer(name, parametrization=base), False
    if rest in ("Spherical", "SphericalZYX"):
        return Spherical(name, "zyx" if rest.endswith("ZYX") else "quaternion", armature=armature), False
    if rest == "Universal":
        return Universal(name, _vector(joint.axis1), _vector(joint.axis2), armature=armature), False
    if rest in ("Planar", "Translation"):
        return (Planar if rest == "Planar" else Translation)(name, armature=armature), False
    if rest == "Composite" and (axis := _cylinder_axis(joint)) is not None:
        return Cylindrical(name, axis=axis, armature=armature), False
    raise ModelError(f"joint '{name}': unsupported joint type {kind} (eomgen models Pinocchio's revolute, "
                     "prismatic, helical, free-flyer, spherical, universal, planar, translation and mimic "
                     "joints, and the cylindrical composite of a prismatic and a revolute joint on one "
                     "axis)")


def parse_urdf(path, floating_base: bool = False, srdf=None, mimic: str = "mimic"):
    """The Pinocchio model of a URDF file (with mimic joints for mimic="mimic"; armature from the
    SRDF's rotor parameters, if given)."""
    import pinocchio as pin

    path = Path(path)
    check_urdf(path, mimic)
    root = [pin.JointModelFreeFlyer()] if floating_base else []
    try:
        model = pin.buildModelFromUrdf(str(path), *root, mimic=mimic == "mimic")
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
    """A `System` equal to a Pinocchio model (joint types: see `_joint`; a free flyer only between the
    world and a root body). `strict=False`: impossible inertias warn instead of raising;
    `base="euler"`: free flyers in ZYX Euler angles, for which Pinocchio has no counterpart."""
    import pinocchio as pin

    system = System(gravity=tuple(number(x) for x in (model.gravity.linear if gravity is None else gravity)),
                    strict=strict)
    frames = list(model.frames)
    body_frame = {}  # joint index -> name of the link it moves: the joint's own where the link is not at
    for f in frames:  # the joint's frame (an MJCF joint with pos; the link is a frame on it then)
        if f.type == pin.FrameType.BODY and f.parentJoint not in body_frame:
            at_joint = f.placement.isIdentity(1e-14)
            body_frame[f.parentJoint] = f.name if at_joint else model.names[f.parentJoint]
    joints = [_joint(model, i, base) for i in range(1, model.njoints)]
    for i, (joint, _) in enumerate(joints, 1):
        if isinstance(joint, FreeFlyer) and model.parents[i] != 0:
            parent = model.names[model.parents[i]]
            raise ModelError(f"joint '{joint.name}': a floating joint below joint '{parent}'; eomgen's "
                             "FreeFlyer joins a root body to the world only (from_urdf's floating_base adds "
                             "one above the file's root link)")
    floating = any(isinstance(joint, FreeFlyer) for joint, _ in joints)
    root = body_frame.get(0, "world")
    bodies = {0: None if floating else system.add_body(root, joint=Fixed(f"{root}_fixed"))}
    continuous = []
    for i, (joint, is_continuous) in enumerate(joints, 1):
        inertia = model.inertias[i]
        M = model.jointPlacements[i]
        body_name = body_frame.get(i, f"{joint.name}_body")
        bodies[i] = system.add_body(body_name, parent=bodies[model.parents[i]], joint=joint,
                                    mass=number(inertia.mass), com=[number(x) for x in inertia.lever],
                                    inertia=_matrix(inertia.inertia),
                                    placement=placement(M))
        continuous += [is_continuous] if joint.dof else []  # a mimic has no coordinate
    taken = {b.name for b in system.bodies}
    for f in frames:
        if f.name in taken or f.name == "universe" or bodies[f.parentJoint] is None:
            continue
        taken.add(f.name)
        system.add_frame(f.name, bodies[f.parentJoint], placement(f.placement))
    system.pinocchio_model = model if base == "quaternion" else None
    system.continuous = continuous
    return system


def from_urdf(path, floating_base: bool | str = False, srdf=None, strict: bool = True,
              mimic: str = "mimic") -> System:
    """Import a URDF file with numeric parameters; frames are the URDF links and fixed joints by name.
    mimic: "mimic" (a `<mimic>` joint follows its driver, as in Pinocchio's model with mimic=True),
    "independent" (an independent joint, as in Pinocchio's default model; warned) or "refuse".
    Planar joints move in their frame's xy plane, a floating joint joins a root link to the world.
    floating_base: False (fixed), True or "quaternion" (Pinocchio's free flyer), "euler" (ZYX angles).
    Armature comes from the SRDF's rotor parameters when `srdf` is given. With `strict=False` an
    inertia that is not physically possible is a warning, not an error."""
    if floating_base not in (False, True, "quaternion", "euler"):
        raise ModelError("floating_base must be False, True, 'quaternion' or 'euler', "
                         f"got {floating_base!r}")
    base = floating_base if isinstance(floating_base, str) else "quaternion"
    system = from_pinocchio(parse_urdf(path, bool(floating_base), srdf, mimic), strict=strict, base=base)
    system.source = str(path)
    return system


def pinocchio_configuration(system: System, q) -> np.ndarray:
    """Pinocchio's q from eomgen's: a continuous joint's angle θ becomes (cos θ, sin θ), as does a planar
    joint's; the quaternions of a free flyer and a ball joint are the same numbers in both."""
    q = np.asarray(q, float)
    parts, k = [], 0
    continuous = getattr(system, "continuous", [False] * len(system.joints))
    for joint, is_continuous in zip(system.joints, continuous):
        n = len(joint.coordinates)
        parts += [q[..., k + i] for i in range(n - 1)] if isinstance(joint, Planar) else []
        angle = is_continuous or isinstance(joint, Planar)
        parts += [np.cos(q[..., k + n - 1]), np.sin(q[..., k + n - 1])] if angle else \
            [q[..., k + i] for i in range(n)]
        k += n
    return np.stack(parts, axis=-1)
