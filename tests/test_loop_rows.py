"""Loop closures against Pinocchio: J_loop = getConstraintJacobian, the constrained accelerations and loop
forces = constraintDynamics with rigid constraint models (random trees, loops closed at the drawn state),
residuals = the frames' placements; a revolute loop replacing a tree joint = the tree (aba, rnea's joint
wrench); the free cut with the loop cut open = the constrained dynamics."""

import numpy as np
import pinocchio as pin
import pytest
import sympy as sp
from hypothesis import assume, given, settings, strategies as st

import eomgen as eg
import strategies as S
from eomgen.model import pinocchio_configuration
from eomgen.verify import to_pinocchio

COMMON = dict(
    deadline=None, derandomize=True, suppress_health_check=list(__import__("hypothesis").HealthCheck)
)
KINDS = {"point": pin.ContactType.CONTACT_3D, "frame": pin.ContactType.CONTACT_6D}
A, B = "closure frame a", "closure frame b"
# joints whose axes turn with their own angles: Pinocchio 4.1's constraintDynamics leaves out their Ṡ u
# (its accelerations then break M u̇ + b + g = τ + Jᵀλ); J̇u of loops through them is checked by differences
RATE_AXES = {"universal", "zyx"}  # not among the strategies' names (they hold no such pair)


def _pinocchio_constraint(model, kind, frame_a, frame_b):
    fa, fb = (model.frames[model.getFrameId(x, pin.FrameType.OP_FRAME)] for x in (frame_a, frame_b))
    return pin.RigidConstraintModel(
        KINDS[kind],
        model,
        fa.parentJoint,
        fa.placement,
        fb.parentJoint,
        fb.placement,
        pin.ReferenceFrame.LOCAL_WORLD_ALIGNED,
    )


def closed_tree(tree, kind, a, b, rng):
    """The tree with frame A on body a (random placement) and frame B on body b (or the world, b < 0) placed
    where A is at a random state: a loop closed at that state."""
    system = S.eomgen_system(tree)
    q, u = S.random_state(tree, rng)
    system.add_frame(
        A,
        system.bodies[a],
        eg.Placement(
            rotation=S.rotation_from_quaternion(rng.normal(size=4)), translation=rng.uniform(-0.3, 0.3, 3)
        ),
    )
    model, data = placements(system, q)
    oMb = (
        pin.SE3.Identity()
        if b < 0
        else data.oMf[model.getFrameId(system.bodies[b].name, pin.FrameType.BODY)]
    )
    placement = oMb.actInv(data.oMf[model.getFrameId(A, pin.FrameType.OP_FRAME)])
    system.add_frame(
        B,
        None if b < 0 else system.bodies[b],
        eg.Placement(rotation=placement.rotation, translation=placement.translation),
    )
    system.add_loop(A, B, kind=kind)
    return system, q, u


def placements(system, q):
    model = to_pinocchio(system)
    data = model.createData()
    pin.framesForwardKinematics(model, data, pinocchio_configuration(system, q))
    return model, data


def moving(tree, i: int) -> int:
    """The body itself or its first ancestor through fixed joints that moves (−1: the world)."""
    while i >= 0 and tree.bodies[i].kind == "fixed":
        i = tree.bodies[i].parent
    return i


@st.composite
def loops(draw, rate_axes: bool = False):
    tree = draw(
        S.trees(max_bodies=5, loads=False).filter(
            lambda t: rate_axes or not {b.kind for b in t.bodies} & RATE_AXES
        )
    )
    a = draw(st.sampled_from(range(len(tree.bodies))))
    others = [i for i in range(-1, len(tree.bodies)) if moving(tree, i) != moving(tree, a)]
    assume(others)
    b = draw(st.sampled_from(others))
    return tree, a, b, draw(st.sampled_from(sorted(KINDS))), draw(st.integers(0, 2**31))


