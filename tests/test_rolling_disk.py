"""The rolling disk built with add_rolling (examples/rolling_disk.py: rails x, y, z, yaw, lean, spin; z
and ẋ, ẏ, ż dependent; and on a free-flyer base) against sympy's KanesMethod of the classic disk (yaw,
lean, spin; the contact point at rest, the centre R above it along the lean frame's z); upright rolling
stable above ω² = g/(3R) by simulation (the linearized lean equation by hand gives the amplitude); bad
input."""
import runpy
import sys
import warnings
from pathlib import Path

import numpy as np
import pytest
import sympy as sp
import sympy.physics.mechanics as me
from scipy.integrate import solve_ivp
from scipy.spatial.transform import Rotation

import eomgen as eg
import kane_systems as K

sys.path.insert(0, str(Path(__file__).parents[1] / "examples"))
from rolling_disk import LEAN, VALUES, critical_spin, roll, rolling_disk  # noqa: E402


def classic_disk_sympy(lean_axis: str = "x", speeds: str = "rates"):
    """sympy's KanesMethod of the disk: q = (yaw, lean, spin), R = Rz(yaw) R_lean R_spin with the lean
    about `lean_axis` ("x": the axle y; "y": the axle x); speeds the angle rates, ω in disk axes
    ("body") or the yaw and lean rates and ω along the axle ("axle": θ̇ + ψ̇ sin(lean), lean about x).
    The contact point has zero velocity (no slip), the centre G = contact + R e_z of the lean frame.
    Returns (km, q, u, parameter values)."""
    q = me.dynamicsymbols("q1:4")
    u = me.dynamicsymbols("u1:4")
    m, R, g = sp.symbols("m R g", positive=True)
    N = me.ReferenceFrame("N")
    A = N.orientnew("A", "Axis", [q[0], N.z])
    lean, axle = (A.x, "y") if lean_axis == "x" else (A.y, "x")
    B = A.orientnew("B", "Axis", [q[1], lean])
    C = B.orientnew("C", "Axis", [q[2], getattr(B, axle)])
    if speeds == "axle":
        kd = [u[0] - q[0].diff(), u[1] - q[1].diff(), u[2] - q[2].diff() - q[0].diff() * sp.sin(q[1])]
    elif speeds == "rates":
        A.set_ang_vel(N, u[0] * N.z)
        B.set_ang_vel(A, u[1] * lean)
        C.set_ang_vel(B, u[2] * getattr(B, axle))
        kd = [ui - qi.diff() for ui, qi in zip(u, q)]
    else:
        kd = [C.ang_vel_in(N).dot(e) - ui for e, ui in zip((C.x, C.y, C.z), u)]
        C.set_ang_vel(N, u[0] * C.x + u[1] * C.y + u[2] * C.z)
    contact = me.Point("contact")
    contact.set_vel(N, 0)
    G = contact.locatenew("G", R * B.z)
    G.v2pt_theory(contact, N, C)
    I = [m * R**2 / 4] * 3
    I["xyz".index(axle)] = m * R**2 / 2
    disk = me.RigidBody("disk", G, C, m, (me.inertia(C, *I), G))
    km = me.KanesMethod(N, q_ind=q, u_ind=u, kd_eqs=kd)
    km.kanes_equations([disk], [(G, -m * g * N.z)])
    return km, q, u, {m: VALUES["m"], R: VALUES["R"], g: VALUES["g"]}


def free_disk(parametrization: str) -> tuple[eg.System, eg.KaneEquations]:
    """The disk on a free-flyer base (axle x; ZYX Euler angles: yaw, lean = pitch, spin = roll; or the
    quaternion with u = the base twist in disk axes), z dependent, the angular speeds independent."""
    m, R, g = sp.symbols("m R g", positive=True)
    system = eg.System(gravity=(0, 0, -g))
    disk = system.add_body("disk", joint=eg.FreeFlyer("base", parametrization), mass=m,
                           inertia=sp.diag(m * R**2 / 2, m * R**2 / 4, m * R**2 / 4))
    system.add_rolling(disk, radius=R, axis=(1, 0, 0))
    return system, eg.kane(system, dependent_coordinates=[system.q[2]], independent=list(system.u[3:]))


