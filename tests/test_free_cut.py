"""Newton-Euler with a free cut: the closed form, agreement with the other methods, and the reaction
forces against Pinocchio's rnea joint forces, a hand-derived rod force and statics."""
import numpy as np
import pinocchio as pin
import pytest
import sympy as sp

import eomgen as eg
from models import ARM6, assert_methods_agree, cart_pendulum, double_pendulum, numeric_arm, spatial_arm_3dof
from test_pinocchio import pinocchio_model


def test_cart_pendulum_closed_form_and_rod_force():
    system, (m_c, m_p, l, g) = cart_pendulum()
    x, phi = system.q
    xd, phid = system.u
    xdd, phidd = system.ud
    eom = eg.derive(system, method="free_cut")
    M = sp.Matrix([[m_c + m_p, m_p * l * sp.cos(phi)], [m_p * l * sp.cos(phi), m_p * l**2]])
    assert sp.simplify(eom.M - M) == sp.zeros(2, 2)
    assert sp.simplify(eom.b - sp.Matrix([-m_p * l * sp.sin(phi) * phid**2, 0])) == sp.zeros(2, 1)
    assert sp.simplify(eom.g - sp.Matrix([0, m_p * g * l * sp.sin(phi)])) == sp.zeros(2, 1)
    # by hand: the rod pulls the mass towards the pivot with S = m_p (l φ̇² + g cos φ − ẍ sin φ)
    # (radial balance of the point mass in the cart's accelerating frame)
    F, T = eom.reactions["phi"]
    towards_pivot = sp.Matrix([-sp.sin(phi), sp.cos(phi), 0])
    S = m_p * (l * phid**2 + g * sp.cos(phi) - xdd * sp.sin(phi))
    assert sp.simplify((towards_pivot.T * F)[0] - S) == 0
    assert T == sp.zeros(3, 1)
    # the cart's rail carries the weight of both and the vertical inertia of the pendulum
    F_cart, _ = eom.reactions["x"]
    assert sp.simplify(F_cart[0]) == 0


def test_cart_pendulum_cut_equations():
    """The lecture's count: 6 equations in 6 unknowns, 12 with the kinematics; solving the cut
    system directly gives the same accelerations as M u̇ = τ − b − g."""
    system, _ = cart_pendulum()
    eom = eg.derive(system, method="free_cut")
    cut = eom.cut_equations
    assert cut.planar_normal == 2
    assert (len(cut.equations), len(cut.unknowns)) == (6, 6)
    eqs, unknowns = cut.with_kinematics()
    assert (len(eqs), len(unknowns)) == (12, 12)
    assert str(cut) == "6 equations in 6 unknowns (12 in 12 with the kinematics)"
    solution = sp.solve(cut.equations, cut.unknowns, dict=True)
    assert len(solution) == 1
    tau = eom.tau_actuated
    ud = eom.M.LUsolve(tau - eom.b - eom.g)
    for k, udk in enumerate(system.ud):
        assert sp.simplify(solution[0][udk] - ud[k]) == 0
    big = sp.solve(eqs, unknowns, dict=True)[0]
    assert all(sp.simplify(big[udk] - solution[0][udk]) == 0 for udk in system.ud)


def test_spatial_cut_equations_have_six_per_body():
    system = spatial_arm_3dof()
    cut = eg.derive(system, method="free_cut").cut_equations
    assert cut.planar_normal is None
    assert len(cut.equations) == 18 and len(cut.unknowns) == 3 * 5 + 3


SPATIAL = pytest.param(spatial_arm_3dof, marks=pytest.mark.slow)  # symbolic: 22 s


@pytest.mark.parametrize("build", [double_pendulum, SPATIAL])
def test_agrees_with_other_methods_symbolically(build):
    assert_methods_agree(build(), "free_cut")
    assert_methods_agree(build(), "free_cut", reference="lagrange")


def test_agrees_with_lagrange_numerically_with_loads():
    rng = np.random.default_rng(21)
    system, _ = numeric_arm(rng)
    system.add_force("link5", (1.0, 2.0, -0.5), point=(0.1, 0.2, 0.0), in_body_frame=True)
    system.add_actuator("link4", torque=(0.3, 0.0, 0.2), force=0.7, point=(0.1, 0, 0), reaction_point=(0, 0.1, 0.2))
    system.add_spring((None, (0.3, 0.2, 0.1)), ("link5", (0.0, 0.1, 0.1)), stiffness=30.0, rest_length=0.2)
    system.add_damper("link1", ("link3", (0.1, 0.0, 0.0)), damping=2.0)
    fc, la = (eg.codegen(eg.derive(system, method=m)) for m in ("free_cut", "lagrange"))
    for _ in range(5):
        q, u = rng.uniform(-2, 2, 6), rng.uniform(-2, 2, 6)
        np.testing.assert_allclose(fc.M(q), la.M(q), rtol=1e-12, atol=1e-12)
        np.testing.assert_allclose(fc.b(q, u), la.b(q, u), rtol=1e-12, atol=1e-12)
        np.testing.assert_allclose(fc.g(q), la.g(q), rtol=1e-12, atol=1e-12)
        np.testing.assert_allclose(fc.tau(q, u), la.tau(q, u), rtol=1e-12, atol=1e-12)