@settings(max_examples=15, phases=[__import__("hypothesis").Phase.generate], **COMMON)
@given(case=loops())
def test_loops_equal_pinocchio_constraint_dynamics(case):
    """J_c = getConstraintJacobian (LOCAL_WORLD_ALIGNED rows); (u̇, F) = constraintDynamics where the rows
    are independent; the residual vanishes at the closed state and equals the frames' offset elsewhere."""
    tree, a, b, kind, seed = case
    rng = np.random.default_rng(seed)
    system, q, u = closed_tree(tree, kind, a, b, rng)
    f = eg.codegen(eg.derive(system, method="recursive"))
    model, data = placements(system, q)
    constraint = _pinocchio_constraint(model, kind, A, B)
    models, datas = pin.StdVec_RigidConstraintModel(), pin.StdVec_RigidConstraintData()
    models.append(constraint)
    datas.append(constraint.createData())
    tau_a = rng.uniform(-1, 1, f.S.shape[0])
    J = f.contact_jacobian(q)
    u = u - np.linalg.pinv(J) @ (J @ u)  # speeds the loop allows (else J u̇ = −J̇ u may have no solution)
    redundant = np.linalg.matrix_rank(J, tol=1e-9) < J.shape[0]
    pin.initConstraintDynamics(model, data, models, datas)
    settings = (
        [pin.ProximalSettings(1e-14, 1e-6, 1000)] if redundant else []
    )  # a redundant set: regularized
    ddq = pin.constraintDynamics(
        model, data, pinocchio_configuration(system, q), u, f.S.T @ tau_a, models, datas, *settings
    )
    J_pin = pin.getConstraintJacobian(model, data, constraint, datas[0]).reshape(J.shape)
    assert np.allclose(J, J_pin, atol=1e-10), np.abs(J - J_pin).max()
    assert np.allclose(f.closure_residual(q), 0, atol=1e-10)
    q2, _ = S.random_state(tree, rng)
    model2, data2 = placements(system, q2)
    oMa, oMb = (data2.oMf[model2.getFrameId(x, pin.FrameType.OP_FRAME)] for x in (A, B))
    E = oMa.rotation @ oMb.rotation.T
    expected = np.concatenate(
        [
            oMa.translation - oMb.translation,
            2 / (1 + np.trace(E)) * np.array([E[2, 1] - E[1, 2], E[0, 2] - E[2, 0], E[1, 0] - E[0, 1]]),
        ]
    )
    assert np.allclose(f.closure_residual(q2), expected[: J.shape[0]], atol=1e-10)
    M = f.M(q)
    assume(np.linalg.eigvalsh(M).min() > 1e-6 * np.abs(M).max())  # massless leaves: M (near) singular
    sigma = np.linalg.svd(J, compute_uv=False) / np.abs(J).max()
    assume(not np.any((sigma > 1e-12) & (sigma < 1e-6)))  # near-singular sets: test_contacts
    ud, F = f.constrained_dynamics(q, u, tau_a)
    scale = 1e-8 * (1 + np.abs(F).max() + np.abs(ud).max())
    if not redundant:
        assert np.allclose(ud, ddq, atol=scale), np.abs(ud - ddq).max()
        assert np.allclose(F, data.lambda_c, atol=scale), np.abs(F - data.lambda_c).max()
    # in any case (a redundant set's forces are not unique, and Pinocchio's proximal solve of it stops
    # near 1e-6): (u̇, F) satisfy Pinocchio's equations, F in the range of J (eomgen's minimum-norm forces)
    qp = pinocchio_configuration(system, q)
    pin.forwardKinematics(model, data, qp, u, 0 * u)
    pin.updateFramePlacements(model, data)
    a = [
        pin.getFrameClassicalAcceleration(
            model, data, model.getFrameId(x, pin.FrameType.OP_FRAME), pin.ReferenceFrame.LOCAL_WORLD_ALIGNED
        )
        for x in (A, B)
    ]
    Jdot_u = np.concatenate([a[0].linear - a[1].linear, a[0].angular - a[1].angular])[: J.shape[0]]
    tau = pin.rnea(
        model, data, qp, u, ud
    )  # inverse dynamics (crba can differ from it: a helical pitch 1e-45)
    scale = 1e-8 * (1 + np.abs(tau).max() + np.abs(J.T @ F).max())
    assert np.allclose(tau - f.S.T @ tau_a - J_pin.T @ F, 0, atol=scale)
    conditioning = (
        np.abs(J).max() * (np.abs(tau).max() + np.abs(J.T @ F).max()) / np.linalg.eigvalsh(M).min()
    )
    assert np.allclose(J_pin @ ud + Jdot_u, 0, atol=1e-8 * (1 + conditioning))
    null = np.linalg.svd(J.T)[2][np.linalg.matrix_rank(J, tol=1e-9) :]
    assert np.allclose(null @ F, 0, atol=1e-8 * (1 + np.abs(F).max()))