def test_equals_sympy_classic_disk():
    """At random consistent states (x, y anywhere, z = R cos(lean) by hand, |lean| < 1.3): M̃ and f̃ in
    the yaw, lean and spin rates equal sympy's, the height residual is 0, ẋ, ẏ, ż make the contact
    point's velocity zero (by hand: v_G = ω × R e_z of the lean frame)."""
    system, k = rolling_disk()
    assert k.dependent_coordinates == [system.q[2]] and k.dependent == list(system.u[:3])
    f = eg.codegen(k)
    km, qs, us, values = classic_disk_sympy()
    rng = np.random.default_rng(4)
    for _ in range(5):
        x, y, yaw, spin = rng.uniform(-3, 3, 4)
        lean = rng.uniform(-1.3, 1.3)
        q = np.array([x, y, VALUES["R"] * np.cos(lean), yaw, lean, spin])
        w = rng.uniform(-3, 3, 3)
        np.testing.assert_allclose(f.holonomic_residual(q, VALUES), 0, atol=1e-15)
        at = {**values, **dict(zip(qs, q[3:])), **dict(zip(us, w))}
        np.testing.assert_allclose(f.mass_matrix(q, w, VALUES), K.number(km.mass_matrix, at), rtol=1e-12,
                                   atol=1e-14)
        np.testing.assert_allclose(f.forcing(q, w, VALUES), K.number(km.forcing, at)[:, 0], rtol=1e-12,
                                   atol=1e-12)
        c, s = np.cos, np.sin
        e_z = np.array([s(yaw) * s(lean), -c(yaw) * s(lean), c(lean)])  # Rz(yaw) Rx(lean) e_z
        e_y = np.array([-s(yaw) * c(lean), c(yaw) * c(lean), s(lean)])  # Rz(yaw) Rx(lean) e_y
        omega = w[0] * np.array([0, 0, 1]) + w[1] * np.array([c(yaw), s(yaw), 0]) + w[2] * e_y
        np.testing.assert_allclose(f.dependent_speeds(q, w, VALUES), np.cross(omega, VALUES["R"] * e_z),
                                   atol=1e-13)


def test_new_speeds_through_kinematic_equations():
    """The disk of examples/rolling_disk.py in new speeds w (ẋ, ẏ, ż; ψ̇, φ̇ and ω along the axle
    θ̇ + ψ̇ sin φ): the rolling rows, in u, are written in w through u = −Y⁻¹ (K w + k0); M̃ and f̃ equal
    sympy's disk in the same speeds."""
    system, _ = rolling_disk()
    w = sp.symbols("w1:7")
    u, lean = system.u, system.q[4]
    kinematic = [w[i] - u[i] for i in range(5)] + [w[5] - u[5] - u[3] * sp.sin(lean)]
    k = eg.kane(system, speeds=w, kinematic_equations=kinematic, dependent_coordinates=[system.q[2]],
                independent=w[3:])
    f = eg.codegen(k)
    km, qs, us, values = classic_disk_sympy("x", "axle")
    rng = np.random.default_rng(6)
    for _ in range(3):
        yaw, spin, lean = *rng.uniform(-3, 3, 2), rng.uniform(-1.3, 1.3)
        q, ws = np.array([0.3, -0.2, VALUES["R"] * np.cos(lean), yaw, lean, spin]), rng.uniform(-3, 3, 3)
        at = {**values, **dict(zip(qs, q[3:])), **dict(zip(us, ws))}
        np.testing.assert_allclose(f.mass_matrix(q, ws, VALUES), K.number(km.mass_matrix, at), rtol=1e-12,
                                   atol=1e-14)
        np.testing.assert_allclose(f.forcing(q, ws, VALUES), K.number(km.forcing, at)[:, 0], rtol=1e-11,
                                   atol=1e-12)


