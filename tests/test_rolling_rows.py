"""A rolling disk's rows against the disk's closed forms (centre at height z, lean φ, yaw ψ, spin θ):
the lowest point is at z − R cos φ, the contact point at the centre + R (−sin φ sin ψ, sin φ cos ψ, −cos φ)
in the chain x, y, z, ψ (about z), φ (about the turned x), θ (about the leaned y): the material point at the
contact moves with v_centre + ω × c; J̇u = d/dt (J u) by differences."""
import functools

import mpmath
import numpy as np
import pytest
import sympy as sp
from hypothesis import example, given, settings, strategies as st

import eomgen as eg
from eomgen.errors import ModelError

R = 0.3


def disk(gravity=(0, 0, -9.81), axis=(0, 1, 0), ground=None):
    system = eg.System(gravity=gravity)
    system.add_body("x", joint=eg.Prismatic("x", axis=(1, 0, 0)))
    system.add_body("y", parent="x", joint=eg.Prismatic("y", axis=(0, 1, 0)))
    system.add_body("z", parent="y", joint=eg.Prismatic("z", axis=(0, 0, 1)))
    system.add_body("yaw", parent="z", joint=eg.Revolute("psi", axis=(0, 0, 1)))
    system.add_body("lean", parent="yaw", joint=eg.Revolute("phi", axis=(1, 0, 0)))
    system.add_body("wheel", parent="lean", joint=eg.Revolute("theta", axis=(0, 1, 0)), mass=2,
                    inertia=np.diag([2 * R**2 / 4, 2 * R**2 / 2, 2 * R**2 / 4]))
    system.add_rolling("wheel", radius=R, axis=axis, ground=ground)
    return system


@functools.cache
def numeric_disk():
    return eg.codegen(eg.derive(disk(), method="recursive"))


def closed_forms(q, u):
    x, y, z, psi, phi, theta = q
    c = R * np.array([-np.sin(phi) * np.sin(psi), np.sin(phi) * np.cos(psi), -np.cos(phi)])
    # ω = ψ̇ e_z + φ̇ e_x' + θ̇ e_y'' (e_x' = Rz e_x, e_y'' = Rz Rx e_y)
    e_x = np.array([np.cos(psi), np.sin(psi), 0])
    e_y = np.array([-np.sin(psi) * np.cos(phi), np.cos(psi) * np.cos(phi), np.sin(phi)])
    omega = u[3] * np.array([0, 0, 1]) + u[4] * e_x + u[5] * e_y
    return z + c[2], u[:3] + np.cross(omega, c)


def test_height_and_contact_velocity_equal_the_closed_forms():
    f = eg.codegen(eg.derive(disk(), method="recursive"))
    rng = np.random.default_rng(0)
    for _ in range(5):
        q, u = rng.uniform(-1.2, 1.2, 6), rng.uniform(-2, 2, 6)
        height, v = closed_forms(q, u)
        assert f.closure_rows == ["wheel_rolling.height"]
        assert f.constraint_rows == ["wheel_rolling.t1", "wheel_rolling.t2", "wheel_rolling.n"]
        assert np.isclose(f.closure_residual(q)[0], height, atol=1e-14)
        assert np.allclose(f.contact_jacobian(q) @ u, v, atol=1e-13)
        h = 1e-5
        rate = (f.contact_jacobian(q + h * u) - f.contact_jacobian(q - h * u)) / (2 * h)
        assert np.allclose(f.contact_jacobian_dot_u(q, u), rate @ u, atol=1e-7)


def test_ground_below_a_downward_gravity_and_a_placed_ground():
    """gravity along +z (z down): the default ground's normal is −z, its rows t1 = x, t2 = −y, n = −z."""
    f = eg.codegen(eg.derive(disk(gravity=(0, 0, 9.81)), method="recursive"))
    q, u = np.array([0.1, 0.2, -0.25, 0.3, 0.2, 0.4]), np.array([0.3, -0.1, 0.2, 0.5, -0.4, 1.0])
    height, v = closed_forms(q, u)  # the lowest point now at z + R cos φ along −z: the disk hangs "up"
    assert np.isclose(f.closure_residual(q)[0], -(q[2] + R * np.cos(q[4])), atol=1e-14)
    ground = eg.Placement(translation=(0, 0, 0.5))  # the plane z = 0.5, normal +z
    g = eg.codegen(eg.derive(disk(ground=ground), method="recursive"))
    assert np.isclose(g.closure_residual(q)[0], height - 0.5, atol=1e-14)
    assert np.allclose(g.contact_jacobian(q) @ u, v, atol=1e-13)