@settings(max_examples=10, phases=[__import__("hypothesis").Phase.generate], **COMMON)
@given(case=loops(rate_axes=True))
def test_loop_bias_is_the_rate_of_J_u(case):
    """J̇u = d/dt (J(q(t)) u) at fixed u, central differences along q(t) = integrate(q, u, t), any joint."""
    tree, a, b, kind, seed = case
    rng = np.random.default_rng(seed)
    system, q, u = closed_tree(tree, kind, a, b, rng)
    f = eg.codegen(eg.derive(system, method="recursive"))
    h = 1e-5
    rate = (
        f.contact_jacobian(eg.integrate(system, q, u, h))
        - f.contact_jacobian(eg.integrate(system, q, u, -h))
    ) / (2 * h)
    assert np.allclose(f.contact_jacobian_dot_u(q, u), rate @ u, atol=1e-6 * (1 + np.abs(rate @ u).max()))


def at(*translation) -> eg.Placement:
    return eg.Placement(translation=translation)


def link(system, name, joint, parent=None, mass=1.0, com=(0, 0, 0), placement=None):
    """A body with the inertia diag(0.1, 0.2, 0.25)."""
    return system.add_body(
        name,
        parent=parent,
        joint=joint,
        mass=mass,
        com=com,
        inertia=np.diag([0.1, 0.2, 0.25]),
        placement=placement,
    )


def test_revolute_loop_replacing_a_joint_equals_the_tree():
    """A chain world → A → B → C with revolute joints; B cut off the chain onto a free flyer and held to A by
    a revolute loop: the constrained accelerations are the tree's (Pinocchio aba: A's and C's q̈, B's spatial
    acceleration in its own axes), the loop force is minus the joint wrench B gets from A (rnea's data.f).
    """
    rng = np.random.default_rng(3)
    joint_B = eg.Placement(
        rotation=S.rotation_from_quaternion(rng.normal(size=4)), translation=(0.4, 0.1, -0.2)
    )
    tree = eg.System(gravity=(0, 0, -9.81))
    link(tree, "A", joint=eg.Revolute("a", axis=(0, 1, 0)), mass=2, com=(0.2, 0, 0.1))
    link(tree, "B", eg.Revolute("b", axis=(0, 0, 1)), "A", 1.5, (0.1, 0.2, 0), joint_B)
    joint_C = eg.Placement(translation=(0.3, 0, 0.1))
    link(tree, "C", eg.Revolute("c", axis=(1, 0, 0)), "B", 1, (0, 0.1, 0.3), joint_C)
    q, u, tau = rng.uniform(-1, 1, 3), rng.uniform(-1, 1, 3), rng.uniform(-1, 1, 3) * [1, 0, 1]  # b passive
    model = to_pinocchio(tree)
    data = model.createData()
    ddq = pin.aba(model, data, q, u, tau)
    pin.rnea(model, data, q, u, ddq)
    pin.forwardKinematics(model, data, q, u, ddq)
    jB = model.getJointId("b")
    oMB, v_B, a_B, f_B = data.oMi[jB], data.v[jB], data.a[jB], data.f[jB]

    cut = eg.System(gravity=(0, 0, -9.81))
    link(cut, "A", joint=eg.Revolute("a", axis=(0, 1, 0)), mass=2, com=(0.2, 0, 0.1))
    link(cut, "B", joint=eg.FreeFlyer("base"), mass=1.5, com=(0.1, 0.2, 0))
    link(cut, "C", eg.Revolute("c", axis=(1, 0, 0)), "B", 1, (0, 0.1, 0.3), joint_C)
    cut.add_frame("joint b", "A", joint_B)
    cut.add_loop("joint b", "B", kind="revolute", axis=(0, 0, 1))
    f = eg.codegen(eg.derive(cut, method="recursive"))
    quat = pin.Quaternion(oMB.rotation).coeffs()
    q_cut = np.concatenate([[q[0]], oMB.translation, quat, [q[2]]])
    u_cut = np.concatenate([[u[0]], v_B.linear, v_B.angular, [u[2]]])
    assert np.allclose(f.closure_residual(q_cut), 0, atol=1e-12)
    assert np.allclose(f.contact_jacobian(q_cut) @ u_cut, 0, atol=1e-12)
    ud, F = f.constrained_dynamics(q_cut, u_cut, tau_a=tau[[0, 2]])
    assert np.allclose(ud, np.concatenate([[ddq[0]], a_B.linear, a_B.angular, [ddq[2]]]), atol=1e-10)
    R_B, R_frame = oMB.rotation, data.oMi[model.getJointId("a")].rotation @ np.array(
        joint_B.rotation, float
    )
    normals = [R_frame @ np.array(n, float).ravel() for n in cut.loops[0].normals]
    expected = np.concatenate([-R_B @ f_B.linear, [-t @ R_B @ f_B.angular for t in normals]])
    assert np.allclose(F, expected, atol=1e-10), (F, expected)


