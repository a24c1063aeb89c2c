"""The cart-pendulum closed form and the generalized forces of its loads."""
import pytest
import sympy as sp

import eomgen as eg
from models import cart_pendulum

METHODS = ["projected_newton_euler", "lagrange", "free_cut"]


@pytest.mark.parametrize("method", METHODS)
def test_closed_form(method):
    system, (m_c, m_p, l, g) = cart_pendulum()
    x, phi = system.q
    phid = system.u[1]
    eom = eg.derive(system, method=method)
    M = sp.Matrix([[m_c + m_p, m_p * l * sp.cos(phi)], [m_p * l * sp.cos(phi), m_p * l**2]])
    b = sp.Matrix([-m_p * l * sp.sin(phi) * phid**2, 0])
    G = sp.Matrix([0, m_p * g * l * sp.sin(phi)])
    assert sp.simplify(eom.M - M) == sp.zeros(2, 2)
    assert sp.simplify(eom.b - b) == sp.zeros(2, 1)
    assert sp.simplify(eom.g - G) == sp.zeros(2, 1)
    T = (system.u.T * M * system.u)[0] / 2
    assert sp.simplify(eom.T - T) == 0
    assert sp.simplify(eom.U - (-m_p * g * l * sp.cos(phi))) == 0


@pytest.mark.parametrize("method", METHODS)
def test_generalized_forces_of_loads(method):
    system, (m_c, m_p, l, g) = cart_pendulum()
    x, phi = system.q
    cart, pend = system.bodies
    T_a, F, k, Px, Py = sp.symbols("T_a F k P_x P_y")
    system.add_actuator(pend, torque=(0, 0, T_a), reaction=cart, name="motor")
    system.add_force(cart, (F, 0, 0), name="push")
    system.add_spring((None, (Px, Py, 0)), "tip", stiffness=k, name="spring")
    eom = eg.derive(system, method=method)
    assert sp.simplify(eom.tau_of("motor") - sp.Matrix([0, T_a])) == sp.zeros(2, 1)
    assert sp.simplify(eom.tau_of("push") - sp.Matrix([F, 0])) == sp.zeros(2, 1)
    # by hand: r = (x + l sin φ, −l cos φ, 0), J_s = ∂r/∂q, F_s = −k (r − P)
    r = sp.Matrix([x + l * sp.sin(phi), -l * sp.cos(phi), 0])
    J_s = sp.Matrix([[1, l * sp.cos(phi)], [0, l * sp.sin(phi)], [0, 0]])
    tau_spring = J_s.T * (-k * (r - sp.Matrix([Px, Py, 0])))
    assert sp.simplify(eom.tau_of("spring") - tau_spring) == sp.zeros(2, 1)
    d = r - sp.Matrix([Px, Py, 0])
    assert sp.simplify(eom.U - (-m_p * g * l * sp.cos(phi) + k * (d.T * d)[0] / 2)) == 0


def test_example_runs(capsys):
    import runpy
    from pathlib import Path

    runpy.run_path(str(Path(__file__).parents[1] / "examples" / "cart_pendulum.py"), run_name="__main__")
    out = capsys.readouterr().out
    assert "motor" in out and "[0, T_a]" in out
    assert "6 equations in 6 unknowns (12 in 12 with the kinematics)" in out
