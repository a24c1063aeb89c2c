"""The planar four-bar closed by a loop (examples/four_bar.py) against hand-derived closed forms: the
crank's equation J(θ) θ̈ + ½ J'(θ) θ̇² + V'(θ) = τ from `eg.reduce`, the loop force from the links'
free-body diagrams, the kinetic-energy projection of the speeds (Pinocchio's M and Jacobians), a 10 s
simulation that keeps the loop closed; refused loops and reductions."""
import functools
import sys
from pathlib import Path

import numpy as np
import pinocchio as pin
import pytest
import sympy as sp
from hypothesis import given, settings, strategies as st
from scipy.linalg import null_space

import eomgen as eg
from eomgen.verify import to_pinocchio

sys.path.insert(0, str(Path(__file__).parents[1] / "examples"))
from four_bar import LENGTHS, MASSES, four_bar  # noqa: E402

A, B, C, D = LENGTHS
GRAVITY = 9.81


@functools.cache
def numeric(kind="revolute"):
    eom = eg.derive(four_bar(kind=kind), method="recursive")
    return eom, eg.codegen(eom), eg.reduce(eom, independent=["th1"])


@functools.cache
def hand():
    """The four-bar by hand, in the absolute angles θ (crank), φ2 (coupler), φ3 (rocker): the closure
    a e^{iθ} + b e^{iφ2} = d + c e^{iφ3} differentiated gives the velocity ratios
    k2 = φ2'/θ' = −a sin(θ − φ3) / (b sin(φ2 − φ3)), k3 = φ3'/θ' = a sin(θ − φ2) / (c sin(φ3 − φ2));
    d/dθ along the mechanism is ∂/∂θ + k2 ∂/∂φ2 + k3 ∂/∂φ3. T = ½ J θ'², J = Σ m |v_G / θ'|² + I (ω / θ')²,
    V = g Σ m y_G. Returns numeric functions of (θ, φ2, φ3)."""
    t, p2, p3 = sp.symbols("theta phi2 phi3")
    k2 = -A * sp.sin(t - p3) / (B * sp.sin(p2 - p3))
    k3 = A * sp.sin(t - p2) / (C * sp.sin(p3 - p2))

    def along(x):
        return sp.diff(x, t) + k2 * sp.diff(x, p2) + k3 * sp.diff(x, p3)

    def e(angle):
        return sp.Matrix([sp.cos(angle), sp.sin(angle)])

    ground = sp.Matrix([D, 0])
    joint_b, joint_c = A * e(t), ground + C * e(p3)
    G = [A / 2 * e(t), joint_b + B / 2 * e(p2), ground + C / 2 * e(p3)]
    I_G = [m * L**2 / 12 for m, L in zip(MASSES, (A, B, C))]
    J = sum(m * along(g).dot(along(g)) + I * k**2 for m, g, I, k in zip(MASSES, G, I_G, (1, k2, k3)))
    V = GRAVITY * sum(m * g[1] for m, g in zip(MASSES, G))
    exprs = dict(J=J, dJ=along(J), dV=along(V), k2=k2, k3=k3, dk2=along(k2), dk3=along(k3),
                 B=joint_b, C=joint_c, G2=G[1], G3=G[2], dG2=along(G[1]), ddG2=along(along(G[1])), I=I_G)
    return {k: sp.lambdify((t, p2, p3), v, "numpy") for k, v in exprs.items()}


def closed_form(theta: float) -> np.ndarray:
    """q = (θ, φ2 − θ, φ3) with C the intersection of the circles about B (radius b) and D (radius c) on
    the branch above BD (the assembly of the examples)."""
    joint_b, ground = A * np.array([np.cos(theta), np.sin(theta)]), np.array([D, 0.0])
    n = (ground - joint_b) / np.linalg.norm(ground - joint_b)
    L = np.linalg.norm(ground - joint_b)
    x = (B**2 - C**2 + L**2) / (2 * L)
    joint_c = joint_b + x * n + np.sqrt(B**2 - x**2) * np.array([-n[1], n[0]])
    phi2, phi3 = (np.arctan2(*(joint_c - p)[::-1]) for p in (joint_b, ground))
    return np.array([theta, phi2 - theta, phi3])