def test_free_cut_with_the_loop_cut_open_equals_the_constrained_dynamics():
    """A spatial loop between two branches: the cut-free balances with the loop force as unknowns, solved at
    a state, give the u̇ and loop forces of the constrained dynamics."""
    system = eg.System(gravity=(0, 0, -9.81))
    link(system, "a1", joint=eg.Revolute("q1", axis=(0, 0, 1)), mass=1, com=(0.2, 0, 0))
    link(system, "a2", eg.Revolute("q2", axis=(0, 1, 0)), "a1", 1, (0.2, 0, 0), at(0.5, 0, 0))
    link(system, "b1", eg.Spherical("ball"), None, 1, (0, 0, 0.2), at(0.6, 0.4, 0))
    system.add_frame("tip", "a2", eg.Placement(translation=(0.4, 0, 0)))
    system.add_frame("end", "b1", eg.Placement(translation=(0, 0, 0.5)))
    system.add_loop("tip", "end", kind="point")
    eom = eg.derive(system, method="free_cut")
    f = eg.codegen(eom)
    rng = np.random.default_rng(5)
    quaternion = rng.normal(size=4)
    q = np.concatenate([rng.uniform(-1, 1, 2), quaternion / np.linalg.norm(quaternion)])
    u = rng.uniform(-1, 1, 5)
    tau_a = rng.uniform(-1, 1, f.S.shape[0])
    ud, F = f.constrained_dynamics(q, u, tau_a)
    cut = eom.cut_equations
    values = {**dict(zip(system.q, q)), **dict(zip(system.u, u))}
    equations = [sp.sympify(e).xreplace(values) for e in cut.equations]
    efforts = sorted(set().union(*(e.free_symbols for e in equations)) - set(cut.unknowns), key=str)
    assert [x.name for x in efforts] == ["tau_ball_0", "tau_ball_1", "tau_ball_2", "tau_q1", "tau_q2"]
    order = [2, 3, 4, 0, 1]  # S's rows follow the joints: q1, q2, ball
    A, b = sp.linear_eq_to_matrix(
        [e.xreplace(dict(zip(efforts, tau_a[order]))) for e in equations], cut.unknowns
    )
    x = np.linalg.lstsq(np.array(A, float), np.array(b, float).ravel(), rcond=None)[0]
    solved = dict(zip(cut.unknowns, x))
    assert np.allclose([solved[s] for s in system.ud], ud, atol=1e-10)
    loop_forces = [s for s in cut.unknowns if s.name.startswith("F_tip-end")]
    assert np.allclose([solved[s] for s in loop_forces], F, atol=1e-10)


def test_a_loop_within_one_rigid_body_is_refused():
    system = eg.System()
    system.add_body("arm", joint=eg.Revolute("q", axis=(0, 0, 1)), mass=1, inertia=np.eye(3))
    system.add_body(
        "flange", parent="arm", mass=1, inertia=np.eye(3), placement=eg.Placement(translation=(1, 0, 0))
    )
    system.add_body("bracket", mass=1, inertia=np.eye(3))
    system.add_frame("tip", "flange")
    system.add_frame("ground", None)
    with pytest.raises(eg.ModelError, match="both fixed on body 'arm'"):
        system.add_loop("tip", "arm")
    with pytest.raises(eg.ModelError, match="both fixed on the world"):
        system.add_loop("bracket", "ground")
    with pytest.raises(eg.ModelError, match="and itself"):
        system.add_loop("tip", "tip")
    with pytest.raises(eg.ModelError, match="unknown frame"):
        system.add_loop("tip", "nowhere")
    with pytest.raises(eg.ModelError, match="kind must be one of"):
        system.add_loop("tip", "ground", kind="prismatic")


