"""Comparison with Pinocchio: M, b, g, frame Jacobians and J̇u at random states.

J̇ u is compared with the frame's classical acceleration at u̇ = 0 from `forwardKinematics`: Pinocchio's
`getFrameJacobianTimeVariation` leaves out the rate of a joint's own motion subspace (Ṡ of a universal
or ZYX spherical joint), which finite differences of its own Jacobian show.

The reference is the Pinocchio model the system was imported from (URDF), or else one built from the
system with Pinocchio's own API (addJoint, appendBodyToJoint, addFrame)."""
from __future__ import annotations

import time
from dataclasses import dataclass, field

import numpy as np

from .numeric import codegen
from .errors import ModelError
from .methods import derive
from .model import (Cylindrical, FreeFlyer, Helical, Planar, Prismatic, Revolute, Spherical, System,
                    Translation, Universal)
from .model.urdf import pinocchio_configuration
from .state import random_states


def pinocchio_joint(joint, arr):
    """Pinocchio's model of an eomgen joint (a cylindrical joint is a composite of its translation and
    rotation; a mimic joint is built as its type and turned into a mimic afterwards)."""
    import pinocchio as pin

    def axis_model(kind, axis):
        a = arr(axis).ravel()
        principal = {(1.0, 0.0, 0.0): "X", (0.0, 1.0, 0.0): "Y", (0.0, 0.0, 1.0): "Z"}.get(tuple(a))
        return getattr(pin, f"JointModel{kind}{principal}")() if principal else \
            getattr(pin, {"R": "JointModelRevoluteUnaligned", "P": "JointModelPrismaticUnaligned"}[kind])(a)

    if isinstance(joint, FreeFlyer):
        if joint.parametrization != "quaternion":
            raise ModelError(f"joint '{joint.name}': Pinocchio has no ZYX Euler free flyer; compare "
                             "the quaternion base with Pinocchio and map the speeds")
        return pin.JointModelFreeFlyer()
    if isinstance(joint, Spherical):
        quaternion = joint.parametrization == "quaternion"
        return pin.JointModelSpherical() if quaternion else pin.JointModelSphericalZYX()
    if isinstance(joint, Universal):
        return pin.JointModelUniversal(arr(joint.axis1).ravel(), arr(joint.axis2).ravel())
    if isinstance(joint, Helical):
        return pin.JointModelHelicalUnaligned(arr(joint.axis).ravel(), float(joint.pitch))
    if isinstance(joint, Cylindrical):
        composite = pin.JointModelComposite(axis_model("P", joint.axis))
        composite.addJoint(axis_model("R", joint.axis))
        return composite
    simple = {Planar: pin.JointModelPlanar, Translation: pin.JointModelTranslation}
    if type(joint) in simple:
        return simple[type(joint)]()
    if isinstance(joint, (Revolute, Prismatic)):
        return axis_model("R" if isinstance(joint, Revolute) else "P", joint.axis)
    raise ModelError(f"joint '{joint.name}': no Pinocchio counterpart for {type(joint).__name__}")


def to_pinocchio(system: System):
    """A Pinocchio model of a numeric system (every joint type by Pinocchio's joint model, fixed bodies
    merged into their moving ancestor, bodies and frames as frames, mimic joints as Pinocchio's)."""
    import pinocchio as pin

    def arr(m):
        try:
            return np.array(m.tolist(), dtype=float)
        except TypeError:
            raise ModelError("verification against Pinocchio needs numeric parameters; "
                             f"symbols left: {sorted(map(str, system.parameters))}") from None

    model = pin.Model()
    model.gravity.linear = arr(system.gravity).ravel()
    # where: body -> (Pinocchio joint id, SE3 of the body frame in that joint's frame)
    where, ids, mimics = {}, {}, []
    for body in system.bodies:
        jid, M_parent = where[body.parent] if body.parent else (0, pin.SE3.Identity())
        M = M_parent * pin.SE3(arr(body.placement.rotation), arr(body.placement.translation).ravel())
        if body.speed_indices:
            jid = model.addJoint(jid, pinocchio_joint(body.joint, arr), M, body.joint.name)
            ids[body.joint.name] = jid
            if body.index is not None:
                for k in range(body.joint.dof):
                    model.armature[model.joints[jid].idx_v + k] = float(body.joint.armature)
            else:
                mimics.append(body.joint)
            M = pin.SE3.Identity()
        inertia = pin.Inertia(float(body.mass), arr(body.com).ravel(), arr(body.inertia))
        model.appendBodyToJoint(jid, inertia, M)
        model.addFrame(pin.Frame(body.name, jid, M, pin.FrameType.BODY))
        where[body] = (jid, M)
    where[None] = (0, pin.SE3.Identity())  # frames fixed in the world
    for f in system.frames.values():
        jid, M = where[f.body]
        placement = M * pin.SE3(arr(f.placement.rotation), arr(f.placement.translation).ravel())
        model.addFrame(pin.Frame(f.name, jid, placement, pin.FrameType.OP_FRAME))
    for joint in mimics:
        model = pin.transformJointIntoMimic(model, ids[joint.mimic.driver.name], ids[joint.name],
                                            float(joint.mimic.multiplier), float(joint.mimic.offset))
    for joint in mimics:  # a mimic's rotor turns with k u_driver: k² I_a on the driver's speed
        model.armature[model.joints[ids[joint.mimic.driver.name]].idx_v] += (
            float(joint.mimic.multiplier) ** 2 * float(joint.armature))
    return model


