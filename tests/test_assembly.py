"""A Delta parallel robot (examples/delta_robot.py): `eg.assemble` against the closed-form forward
kinematics (three spheres' intersection), the reduced dynamics of `eg.reduce` against Pinocchio's full
model (crba, gravity, non-linear effects) with its loop Jacobian; refused assemblies."""
import functools
import sys
from pathlib import Path

import numpy as np
import pinocchio as pin
import pytest
from hypothesis import given, settings, strategies as st

import eomgen as eg
from eomgen.numeric.assembly import speed_indices
from eomgen.verify import to_pinocchio

sys.path.insert(0, str(Path(__file__).parents[1] / "examples"))
from delta_robot import ANGLES, ARM, BASE, FOREARM, PLATFORM, SHOULDERS, delta_robot, guess  # noqa: E402
from four_bar import LENGTHS, MASSES, four_bar, rod  # noqa: E402

thetas = st.lists(st.floats(-0.3, 0.9), min_size=3, max_size=3)


@functools.cache
def delta():
    system = delta_robot()
    eom = eg.derive(system, method="recursive")
    return system, eg.codegen(eom), eg.reduce(eom, SHOULDERS)


def three_spheres(theta) -> np.ndarray:
    """The platform centre P: |P − c_i| = L_f with c_i the elbow E_i = S_i + L_a (cos θ_i r_i − sin θ_i z)
    less the ball's offset ρ r_i (r_i the arm's radial direction); differences of the sphere equations
    give the line 2 (c_j − c_1)·P = |c_j|² − |c_1|², which meets the first sphere twice: the lower point."""
    radial = [np.array([np.cos(g), np.sin(g), 0]) for g in ANGLES]
    c = [BASE * r + ARM * (np.cos(t) * r - np.sin(t) * np.array([0, 0, 1])) - PLATFORM * r
         for r, t in zip(radial, theta)]
    A = 2 * np.array([c[1] - c[0], c[2] - c[0]])
    rhs = np.array([c[1] @ c[1] - c[0] @ c[0], c[2] @ c[2] - c[0] @ c[0]])
    p0 = np.linalg.lstsq(A, rhs, rcond=None)[0]
    n = np.cross(A[0], A[1])
    # |p0 + t n − c1|² = L_f²
    a, b, k = n @ n, 2 * n @ (p0 - c[0]), (p0 - c[0]) @ (p0 - c[0]) - FOREARM**2
    roots = (-b + np.array([-1, 1]) * np.sqrt(b * b - 4 * a * k)) / (2 * a)
    return min((p0 + t * n for t in roots), key=lambda p: p[2])


@settings(max_examples=20, deadline=None)
@given(theta=thetas)
def test_assemble_equals_three_spheres(theta):
    """The platform position for given shoulder angles, to 1e-12 m; the shoulders untouched."""
    _, f, _ = delta()
    q = eg.assemble(f, guess(theta), fixed=SHOULDERS)
    np.testing.assert_allclose(q[:3], three_spheres(theta), atol=1e-12)
    np.testing.assert_array_equal(q[[3, 6, 9]], theta)


def _pinocchio_loops(model, data, q, v):
    """J_c = J_wrist − J_ball (translations, world axes) of the three legs and J̇_c v, from Pinocchio."""
    pin.forwardKinematics(model, data, q, v, np.zeros(model.nv))
    pin.computeJointJacobians(model, data, q)
    pin.updateFramePlacements(model, data)
    J, Jdot_v = [], []
    for i in (1, 2, 3):
        a, b = (model.getFrameId(f"{x}{i}") for x in ("wrist", "ball"))
        J.append(pin.getFrameJacobian(model, data, a, pin.LOCAL_WORLD_ALIGNED)[:3]
                 - pin.getFrameJacobian(model, data, b, pin.LOCAL_WORLD_ALIGNED)[:3])
        Jdot_v.append(pin.getFrameClassicalAcceleration(model, data, a, pin.LOCAL_WORLD_ALIGNED).linear
                      - pin.getFrameClassicalAcceleration(model, data, b, pin.LOCAL_WORLD_ALIGNED).linear)
    return np.vstack(J), np.concatenate(Jdot_v)


