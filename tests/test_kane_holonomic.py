"""Kane's method with holonomic constraints and on a floating base: a planar four-bar (configuration
constraints, dependent coordinates q2, q3) against sympy's KanesMethod, its pose by hand, its energy in a
simulation; a free-flyer base (quaternion and ZYX Euler) and a ball-joint base with an arm against
sympy's KanesMethod written independently, the recursive method and Pinocchio; bad input."""
import numpy as np
import pinocchio as pin
import pytest
import sympy as sp
import sympy.physics.mechanics as me
from scipy.integrate import solve_ivp
from scipy.spatial.transform import Rotation

import eomgen as eg
import kane_systems as K
from eomgen.model.urdf import pinocchio_configuration
from eomgen.verify import to_pinocchio

RNG = np.random.default_rng(15)


@pytest.mark.parametrize("speeds", ["rates", "absolute"])
def test_four_bar_equals_sympy_kanes_method(speeds):
    """At poses by hand (random crank angles): f(q) = 0, the dependent speeds satisfy sympy's velocity
    constraints, F̃_r equal and F̃_r + F̃*_r equal sympy's for random ẇ_ind; speeds q̇ or the links'
    absolute rates (u = −Y⁻¹ (K w + k0) put in ḟ)."""
    system, args = K.four_bar(speeds)
    k = eg.kane(system, **args)
    assert k.dependent_coordinates == list(system.q[1:]) and k.independent_coordinates == [system.q[0]]
    f = eg.codegen(k)
    km, qs, us = K.four_bar_sympy(speeds)
    for q1 in RNG.uniform(-np.pi, np.pi, 4):
        q, w = np.array(K.four_bar_pose(q1)), RNG.uniform(-2, 2, 1)
        np.testing.assert_allclose(f.holonomic_residual(q), 0, atol=1e-14)
        values = {**dict(zip(qs, q)), **dict(zip(us, [*w, *f.dependent_speeds(q, w)]))}
        np.testing.assert_allclose(K.number(km._f_nh, values)[:, 0], 0, atol=1e-13)
        np.testing.assert_allclose(f.active_forces(q, w), K.number(km._fr, values)[:, 0], atol=1e-12)
        for wd in RNG.uniform(-1, 1, (2, 1)):
            np.testing.assert_allclose(f.forcing(q, w) - f.mass_matrix(q, w) @ wd,
                                       K.sympy_residuals(km, 1, values, wd), rtol=1e-10, atol=1e-10)


def test_assemble_finds_the_pose_by_hand():
    """assemble(q_guess) holds q1 and solves q2, q3 by Newton: the pose by hand to 1e-12 from guesses
    0.1 rad off (one state and a batch; NumPy and C); a two-link arm asked to reach beyond its length
    fails, saying by how much."""
    system, args = K.four_bar()
    k = eg.kane(system, **args)
    q1 = RNG.uniform(-np.pi, np.pi, 5)
    poses = np.array([K.four_bar_pose(x) for x in q1])
    guesses = poses + np.c_[np.zeros(5), RNG.uniform(-0.1, 0.1, (5, 2))]
    for f in (eg.codegen(k), eg.codegen(k, backend="c")):
        np.testing.assert_allclose(f.assemble(guesses), poses, atol=1e-12)
        np.testing.assert_allclose(f.assemble(guesses[0]), poses[0], atol=1e-12)
    far = eg.System(gravity=(0, -9.81, 0))
    link = far.add_body("l1", joint=eg.Revolute("p1", axis=(0, 0, 1)), mass=1, inertia=sp.eye(3))
    far.add_body("l2", parent=link, joint=eg.Revolute("p2", axis=(0, 0, 1)), mass=1, inertia=sp.eye(3),
                 placement=eg.Placement(translation=(1, 0, 0)))
    p1, p2 = far.q
    reach = [sp.cos(p1) + sp.cos(p1 + p2) - 3]  # a two-link arm of reach 2 to x = 3: fails by ≥ 1
    g = eg.codegen(eg.kane(far, holonomic=reach, dependent_coordinates=[p2], independent=[far.u[0]]))
    with pytest.raises(eg.ModelError, match=r"assemble: the holonomic constraints fail by 1\.\d+"):
        g.assemble([0.0, 0.3])