def _angles(q):
    return q[0], q[0] + q[1], q[2]


def _cross(r, F):
    return r[0] * F[1] - r[1] * F[0]


@pytest.mark.parametrize("kind", ["revolute", "point"])
@settings(max_examples=25, deadline=None)
@given(theta=st.floats(-np.pi, np.pi), rate=st.floats(-3, 3))
def test_reduced_equation_equals_hand_closed_form(kind, theta, rate):
    """M_r = J(θ), b_r = ½ J'(θ) θ̇², g_r = V'(θ) at the closed-form assembly, to 1e-12 (relative); the
    symbolic reduction (adjugate) the same."""
    eom, f, reduced = numeric(kind)
    h, q = hand(), closed_form(theta)
    angles = _angles(q)
    expected = [h["J"](*angles), 0.5 * h["dJ"](*angles) * rate**2, h["dV"](*angles)]
    got = [reduced.M(q)[0, 0], reduced.b(q, [rate])[0], reduced.g(q)[0]]
    np.testing.assert_allclose(got, expected, rtol=1e-11, atol=1e-11)
    forms = reduced.symbolic()
    state = {**dict(zip(eom.q, q)), forms.u_independent[0]: rate}
    symbolic = [float(x.xreplace(state)) for x in (forms.M[0, 0], forms.b[0], forms.g[0])]
    np.testing.assert_allclose(symbolic, expected, rtol=1e-10, atol=1e-10)


@settings(max_examples=20, deadline=None)
@given(theta=st.floats(-np.pi, np.pi), offset=st.floats(-0.2, 0.2))
def test_assemble_equals_closed_form(theta, offset):
    """assemble with the crank held, from a guess off by up to 0.2 rad, gives the closed-form angles."""
    _, f, _ = numeric()
    exact = closed_form(theta)
    q = eg.assemble(f, exact + [0, offset, -offset], fixed=["th1"])
    np.testing.assert_allclose(np.angle(np.exp(1j * (q - exact))), 0, atol=1e-11)
    assert np.linalg.norm(f.closure_residual(q)) <= 1e-12


def newton_euler(theta: float, rate: float, torque: float) -> tuple[float, np.ndarray, np.ndarray]:
    """(θ̈, F, u) at the closed-form state: θ̈ from the crank's equation, the links' accelerations by
    differentiating the closure (α = k θ̈ + k' θ̇², a = G' θ̈ + G'' θ̇²), and the loop force F on the coupler
    at its end (−F on the rocker) from the free-body diagrams: the rocker about its ground pivot D,
    I_D α3 = (G3 − D) × m3 g + (C − D) × (−F); the coupler about its joint B,
    I_G α2 + (G2 − B) × m2 a_G2 = (C − B) × F + (G2 − B) × m2 g."""
    h = hand()
    angles = _angles(closed_form(theta))
    J, dJ, dV = (h[k](*angles) for k in ("J", "dJ", "dV"))
    acc = (torque - 0.5 * dJ * rate**2 - dV) / J
    k2, k3, dk2, dk3 = (h[k](*angles) for k in ("k2", "k3", "dk2", "dk3"))
    alpha2, alpha3 = k2 * acc + dk2 * rate**2, k3 * acc + dk3 * rate**2
    a_G2 = np.ravel(h["dG2"](*angles)) * acc + np.ravel(h["ddG2"](*angles)) * rate**2
    joint_b, joint_c, G2, G3 = (np.ravel(h[k](*angles)) for k in ("B", "C", "G2", "G3"))
    ground = np.array([D, 0.0])
    I2, I3 = h["I"](*angles)[1:]
    m2, m3 = MASSES[1:]
    weight2, weight3 = np.array([0, -m2 * GRAVITY]), np.array([0, -m3 * GRAVITY])
    rc_d, rc_b = joint_c - ground, joint_c - joint_b  # rows [−r_y, r_x]·F = r × F
    lhs = np.array([[rc_d[1], -rc_d[0]], [-rc_b[1], rc_b[0]]])
    rhs = np.array([(I3 + m3 * (C / 2) ** 2) * alpha3 - _cross(G3 - ground, weight3),
                    I2 * alpha2 + _cross(G2 - joint_b, m2 * a_G2) - _cross(G2 - joint_b, weight2)])
    return acc, np.linalg.solve(lhs, rhs), np.array([rate, (k2 - 1) * rate, k3 * rate])