@settings(max_examples=10, deadline=None)
@given(theta=thetas, rates=st.lists(st.floats(-2, 2), min_size=3, max_size=3))
def test_reduced_dynamics_equal_pinocchio(theta, rates):
    """With Pinocchio's M (crba), g, b = nle − g and loop Jacobian: R = [1; −J_d⁻¹ J_i], s = [0; −J_d⁻¹ J̇u],
    M_r = Rᵀ M R, g_r = Rᵀ g, b_r = Rᵀ (b + M s), to 1e-10; the platform's rows of R equal ∂P/∂θ of the
    closed-form forward kinematics (central differences, 1e-6)."""
    system, f, reduced = delta()
    model = to_pinocchio(system)
    data = model.createData()
    q = eg.assemble(f, guess(theta), fixed=SHOULDERS)
    ind, dep = [3, 6, 9], [k for k in range(12) if k not in (3, 6, 9)]
    J = _pinocchio_loops(model, data, q, np.zeros(12))[0]
    R = np.zeros((12, 3))
    R[ind], R[dep] = np.eye(3), -np.linalg.solve(J[:, dep], J[:, ind])
    v = R @ rates
    J, Jdot_v = _pinocchio_loops(model, data, q, v)
    s = np.zeros(12)
    s[dep] = -np.linalg.solve(J[:, dep], Jdot_v)
    M = pin.crba(model, data, q)
    M = np.triu(M) + np.triu(M, 1).T
    g = pin.computeGeneralizedGravity(model, data, q)
    b = pin.nonLinearEffects(model, data, q, v) - g
    np.testing.assert_allclose(reduced.R(q), R, atol=1e-10)
    np.testing.assert_allclose(reduced.M(q), R.T @ M @ R, atol=1e-10)
    np.testing.assert_allclose(reduced.g(q), R.T @ g, atol=1e-10)
    np.testing.assert_allclose(reduced.b(q, rates), R.T @ (b + M @ s), atol=1e-10)
    h = 1e-6
    dP = np.column_stack([(three_spheres(np.add(theta, e)) - three_spheres(np.subtract(theta, e))) / (2 * h)
                          for e in np.eye(3) * h])
    np.testing.assert_allclose(R[:3], dP, atol=1e-7)


def test_assemble_from_a_system_and_project_onto_the_legs():
    """A System is derived on the way; project leaves an assembled state with J_c u = 0."""
    system, f, _ = delta()
    q = eg.assemble(system, guess([0.2, 0.4, 0.3]), fixed=["shoulder1", "shoulder2", "shoulder3"])
    np.testing.assert_allclose(q[:3], three_spheres([0.2, 0.4, 0.3]), atol=1e-12)
    q2, u = eg.project(f, q + 1e-3, np.ones(12))
    assert np.linalg.norm(f.closure_residual(q2)) <= 1e-12
    assert np.linalg.norm(f.contact_jacobian(q2) @ u) <= 1e-12


@functools.cache
def shifted_four_bar(x: float):
    """examples/four_bar.py with its ground pivots at (x, 0, 0) and (x + d, 0, 0)."""
    (a, b, c, d), system = LENGTHS, eg.System(gravity=(0, -9.81, 0))
    crank = system.add_body("crank", joint=eg.Revolute("th1"), **rod(MASSES[0], a),
                            placement=eg.Placement(translation=(x, 0, 0)))
    coupler = system.add_body("coupler", parent=crank, joint=eg.Revolute("th2", actuated=False),
                              placement=eg.Placement(translation=(a, 0, 0)), **rod(MASSES[1], b))
    rocker = system.add_body("rocker", joint=eg.Revolute("th3", actuated=False),
                             placement=eg.Placement(translation=(x + d, 0, 0)), **rod(MASSES[2], c))
    system.add_frame("coupler_end", coupler, eg.Placement(translation=(b, 0, 0)))
    system.add_frame("rocker_end", rocker, eg.Placement(translation=(c, 0, 0)))
    system.add_loop("coupler_end", "rocker_end", kind="revolute", name="loop")
    return eg.codegen(eg.derive(system, method="recursive"))


