"""Floating-base robots: a free-flyer base (Pinocchio's q layout, u = base twist in the base frame)."""
import numpy as np
import pytest

import eomgen as eg
from eomgen.verify import verify

# Every floating-base robot of example-robot-data 6 that Pinocchio loads (cassie ships an SDF only).
FLOATING = ["a1", "anymal", "anymal_c", "anymal_kinova", "b1", "b1_z1", "bolt", "go1", "hector", "hyq", "icub",
            "icub_reduced", "iris", "laikago", "romeo", "simple_humanoid", "simple_humanoid_classical", "solo12",
            "solo8", "talos", "talos_box", "talos_full", "talos_full_box"]


def test_the_list_is_complete():
    assert sorted(FLOATING) == eg.robots.names(floating_base=True)


@pytest.mark.filterwarnings("ignore:body")  # some files carry inertias Pinocchio takes as they are
@pytest.mark.parametrize("name", FLOATING)
def test_recursive_equals_pinocchio(name):
    """M, b, g, foot / hand Jacobians and J̇u at 20 random states with random base orientations and
    twists, relative 1e-10."""
    report = verify(eg.robots.load(name), method="recursive", states=20, seed=3)
    assert report.ok(1e-10), str(report)


@pytest.mark.parametrize("name", ["solo12", "talos"])
def test_projected_newton_euler_equals_pinocchio(name):
    report = verify(eg.robots.load(name), states=20, seed=4)
    assert report.ok(1e-10), str(report)


def test_lagrange_on_a_quaternion_base():
    """Lagrange in quasi-velocities (Hamel's terms for the base twist): solo12 = Pinocchio; a free body
    with a com offset, an arm, a spring and a damper to the world and a force: M, b, g and each load's
    τ = projected Newton-Euler's (which projects with Jacobians) at random states, unit quaternions."""
    report = verify(eg.robots.load("solo12"), method="lagrange", states=10, seed=6)
    assert report.ok(1e-10), str(report)
    s = eg.System(gravity=(0.0, 0.0, -9.81))
    box = s.add_body("box", joint=eg.FreeFlyer("ff"), mass=2, com=(0.1, -0.05, 0.2),
                     inertia=[[0.3, 0.01, 0.0], [0.01, 0.2, 0.02], [0.0, 0.02, 0.4]])
    s.add_body("arm", parent=box, joint=eg.Revolute("q1", axis=(0, 1, 0)), mass=1, com=(0.4, 0, 0),
               placement=eg.Placement(translation=(0.2, 0, 0.1)))
    s.add_spring((box, (0.1, 0.2, 0.0)), (None, (1.0, 0.5, 2.0)), 30.0, rest_length=0.5, name="spring")
    s.add_damper(("arm", (0.5, 0.0, 0.0)), None, 4.0, name="damper")
    s.add_force("arm", (1.0, -2.0, 0.5), point=(0.3, 0, 0), name="push")
    fl, fp = eg.codegen(eg.derive(s, method="lagrange")), eg.codegen(eg.derive(s))
    q, u, _ = eg.random_states(s, 20, np.random.default_rng(25))
    for key, x, y in [("M", fl.M(q), fp.M(q)), ("b", fl.b(q, u), fp.b(q, u)), ("g", fl.g(q), fp.g(q))] + \
            [(load, fl.tau_of(load, q, u), fp.tau_of(load, q, u)) for load in ("spring", "damper", "push")]:
        np.testing.assert_allclose(x, y, rtol=0, atol=1e-11 * max(1, np.abs(y).max()), err_msg=key)


