"""Joints of prescribed motion (`Revolute(..., motion=θ(eg.t))`): the coordinate leaves q and u, t enters
the functions as the state parameter "t". Checked against the same system with that joint free, derived
by the recursive method (an independent path, verified against Pinocchio elsewhere): the reduced
equations are its rows r with q_k = θ(t), u_k = θ̇(t), u̇_k = θ̈(t) (M_rr, b_r + M_rk θ̈, g_r), and the
driving effort its row k of the inverse dynamics (every backend and the written module); a pendulum on
a spinning arm against its closed form; refusals by name."""
from __future__ import annotations

import numpy as np
import pytest
import sympy as sp
from hypothesis import given, settings
from hypothesis import strategies as st

import eomgen as eg
from eomgen.symbols import t

MOTIONS = [0.3 * sp.sin(1.7 * t) + 0.2 * t**2, 0.1 * sp.cos(2 * t) - 0.05 * t, 0.8 * t]


def chain(prescribed: int | None):
    """A spatial 3-joint chain (revolute z, prismatic x, revolute about (0, 1, 1)/√2; each with an
    armature) with joint `prescribed` driven by MOTIONS[prescribed] (None: all free)."""
    joints = [eg.Revolute, eg.Prismatic, eg.Revolute]
    axes = [(0, 0, 1), (1, 0, 0), (0, 1, 1)]
    system, parent = eg.System(gravity=(0, -9.81, -2.0)), None
    for k, (joint, axis) in enumerate(zip(joints, axes)):
        motion = {"motion": MOTIONS[k]} if k == prescribed else {}
        moving = joint(f"q{k}", axis=axis, armature=0.05, **motion)
        parent = system.add_body(f"b{k}", parent=parent, joint=moving,
                                 mass=1.0 + k, com=(0.2, 0.1 * k, -0.1),
                                 inertia=[[0.1, 0.01, 0], [0.01, 0.2, 0.02], [0, 0.02, 0.15 + 0.01 * k]],
                                 placement=eg.Placement(translation=(0.3, 0.1, 0.2 * k)))
    return system


@pytest.fixture(scope="module")
def functions():
    full = eg.codegen(eg.derive(chain(None)))
    return full, {k: eg.codegen(eg.derive(chain(k))) for k in range(3)}


@settings(max_examples=30, deadline=None)
@given(k=st.integers(0, 2), seed=st.integers(0, 2**32 - 1))
def test_the_reduced_rows_of_the_free_system(functions, k, seed):
    full, reduced = functions[0], functions[1][k]
    rng = np.random.default_rng(seed)
    time, q, u, ud = rng.uniform(-2, 2), *rng.uniform(-1.5, 1.5, (3, 2))
    theta = [sp.lambdify(t, sp.diff(MOTIONS[k], t, n))(time) for n in range(3)]
    r = [i for i in range(3) if i != k]
    Q, U, UD = (np.insert(x, k, v) for x, v in zip((q, u, ud), theta))
    p = {"t": time}
    assert reduced.nq == reduced.nv == 2 and reduced.parameters.names == ("t",)
    M = full.M(Q)
    np.testing.assert_allclose(reduced.M(q, p), M[np.ix_(r, r)], rtol=1e-12, atol=1e-12)
    np.testing.assert_allclose(reduced.b(q, u, p), full.b(Q, U)[r] + M[r, k] * theta[2], rtol=1e-11,
                               atol=1e-11)
    np.testing.assert_allclose(reduced.g(q, p), full.g(Q)[r], rtol=1e-12, atol=1e-12)
    tau = full.inverse_dynamics(Q, U, UD)
    np.testing.assert_allclose(reduced.inverse_dynamics(q, u, ud, p), tau[r], rtol=1e-11, atol=1e-11)
    assert reduced.driving_effort(f"q{k}", q, u, ud, p) == pytest.approx(tau[k], rel=1e-11, abs=1e-11)


def test_the_driving_effort_in_every_output(tmp_path):
    """NumPy, C and the written module give the same effort, the free system's row k of τ_ID."""
    import importlib.util

    eom, full = eg.derive(chain(2)), eg.codegen(eg.derive(chain(None)))
    path = eg.write_module(eom, tmp_path / "driven.py")
    spec = importlib.util.spec_from_file_location("driven", path)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    q, u, ud, time = np.array([0.3, -0.2]), np.array([0.5, 0.1]), np.array([-0.4, 0.7]), 0.9
    theta = [float(sp.diff(MOTIONS[2], t, n).subs(t, time)) for n in range(3)]
    expected = full.inverse_dynamics(*(np.r_[x, v] for x, v in zip((q, u, ud), theta)))[2]
    assert module.DRIVES == ("q2",)
    for value in (eg.codegen(eom, backend="c").driving_effort("q2", q, u, ud, {"t": time}),
                  module.driving_effort("q2", q, u, ud, {"t": time})):
        assert np.shape(value) == () and value == pytest.approx(expected, rel=1e-12)
    with pytest.raises(eg.ModelError, match="q0"):
        eg.codegen(eom).driving_effort("q0", q, u, ud, {"t": time})