def two_circles(theta1: float) -> np.ndarray:
    """The coupler's end B (relative to the crank's pivot) on the circles |B − A| = b about the crank's end
    A = a (cos θ1, sin θ1) and |B − D| = c about D = (d, 0): the upper of their two intersections."""
    a, b, c, d = LENGTHS
    A, D = a * np.array([np.cos(theta1), np.sin(theta1)]), np.array([d, 0.0])
    e = np.linalg.norm(D - A)
    along = (b**2 - c**2 + e**2) / (2 * e)
    n = (D - A) / e
    return A + along * n + np.sqrt(b**2 - along**2) * np.array([-n[1], n[0]])


@pytest.mark.parametrize("x", [0.0, 1e4, 1e5])
def test_assemble_and_simulate_far_from_the_origin(x):
    """From the guess of examples/four_bar.py (coupler parallel to rocker: J_r singular) the closure at
    θ1 = 0.3 is the two circles' intersection wherever the mechanism stands; 0.5 s with projection keeps
    ‖r‖ within 1e-12 max(1, |p|) and the energy (no load) to 1e-6 J; `tol` reaches the projection."""
    f = shifted_four_bar(x)
    q = eg.assemble(f, [0.3, 1.2, 1.5], fixed=["th1"])
    a, b, c, d = LENGTHS
    B = two_circles(0.3)
    np.testing.assert_allclose(a * np.array([np.cos(0.3), np.sin(0.3)])
                               + b * np.array([np.cos(0.3 + q[1]), np.sin(0.3 + q[1])]), B, atol=1e-10)
    np.testing.assert_allclose([d + c * np.cos(q[2]), c * np.sin(q[2])], B, atol=1e-10)
    u = eg.reduce(f.eom, independent=["th1"]).R(q) @ [2.0]
    sim = eg.simulate(f, (q, u), (0, 0.5))
    assert sim.closure_drift.max() <= 1e-12 * max(1, x + d + c) and np.ptp(sim.energy) <= 1e-6
    with pytest.raises(eg.ModelError, match="assemble: "):
        eg.simulate(f, (q, u), (0, 0.5), tol=1e-30)


@pytest.mark.parametrize("x", [0.0, 1e5])
def test_steps_stay_near_the_guess(x):
    """From θ2 = 3, θ3 = 0 (coupler folded back) the first Gauss–Newton step would turn the coupler by
    turns: limited to 1 rad per step, the closure found (the crank's end plus the coupler meets the
    rocker's end, by hand) lies within 2 rad of the guess."""
    f = shifted_four_bar(x)
    q = eg.assemble(f, [0.3, 3.0, 0.0], fixed=["th1"])
    a, b, c, d = LENGTHS
    np.testing.assert_allclose(a * np.array([np.cos(0.3), np.sin(0.3)])
                               + b * np.array([np.cos(0.3 + q[1]), np.sin(0.3 + q[1])]),
                               [d + c * np.cos(q[2]), c * np.sin(q[2])], atol=1e-10)
    assert np.abs(q - [0.3, 3.0, 0.0]).max() < 2