@pytest.mark.parametrize("parametrization", ["euler", "quaternion"])
def test_disk_on_a_free_flyer_equals_sympy(parametrization):
    """The disk on a free flyer (add_rolling, axle x): M̃, f̃ in the ZYX angle rates, or in ω in disk axes
    (quaternion), equal sympy's classic disk leaning about y, at random consistent states (the base's
    height z = R cos(pitch), the quaternion's ZYX angles for sympy)."""
    system, k = free_disk(parametrization)
    f = eg.codegen(k)
    km, qs, us, values = classic_disk_sympy("y", "rates" if parametrization == "euler" else "body")
    rng = np.random.default_rng(5)
    for _ in range(4):
        yaw, spin, x, y = rng.uniform(-3, 3, 4)
        lean = rng.uniform(-1.3, 1.3)
        angles = Rotation.from_euler("ZYX", [yaw, lean, spin])
        q = np.r_[x, y, VALUES["R"] * np.cos(lean), [yaw, lean, spin] if parametrization == "euler" else
                  angles.as_quat()]
        w = rng.uniform(-3, 3, 3)
        np.testing.assert_allclose(f.holonomic_residual(q, VALUES), 0, atol=1e-15)
        at = {**values, **dict(zip(qs, [yaw, lean, spin])), **dict(zip(us, w))}
        np.testing.assert_allclose(f.mass_matrix(q, w, VALUES), K.number(km.mass_matrix, at), rtol=1e-12,
                                   atol=1e-14)
        np.testing.assert_allclose(f.forcing(q, w, VALUES), K.number(km.forcing, at)[:, 0], rtol=1e-11,
                                   atol=1e-12)


@pytest.mark.parametrize("factor", [1.2, 0.8])
def test_upright_rolling_stable_above_critical_spin(factor):
    """6 s from lean 0.02 rad at factor × ω_c, ω_c² = g/(3R). Linearized by hand (I = m R²/4, J = m R²/2,
    k = factor²): (5/4) m R² φ̈ + m g R (k − 1) φ = m g R k φ0, so φ oscillates about k φ0/(k − 1) and
    |φ| ≤ φ0 (2k/(k − 1) − 1) = 5.55 φ0 at 1.2 (within 5 %), and grows as e^(λt) at 0.8 (past 0.5 rad).
    The height residual stays below 1e-9 without projection."""
    system, k = rolling_disk()
    f = eg.codegen(k)
    sol = roll(f, factor, lean=0.02, seconds=6.0)
    assert sol.success
    lean = np.abs(sol.y[LEAN])
    assert np.max(np.abs(f.holonomic_residual(sol.y[:6].T, VALUES))) < 1e-9
    if factor > 1:
        bound = 0.02 * (2 * factor**2 / (factor**2 - 1) - 1)
        assert bound * 0.95 < lean.max() < bound * 1.05
        assert lean[sol.t > 3].min() < 0.03  # back near the start: an oscillation, not a drift
    else:
        assert lean.max() > 0.5
    assert critical_spin() == pytest.approx(np.sqrt(9.81 / 0.9))


def test_rolling_needs_its_dependent_coordinate():
    """The disk's height needs a dependent coordinate of its own, and three dependent speeds; a disk whose
    axle is along the ground normal is refused where it is added."""
    system, _ = rolling_disk()
    with pytest.raises(eg.ModelError, match=r"rolling disks \['disk_rolling'\] \(one height each\) need"):
        eg.kane(system, independent=list(system.u[3:]))
    with pytest.raises(eg.ModelError, match="and 1 rolling disks .3 rows each. need as many dependent"):
        eg.kane(system, dependent_coordinates=[system.q[2]], independent=list(system.u[2:]))
    flat = eg.System()
    body = flat.add_body("wheel", joint=eg.Translation("t"), mass=1, inertia=sp.eye(3))
    with pytest.raises(eg.ModelError, match="axle is normal to the ground"):
        flat.add_rolling(body, radius=0.3, axis=(0, 0, 1))


def test_example_prints_both_rates(capsys):
    """examples/rolling_disk.py prints the critical rate and both runs: up at 1.2 ×, leaning far at 0.8 ×."""
    runpy.run_path(str(Path(__file__).parents[1] / "examples" / "rolling_disk.py"), run_name="__main__")
    lines = capsys.readouterr().out.splitlines()
    assert lines[0].startswith("critical spin rate √(g/(3R)) = 3.3015 rad/s")
    assert lines[1].startswith("1.2 × ω_c") and "stayed up" in lines[1]
    assert lines[2].startswith("0.8 × ω_c") and float(lines[2].split("largest |lean| ")[1].split()[0]) > 0.5