def test_four_bar_simulation_keeps_the_loop_and_energy():
    """3 s of the unforced four-bar (τ = 0 through a zero torque parameter) integrating all q with the
    generated rhs: the loop stays closed to 1e-9 without projection, the energy ½ Σ (m v_G² + I ω²) + m g
    y_G (by hand) to 1e-9 relative."""
    system, args = K.four_bar()
    system.loads.clear()
    f = eg.codegen(eg.kane(system, **args))
    q0 = K.four_bar_pose(0.4)
    sol = solve_ivp(f.rhs, (0, 3), np.r_[q0, 3.0], method="DOP853", rtol=1e-12, atol=1e-12,
                    t_eval=np.linspace(0, 3, 31))
    assert sol.success
    q, w = sol.y[:3].T, sol.y[3:].T
    assert np.max(np.abs(f.holonomic_residual(q))) < 1e-9
    u = f.joint_speeds(q, w)
    energies = 0
    angles, rates, tip, tip_v = np.cumsum(q, 1), np.cumsum(u, 1), 0, 0
    for i in range(3):
        length, m, I = (K.BAR[f"{k}{i + 1}"] for k in ("l", "m", "I"))
        e = np.c_[np.cos(angles[:, i]), np.sin(angles[:, i])]
        e_perp = np.c_[-e[:, 1], e[:, 0]] * rates[:, i:i + 1]
        G, v_G = tip + length / 2 * e, tip_v + length / 2 * e_perp
        energies = (energies + 0.5 * m * np.sum(v_G**2, 1) + 0.5 * I * rates[:, i]**2
                    + m * K.BAR["g"] * G[:, 1])
        tip, tip_v = tip + length * e, tip_v + length * e_perp
    assert np.ptp(energies) < 1e-9 * np.max(np.abs(energies))
    assert np.ptp(q[:, 0]) > 1  # it moved


def test_closed_forms_of_a_line():
    """A particle on rails x, y held on the line x = a y (gravity −y), x dependent: by hand M̃ = m (1 + a²),
    f̃ = −m g, ẋ = a ẏ; the worked solution shows the holonomic constraint."""
    m, a, g = sp.symbols("m a g", positive=True)
    system = eg.System(gravity=(0, -g, 0))
    rail = system.add_body("rail_x", joint=eg.Prismatic("x", axis=(1, 0, 0)))
    system.add_body("p", parent=rail, joint=eg.Prismatic("y", axis=(0, 1, 0)), mass=m, inertia=sp.zeros(3))
    x, y = system.q
    k = eg.kane(system, holonomic=[x - a * y], dependent_coordinates=[x], independent=[system.u[1]])
    assert sp.simplify(k.mass_matrix - sp.Matrix([[m * (1 + a**2)]])) == sp.zeros(1, 1)
    assert sp.simplify(k.forcing - sp.Matrix([-m * g])) == sp.zeros(1, 1)
    assert k.dependent_speeds == sp.Matrix([a * system.u[1]]) and k.holonomic == sp.Matrix([x - a * y])
    assert eg.solution(k)["holonomic constraints"] == sp.Matrix([x - a * y])