def test_simulate_backward_and_refused_times():
    """Time reversed: from the state the four-bar reaches at t = 1, (1, 0) with t_eval [1, 0.5, 0] gives
    back the forward states at 0.5 and 0 (to 1e-5), with projection and with Baumgarte; t_eval outside
    t_span or out of order, and an unknown method, refused."""
    f = shifted_four_bar(0.0)
    q = eg.assemble(f, [0.3, 1.2, 1.5], fixed=["th1"])
    u = eg.reduce(f.eom, independent=["th1"]).R(q) @ [2.0]
    forward = eg.simulate(f, (q, u), (0, 1), t_eval=[0, 0.5, 1])
    for stabilization in ("projection", "baumgarte"):
        back = eg.simulate(f, (forward.q[-1], forward.u[-1]), (1, 0), t_eval=[1, 0.5, 0],
                           stabilization=stabilization)
        np.testing.assert_array_equal(back.t, [1, 0.5, 0])
        np.testing.assert_allclose(back.q[::-1], forward.q, atol=1e-5)
        np.testing.assert_allclose(back.u[::-1], forward.u, atol=1e-5)
    for stabilization in ("projection", None):
        with pytest.raises(eg.ModelError, match=r"t_eval \[2.0\] outside t_span \(0.0, 1.0\)"):
            eg.simulate(f, (q, u), (0, 1), t_eval=[0.5, 2], stabilization=stabilization)
        with pytest.raises(eg.ModelError, match="t_eval must run from t0 = 1.0 to t1 = 0.0 in order"):
            eg.simulate(f, (q, u), (1, 0), t_eval=[0, 0.5], stabilization=stabilization)
    with pytest.raises(eg.ModelError, match=r"method must be one of \['RK45', .*'LSODA'\], got 'Euler'"):
        eg.simulate(f, (q, u), (0, 1), method="Euler", stabilization=None)


def test_unsatisfiable_closure_says_by_how_much():
    """The four-bar with crank (th1 = 0) and rocker (th3 = π) held: the coupler's end (length 1 about
    (0.3, 0)) comes no closer than 0.8 to the rocker's end (0.1, 0), along x; the Delta with its platform
    2 m down."""
    f = eg.codegen(eg.derive(four_bar(), method="recursive"))
    with pytest.raises(eg.ModelError, match=r"cannot be satisfied with \['th1dot', 'th3dot'\] held: they "
                                            r"fail by ‖r‖ = 8.000e-01 .* worst row 'loop.x' = -8.000e-01"):
        eg.assemble(f, [0.0, 3.0, np.pi], fixed=["th1", "th3"])
    _, f, _ = delta()
    q = guess([0.3, 0.3, 0.3])
    q[2] = -2.0
    with pytest.raises(eg.ModelError, match=r"cannot be satisfied .* ‖r‖ = .* worst row 'leg\d.z'"):
        eg.assemble(f, q, fixed=SHOULDERS + ["platform_z"])


def test_a_guess_that_stops_short_is_not_called_unsatisfiable():
    """One Gauss–Newton step from the four-bar's example guess leaves ‖r‖ > 0 where a step still helps:
    no closure found from this guess (the closure exists: see the test above)."""
    f = shifted_four_bar(0.0)
    with pytest.raises(eg.ModelError, match=r"no closure found from this guess with \['th1dot'\] held "
                                            r"\(‖r‖ = .* worst row 'loop\.[xy]'"):
        eg.assemble(f, [0.3, 1.2, 1.5], fixed=["th1"], max_iter=1)


def test_bad_fixed_names_are_refused():
    _, f, _ = delta()
    with pytest.raises(eg.ModelError, match="fixed: unknown coordinate or speed 'shoulder4'; coordinates"):
        eg.assemble(f, guess([0, 0, 0]), fixed=["shoulder1", "shoulder4"])
    with pytest.raises(eg.ModelError, match="'shoulder1dot' names speed 'shoulder1dot' a second time"):
        eg.assemble(f, guess([0, 0, 0]), fixed=["shoulder1", "shoulder1dot"])
    with pytest.raises(eg.ModelError, match=r"q_guess: expected 12 finite numbers, got shape"):
        eg.assemble(f, np.zeros(3), fixed=["shoulder1"])
    with pytest.raises(eg.ModelError, match="no loops or rolling disks"):
        eg.assemble(_tree(), [0.0])


