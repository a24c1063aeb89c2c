"""The energy balance of eg.simulate, E(t) − E(t0) = W(t), against physics: a pendulum with a spring, a
damper and a controller whose energy and work are computed by hand; a tumbling free body (energy and
angular momentum constant); Kane's rolling disk, free (energy constant) and driven (the drive's work by
hand); two DC motors (the sources' work less the resistive and friction losses)."""

import sys
from pathlib import Path

import numpy as np
import pytest
import sympy as sp
from scipy.integrate import cumulative_simpson

import eomgen as eg
import kane_systems as K

sys.path.insert(0, str(Path(__file__).parents[1] / "examples"))
from rolling_disk import VALUES, critical_spin, rolling_disk  # noqa: E402
from two_link_dc_motors import NUMBERS, two_link_arm  # noqa: E402

PENDULUM = dict(m=1.2, L=0.8, I_c=0.05, g=9.81, k=40.0, l0=0.5, c=0.7)
SPRING_AT, DAMPER_AT = np.array([0.6, -0.2]), np.array([-0.5, -1.0])


def pendulum() -> eg.System:
    """A bob (centre of mass at L below the pivot) on a spring to SPRING_AT and a damper to DAMPER_AT."""
    p = {k: sp.Float(v) for k, v in PENDULUM.items()}
    system = eg.System(gravity=(0, -p["g"], 0))
    bob = system.add_body(
        "bob", joint=eg.Revolute("phi"), mass=p["m"], com=(0, -p["L"], 0), inertia=sp.eye(3) * p["I_c"]
    )
    system.add_spring((bob, (0, -p["L"], 0)), (None, (*SPRING_AT, 0)), p["k"], rest_length=p["l0"])
    system.add_damper((bob, (0, -p["L"], 0)), (None, (*DAMPER_AT, 0)), p["c"])
    return system


def test_pendulum_energy_and_work_by_hand():
    """E = ½ (I_c + m L²) φ̇² − m g L cos φ + ½ k (‖p − s‖ − l0)² (the spring in U only) at every state to
    1e-12; W = ∫ τ φ̇ − c l̇² dt (l̇ = (p − d) · ṗ / ‖p − d‖ the damper's rate) by Simpson's rule on the
    states to 1e-8 of the largest; the balance E − E0 − W within 1e-8 J; the work ≠ the energy change
    without the damper (it dissipates)."""
    P = PENDULUM
    sim = eg.simulate(
        pendulum(),
        ([0.4], [1.0]),
        (0, 3),
        controller=lambda t, q, u: [2 * np.sin(3 * t) - 0.5 * q[0]],
        t_eval=np.linspace(0, 3, 1201),
    )
    phi, phid = sim.q[:, 0], sim.u[:, 0]
    p = P["L"] * np.stack([np.sin(phi), -np.cos(phi)], -1)
    pd = P["L"] * phid[:, None] * np.stack([np.cos(phi), np.sin(phi)], -1)
    stretch = np.linalg.norm(p - SPRING_AT, axis=1) - P["l0"]
    E = (
        0.5 * (P["I_c"] + P["m"] * P["L"] ** 2) * phid**2
        - P["m"] * P["g"] * P["L"] * np.cos(phi)
        + 0.5 * P["k"] * stretch**2
    )
    np.testing.assert_allclose(sim.energy, E, rtol=0, atol=1e-12 * np.abs(E).max())
    rate = np.einsum("ij,ij->i", p - DAMPER_AT, pd) / np.linalg.norm(p - DAMPER_AT, axis=1)
    tau = 2 * np.sin(3 * sim.t) - 0.5 * phi
    np.testing.assert_allclose(sim.tau[:, 0], tau, rtol=1e-15)
    damper = cumulative_simpson(-P["c"] * rate**2, x=sim.t, initial=0)
    W = cumulative_simpson(tau * phid, x=sim.t, initial=0) + damper
    np.testing.assert_allclose(sim.work, W, rtol=0, atol=1e-8 * np.abs(W).max())
    assert np.abs(sim.balance).max() < 1e-8 and -damper[-1] > 0.2  # the damper took more than 0.2 J


def tumbling_box() -> eg.System:
    """A box (centre of mass at the origin, principal inertias 0.3, 0.2, 0.1) on a free flyer; gravity."""
    system = eg.System(gravity=(0, 0, -9.81))
    system.add_body("box", joint=eg.FreeFlyer("base"), mass=2.0, inertia=sp.diag(0.3, 0.2, 0.1))
    return system