@pytest.mark.parametrize("kind", ["revolute", "point"])
@settings(max_examples=20, deadline=None)
@given(theta=st.floats(-np.pi, np.pi), rate=st.floats(-3, 3), torque=st.floats(-5, 5))
def test_loop_force_equals_newton_euler(kind, theta, rate, torque):
    """The loop force and the crank's acceleration equal the free-body diagrams' (`newton_euler`)."""
    _, f, _ = numeric(kind)
    acc, F, u = newton_euler(theta, rate, torque)
    q = closed_form(theta)
    ud, _ = f.constrained_dynamics(q, u, [torque])
    got = f.constraint_forces(q, u, [torque])["loop"]
    np.testing.assert_allclose(ud[0], acc, rtol=1e-9, atol=1e-9)
    np.testing.assert_allclose(got[:2], F, rtol=1e-9, atol=1e-8)
    np.testing.assert_allclose(got[2:], 0, atol=1e-12)  # no force out of the plane


def test_projected_speeds_are_the_kinetic_energy_nearest():
    """project: q back on the closure, u ← argmin (u' − u)ᵀ M (u' − u) over J_c u' = 0, checked with
    Pinocchio's M (crba) and loop Jacobian (its frames' Jacobians): u' = Z (Zᵀ M Z)⁻¹ Zᵀ M u, Z a basis of
    the null space of J_c."""
    eom, f, _ = numeric()
    model = to_pinocchio(eom.system)
    data = model.createData()
    rng = np.random.default_rng(3)
    for _ in range(5):
        q0 = closed_form(rng.uniform(-np.pi, np.pi)) + rng.normal(0, 0.01, 3)
        u0 = rng.uniform(-2, 2, 3)
        q, u = eg.project(f, q0, u0)
        assert np.linalg.norm(f.closure_residual(q)) <= 1e-12 and np.linalg.norm(q - q0) < 0.1
        M = pin.crba(model, data, q)
        M = np.triu(M) + np.triu(M, 1).T
        pin.computeJointJacobians(model, data, q)
        pin.updateFramePlacements(model, data)
        J = [pin.getFrameJacobian(model, data, model.getFrameId(name), pin.LOCAL_WORLD_ALIGNED)[:2]
             for name in ("coupler_end", "rocker_end")]
        Z = null_space(J[0] - J[1])
        np.testing.assert_allclose(u, Z @ np.linalg.solve(Z.T @ M @ Z, Z.T @ M @ u0), atol=1e-12)


def test_simulation_keeps_the_loop_closed():
    """10 s of free motion (projection): ‖r‖ ≤ 1e-9, ‖J_c u‖ ≤ 1e-12, the energy constant to 1e-7 J
    (no load: loop forces do no work). At rtol 1e-6 the unstabilised loop drifts open (> 1e-7) and
    Baumgarte's keeps it ten times closer."""
    _, f, reduced = numeric()
    q0 = closed_form(0.3)
    x0 = (q0, reduced.R(q0) @ [2.0])
    sim = eg.simulate(f, x0, (0, 10))
    assert sim.t[-1] == 10 and sim.closure_drift.max() <= 1e-9 and sim.velocity_drift.max() <= 1e-12
    assert np.ptp(sim.energy) <= 1e-7
    loose = {s: eg.simulate(f, x0, (0, 10), stabilization=s, rtol=1e-6, atol=1e-6).closure_drift.max()
             for s in ("projection", "baumgarte", None)}
    assert loose["projection"] <= 1e-12 < 1e-7 < loose[None] and loose["baumgarte"] < loose[None] / 10


