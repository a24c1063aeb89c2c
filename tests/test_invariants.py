"""Physical invariants: Ṁ − 2C skew-symmetric, C u = b, and the power balance
d(T + U)/dt = uᵀ τ_nonconservative in a simulation."""
import numpy as np
import pytest
import sympy as sp
from scipy.integrate import solve_ivp

import eomgen as eg
from models import double_pendulum, matrices_trig_equal, numeric_arm, spatial_arm_3dof


SPATIAL = pytest.param(spatial_arm_3dof, marks=pytest.mark.slow)  # symbolic: 23 s


@pytest.mark.parametrize("build", [double_pendulum, SPATIAL])
@pytest.mark.parametrize("method", ["projected_newton_euler", "lagrange"])
def test_Mdot_minus_2C_is_skew(build, method):
    system = build()
    eom = eg.derive(system, method=method)
    q, u = list(system.q), system.u
    C = eom.coriolis_matrix()
    Mdot = sum((eom.M.diff(qk) * uk for qk, uk in zip(q, u)), sp.zeros(len(q)))
    N = Mdot - 2 * C
    assert matrices_trig_equal(N + N.T, sp.zeros(len(q)), q)
    assert matrices_trig_equal(C * u, eom.b, q)


@pytest.mark.parametrize("method", ["projected_newton_euler", "lagrange"])
def test_power_balance_in_simulation(method):
    """6-DOF arm with a spring, a damper and a body force: integrate M u̇ = τ − b − g together with the
    work W = ∫ uᵀ τ_nc dt of the nonconservative loads; T + U − W must stay constant."""
    rng = np.random.default_rng(3)
    system, _ = numeric_arm(rng)
    system.add_spring((None, (0.3, 0.2, 0.4)), ("link5", (0.1, 0.0, 0.0)), stiffness=20.0, rest_length=0.1,
                      name="spring")
    system.add_damper("link1", ("link4", (0.0, 0.1, 0.0)), damping=1.5, name="damper")
    system.add_force("link3", (0.0, 2.0, 1.0), point=(0.0, 0.1, 0.0), in_body_frame=True, name="push")
    system.add_actuator("link5", torque=(0.0, 0.0, 0.5), name="motor")
    eom = eg.derive(system, method=method)
    f = eg.codegen(eom)
    n = 6
    nonconservative = [name for name in eom.load_names if name != "spring"]

    def rhs(t, x):
        q, u = x[:n], x[n:2 * n]
        ud = f.forward_dynamics(q, u)
        return np.concatenate([u, ud, [u @ sum(f.tau_of(name, q, u) for name in nonconservative)]])

    x0 = np.concatenate([rng.uniform(-1, 1, n), rng.uniform(-1, 1, n), [0.0]])
    sol = solve_ivp(rhs, (0, 1.0), x0, method="DOP853", rtol=1e-11, atol=1e-11, t_eval=np.linspace(0, 1, 11))
    assert sol.success
    E = [f.T(x[:n], x[n:2 * n]) + f.U(x[:n]) - x[-1] for x in sol.y.T]
    W = sol.y[-1]
    assert np.ptp(W) > 1e-2  # the loads do work, so the check can fail
    assert np.ptp(E) < 1e-7 * max(1.0, np.abs(E).max())