def test_free_cut_on_a_floating_base():
    """solo12 by the free cut: M, b, g, feet J and J̇u = Pinocchio; every joint wrench = rnea's data.f
    (in the joint frame), the base's is zero (nothing holds it: its six equations are the u̇ of the base);
    the Euler base equals projected Newton-Euler."""
    import pinocchio as pin

    from eomgen.model.urdf import pinocchio_configuration

    system = eg.robots.load("solo12")
    report = verify(system, method="free_cut", states=10, seed=5)
    assert report.ok(1e-10), str(report)
    f = eg.codegen(eg.derive(system, method="free_cut"))
    model = system.pinocchio_model
    data, placements = model.createData(), model.createData()
    rng = np.random.default_rng(24)
    q, u, _ = eg.random_states(system, 5, rng)
    for k in range(5):
        a = rng.uniform(-3, 3, system.nv)
        qp = pinocchio_configuration(system, q[k])
        tau = pin.rnea(model, data, qp, u[k], a)
        pin.forwardKinematics(model, placements, qp)
        for i, joint in enumerate(system.joints):
            F, T = f.joint_wrench(joint.name, q[k], u[k], a)
            R = placements.oMi[i + 1].rotation
            np.testing.assert_allclose(R.T @ F, data.f[i + 1].linear, rtol=0, atol=1e-9 * max(1, np.abs(F).max()))
            np.testing.assert_allclose(R.T @ T, data.f[i + 1].angular, rtol=0, atol=1e-9 * max(1, np.abs(T).max()))
        reactions = f.reactions(q[k], u[k], tau_a=tau[6:])
        assert not np.any(reactions["root_joint"][0]) and not np.any(reactions["root_joint"][1])
    euler = eg.robots.load("solo12", base="euler")
    fe, fp = eg.codegen(eg.derive(euler, method="free_cut")), eg.codegen(eg.derive(euler))
    q, u, _ = eg.random_states(euler, 5, rng)
    for key, x, y in [("M", fe.M(q), fp.M(q)), ("b", fe.b(q, u), fp.b(q, u)), ("g", fe.g(q), fp.g(q))]:
        np.testing.assert_allclose(x, y, rtol=0, atol=1e-10 * max(1, np.abs(y).max()), err_msg=key)


def test_free_flyer_model_and_errors():
    system = eg.robots.load("solo12")
    assert (system.nq, system.nv) == (19, 18)
    S = np.array(system.S.tolist(), float)
    assert S.shape == (12, 18) and not S[:, :6].any() and (S[:, 6:] == np.eye(12)).all()
    euler = eg.robots.load("solo12", base="euler")  # the recursive method takes the Euler base too
    f_rec, f_ne = (eg.codegen(eg.derive(euler, method=m)) for m in ("recursive", "projected_newton_euler"))
    q, u, _ = eg.random_states(euler, 3, np.random.default_rng(1))
    for qk, uk in zip(q, u):
        assert np.allclose(f_rec.M(qk), f_ne.M(qk), atol=1e-12) and np.allclose(f_rec.b(qk, uk), f_ne.b(qk, uk))
    s = eg.System()
    base = s.add_body("base", joint=eg.Revolute("q0"), mass=1)
    with pytest.raises(eg.ModelError, match="FreeFlyer joint must attach the root body"):
        s.add_body("second", parent=base, joint=eg.FreeFlyer("ff"), mass=1)


def _euler_to_quaternion_state(qe):
    """Quaternion-base q and the speed map T (u_quaternion = T u_euler) for a ZYX Euler-base q."""
    from scipy.spatial.transform import Rotation

    yaw, pitch, roll = qe[3:6]
    R = Rotation.from_euler("ZYX", [yaw, pitch, roll]).as_matrix()
    Rz, Ry = Rotation.from_euler("Z", yaw).as_matrix(), Rotation.from_euler("Y", pitch).as_matrix()
    E = np.column_stack([[0, 0, 1], Rz[:, 1], (Rz @ Ry)[:, 0]])  # ω = E (ψ̇, θ̇, φ̇)
    T = np.eye(len(qe))
    T[:3, :3], T[3:6, 3:6] = R.T, R.T @ E
    return np.concatenate([qe[:3], Rotation.from_matrix(R).as_quat(), qe[6:]]), T