def test_tumbling_body_is_conservative():
    """Spun near the intermediate axis and falling for 6 s, the box flips (ω_y changes sign) while
    E = ½ m v² + ½ ωᵀ I ω + m g z (by hand at the start) stays constant to 1e-9 of the kinetic energy it
    gains and the angular momentum R I ω to 1e-8, W = 0, the quaternion stays unit to 1e-11."""
    q0 = np.array([0, 0, 1.0, 0, 0, 0, 1])
    u0 = np.array([0.5, 0.0, 3.0, 0.01, 4.0, 0.01])
    sim = eg.simulate(tumbling_box(), (q0, u0), (0, 6))
    I = np.diag([0.3, 0.2, 0.1])
    assert sim.energy[0] == pytest.approx(
        0.5 * 2 * u0[:3] @ u0[:3] + 0.5 * u0[3:] @ I @ u0[3:] + 2 * 9.81, rel=1e-14
    )
    gained = np.ptp(0.5 * 2.0 * (sim.u[:, :3] ** 2).sum(1))  # ½ m |v|²: to about 3500 J
    assert np.ptp(sim.energy) < 1e-9 * gained and np.all(sim.work == 0) and sim.velocity_drift is None
    assert sim.u[:, 4].min() < -3.5  # it flipped
    x, y, z, w = sim.q[:, 3:].T
    np.testing.assert_allclose(x**2 + y**2 + z**2 + w**2, 1, atol=1e-11)
    R = np.stack(
        [
            [1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
            [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
            [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)],
        ]
    ).transpose(2, 0, 1)
    momentum = np.einsum("nij,nj->ni", R, sim.u[:, 3:] @ I)
    np.testing.assert_allclose(momentum, np.tile(momentum[0], (len(momentum), 1)), atol=1e-8 * 0.8)


def test_rolling_disk_kane_energy():
    """Kane's equations (z dependent, no slip): rolling upright at 1.2 ω_c with a small lean, 4 s: E constant
    to 1e-9 relative, W = 0 (rolling without slip does no work), the height drift ‖f(q)‖ below 1e-9; the
    KaneEquations given to simulate directly."""
    _, k = rolling_disk()
    f = eg.codegen(k)
    q = f.assemble(np.array([0, 0, VALUES["R"], 0, 0.05, 0]), VALUES)
    sim = eg.simulate(k, (q, [0.0, 0.0, 1.2 * critical_spin()]), (0, 4), params=VALUES)
    assert np.ptp(sim.energy) < 1e-9 * sim.energy[0] and np.all(sim.work == 0)
    assert sim.closure_drift.max() < 1e-9 and sim.velocity_drift is None and np.abs(sim.q[:, 4]).max() < 0.3


def test_driven_rolling_disk_work():
    """The upright disk (Kane) driven by τ_d = 0.5 − 0.2 φ̇ about its axle and steered by τ_s = 0.1 sin t:
    W = ∫ τ_d φ̇ + τ_s θ̇ dt by hand (Simpson) to 1e-8, the balance within 1e-9 J."""
    system, args = K.rolling_disk()
    f = eg.codegen(eg.kane(system, **args))
    values = {"m": 1.3, "R": 0.3, "g": 9.81}
    sim = eg.simulate(
        f,
        ([0, 0, 0, 0], [0.2, 1.0]),
        (0, 3),
        params=values,
        t_eval=np.linspace(0, 3, 601),
        controller=lambda t, q, w: [0, 0, 0.1 * np.sin(t), 0.5 - 0.2 * w[1]],
    )
    W = cumulative_simpson(
        (0.5 - 0.2 * sim.u[:, 1]) * sim.u[:, 1] + 0.1 * np.sin(sim.t) * sim.u[:, 0], x=sim.t, initial=0
    )
    np.testing.assert_allclose(sim.work, W, rtol=0, atol=1e-8 * np.abs(W).max())
    assert W[-1] > 0.5 and np.abs(sim.balance).max() < 1e-9


def test_motors_electrical_mechanical_balance():
    """The two-link arm's voltage step (12 V, 6 V) for 0.3 s: E = T + U + ½ L Σ i² and
    W = ∫ Σ (U i − R i² − f (N q̇)²) dt by hand (Simpson) to 1e-7 of the largest; the balance within 1e-9 J.
    """
    fn = eg.codegen(eg.derive(two_link_arm(motors=True), method="lagrange"))
    times = np.r_[np.linspace(0, 0.02, 801)[:-1], np.linspace(0.02, 0.3, 701)]  # dense while i rises (L/R)
    sim = eg.simulate(fn, ([-np.pi / 2, 0], [0, 0], [0, 0]), (0, 0.3), params=NUMBERS, t_eval=times)
    i, qd, n = sim.currents, sim.u, NUMBERS
    mechanical = fn.T(sim.q, sim.u, n) + fn.U(sim.q, n)
    np.testing.assert_allclose(sim.energy, mechanical + 0.5 * n["L"] * (i**2).sum(1), rtol=1e-13)
    power = (
        i @ [n["U_motor_q_1"], n["U_motor_q_2"]]
        - n["R"] * (i**2).sum(1)
        - n["f"] * n["N"] ** 2 * (qd**2).sum(1)
    )
    W = cumulative_simpson(power, x=sim.t, initial=0)
    np.testing.assert_allclose(sim.work, W, rtol=0, atol=1e-7 * np.abs(W).max())
    assert W[-1] > 0.1 and np.abs(sim.balance).max() < 1e-9
