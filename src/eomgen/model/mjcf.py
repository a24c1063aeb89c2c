"""MJCF import through Pinocchio's parser: the same joint order and q layout as the model of
`pinocchio.buildModelAndLegacyConstraintsFromMJCF`, its connect and weld equalities as loops.

A constraint of Pinocchio joins joint1_placement on joint 1 to joint2_placement on joint 2 (joint 0: the
world). Each becomes two frames there, "<equality>_1" and "<equality>_2", and
`system.add_loop("<equality>_1", "<equality>_2", kind)`: "point" for a connect (3 rows), "frame" for a
weld (6 rows). Pinocchio's rows are in the axes of the first frame (LOCAL), eomgen's in the world's:
J_eomgen = blockdiag(R_1, R_1) J_Pinocchio and F_world = R_1 λ_local (R_1 the first frame's rotation)."""
from __future__ import annotations

from pathlib import Path

import numpy as np

from ..errors import ModelError
from .mjcf_check import NOT_MODELLED, Equality, check_mjcf
from .system import System
from .urdf import from_pinocchio, placement


def parse_mjcf(path, floating_base: bool | None = None):
    """Pinocchio's model of an MJCF file (gravity from `<option>`) and its rigid constraint models;
    floating_base: None (as the file says), True (a free flyer above a root body that has none), False
    (a root body with a free joint refused)."""
    import pinocchio as pin

    path = Path(path)
    gravity, equalities, welded = check_mjcf(path)
    try:
        model, constraints = pin.buildModelAndLegacyConstraintsFromMJCF(str(path))
        free = model.njoints > 1 and model.joints[1].shortname() == "JointModelFreeFlyer"
        if floating_base and not free:
            model, constraints = pin.buildModelAndLegacyConstraintsFromMJCF(str(path),
                                                                            pin.JointModelFreeFlyer())
    except Exception as exc:  # Pinocchio raises ValueError / RuntimeError with the parser's message
        raise ModelError(f"cannot read MJCF {path}: {exc}") from None
    if floating_base is False and free:
        raise ModelError(f"MJCF {path.name}: joint '{model.names[1]}' is a free joint, but "
                         "floating_base=False (leave floating_base as None to take the file's free joint)")
    if model.njoints > 1 and model.joints[1].shortname() == "JointModelFreeFlyer":
        model.jointPlacements[1] = pin.SE3.Identity()  # MuJoCo's q is the body's pose (the parser: p − R p)
    if gravity is not None:
        model.gravity.linear = np.array(gravity)
    forces = (("damping", model.damping), ("frictionloss", model.friction))
    passive = [(name, what, x) for what, values in forces
               for joint, name in zip(model.joints[1:], model.names[1:])
               for x in values[joint.idx_v:joint.idx_v + joint.nv] if x]
    if passive:
        name, what, x = passive[0]
        raise ModelError(f"MJCF {path.name}: joint '{name}': {what} {x:g} {NOT_MODELLED}")
    return model, _matched(model, constraints, equalities, path.name), welded


def _frame(model, name: str, by: str):
    """Pinocchio's frame of a body or a site (a joint may have the same name)."""
    import pinocchio as pin

    kind = pin.FrameType.BODY if by == "body" else pin.FrameType.OP_FRAME
    return model.frames[model.getFrameId(name, kind)]


def _joint_of(model, equality: Equality, which: int, owner: str) -> int:
    """The joint that carries body/site `which` (1 or 2; 0 for the world) of the equality; a body must sit
    at its joint's frame (Pinocchio puts the anchor of a body in the joint's frame)."""
    name = equality.first if which == 1 else equality.second
    if name is None:
        return 0
    frame = _frame(model, name, equality.by)
    if equality.by == "body" and not frame.placement.isIdentity(1e-12):
        raise ModelError(f"{owner}: equality '{equality.name}': body '{name}' is not at its joint's frame "
                         "(a joint pos, or a body without a joint) and Pinocchio's parser would misplace "
                         "the constraint on it: state the equality with sites (site1, site2)")
    return frame.parentJoint


def _matched(model, constraints, equalities: list[Equality], owner: str) -> list:
    """[(equality, Pinocchio's constraint)] in Pinocchio's order (its own, by name; it keeps one
    equality per name, and names unnamed ones after their bodies in a way of its own)."""
    import pinocchio as pin

    if len(constraints) != len(equalities):
        raise ModelError(f"MJCF {owner}: Pinocchio's parser kept {len(constraints)} of the "
                         f"{len(equalities)} equalities (one per name; it names unnamed ones after their "
                         "bodies): give each a name of its own")
    left = {id(e): (e, _joint_of(model, e, 1, owner), _joint_of(model, e, 2, owner)) for e in equalities}
    pairs = []
    for c in constraints:
        kind = "point" if c.type == pin.ContactType.CONTACT_3D else "frame"
        for e, j1, j2 in left.values():
            which, where = e.key
            expected = _frame(model, where, "site").placement.translation if e.by == "site" else where
            found = (c.joint1_placement if which == 1 else c.joint2_placement).translation
            same = (e.kind, j1, j2) == (kind, c.joint1_id, c.joint2_id)
            if same and np.allclose(found, expected, 0, 1e-12):
                pairs.append((e, c))
                del left[id(e)]
                break
        else:
            joints = f"'{model.names[c.joint1_id]}' and '{model.names[c.joint2_id]}'"
            raise ModelError(f"MJCF {owner}: cannot tell which equality Pinocchio's {kind} constraint "
                             f"between joints {joints} is")
    return pairs


def from_mjcf(path, floating_base: bool | None = None, strict: bool = True) -> System:
    """Import an MJCF file with numeric parameters: hinge, slide, ball and free joints, inertias (given or
    from geoms, as Pinocchio computes them), armature, gravity; connect and weld equalities as loops
    (see the module). Frames: the bodies and sites by name. floating_base: see `parse_mjcf`."""
    if floating_base not in (None, False, True):
        raise ModelError(f"floating_base must be None, False or True, got {floating_base!r}")
    import pinocchio as pin

    model, pairs, welded = parse_mjcf(path, floating_base)
    system = from_pinocchio(model, strict=strict)
    for name, on_root, R, p in welded:  # the sites the parser drops
        if name not in system.frames:
            root = system.bodies[0] if on_root and not system.floating_base else None
            system.add_frame(name, root, placement(pin.SE3(R, p)))
    body = {b.joint.name: b.name for b in system.bodies}
    for equality, c in pairs:
        frames = []
        for k, joint, M in ((1, c.joint1_id, c.joint1_placement), (2, c.joint2_id, c.joint2_placement)):
            frames.append(f"{equality.name}_{k}")
            system.add_frame(frames[-1], body[model.names[joint]] if joint else None, placement(M))
        system.add_loop(*frames, kind=equality.kind, name=equality.name)
    system.source = str(path)
    return system