@pytest.mark.parametrize("pitch", [0.3, -1.2, np.pi / 2 - 1e-4])
def test_euler_base_equals_quaternion_base(pitch):
    """M_e = Tᵀ M_q T, g_e = Tᵀ g_q, b_e = Tᵀ (b_q + M_q Ṫ u_e) (Ṫ u_e by central differences); near
    pitch 90° the forward dynamics warns with the condition number of M."""
    euler, quat = eg.robots.load("solo12", base="euler"), eg.robots.load("solo12")
    assert euler.nq == euler.nv == 18
    fe, fq = eg.codegen(eg.derive(euler)), eg.codegen(eg.derive(quat, method="recursive"))
    rng = np.random.default_rng(9)
    qe = np.concatenate([rng.uniform(-1, 1, 3), [0.4, pitch, -0.7], rng.uniform(-1, 1, 12)])
    ue = rng.uniform(-1, 1, 18)
    qq, T = _euler_to_quaternion_state(qe)
    Mq = fq.M(qq)
    np.testing.assert_allclose(fe.M(qe), T.T @ Mq @ T, rtol=0, atol=1e-12)
    np.testing.assert_allclose(fe.g(qe), T.T @ fq.g(qq), rtol=0, atol=1e-12)
    h = 1e-6
    Tdot_u = (_euler_to_quaternion_state(qe + h * ue)[1] - _euler_to_quaternion_state(qe - h * ue)[1]) @ ue / (2 * h)
    np.testing.assert_allclose(fe.b(qe, ue), T.T @ (fq.b(qq, T @ ue) + Mq @ Tdot_u), rtol=0, atol=1e-8)
    # the same motion: u̇_q = T u̇_e + Ṫ u_e; the error of the Euler forward dynamics grows with cond(M)
    cond = np.linalg.cond(fe.M(qe))
    if abs(np.cos(pitch)) < 1e-3:
        with pytest.warns(UserWarning, match=r"pitch 1.570696 rad is 1.0e-04 from ±90°.*cond\(M\) = "):
            ud_e = fe.forward_dynamics(qe, ue)
        assert cond > 1e8
    else:
        assert fe.euler_singularity(qe) is None and cond < 1e6
        ud_e = fe.forward_dynamics(qe, ue)
    ud_q = fq.forward_dynamics(qq, T @ ue)
    error = np.abs(T @ ud_e + Tdot_u - ud_q).max() / np.abs(ud_q).max()
    print(f"pitch {pitch:.6f}: cond(M_euler) = {cond:.2e}, relative error of the mapped acceleration {error:.1e}")
    assert error < 1e-6 + cond * 1e-13  # finite-difference Ṫu limits the regular case to ~1e-8


def test_euler_base_lagrange_equals_projected_newton_euler():
    """With u = q̇ Lagrange II applies to the Euler base: a flying box carrying one link."""
    system = eg.System(gravity=(0, 0, -9.81))
    base = system.add_body("box", joint=eg.FreeFlyer("base", parametrization="euler"), mass=2.0,
                           com=(0.1, 0.0, -0.05), inertia=np.diag([0.05, 0.08, 0.1]).tolist())
    system.add_body("arm", parent=base, joint=eg.Revolute("q_1", axis=(0, 1, 0)), mass=0.5, com=(0.3, 0, 0),
                    inertia=np.diag([0.001, 0.01, 0.01]).tolist(), placement=eg.Placement(translation=(0.2, 0, 0.1)))
    fl, fp = eg.codegen(eg.derive(system, method="lagrange")), eg.codegen(eg.derive(system))
    rng = np.random.default_rng(10)
    for _ in range(5):
        q, u = rng.uniform(-1, 1, 7), rng.uniform(-2, 2, 7)
        np.testing.assert_allclose(fl.M(q), fp.M(q), rtol=1e-12, atol=1e-12)
        np.testing.assert_allclose(fl.b(q, u), fp.b(q, u), rtol=1e-12, atol=1e-12)
        np.testing.assert_allclose(fl.g(q), fp.g(q), rtol=1e-12, atol=1e-12)
    with pytest.raises(eg.ModelError, match="Pinocchio has no ZYX Euler free flyer"):
        eg.verify(system)


def test_integrate_equals_pinocchio():
    system = eg.robots.load("solo12")
    q, u, _ = eg.random_states(system, 5, np.random.default_rng(11))
    import pinocchio as pin

    for k in range(5):
        for dt in (1e-3, 0.37):
            np.testing.assert_allclose(eg.integrate(system, q[k], u[k], dt),
                                       pin.integrate(system.pinocchio_model, q[k], u[k] * dt), atol=1e-14)