def test_c_backend_and_output_times():
    """The compiled functions serve assemble and reduce alike; simulate at given times (projection: each
    interpolated and projected; Baumgarte: solve_ivp's) keeps the loop closed."""
    eom, _, _ = numeric()
    f = eg.codegen(eom, backend="c")
    q = eg.assemble(f, closed_form(1.0) + [0, 0.1, 0.1], fixed=["th1"])
    np.testing.assert_allclose(q, closed_form(1.0), atol=1e-11)
    np.testing.assert_allclose(eg.reduce(f, ["th1"]).M(q)[0, 0], hand()["J"](*_angles(q)), rtol=1e-12)
    times = np.linspace(0, 1, 11)
    x0 = (q, eg.reduce(f, ["th1"]).R(q) @ [1.0])
    for stabilization in ("projection", "baumgarte"):
        sim = eg.simulate(f, x0, (0, 1), stabilization=stabilization, t_eval=times)
        np.testing.assert_array_equal(sim.t, times)
        assert sim.closure_drift.max() <= 1e-10


def test_bad_loops_and_reductions_are_refused():
    """A loop between a frame and itself, between two frames on one body; reduce with an unknown name,
    with too few independent speeds, and at the toggle position (crank and coupler in line: th3 cannot
    determine th1, th2)."""
    system = four_bar()
    system.add_frame("coupler_mid", "coupler", eg.Placement(translation=(0.5, 0, 0)))
    with pytest.raises(eg.ModelError, match="'coupler_end' and itself"):
        system.add_loop("coupler_end", "coupler_end")
    with pytest.raises(eg.ModelError, match="both fixed on body 'coupler'"):
        system.add_loop("coupler_end", "coupler_mid")
    eom, f, _ = numeric()
    with pytest.raises(eg.ModelError, match="unknown coordinate or speed 'crank'"):
        eg.reduce(eom, ["crank"])
    with pytest.raises(eg.ModelError, match="2 constraint rows .* but 3 dependent speeds"):
        eg.reduce(eom, [])
    toggle = np.arccos(((A + B) ** 2 + D**2 - C**2) / (2 * (A + B) * D))
    q = np.array([toggle, 0.0, np.arctan2((A + B) * np.sin(toggle), (A + B) * np.cos(toggle) - D)])
    assert np.linalg.norm(f.closure_residual(q)) < 1e-12
    with pytest.raises(eg.ModelError, match=r"J_d is singular .* dependent speeds \['th1dot', 'th2dot'\]"):
        eg.reduce(eom, ["th3"]).M(q)
    with pytest.raises(eg.ModelError, match="stabilization must be one of"):
        eg.simulate(f, (q, np.zeros(3)), (0, 1), stabilization="stiff")
    with pytest.raises(eg.ModelError, match="projection needs an explicit Runge–Kutta method"):
        eg.simulate(f, (q, np.zeros(3)), (0, 1), method="LSODA")
    with pytest.raises(eg.ModelError, match="x0 must be"):
        eg.simulate(f, q, (0, 1))


@pytest.mark.slow
def test_example_runs():
    """examples/four_bar.py (six 10 s simulations, about 20 s)."""
    import runpy

    runpy.run_path(str(Path(__file__).parents[1] / "examples" / "four_bar.py"), run_name="__main__")


def test_loop_stated_twice_is_dropped_with_a_warning():
    """The loop closed twice: `reduce` drops the repeated rows with a warning naming them (as the
    constrained dynamics do; was "name -1 independent speeds") and gives the hand closed form J(θ)."""
    system = four_bar()
    system.add_loop("coupler_end", "rocker_end", kind="revolute", name="again")
    eom = eg.derive(system, method="recursive")
    q = closed_form(0.7)
    with pytest.warns(UserWarning, match=r"reduce: constraint rows \['again.x', 'again.y'\] repeat other"):
        reduced = eg.reduce(eom, ["th1"])
    assert reduced.M(q)[0, 0] == pytest.approx(hand()["J"](*_angles(q)), rel=1e-12)
