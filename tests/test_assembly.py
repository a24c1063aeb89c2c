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
from eomgen.verify import to_pinocchio

sys.path.insert(0, str(Path(__file__).parents[1] / "examples"))
from delta_robot import ANGLES, ARM, BASE, FOREARM, PLATFORM, SHOULDERS, delta_robot, guess  # noqa: E402
from four_bar import four_bar  # noqa: E402

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


def test_unsatisfiable_closure_says_by_how_much():
    """The four-bar with crank (th1 = 0) and rocker (th3 = π) held: the coupler's end (length 1 about
    (0.3, 0)) comes no closer than 0.8 to the rocker's end (0.1, 0), along x; the Delta with its platform
    2 m down."""
    f = eg.codegen(eg.derive(four_bar(), method="recursive"))
    with pytest.raises(eg.ModelError, match=r"with \['th1dot', 'th3dot'\] held: ‖r‖ = 8.000e-01 .* "
                                            r"worst row 'loop.x' = -8.000e-01"):
        eg.assemble(f, [0.0, 3.0, np.pi], fixed=["th1", "th3"])
    _, f, _ = delta()
    q = guess([0.3, 0.3, 0.3])
    q[2] = -2.0
    with pytest.raises(eg.ModelError, match=r"cannot be satisfied .* ‖r‖ = .* worst row 'leg\d.z'"):
        eg.assemble(f, q, fixed=SHOULDERS + ["platform_z"])


def test_bad_fixed_names_are_refused():
    _, f, _ = delta()
    with pytest.raises(eg.ModelError, match="fixed: unknown coordinate or speed 'shoulder4'; coordinates"):
        eg.assemble(f, guess([0, 0, 0]), fixed=["shoulder1", "shoulder4"])
    with pytest.raises(eg.ModelError, match="'shoulder1dot' names speed 'shoulder1dot' a second time"):
        eg.assemble(f, guess([0, 0, 0]), fixed=["shoulder1", "shoulder1dot"])
    with pytest.raises(eg.ModelError, match=r"q_guess must have shape \(12,\)"):
        eg.assemble(f, np.zeros(3), fixed=["shoulder1"])
    with pytest.raises(eg.ModelError, match="no loops or rolling disks"):
        eg.assemble(_tree(), [0.0])


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
