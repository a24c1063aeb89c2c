"""eg.simulate's inputs: a System, EquationsOfMotion, KaneEquations or generated functions (NumPy, C, bound);
efforts by `tau` (constant: a pendulum held where its torque balances gravity) or by `controller` (a PD
law brings a cart-pendulum's cart to rest); every implicit method on a system without constraints;
refused inputs."""

import numpy as np
import pytest
import sympy as sp

import eomgen as eg
import kane_systems as K
from models import cart_pendulum
from test_rhs import CART

BOB = dict(m=0.8, L=0.5, g=9.81)


def pendulum() -> eg.System:
    """A point-like bob at L below the pivot, gravity −y."""
    system = eg.System(gravity=(0, -BOB["g"], 0))
    system.add_body(
        "bob", joint=eg.Revolute("phi"), mass=BOB["m"], com=(0, -BOB["L"], 0), inertia=sp.eye(3) * 1e-3
    )
    return system


@pytest.mark.parametrize("given", ["system", "equations", "numpy", "c"])
def test_constant_torque_holds_the_pendulum(given, tmp_path, monkeypatch):
    """τ = m g L sin φ0 holds the pendulum at φ0 for 2 s (to 1e-9), from whatever it is given; its work is
    zero (it does not move), and the efforts recorded are τ."""
    monkeypatch.setenv("EOMGEN_CACHE", str(tmp_path))
    system = pendulum()
    source = {
        "system": system,
        "equations": eg.derive(system),
        "numpy": eg.codegen(eg.derive(system)),
        "c": eg.codegen(eg.derive(system), backend="c"),
    }[given]
    phi0 = 0.7
    torque = BOB["m"] * BOB["g"] * BOB["L"] * np.sin(phi0)
    sim = eg.simulate(source, ([phi0], [0.0]), (0, 2), tau=[torque])
    np.testing.assert_allclose(sim.q[:, 0], phi0, atol=1e-9)
    np.testing.assert_allclose(sim.work, 0, atol=1e-9)
    np.testing.assert_allclose(sim.tau, torque, rtol=1e-15)
    assert sim.currents is None and sim.closure_drift is None


@pytest.mark.parametrize("method", ["RK45", "Radau", "BDF", "LSODA"])
def test_controller_brings_the_cart_to_rest(method):
    """F = −k_p x − k_d ẋ on the cart (the pendulum free): the cart ends near rest at x = 0 in 8 s, the
    pendulum's swing damped through the cart; with the default stabilization, which has nothing to hold."""
    system, _ = cart_pendulum()
    f = eg.codegen(eg.derive(system)).bind(CART)
    sim = eg.simulate(
        f,
        ([0.3, 0.4], [0, 0]),
        (0, 8),
        controller=lambda t, q, u: [-20 * q[0] - 8 * u[0], 0.0],
        method=method,
        rtol=1e-8,
        atol=1e-8,
    )
    assert abs(sim.q[-1, 0]) < 0.05 and sim.work[-1] < 0 and np.abs(sim.balance).max() < 1e-5


def test_kane_sources():
    """KaneEquations and their functions alike: the same motion."""
    system, args = K.rolling_disk()
    k = eg.kane(system, **args)
    values = {"m": 1.3, "R": 0.3, "g": 9.81}
    one = eg.simulate(k, ([0, 0, 0, 0], [0.3, 2.0]), (0, 1), params=values, t_eval=[0, 0.5, 1])
    two = eg.simulate(eg.codegen(k).bind(values), np.r_[0, 0, 0, 0, 0.3, 2.0], (0, 1), t_eval=[0, 0.5, 1])
    np.testing.assert_allclose(one.q, two.q, rtol=1e-14, atol=1e-14)
    assert one.u.shape == (3, 2) and one.tau is None


def test_refused():
    system = pendulum()
    f = eg.codegen(eg.derive(system))
    with pytest.raises(eg.ModelError, match="by controller or by tau, not both"):
        eg.simulate(f, ([0.1], [0]), (0, 1), controller=lambda t, q, u: [0.0], tau=[0.0])
    with pytest.raises(eg.ModelError, match="controller must be a function"):
        eg.simulate(f, ([0.1], [0]), (0, 1), controller=[0.0])
    with pytest.raises(eg.ModelError, match="tau: expected the actuator efforts"):
        eg.simulate(f, ([0.1], [0]), (0, 1), tau={"phi": 1.0})
    with pytest.raises(eg.ModelError, match=r"expected a System, EquationsOfMotion, KaneEquations"):
        eg.simulate("pendulum", ([0.1], [0]), (0, 1))
    with pytest.raises(
        eg.ModelError, match=r"x0 must be \(q0, u0\) with 2 values in all, got shape \(3,\)"
    ):
        eg.simulate(f, ([0.1], [0], [0]), (0, 1))
    kane = eg.codegen(eg.kane(*K.rolling_disk()[:1], **K.rolling_disk()[1]))
    with pytest.raises(eg.ModelError, match=r"x0 must be \(q0, w0\) with 6 values"):
        eg.simulate(kane, ([0, 0, 0, 0], [0.3, 2.0, 0]), (0, 1))
    with pytest.raises(TypeError, match="tau_a"):
        eg.simulate(f, ([0.1], [0]), (0, 1), tau_a=[0.0])  # the old name: one API, tau or controller


def test_kane_with_motors_refused_in_simulation():
    """Kane's rhs has no circuit: a DC motor's current would stay a constant, so it is refused by name."""
    system = pendulum()
    system.add_motor(system.bodies[0], resistance=1.0, inductance=0.01, torque_constant=0.1,
                     rotor_inertia=0.01, voltage=6.0)
    kane = eg.codegen(eg.kane(system))
    for call in (lambda: kane.rhs(0.0, np.zeros(2)), lambda: kane.energy(np.zeros(2)),
                 lambda: eg.simulate(kane, ([0.1], [0.0]), (0, 1))):
        with pytest.raises(eg.ModelError, match=r"DC motors \['i_.*'\]"):
            call()
