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
    0.1 rad off (one state and a batch); a crank too long to close the loop fails, saying by how much."""
    system, args = K.four_bar()
    f = eg.codegen(eg.kane(system, **args))
    q1 = RNG.uniform(-np.pi, np.pi, 5)
    poses = np.array([K.four_bar_pose(x) for x in q1])
    guesses = poses + np.c_[np.zeros(5), RNG.uniform(-0.1, 0.1, (5, 2))]
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
        energies = energies + 0.5 * m * np.sum(v_G**2, 1) + 0.5 * I * rates[:, i]**2 + m * K.BAR["g"] * G[:, 1]
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
    with pytest.raises(eg.ModelError, match="2 holonomic constraints need as many distinct dependent_coord"):
        eg.kane(system, **{**args, "dependent_coordinates": [q[1]]})
    with pytest.raises(eg.ModelError, match=r"dependent_coordinates \[z\] are not coordinates of the system"):
        eg.kane(system, **{**args, "dependent_coordinates": [q[1], sp.Symbol("z")]})
    with pytest.raises(eg.ModelError, match="holonomic constraint 1 depends on the speeds"):
        eg.kane(system, **{**args, "holonomic": [args["holonomic"][0], u[0]]})
    with pytest.raises(eg.ModelError, match="2 holonomic and 0 nonholonomic constraints need as many dep"):
        eg.kane(system, **{**args, "independent": list(u[:2])})
    with pytest.raises(eg.ModelError, match=r"∂\(holonomic constraints\)/∂\(dependent coordinates\) is not inv"):
        eg.kane(system, holonomic=[sp.cos(q[0]) - 0.5, sp.sin(q[2]) - 0.1], dependent_coordinates=q[1:],
                independent=[u[0]])
    with pytest.raises(eg.ModelError, match="kane: holonomic constraint 0: expected a number or a sympy"):
        eg.kane(system, **{**args, "holonomic": ["q1", 0]})
    with pytest.raises(eg.ModelError, match="assemble: these Kane's equations have no holonomic constraints"):
        eg.codegen(eg.kane(system)).assemble(np.zeros(3))