def test_a_pendulum_on_a_spinning_arm():
    """A pendulum (angle φ about the arm's y axis, bob at 1 below the pivot at radius a) on an arm
    spinning at Ω: φ̈ + Ω² (a − sin φ) cos φ + g sin φ = 0 (Lagrange in the turning frame); simulated
    with eg.simulate, which gives the functions the integrator's t."""
    W, a = sp.symbols("W a", positive=True)
    system = eg.System(gravity=(0, 0, -9.81))
    arm = system.add_body("arm", joint=eg.Revolute("h", motion=W * t), mass=0)
    system.add_body("bob", parent=arm, joint=eg.Revolute("phi", axis=(0, 1, 0)), mass=1.0, com=(0, 0, -1),
                    inertia=np.zeros((3, 3)).tolist(), placement=eg.Placement(translation=(a, 0, 0)))
    eom = eg.derive(system)
    phi = system.q[0]
    assert eom.method == "lagrange"
    assert sp.simplify(eom.b[0] - W**2 * (a - sp.sin(phi)) * sp.cos(phi)) == 0
    assert sp.simplify(eom.g[0] - 9.81 * sp.sin(phi)) == 0
    for backend in ("numpy", "c"):
        f = eg.codegen(eom, backend=backend).bind({"W": 2.0, "a": 0.5})
        sim = eg.simulate(f, ([0.3], [0.0]), (0, 1.0), t_eval=[1.0])
        from scipy.integrate import solve_ivp
        ref = solve_ivp(lambda _, x: [x[1], -4 * (0.5 - np.sin(x[0])) * np.cos(x[0]) - 9.81 * np.sin(x[0])],
                        (0, 1.0), [0.3, 0.0], rtol=1e-11, atol=1e-12).y[:, -1]
        np.testing.assert_allclose(np.r_[sim.q[-1], sim.u[-1]], ref, rtol=1e-7, atol=1e-8)


def test_refusals_name_the_joint():
    with pytest.raises(eg.ModelError, match="method 'recursive' does not handle the prescribed motion of "
                                            "joint 'q0'"):
        eg.derive(chain(0), method="recursive")
    with pytest.raises(eg.ModelError, match="kane: the prescribed motion of joint 'q0'"):
        eg.kane(chain(0), independent=None)
    with pytest.raises(eg.ModelError, match="joint 'j': motion uses .* not the time eg.t"):
        eg.Revolute("j", motion=sp.Symbol("t", real=True))
    other = eg.System()
    arm = other.add_body("arm", joint=eg.Revolute("q1"), mass=1.0)
    with pytest.raises(eg.ModelError, match=r"body 'b': joint motion depends on the coordinates or speeds "
                                            r"\['q1'\]; it must be a function of eg.t and parameters"):
        other.add_body("b", parent=arm, joint=eg.Revolute("h", motion=other.q[0] + t), mass=1.0)
    with pytest.raises(eg.ModelError, match="joint 'j': give mimic or motion, not both"):
        eg.Revolute("j", mimic=("k", 1, 0), motion=t)
    with pytest.raises(eg.ModelError, match=r"joint 'j': motion: theta\(t\) is not a value"):
        eg.Revolute("j", motion=sp.Function("theta")(t))
    with pytest.raises(eg.ModelError, match="joint 'j': motion: expected a number or a sympy expression"):
        eg.Revolute("j", motion="sin(t)")
    f = eg.codegen(eg.derive(chain(1)))
    for call in (lambda: f.call("A_G", np.zeros(2), params={"t": 0.0}),
                 lambda: f.call("Jdot_u:b2", np.zeros(2), np.zeros(2), params={"t": 0.0}),
                 lambda: f.regressor(np.zeros(2), np.zeros(2), np.zeros(2), params={"t": 0.0})):
        with pytest.raises(eg.ModelError, match="joint 'q1'"):
            call()


def test_what_a_prescribed_motion_refuses_or_takes_along():
    """Values in t other than a motion, a motor on the driven joint, worked solutions, JAX's rhs and the
    energy balance (which misses the drive's work) are refused by name; a motion without t simulates."""
    timed = chain(0)
    timed.add_body("extra", parent=timed.body("b2"), joint=eg.Revolute("q3"), mass=1.0, com=(0.1 * t, 0, 0))
    with pytest.raises(eg.ModelError, match="body 'extra' depends on the time eg.t"):
        eg.derive(timed)
    with pytest.raises(eg.ModelError, match="joint 'q0' has a prescribed motion"):
        chain(0).add_motor("b0", resistance=1, inductance=0.1, torque_constant=0.1, rotor_inertia=0.01)
    with pytest.raises(eg.ModelError, match="solution: joint 'q0' has a prescribed motion"):
        eg.solution(chain(0))
    f = eg.codegen(eg.derive(chain(0)), backend="jax")
    with pytest.raises(eg.ModelError, match="rhs does not give the time to the prescribed motion of joint"):
        f.rhs(0.5, np.zeros(4))
    sim = eg.simulate(eg.derive(chain(0)), (np.zeros(2), np.zeros(2)), (0, 0.2))
    assert np.isfinite(sim.energy).all()
    with pytest.raises(eg.ModelError, match="balance: the work of joint 'q0'"):
        sim.balance
    held = eg.System(gravity=(0, 0, -9.81))
    arm = held.add_body("arm", joint=eg.Revolute("h", motion=0.5), mass=1.0, com=(0.2, 0, 0))
    held.add_body("bob", parent=arm, joint=eg.Revolute("phi", axis=(0, 1, 0)), mass=1.0, com=(0, 0, -1))
    sim = eg.simulate(eg.derive(held), ([0.3], [0.0]), (0, 0.5))
    assert np.ptp(sim.energy) < 1e-8  # held still: the drive does no work, T + U is conserved