def _pinocchio_double_pendulum(system):
    model = pin.Model()
    model.gravity.linear = np.array([0.0, -9.81, 0.0])
    parent = 0
    for b in system.bodies:
        jid = model.addJoint(parent, pin.JointModelRZ(), pin.SE3(np.eye(3), np.array(b.placement.translation, float).ravel()),
                             b.joint.name)
        model.appendBodyToJoint(jid, pin.Inertia(float(b.mass), np.array(b.com, float).ravel(),
                                                 np.array(b.inertia.tolist(), float)), pin.SE3.Identity())
        parent = jid
    return model


@pytest.mark.parametrize("robot", ["arm6", "tree", "double_pendulum"])
def test_joint_wrenches_equal_rnea_forces(robot):
    """data.f[i] after rnea(q, v, a) is the spatial force joint i transmits to its body, in the
    joint's local frame; its component along the joint axis is τ_i, the rest is the reaction."""
    rng = np.random.default_rng({"arm6": 31, "tree": 32, "double_pendulum": 33}[robot])
    if robot == "double_pendulum":
        system = double_pendulum(numeric=True)
        model = _pinocchio_double_pendulum(system)
    else:
        system, spec = numeric_arm(rng, ARM6, branch_at=2 if robot == "tree" else None)
        model, _ = pinocchio_model(system, spec)
    data, placements = model.createData(), model.createData()
    f = eg.codegen(eg.derive(system, method="free_cut"))
    n = system.nq
    for _ in range(20):
        q, v, a = rng.uniform(-3, 3, n), rng.uniform(-3, 3, n), rng.uniform(-3, 3, n)
        tau = pin.rnea(model, data, q, v, a)
        pin.forwardKinematics(model, placements, q)  # rnea leaves data.oMi alone
        for i, joint in enumerate(system.joints):
            F, T = f.joint_wrench(joint.name, q, v, a)
            R = placements.oMi[i + 1].rotation
            np.testing.assert_allclose(R.T @ F, data.f[i + 1].linear, rtol=0, atol=1e-10 * max(1, np.abs(F).max()))
            np.testing.assert_allclose(R.T @ T, data.f[i + 1].angular, rtol=0, atol=1e-10 * max(1, np.abs(T).max()))
        # the free components are the joint forces; the reactions have none along the axis
        reactions = f.reactions(q, v, tau_a=tau)
        np.testing.assert_allclose(f.forward_dynamics(q, v, tau), a, atol=1e-9)
        for i, joint in enumerate(system.joints):
            F, T = f.joint_wrench(joint.name, q, v, a)
            e = placements.oMi[i + 1].rotation @ np.array(joint.axis.tolist(), float).ravel()
            free = e @ (F if isinstance(joint, eg.Prismatic) else T)
            assert abs(free - tau[i]) < 1e-9 * max(1, abs(tau[i]))
            RF, RT = reactions[joint.name]
            assert abs(e @ (RF if isinstance(joint, eg.Prismatic) else RT)) < 1e-9 * max(1, np.abs(RT).max())


def test_hanging_chain_carries_its_weight():
    """A chain of 5 links hanging at rest: the top joint carries the whole weight, every joint the
    weight below it, and no torque about the axes (the links hang straight)."""
    masses = [1.0, 2.0, 0.5, 3.0, 1.5]
    system = eg.System(gravity=(0, 0, -9.81))
    parent = None
    for i, m in enumerate(masses):
        parent = system.add_body(f"link{i}", parent=parent, joint=eg.Revolute(f"q_{i}", axis=(1, 0, 0) if i % 2 else (0, 1, 0)),
                                 mass=m, com=(0, 0, -0.25), inertia=np.diag([0.02, 0.02, 0.001]).tolist(),
                                 placement=eg.Placement(translation=(0, 0, -0.5 if i else 0)))
    f = eg.codegen(eg.derive(system, method="free_cut"))
    zero = np.zeros(5)
    reactions = f.reactions(zero, zero)
    np.testing.assert_allclose(f.forward_dynamics(zero, zero), zero, atol=1e-14)
    for i in range(5):
        F, T = reactions[f"q_{i}"]
        np.testing.assert_allclose(F, [0, 0, 9.81 * sum(masses[i:])], rtol=1e-14, atol=1e-12)
        np.testing.assert_allclose(T, 0, atol=1e-12)


def test_reactions_need_the_free_cut():
    system, _ = cart_pendulum()
    with pytest.raises(eg.ModelError, match="free cut"):
        eg.derive(system).reactions
