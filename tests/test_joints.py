"""Every joint type against Pinocchio's own joint model (JointModelSpherical, SphericalZYX, Universal,
Planar, Translation, HelicalUnaligned, a composite for the cylindrical joint, Mimic): M, b, g, frame
Jacobians and J̇u of every derivation, with the joint at the root, in the middle and at a leaf of a
branched tree; the free cut's joint wrenches against rnea's data.f; integration against
pinocchio.integrate; a ball joint against a free flyer whose translation is locked; bad input."""
from __future__ import annotations

import numpy as np
import pinocchio as pin
import pytest
import sympy as sp

import eomgen as eg
from eomgen.model.joints import rotation_about
from eomgen.model.urdf import pinocchio_configuration
from eomgen.verify import to_pinocchio, verify

JOINTS = {
    "spherical": lambda n: eg.Spherical(n),
    "zyx": lambda n: eg.Spherical(n, parametrization="zyx"),
    "universal": lambda n: eg.Universal(n, (1, 0, 0), (0.2, 1, 0.3)),
    "planar": lambda n: eg.Planar(n),
    "cylindrical": lambda n: eg.Cylindrical(n, (0.3, 0.2, 1)),
    "translation": lambda n: eg.Translation(n),
    "helical": lambda n: eg.Helical(n, (0.1, 0.3, 1), pitch=0.2),
}
METHODS = ("recursive", "projected_newton_euler", "free_cut", "lagrange")


def _rotation(rng) -> sp.Matrix:
    a = sp.Matrix([sp.Rational(int(x), 100) for x in rng.uniform(-100, 100, 3)])
    return rotation_about(a / sp.sqrt((a.T * a)[0]), sp.Rational(int(rng.uniform(-300, 300)), 100))


def _inertia(rng) -> sp.Matrix:
    """R diag(λ) Rᵀ with principal moments that keep the triangle inequality."""
    R = _rotation(rng)
    return (R * sp.diag(*[sp.Rational(int(x), 1000) for x in rng.uniform(100, 150, 3)]) * R.T).evalf(30)


def tree(make, where: int, seed: int = 0) -> eg.System:
    """Four bodies, b0 → b1 → b2 and b0 → b3 (a branch), revolute joints on skew axes, rotated and
    offset placements; the joint under test moves body `where` (0 root, 1 middle, 2 leaf)."""
    rng = np.random.default_rng(seed)
    system = eg.System(gravity=(0.3, -0.2, -9.81))
    parents = [None, "b0", "b1", "b0"]
    axes = [(1, 0, 0), (0.3, 0.4, 0.5), (0, 0, 1), (0, 1, 0)]
    for k, parent in enumerate(parents):
        joint = make(f"j{k}") if k == where else eg.Revolute(f"r{k}", axis=axes[k])
        system.add_body(f"b{k}", parent=parent, joint=joint, mass=sp.Rational(k + 2, 3),
                        com=(0.1, -0.05 * k, 0.2), inertia=_inertia(rng),
                        placement=eg.Placement(rotation=_rotation(rng), translation=(0.2, 0.1 * k, -0.3)))
    system.add_frame("tip", "b2", eg.Placement(translation=(0.1, 0.2, 0.3)))
    return system


@pytest.mark.parametrize("kind", sorted(JOINTS))
@pytest.mark.parametrize("where", [0, 1, 2], ids=["root", "middle", "leaf"])
def test_joint_equals_pinocchio(kind, where):
    """verify: M (crba), b + g (nonLinearEffects), g, frame Jacobians and the classical acceleration at
    u̇ = 0 (J̇u) of Pinocchio's model with the joint's own JointModel, 1e-12 relative."""
    system = tree(JOINTS[kind], where)
    for method in METHODS if where == 1 else ("recursive", "lagrange"):
        report = verify(system, method=method, states=4, frames=["tip", "b1", "b3"])
        assert report.ok(1e-12), str(report)