def mass_matrix(model, data, q) -> np.ndarray:
    """Pinocchio's M: crba (upper triangle mirrored), or, for a model with mimic joints, whose crba in
    Pinocchio 4.1 is wrong with a multi-axis joint between driver and mimic and keeps stale entries of
    a reused data, the columns M e_j = rnea(q, 0, e_j) − g + armature."""
    import pinocchio as pin

    if not any(j.shortname() == "JointModelMimic" for j in model.joints):
        M = pin.crba(model, data, q)
        return np.triu(M) + np.triu(M, 1).T
    g = pin.rnea(model, data, q, np.zeros(model.nv), np.zeros(model.nv))
    M = np.column_stack([pin.rnea(model, data, q, np.zeros(model.nv), e) - g for e in np.eye(model.nv)])
    return M


def end_frames(system: System) -> list[str]:
    """The frames on the leaves of the tree (bodies with no moving descendant), and those bodies."""
    parents = {b.parent for b in system.bodies}
    leaves = {b for b in system.bodies if b not in parents}
    ends = [b.name for b in system.bodies if b in leaves and b.index is not None]
    ends += [name for name, f in system.frames.items() if f.body in leaves]
    return ends


@dataclass
class Report:
    """Maximum absolute and relative error of each quantity over the states (relative to
    ``max(1, |ref|)``)."""

    name: str
    method: str
    backend: str
    nq: int
    states: int
    derive_seconds: float
    codegen_seconds: float
    errors: dict[str, tuple[float, float]] = field(default_factory=dict)

    def worst(self) -> float:
        """The largest relative error of all quantities."""
        return max(rel for _, rel in self.errors.values())

    def ok(self, tol: float = 1e-10) -> bool:
        """True if the largest relative error is at most `tol`."""
        return self.worst() <= tol

    def __str__(self) -> str:
        lines = [f"{self.name}: nq = {self.nq}, method {self.method}, backend {self.backend}, "
                 f"{self.states} random states",
                 f"derivation {self.derive_seconds:.2f} s, code generation {self.codegen_seconds:.2f} s",
                 f"{'quantity':40s} {'max abs error':>14s} {'max rel error':>14s}"]
        lines += [f"{k:40s} {a:14.2e} {r:14.2e}" for k, (a, r) in self.errors.items()]
        lines.append(f"worst relative error {self.worst():.2e}: {'OK' if self.ok() else 'FAILED'} (tolerance 1e-10)")
        return "\n".join(lines)


def verify(system: System, method: str | None = None, backend: str = "numpy", states: int = 20,
           frames: list[str] | None = None, seed: int = 0, engine: str | None = None) -> Report:
    """Derive, generate and compare M, b, g and the Jacobians and J̇u of `frames` (default: the end
    frames) with Pinocchio at `states` random states (method and engine: `derive`'s, default the
    cheapest and the fastest)."""
    if not isinstance(system, System):
        raise ModelError(f"verify: expected a System (it derives the equations itself), "
                         f"got {type(system).__name__}")
    import pinocchio as pin

    model = getattr(system, "pinocchio_model", None) or to_pinocchio(system)
    data = model.createData()
    t0 = time.perf_counter()
    frames = end_frames(system) if frames is None else frames
    eom = derive(system, method=method, frames=frames, engine=engine)  # J and J̇ u generated with M, b, g
    t1 = time.perf_counter()
    f = codegen(eom, backend=backend)
    t2 = time.perf_counter()
    name = getattr(system, "name", None) or getattr(system, "source", "system")
    report = Report(name, eom.method, backend,
                    system.nq, states, t1 - t0, t2 - t1)
    q, u, _ = random_states(system, states, np.random.default_rng(seed))
    LWA = pin.ReferenceFrame.LOCAL_WORLD_ALIGNED

    def record(key, ours, ref):
        ref = np.reshape(ref, np.shape(ours))  # Pinocchio returns a 6 × 1 matrix as a flat array
        a = float(np.abs(ours - ref).max())
        r = a / max(1.0, float(np.abs(ref).max()))
        old = report.errors.get(key, (0.0, 0.0))
        report.errors[key] = (max(old[0], a), max(old[1], r))

    for qk, uk in zip(q, u):
        qp = pinocchio_configuration(system, qk)
        g = pin.computeGeneralizedGravity(model, data, qp)
        record("M", f.M(qk), mass_matrix(model, data, qp))
        record("g", f.g(qk), g)
        record("b", f.b(qk, uk), pin.nonLinearEffects(model, data, qp, uk) - g)
        pin.computeJointJacobians(model, data, qp)
        pin.forwardKinematics(model, data, qp, uk, np.zeros(model.nv))  # J̇ u: the acceleration at u̇ = 0
        pin.updateFramePlacements(model, data)
        for name in frames:
            if not model.existFrame(name):
                raise ModelError(f"frame {name!r} is not in the Pinocchio model")
            fid = model.getFrameId(name)
            record(f"J {name}", f.jacobian(name, qk), pin.getFrameJacobian(model, data, fid, LWA))
            a = pin.getFrameClassicalAcceleration(model, data, fid, LWA)
            record(f"Jdot_u {name}", f.jacobian_dot_u(name, qk, uk), np.r_[a.linear, a.angular])
    return report