def test_bad_holonomic_input():
    system, args = K.four_bar()
    q, u = system.q, system.u
    with pytest.raises(eg.ModelError, match=r"2 holonomic constraints and the rolling disks \[\]"):
        eg.kane(system, **{**args, "dependent_coordinates": [q[1]]})
    with pytest.raises(eg.ModelError, match=r"dependent_coordinates \[z\] are not coordinates of"):
        eg.kane(system, **{**args, "dependent_coordinates": [q[1], sp.Symbol("z")]})
    with pytest.raises(eg.ModelError, match="holonomic constraint 1 depends on the speeds"):
        eg.kane(system, **{**args, "holonomic": [args["holonomic"][0], u[0]]})
    with pytest.raises(eg.ModelError, match="2 holonomic and 0 nonholonomic constraints and 0 rolling"):
        eg.kane(system, **{**args, "independent": list(u[:2])})
    with pytest.raises(eg.ModelError, match=r"∂\(holonomic constraints\)/∂\(dependent coordinates\) is"):
        eg.kane(system, holonomic=[sp.cos(q[0]) - 0.5, sp.sin(q[2]) - 0.1], dependent_coordinates=q[1:],
                independent=[u[0]])
    with pytest.raises(eg.ModelError, match="kane: holonomic constraint 0: expected a number"):
        eg.kane(system, **{**args, "holonomic": ["q1", 0]})
    with pytest.raises(eg.ModelError, match="assemble: these Kane's equations have no holonomic"):
        eg.codegen(eg.kane(system)).assemble(np.zeros(3))


# --- floating bases: a body on a free flyer or a ball joint, with an arm on a revolute about its x -------
BASES = {"free_flyer_quaternion": (lambda: eg.FreeFlyer("root"), "body"),
         "free_flyer_euler": (lambda: eg.FreeFlyer("root", "euler"), "rates"),
         "spherical_quaternion": (lambda: eg.Spherical("ball"), "body"),
         "spherical_zyx": (lambda: eg.Spherical("ball", "zyx"), "rates")}
BASE_I = sp.Matrix([[0.3, 0.01, 0.02], [0.01, 0.4, 0.03], [0.02, 0.03, 0.5]])
ARM_AT, ARM_COM, BASE_COM = (0.3, -0.1, 0.2), (0.2, 0, 0.1), (0.1, 0.2, 0.3)


def floating(joint) -> eg.System:
    s = eg.System(gravity=(0, 0, -9.81))
    base = s.add_body("base", joint=joint, mass=2.0, com=BASE_COM, inertia=BASE_I)
    s.add_body("arm", parent=base, joint=eg.Revolute("r", axis=(1, 0, 0)), mass=0.7, com=ARM_COM,
               inertia=sp.diag(0.1, 0.2, 0.15), placement=eg.Placement(translation=ARM_AT))
    return s