@pytest.mark.parametrize("kind", sorted(JOINTS))
def test_free_cut_wrenches_equal_rnea_forces(kind):
    """data.f[i] after rnea(q, v, a) is the wrench joint i transmits, in its child frame; the free
    cut's reactions lie in the directions the joint blocks (no power with its motion subspace)."""
    system = tree(JOINTS[kind], 1, seed=5)
    model = to_pinocchio(system)
    data, frames = model.createData(), model.createData()
    f = eg.codegen(eg.derive(system, method="free_cut"))
    q, u, ud = eg.random_states(system, 4, np.random.default_rng(2))
    for qk, uk, ak in zip(q, u, ud):
        qp = pinocchio_configuration(system, qk)
        tau = pin.rnea(model, data, qp, uk, ak)
        pin.forwardKinematics(model, frames, qp)
        for i, joint in enumerate(system.joints):
            F, T = f.joint_wrench(joint.name, qk, uk, ak)
            R = frames.oMi[i + 1].rotation
            tol = 1e-11 * max(1, np.abs(F).max(), np.abs(T).max())
            np.testing.assert_allclose(R.T @ F, data.f[i + 1].linear, atol=tol)
            np.testing.assert_allclose(R.T @ T, data.f[i + 1].angular, atol=tol)
        reactions = f.reactions(qk, uk, tau_a=tau)
        pin.computeJointJacobians(model, frames, qp)
        for i, joint in enumerate(system.joints):
            J = pin.getJointJacobian(model, frames, i + 1, pin.LOCAL_WORLD_ALIGNED)
            idx = model.joints[i + 1].idx_v
            S = J[:, idx:idx + model.joints[i + 1].nv]  # the joint's motion subspace in world axes
            F, T = reactions[joint.name]
            assert np.abs(S.T @ np.r_[F, T]).max() < 1e-10 * max(1, np.abs(np.r_[F, T]).max())


@pytest.mark.parametrize("kind", sorted(JOINTS))
def test_integrate_equals_pinocchio(kind):
    system = tree(JOINTS[kind], 1)
    model = to_pinocchio(system)
    q, u, _ = eg.random_states(system, 5, np.random.default_rng(3))
    for qk, uk in zip(q, u):
        for dt in (1e-3, 0.7):
            ours = pinocchio_configuration(system, eg.integrate(system, qk, uk, dt))
            theirs = pin.integrate(model, pinocchio_configuration(system, qk), uk * dt)
            np.testing.assert_allclose(ours, theirs, atol=1e-13)


def _on_base(joint, rng_seed: int = 4) -> eg.System:
    """A body on `joint` at the root carrying an arm of two revolute joints."""
    rng = np.random.default_rng(rng_seed)
    system = eg.System()
    system.add_body("base", joint=joint, mass=2, com=(0.1, 0.0, -0.05), inertia=_inertia(rng))
    system.add_body("upper", parent="base", joint=eg.Revolute("a", axis=(0, 1, 0)), mass=1, com=(0, 0, 0.2),
                    inertia=_inertia(rng), placement=eg.Placement(translation=(0.1, 0.2, 0.3)))
    system.add_body("lower", parent="upper", joint=eg.Revolute("b", axis=(1, 0, 0)), mass=0.5,
                    com=(0, 0.1, 0.1), inertia=_inertia(rng),
                    placement=eg.Placement(translation=(0, 0, 0.4)))
    return system


def test_ball_joint_is_a_free_flyer_with_locked_translation():
    """At zero base position and translational speed, the free flyer's rotational rows and columns are
    the ball joint's equations (both in body-axis angular velocity and a unit quaternion)."""
    ball, free = _on_base(eg.Spherical("ball")), _on_base(eg.FreeFlyer("base_joint"))
    fb = eg.codegen(eg.derive(ball, method="projected_newton_euler"))
    ff = eg.codegen(eg.derive(free, method="lagrange"))
    q, u, _ = eg.random_states(ball, 5, np.random.default_rng(6))
    rot = list(range(3, 8))
    for qk, uk in zip(q, u):
        qf, uf = np.r_[0.0, 0.0, 0.0, qk], np.r_[0.0, 0.0, 0.0, uk]
        np.testing.assert_allclose(fb.M(qk), ff.M(qf)[np.ix_(rot, rot)], atol=1e-12)
        np.testing.assert_allclose(fb.b(qk, uk), ff.b(qf, uf)[rot], atol=1e-12)
        np.testing.assert_allclose(fb.g(qk), ff.g(qf)[rot], atol=1e-12)