def test_bad_rolling_disks_are_refused():
    with pytest.raises(ModelError, match="axle is normal to the ground"):
        disk(axis=(0, 0, 1))
    system = disk()
    with pytest.raises(ModelError, match="radius must be positive"):
        system.add_rolling("wheel", radius=0, name="other")
    with pytest.raises(ModelError, match="exists already"):
        system.add_rolling("wheel", radius=R)
    with pytest.raises(ModelError, match="unknown body"):
        system.add_rolling("tyre", radius=R)
    with pytest.raises(ModelError, match=r"direction of gravity \[0, 0, g\] is not known"):
        disk(gravity=(0, 0, sp.Symbol("g", real=True)))
    assert disk(gravity=(0, 0, -sp.Symbol("g", positive=True))).rolling[0].ground.rotation == sp.eye(3)
    with pytest.raises(ModelError, match="axis must not be zero"):
        system.add_rolling("wheel", radius=R, axis=(0, 0, 0), name="third")


def test_default_ground_faces_against_any_gravity_and_a_flat_disk_is_refused_at_its_state():
    """gravity along −y: the ground is the plane y = 0 (normal +y); a disk lying flat at a state has no
    contact point: refused, not a free fall."""
    system = eg.System(gravity=(0, -9.81, 0))
    system.add_body("wheel", joint=eg.FreeFlyer("base", parametrization="euler"), mass=1,
                    inertia=np.diag([0.25, 0.25, 0.5]))
    disk = system.add_rolling("wheel", radius=R, axis=(0, 0, 1))
    n = np.array(disk.ground.rotation, dtype=float)[:, 2]
    assert np.allclose(n, [0, 1, 0]) and np.isclose(np.linalg.det(np.array(disk.ground.rotation, float)), 1)
    f = eg.codegen(eg.derive(system, method="recursive"))
    q = np.array([0.1, R, 0.2, 0.3, 0.0, 0.0])  # axle along world z, touching the ground y = 0
    assert np.isclose(f.closure_residual(q)[0], 0, atol=1e-14)
    flat = np.array([0.1, 0.5, 0.2, 0.0, 0.0, np.pi / 2])  # roll a quarter turn: the axle along +y
    with pytest.raises(ModelError, match=r"'wheel_rolling' \(body 'wheel'\) lies flat: 6.1e-17 rad"):
        f.constrained_dynamics(flat, np.zeros(6))


def closed_forms_mp(q, u):
    """J_c u (world rows) of `closed_forms`, in mpmath (the caller's precision)."""
    x, y, z, psi, phi, theta = q
    s, c = mpmath.sin, mpmath.cos
    contact = mpmath.matrix([-R * s(phi) * s(psi), R * s(phi) * c(psi), -R * c(phi)])
    omega = (u[3] * mpmath.matrix([0, 0, 1]) + u[4] * mpmath.matrix([c(psi), s(psi), 0])
             + u[5] * mpmath.matrix([-s(psi) * c(phi), c(psi) * c(phi), s(phi)]))
    cross = mpmath.matrix([omega[1] * contact[2] - omega[2] * contact[1],
                           omega[2] * contact[0] - omega[0] * contact[2],
                           omega[0] * contact[1] - omega[1] * contact[0]])
    return mpmath.matrix(u[:3]) + cross


@settings(max_examples=10, deadline=None)
@given(st.sampled_from([1e-3, 1e-5, 1e-6, 1e-7]), st.floats(-3, 3), st.sampled_from([1, -1]))
@example(1e-5, 2.65625, -1)  # 1.1e-15 / eps, the worst found (so before and after the chain rule's partials)
def test_contact_rows_near_flat_equal_mpmath(eps, psi, side):
    """eps rad from lying flat (lean ±(π/2 − eps)), J_c equals the closed form in 40-digit mpmath to 1e-9
    relative (was 1e-5 at 1e-6 rad: √(1 − (e · n)²) cancelled); J̇_c u (= d/dt (J_c(q + t u) u) at t = 0 by
    mpmath's differentiation) to 2e-15 / eps (about 9 units of rounding over eps; 1.1e-15 / eps seen): ċ by
    the chain rule through c = ρ e × (e × n) / s loses the digits of ε / s (1e-9 at 1e-6 rad, half of them
    at the flat disk's limit √ε)."""
    f = numeric_disk()
    q = np.array([0.1, -0.2, 0.3, psi, side * (np.pi / 2 - eps), 0.5])
    u = np.array([0.3, -0.1, 0.2, 0.5, -0.4, 1.0])
    with mpmath.workdps(40):
        qm, um = [mpmath.mpf(float(v)) for v in q], [mpmath.mpf(float(v)) for v in u]
        J = np.array([[float(v) for v in closed_forms_mp(qm, list(np.eye(6)[k]))] for k in range(6)]).T
        Jdot_u = np.array([float(mpmath.diff(lambda t: closed_forms_mp(
            [a + t * b for a, b in zip(qm, um)], um)[i], 0)) for i in range(3)])
    assert np.abs(f.contact_jacobian(q) - J).max() <= 1e-9 * np.abs(J).max()
    assert np.abs(f.contact_jacobian_dot_u(q, u) - Jdot_u).max() <= 2e-15 / eps * np.abs(Jdot_u).max()