def test_loop_residuals_have_no_false_zero_at_a_half_turn_and_names_are_one_namespace():
    """A weld of a rotor to the world: 2 tan(θ/2) about the axis (½ vee(E − Eᵀ) would vanish at θ = π);
    a revolute loop whose axes are opposite is open too. Contacts, loops and disks share names."""
    system = eg.System()
    system.add_body("rotor", joint=eg.Revolute("theta", axis=(1, 0, 0)), mass=1, inertia=np.eye(3))
    system.add_frame("ground", None)
    system.add_loop("rotor", "ground", kind="frame", name="weld")
    f = eg.codegen(eg.derive(system, method="recursive"))
    for theta in (0.3, 2.0, np.pi - 1e-3):
        assert np.allclose(f.closure_residual(np.array([theta]))[3:], [2 * np.tan(theta / 2), 0, 0])
    hinge = eg.System()
    hinge.add_body("rotor", joint=eg.Revolute("theta", axis=(1, 0, 0)), mass=1, inertia=np.eye(3))
    hinge.add_frame("ground", None)
    hinge.add_loop("rotor", "ground", kind="revolute", axis=(0, 0, 1))
    g = eg.codegen(eg.derive(hinge, method="recursive"))
    assert np.abs(g.closure_residual(np.array([np.pi - 1e-3]))[3:]).max() > 100
    with pytest.raises(eg.ModelError, match="exists already"):
        system.add_loop("rotor", "ground", kind="point", name="weld")
    system.add_loop("rotor", "ground", kind="point", name="rotor")
    with pytest.raises(eg.ModelError, match="exists already"):
        system.add_contact("rotor")
    with pytest.raises(eg.ModelError, match="an axis is given for a revolute loop only"):
        system.add_loop("rotor", "ground", kind="point", axis=(1, 0, 0))


def test_forces_follow_the_parameters_and_a_changed_system_is_refused():
    """A crank tilted by a parameter: which rows can be violated depends on it (never cached across
    values); functions generated before a contact was added are refused."""
    alpha = sp.Symbol("alpha")
    system = eg.System(gravity=(0, 0, -9.81))
    tilt = eg.Placement(
        rotation=sp.Matrix(
            [[1, 0, 0], [0, sp.cos(alpha), -sp.sin(alpha)], [0, sp.sin(alpha), sp.cos(alpha)]]
        )
    )
    system.add_body(
        "crank",
        joint=eg.Revolute("q", axis=(0, 0, 1)),
        mass=1,
        com=(0.5, 0, 0),
        inertia=np.eye(3) * 0.1,
        placement=tilt,
    )
    system.add_frame("tip", "crank", eg.Placement(translation=(1, 0, 0)))
    system.add_frame("pin", None, eg.Placement(translation=(1, 0, 0)))
    system.add_loop("tip", "pin", kind="point")
    f = eg.codegen(eg.derive(system, method="recursive"))
    q, u = np.zeros(1), np.zeros(1)
    f.constrained_dynamics(q, u, params={"alpha": 0.0})
    u_dot, F = f.constrained_dynamics(q, u, params={"alpha": 0.5})
    J, Jdot_u = f.contact_jacobian(q, {"alpha": 0.5}), f.contact_jacobian_dot_u(q, u, {"alpha": 0.5})
    assert np.allclose(J @ u_dot + Jdot_u, 0, atol=1e-12)
    assert np.allclose(J.T @ F, f.M(q, {"alpha": 0.5}) @ u_dot + f.nle(q, u, {"alpha": 0.5}), atol=1e-12)
    system.add_contact("crank")
    with pytest.raises(eg.ModelError, match="the system changed"):
        f.constrained_dynamics(q, u, params={"alpha": 0.5})