def gripper() -> eg.System:
    """An arm with a palm and two fingers whose joints follow one driving joint (a revolute finger
    with multiplier −1, a prismatic one with 0.5 and an offset)."""
    rng = np.random.default_rng(9)
    s = eg.System()
    s.add_body("arm", joint=eg.Revolute("shoulder", axis=(0, 0, 1)), mass=2, com=(0.2, 0, 0),
               inertia=_inertia(rng))
    s.add_body("palm", parent="arm", joint=eg.Revolute("grip", axis=(0, 1, 0)), mass=0.5, com=(0, 0, 0.05),
               inertia=_inertia(rng), placement=eg.Placement(translation=(0.4, 0, 0)))
    s.add_body("left", parent="palm", joint=eg.Revolute("left_finger", (0, 1, 0), mimic=("grip", -1, 0)),
               mass=0.1, com=(0.05, 0, 0), inertia=_inertia(rng),
               placement=eg.Placement(translation=(0, 0.03, 0.1)))
    s.add_body("right", parent="palm",
               joint=eg.Prismatic("right_finger", (0, 1, 0), mimic=("grip", 0.5, 0.01)),
               mass=0.1, com=(0.05, 0, 0), inertia=_inertia(rng),
               placement=eg.Placement(translation=(0, -0.03, 0.1)))
    s.add_body("nail", parent="left", joint=eg.Revolute("nail", (1, 0, 0)), mass=0.05, com=(0.02, 0, 0),
               inertia=_inertia(rng), placement=eg.Placement(translation=(0.1, 0, 0)))
    return s


@pytest.mark.parametrize("method", METHODS)
def test_mimic_equals_pinocchio(method):
    """A mimic joint has no coordinate; Pinocchio's model made with transformJointIntoMimic."""
    system = gripper()
    assert [str(x) for x in system.q] == ["shoulder", "grip", "nail"]
    report = verify(system, method=method, states=4, frames=["left", "right", "nail"])
    assert report.ok(1e-12), str(report)


def test_mimic_kinematics_follow_the_driver():
    system = gripper()
    q0 = np.array([0.3, 0.4, 0.0])
    f = eg.codegen(eg.derive(system, frames=["left"]))
    # the left finger turns by −grip about the palm's grip axis: its angular velocity from grip is zero
    np.testing.assert_allclose(f.jacobian("left", q0)[3:, 1], 0, atol=1e-15)


@pytest.mark.parametrize("make, match", [
    (lambda s: s.add_body("x", joint=eg.Revolute("m", mimic=("nowhere", 1, 0)), mass=1),
     "mimics the unknown joint 'nowhere'"),
    (lambda s: s.add_body("x", joint=eg.Revolute("a", mimic=("a", 1, 0)), mass=1), "cannot mimic itself"),
    (lambda s: s.add_body("x", parent="b1", joint=eg.Revolute("m2", mimic=("m1", 1, 0)), mass=1),
     "mimics 'm1', which mimics 'r0' itself"),
    (lambda s: s.add_body("x", joint=eg.Revolute("m", mimic=("b", 1)), mass=1),
     r"mimic must be \(joint name"),
    (lambda s: s.add_body("x", joint=eg.Revolute("m", mimic=("r0", "2", 0)), mass=1), "mimic multiplier"),
    (lambda s: s.add_body("x", joint=eg.Spherical("s0"), mass=1, parent="b0") and
     s.add_body("y", joint=eg.Revolute("m", mimic=("s0", 1, 0)), mass=1), "not a one-coordinate joint"),
    (lambda s: eg.Universal("u", (1, 0, 0), (2, 0, 0)), "axis1 .* and axis2 .* are parallel"),
    (lambda s: eg.Universal("u", (0, 0, 0), (1, 0, 0)), "axis1 must not be zero"),
    (lambda s: eg.Spherical("s", parametrization="xyz"), "parametrization must be 'quaternion' or 'zyx'"),
    (lambda s: eg.Planar(""), "joint name must be a non-empty string"),
    (lambda s: eg.Helical("h", (0, 0, 1), pitch="0.1"), "pitch"),
    (lambda s: s.add_body("x", parent="b0", joint=eg.FreeFlyer("f"), mass=1), "must attach the root body"),
])
def test_bad_joints_are_refused(make, match):
    s = eg.System()
    s.add_body("b0", joint=eg.Revolute("r0"), mass=1)
    s.add_body("b1", parent="b0", joint=eg.Revolute("m1", mimic=("r0", 2, 0.1)), mass=1)
    with pytest.raises(eg.ModelError, match=match):
        make(s)


def test_every_speed_of_an_actuated_joint_has_a_row_of_S():
    s = _on_base(eg.Spherical("ball"))
    assert s.actuated == ["ball[0]", "ball[1]", "ball[2]", "a", "b"]
    assert s.S == sp.eye(5)