def textbook_disk() -> eg.System:
    """The textbook disk (sympy's and Moore's formulation): rails x, y (the contact point), yaw, the lean
    about the contact line, the centre R above it along the lean frame's z, the spin about the axle y."""
    m, R, g = sp.symbols("m R g", positive=True)
    system = eg.System(gravity=(0, 0, -g))
    parent = None
    for name, axis in (("x", (1, 0, 0)), ("y", (0, 1, 0))):
        parent = system.add_body(f"rail_{name}", parent=parent, joint=eg.Prismatic(name, axis=axis))
    system.add_body("yaw", parent=parent, joint=eg.Revolute("yaw", axis=(0, 0, 1)))
    system.add_body("lean", parent="yaw", joint=eg.Revolute("lean", axis=(1, 0, 0)))
    disk = system.add_body("disk", parent="lean", joint=eg.Revolute("spin", axis=(0, 1, 0)), mass=m,
                           placement=eg.Placement(translation=(0, 0, R)),
                           inertia=sp.diag(m * R**2 / 4, m * R**2 / 2, m * R**2 / 4))
    system.add_rolling(disk, radius=R, axis=(0, 1, 0))
    return system


def test_textbook_disk_needs_no_dependent_coordinate_and_equals_sympy():
    """The tree keeps the textbook disk on the ground (its height R cos(lean) − R |cos(lean)| is zero):
    no dependent coordinate, ẋ and ẏ dependent; M̃ and f̃ equal sympy's KanesMethod of the same disk at
    random states; 3 s of rolling keep the energy to 1e-9; `eg.reduce` of the equations in u gives the
    same M̃ and −f̃ (the normal row dropped there as well, without a warning)."""
    system = textbook_disk()
    k = eg.kane(system, independent=list(system.u[2:]))
    assert k.grounded == ["disk_rolling"] and k.dependent == list(system.u[:2])
    assert k.dependent_coordinates == []
    f = eg.codegen(k)
    km, qs, us, values = classic_disk_sympy()
    eom = eg.derive(system, method="recursive")
    reduced = eg.reduce(eom, ["yaw", "lean", "spin"])
    rng = np.random.default_rng(8)
    for _ in range(4):
        q = np.r_[rng.uniform(-3, 3, 3), rng.uniform(-1.3, 1.3), rng.uniform(-3, 3)]
        w = rng.uniform(-3, 3, 3)
        at = {**values, **dict(zip(qs, q[2:])), **dict(zip(us, w))}
        M, forcing = K.number(km.mass_matrix, at), K.number(km.forcing, at)[:, 0]
        np.testing.assert_allclose(f.mass_matrix(q, w, VALUES), M, rtol=1e-12, atol=1e-14)
        np.testing.assert_allclose(f.forcing(q, w, VALUES), forcing, rtol=1e-12, atol=1e-12)
        with warnings.catch_warnings():
            warnings.simplefilter("error")
            np.testing.assert_allclose(reduced.M(q, VALUES), M, rtol=1e-12, atol=1e-14)
            np.testing.assert_allclose(-reduced.b(q, w, VALUES) - reduced.g(q, VALUES), forcing, rtol=1e-11,
                                       atol=1e-12)
    x0 = np.r_[0, 0, 0, 0.3, 0, 0.5, -0.4, 2 * critical_spin()]
    sol = solve_ivp(lambda t, x: f.rhs(t, x, params=VALUES), (0, 3), x0, rtol=1e-11, atol=1e-11,
                    method="DOP853")
    energy = f.energy(sol.y.T, VALUES)
    assert sol.success and np.ptp(energy) < 1e-9 * abs(energy).max()


def test_disk_near_flat_is_refused_naming_it():
    """1e-9 rad from lying flat (below √ε) Kane's equations refuse the state naming the disk, its body and
    the angle (was: "u: contains NaN" from 1 − (e · n)² = 0); 1e-6 rad from flat they are finite."""
    _, k = rolling_disk()
    f = eg.codegen(k)
    for eps in (1e-9, 0.0):
        lean = np.pi / 2 - eps
        q = np.array([0, 0, VALUES["R"] * np.cos(lean), 0.3, lean, 0.2])
        with pytest.raises(eg.ModelError, match=r"rolling disk 'disk_rolling' \(body 'disk'\) lies flat: "
                                                r"(1\.0e-09|6\.1e-17) rad from flat"):
            f.rhs(0, np.r_[q, 0.1, 0.2, 0.3], params=VALUES)
    lean = np.pi / 2 - 1e-6
    q = np.array([0, 0, VALUES["R"] * np.cos(lean), 0.3, lean, 0.2])
    assert np.isfinite(f.rhs(0, np.r_[q, 0.1, 0.2, 0.3], params=VALUES)).all()
