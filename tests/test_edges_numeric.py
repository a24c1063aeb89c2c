"""The edges of the numeric layer (issue 25: 8, 10, 15): simulate's time span, gains and controller (copies
of the state, efforts checked, one warning per kind), project's speeds, assemble's tolerances, linearize's
operating point and flags, and loads along a line whose ends meet."""
import sys
import warnings
from pathlib import Path

import numpy as np
import pytest
import sympy as sp
from hypothesis import given, settings, strategies as st

import eomgen as eg
import kane_systems as K
from test_linearize import CART_POLE, cart_pole

sys.path.insert(0, str(Path(__file__).parents[1] / "examples"))
from four_bar import four_bar  # noqa: E402

C, D, K_SPRING = 2.0, 0.7, 3.0  # damping, rest length, stiffness


def pendulum() -> eg.System:
    """A rod pendulum, actuated, gravity −y."""
    system = eg.System(gravity=(0, -9.81, 0))
    system.add_body("rod", joint=eg.Revolute("phi"), mass=1.0, com=(0, -0.5, 0),
                    inertia=np.diag([0.1, 0, 0.1]))
    return system


@pytest.fixture(scope="module")
def bar():
    """The four-bar's functions, a closed pose, and the same with its loop stated twice."""
    f = eg.codegen(eg.derive(four_bar(), method="recursive"))
    twice = four_bar()
    twice.add_loop("coupler_end", "rocker_end", name="again")
    assembled = eg.assemble(f, [0.3, 1.2, 1.5], fixed=["th1"])
    return f, assembled, eg.codegen(eg.derive(twice, method="recursive"))


@pytest.mark.parametrize("t_span", [(0, np.inf), (0, np.nan), (-np.inf, 1), ("0", 1)])
def test_time_span_must_be_two_finite_numbers(t_span):
    with pytest.raises(eg.ModelError, match="simulate: t_span: "):
        eg.simulate(pendulum(), ([0.1], [0.0]), t_span)


def test_baumgarte_gains_are_named(bar):
    f, q0, _ = bar
    with pytest.raises(eg.ModelError, match=r"simulate: baumgarte: contains NaN"):
        eg.simulate(f, (q0, np.zeros(3)), (0, 0.1), stabilization="baumgarte", baumgarte=(np.nan, 1.0))


def test_a_controller_that_changes_its_arguments_leaves_the_motion_alone():
    """q -= q_ref and u *= d inside the controller (its own copies): the same motion, to the last bit, as
    the same law written without side effects."""
    q_ref, kp, kd = 0.4, 20.0, 3.0
    f = eg.codegen(eg.derive(pendulum()))

    def pure(t, q, u):
        return -kp * (q - q_ref) - kd * u

    def in_place(t, q, u):
        q -= q_ref
        u *= kd
        return -kp * q - u

    runs = [eg.simulate(f, ([1.0], [0.5]), (0, 1), controller=c, rtol=1e-8, atol=1e-8)
            for c in (pure, in_place)]
    np.testing.assert_array_equal(runs[0].t, runs[1].t)
    np.testing.assert_array_equal(runs[0].q, runs[1].q)
    np.testing.assert_array_equal(runs[0].tau, runs[1].tau)
    assert abs(runs[0].q[-1, 0] - q_ref) < 0.2  # the law holds it near q_ref


@pytest.mark.parametrize("effort", [None, [True], np.zeros((3, 1)), np.zeros(2), [np.nan], ["1"]])
def test_the_controllers_efforts_are_checked(effort):
    with pytest.raises(eg.ModelError, match="simulate: the controller's efforts τ_a: "):
        eg.simulate(pendulum(), ([0.1], [0.0]), (0, 0.1), controller=lambda t, q, u: effort)


def test_a_redundant_loop_warns_once_per_simulation(bar):
    """The loop stated twice: the rank-deficient contact set is reported once (with its count), not at every
    evaluation of the dynamics."""
    _, q0, twice = bar
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        sim = eg.simulate(twice, (q0, np.zeros(3)), (0, 0.2))
    deficient = [w for w in caught if "rank-deficient contact set" in str(w.message)]
    assert len(deficient) == 1 and "times in this simulation" in str(deficient[0].message)
    assert sim.closure_drift.max() < 1e-9


def test_project_checks_the_speeds(bar):
    f, q0, _ = bar
    with pytest.raises(eg.ModelError, match=r"project: u \(the 3 speeds .*\): contains NaN"):
        eg.project(f, q0, [np.nan, 0, 0])
    with pytest.raises(eg.ModelError,
                       match=r"project: u \(the 3 speeds .*\): expected 3 finite numbers, got "
                             r"shape \(2,\)"):
        eg.project(f, q0, [0, 0])