def floating_sympy(free: bool, speeds: str):
    """sympy's KanesMethod of `floating`: body-fixed ZYX angles (and the position if `free`); speeds
    "body" (the base's velocity and angular velocity in base axes) or "rates" (q̇). Returns (km, q, u)."""
    N = me.ReferenceFrame("N")
    angles, r = me.dynamicsymbols("psi theta phi"), me.dynamicsymbols("r")
    position = me.dynamicsymbols("x y z") if free else []
    q = [*position, *angles, r]
    u = me.dynamicsymbols(f"u1:{len(q) + 1}")
    k = len(position)
    B = N.orientnew("B", "Body", angles, "ZYX")
    rates = [x.diff() for x in q]
    omega = [B.ang_vel_in(N).dot(e) for e in (B.x, B.y, B.z)]  # in the angle rates
    axes = (B.x, B.y, B.z) if speeds == "body" else (N.x, N.y, N.z)
    if speeds == "body":
        kd = [ui - w for ui, w in zip(u[k:k + 3], omega)]
        kd += list(sp.Matrix(rates[:k]) - N.dcm(B) * sp.Matrix(u[:k])) if free else []
        B.set_ang_vel(N, sum((ui * e for ui, e in zip(u[k:k + 3], axes)), me.Vector(0)))
    else:
        kd = [ui - x for ui, x in zip(u[:k + 3], rates[:k + 3])]
        B.set_ang_vel(N, sum((w.xreplace(dict(zip(rates, u))) * e for w, e in zip(omega, (B.x, B.y, B.z))),
                             me.Vector(0)))
    kd.append(u[-1] - rates[-1])
    O = me.Point("O")
    O.set_vel(N, 0)
    P = O.locatenew("P", sum((x * e for x, e in zip(position, (N.x, N.y, N.z))), me.Vector(0)))
    P.set_vel(N, sum((ui * e for ui, e in zip(u[:k], axes)), me.Vector(0)))
    A = B.orientnew("A", "Axis", [r, B.x])
    A.set_ang_vel(B, u[-1] * B.x)
    in_B = lambda v, F: sum((c * e for c, e in zip(v, (F.x, F.y, F.z))), me.Vector(0))  # noqa: E731
    hinge = P.locatenew("hinge", in_B(ARM_AT, B))
    hinge.v2pt_theory(P, N, B)
    G_b, G_a = P.locatenew("G_b", in_B(BASE_COM, B)), hinge.locatenew("G_a", in_B(ARM_COM, A))
    G_b.v2pt_theory(P, N, B)
    G_a.v2pt_theory(hinge, N, A)
    I = BASE_I
    bodies = [me.RigidBody("base", G_b, B, 2.0, (me.inertia(B, I[0, 0], I[1, 1], I[2, 2], I[0, 1], I[1, 2],
                                                              I[0, 2]), G_b)),
              me.RigidBody("arm", G_a, A, 0.7, (me.inertia(A, 0.1, 0.2, 0.15), G_a))]
    km = me.KanesMethod(N, q_ind=q, u_ind=u, kd_eqs=kd)
    km.kanes_equations(bodies, [(G_b, -2.0 * 9.81 * N.z), (G_a, -0.7 * 9.81 * N.z)])
    return km, q, u


@pytest.mark.parametrize("name", BASES)
def test_floating_base_equals_sympy_recursive_and_pinocchio(name):
    """eg.kane on a free-flyer or ball-joint base (w = u: the base twist in base axes for a quaternion,
    the angle rates for Euler angles): M̃, f̃ equal sympy's KanesMethod (ZYX angles of the same rotation);
    u̇ equals the recursive method's and Pinocchio's ABA (no ZYX free flyer in Pinocchio)."""
    joint, speeds = BASES[name]
    system = floating(joint())
    f = eg.codegen(eg.kane(system))
    recursive = eg.codegen(eg.derive(system, method="recursive"))
    km, qs, us = floating_sympy(name.startswith("free"), speeds)
    model = None if name == "free_flyer_euler" else to_pinocchio(system)
    q, u, _ = eg.random_states(system, 3, np.random.default_rng(3))
    k = 3 if name.startswith("free") else 0
    for qi, ui in zip(q, u):
        angles = Rotation.from_quat(qi[k:k + 4]).as_euler("ZYX") if speeds == "body" else qi[k:k + 3]
        values = {**dict(zip(qs, [*qi[:k], *angles, qi[-1]])), **dict(zip(us, ui))}
        np.testing.assert_allclose(f.mass_matrix(qi, ui), K.number(km.mass_matrix, values), rtol=1e-12,
                                   atol=1e-12)
        np.testing.assert_allclose(f.forcing(qi, ui), K.number(km.forcing, values)[:, 0], rtol=1e-11,
                                   atol=1e-11)
        ud = np.linalg.solve(f.mass_matrix(qi, ui), f.forcing(qi, ui))
        np.testing.assert_allclose(ud, recursive.forward_dynamics(qi, ui), rtol=1e-10, atol=1e-10)
        if model is not None:
            reference = pin.aba(model, model.createData(), pinocchio_configuration(system, qi), ui,
                                np.zeros(model.nv))
            np.testing.assert_allclose(ud, reference, rtol=1e-10, atol=1e-10)