def test_coordinates_that_are_no_speed_name_their_joint():
    """A free flyer's position and quaternion components and a planar joint's x are not speeds: the hint
    names the joint and its speeds."""
    f = rolling_disk()
    for name in ("base_x", "base_qw"):
        with pytest.raises(eg.ModelError, match=rf"'{name}' \(a coordinate of FreeFlyer joint 'base' whose "
                                                r"rate is no one speed: name its speeds \['base_vx'"):
            eg.assemble(f, [0, 0, 0.3, 0, 0, 0, 1], fixed=[name])
    system = eg.System()
    system.add_body("cart", joint=eg.Planar("cart"), mass=1)
    with pytest.raises(eg.ModelError, match=r"'cart_x' \(a coordinate of Planar joint 'cart' whose rate "
                                            r"is no one speed: name its speeds \['cart_vx', 'cart_vy'"):
        speed_indices(system, ["cart_x"], "fixed")


def _tree() -> eg.System:
    system = eg.System()
    system.add_body("link", joint=eg.Revolute("q"), mass=1, com=(0.5, 0, 0))
    return system


@functools.cache
def rolling_disk():
    """A uniform thin disk (radius ρ, mass m) on a free flyer rolling on the plane z = 0."""
    system = eg.System()
    rho, m = 0.3, 2.0
    system.add_body("disk", joint=eg.FreeFlyer("base"), mass=m,
                    inertia=np.diag([1, 2, 1]) * m * rho**2 / 4)
    system.add_rolling("disk", rho, axis=(0, 1, 0))
    return eg.codegen(eg.derive(system, method="recursive"))


def test_rolling_disk_keeps_rolling():
    """A disk rolling upright with a tilt rate: project makes the state consistent (height 0, no slip,
    unit quaternion), 3 s with projection keep it there with the energy constant (rolling without slip
    does no work); Baumgarte from 1 cm too high brings the height back (r̈ + 2α ṙ + β² r = 0: below
    1e-8 after 3 s at α = β = 10)."""
    f = rolling_disk()
    q, u = eg.project(f, [0, 0, 0.25, 0, 0, 0, 1.05], [0, 0, 0, 0.2, 3.0, 0])
    np.testing.assert_allclose(q[2:], [0.3, 0, 0, 0, 1], atol=1e-12)
    # no slip at c = (0, 0, −ρ): v_x = ρ ω_y, v_y = −ρ ω_x, v_z = 0; nearest in ½ m v² + ½ I ω²:
    # ω_y = (I_y ω_y0 + m ρ v_x0) / (I_y + m ρ²) = 1, ω_x = I_x ω_x0 / (I_x + m ρ²) = 0.04
    np.testing.assert_allclose(u, [0.3, -0.012, 0, 0.04, 1.0, 0], atol=1e-12)
    sim = eg.simulate(f, (q, u), (0, 3), rtol=1e-9, atol=1e-9)
    assert sim.closure_drift.max() <= 1e-9 and sim.velocity_drift.max() <= 1e-12
    assert np.ptp(sim.energy) <= 1e-7
    np.testing.assert_allclose(np.linalg.norm(sim.q[:, 3:], axis=1), 1, atol=1e-14)
    high = q + [0, 0, 0.01, 0, 0, 0, 0]
    sim = eg.simulate(f, (high, u), (0, 3), stabilization="baumgarte", rtol=1e-9, atol=1e-9)
    assert sim.closure_drift[0] == pytest.approx(0.01) and sim.closure_drift[-1] <= 1e-8


def test_example_runs():
    import runpy

    runpy.run_path(str(Path(__file__).parents[1] / "examples" / "delta_robot.py"), run_name="__main__")