def test_assemble_checks_its_arguments(bar):
    f, q0, _ = bar
    for tol in (-1, 0, np.nan, "1e-9"):
        with pytest.raises(eg.ModelError, match="assemble: tol: "):
            eg.assemble(f, q0, tol=tol)
    with pytest.raises(eg.ModelError, match="assemble: q_guess: expected 3 finite numbers, got str"):
        eg.assemble(f, "0 0 0")


def test_kane_assemble_checks_its_arguments():
    """tol ≤ 0 refused (it can never be met); iterations=0 returns a consistent guess and names the residual
    of an inconsistent one (was UnboundLocalError)."""
    system, args = K.four_bar()
    f = eg.codegen(eg.kane(system, **args))
    pose = np.array(K.four_bar_pose(0.4))
    with pytest.raises(eg.ModelError, match="assemble: tol: expected a finite number > 0, got -1"):
        f.assemble(pose, tol=-1)
    np.testing.assert_array_equal(f.assemble(pose, tol=1e-9, iterations=0), pose)
    with pytest.raises(eg.ModelError, match=r"fail by \d.* after 0 Newton steps"):
        f.assemble(pose + [0, 0.1, 0], iterations=0)
    with pytest.raises(eg.ModelError, match="assemble: iterations: expected an integer ≥ 0"):
        f.assemble(pose, iterations=-1)


def test_linearize_refuses_strings_and_truthy_flags():
    eom, zero = cart_pole(), (np.zeros(2), np.zeros(2))
    for point in ((["0", 0], [0, 0]), {"x": "0", "phi": 0}, ([True, 0], [0, 0])):
        with pytest.raises(eg.ModelError, match=r"op_point: q0 \(the coordinates\): expected numbers, got"):
            eg.linearize(eom, point, params=CART_POLE)
    with pytest.raises(eg.ModelError, match="linearize: symbolic: expected True or False, got 'yes'"):
        eg.linearize(eom, zero, params=CART_POLE, symbolic="yes")


def slider(load: str) -> eg.System:
    """A body sliding along x from the world origin, with a damper, a line actuator or a spring of rest
    length D between the origin and the body: the ends meet at x = 0."""
    system = eg.System(gravity=(0, 0, -9.81))
    system.add_body("slider", joint=eg.Prismatic("x", axis=(1, 0, 0)), mass=1, inertia=np.eye(3))
    if load == "damper":
        system.add_damper(None, "slider", C, name="shock")
    if load == "actuator":
        system.add_actuator("slider", force=sp.Symbol("f"), reaction=None, name="shock")
    if load == "spring":
        system.add_spring(None, "slider", K_SPRING, rest_length=D, name="shock")
    return system


@pytest.fixture(scope="module")
def damper_c(tmp_path_factory):
    with pytest.MonkeyPatch.context() as mp:
        mp.setenv("EOMGEN_CACHE", str(tmp_path_factory.mktemp("cache")))
        return eg.codegen(eg.derive(slider("damper")), backend="c")


@settings(max_examples=20, deadline=None)
@given(x=st.floats(-2, 2).filter(lambda x: abs(x) > 1e-100), xdot=st.floats(-3, 3), n=st.integers(1, 5),
       k=st.integers(0, 4))
def test_a_damper_whose_ends_meet_is_named_with_the_state(damper_c, x, xdot, n, k):
    """Away from x = 0 the damper's generalized force is −c ẋ (the line is x's); at x = 0 (one state, or
    state k of a batch) a ModelError naming the damper and the state, no NaN and no NumPy warning."""
    k = min(k, n - 1)
    for f in (eg.codegen(eg.derive(slider("damper"))), damper_c):
        np.testing.assert_allclose(f.tau([x], [xdot]), [-C * xdot], rtol=1e-14, atol=1e-14)
        q = np.full((n, 1), x)
        q[k] = 0.0
        with warnings.catch_warnings():
            warnings.simplefilter("error")
            with pytest.raises(eg.ModelError, match=r"damper 'shock': its ends meet at q = \[0\.0\]"):
                f.tau([0.0], [xdot])
            with pytest.raises(eg.ModelError, match=rf"damper 'shock': .* \(state {k} of the batch\)"):
                f.tau(q, np.full((n, 1), xdot))
            with pytest.raises(eg.ModelError, match="damper 'shock': its ends meet"):
                f.rhs(0.0, [0.0, xdot])


@pytest.mark.parametrize("load", ["actuator", "spring"])
def test_line_loads_whose_ends_meet_are_named(load):
    """Elsewhere a line actuator pushes its ends apart (f at x > 0), a spring gives −k (|x| − l0) sign(x)."""
    f = eg.codegen(eg.derive(slider(load)))
    params = {"f": 1.5} if load == "actuator" else {}
    want = 1.5 if load == "actuator" else -K_SPRING * (0.4 - D)
    np.testing.assert_allclose(f.tau([0.4], [0.0], params), [want], rtol=1e-14)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        with pytest.raises(eg.ModelError, match=f"{load} 'shock': its ends meet at q = \\[0\\.0\\]"):
            f.tau([0.0], [0.0], params)
