"""DC motors on the two-link arm of the bond-graph paper: closed forms, reflected inertia as Pinocchio's
armature, and the power balance of a simulated voltage step."""
import sys
from pathlib import Path

import numpy as np
import pytest
import sympy as sp

import eomgen as eg

sys.path.insert(0, str(Path(__file__).parents[1] / "examples"))
from two_link_dc_motors import NUMBERS, J_m, N, g, l1, lc1, lc2, m1, m2, I1, I2, simulate, two_link_arm  # noqa: E402
from models import two_link_closed_form  # noqa: E402


@pytest.mark.parametrize("method", ["lagrange", "projected_newton_euler", "recursive", "free_cut"])
def test_two_link_arm_closed_forms(method):
    """M, C q̇ and G of the paper (angles from the horizontal)."""
    system = two_link_arm()
    eom = eg.derive(system, method=method)
    M, Cqd, G = two_link_closed_form(system.q, system.u, m1, m2, l1, lc1, lc2, I1, I2, g)
    assert sp.simplify(eom.M - M) == sp.zeros(2, 2)
    assert sp.simplify(eom.b - Cqd) == sp.zeros(2, 1)
    assert sp.simplify(eom.g - G) == sp.zeros(2, 1)


def test_motor_inertia_is_armature():
    rigid, motors = eg.derive(two_link_arm()), eg.derive(two_link_arm(motors=True))
    assert sp.simplify(motors.M - rigid.M - sp.diag(N**2 * J_m, N**2 * J_m)) == sp.zeros(2, 2)
    # numerically, against Pinocchio with model.armature = N² J_m
    system = two_link_arm(motors=True)
    numbers = {s: NUMBERS[str(s)] for s in system.parameters if str(s) in NUMBERS}
    numeric = eg.System(gravity=tuple(x.xreplace(numbers) for x in system.gravity))
    parent = None
    for b in system.bodies:
        joint = eg.Revolute(b.joint.name, axis=(0, 0, 1), armature=b.joint.armature.xreplace(numbers))
        parent = numeric.add_body(b.name, parent=parent, joint=joint, mass=b.mass.xreplace(numbers),
                                  com=b.com.xreplace(numbers),
                                  inertia=sp.diag(1, 1, 2) * b.inertia[2, 2].xreplace(numbers) / 2,  # planar: I_zz
                                  placement=eg.Placement(translation=b.placement.translation.xreplace(numbers)))
    report = eg.verify(numeric, method="lagrange", states=10)
    assert report.ok(1e-10), str(report)
    assert float(numeric.bodies[0].joint.armature) == pytest.approx(50.0**2 * 2e-5)


def test_power_balance_of_a_voltage_step():
    """U i = d/dt (T + U_g + ½ L i²) + R i² + f (N q̇)² along the simulation, to 1e-8 relative."""
    sol, energy = simulate(1.0)
    assert sol.success
    balance = np.array([energy(x) - x[-1] for x in sol.y.T])
    supplied = sol.y[-1, -1]
    assert supplied > 1.0 and np.abs(sol.y[:2, -1] - sol.y[:2, 0]).max() > 0.5  # it moved, work was done
    assert np.ptp(balance) < 1e-8 * supplied


def test_motor_errors():
    system = eg.System()
    slider = system.add_body("slider", joint=eg.Prismatic("s"), mass=1)
    with pytest.raises(eg.ModelError, match="motor on body 'slider': a DC motor drives a revolute joint"):
        system.add_motor(slider, resistance=1, inductance=1, torque_constant=1, rotor_inertia=1)
    arm = system.add_body("arm", parent=slider, joint=eg.Revolute("q"), mass=1)
    with pytest.raises(eg.ModelError, match="resistance must be non-negative"):
        system.add_motor(arm, resistance=-1, inductance=1, torque_constant=1, rotor_inertia=1)


def test_example_runs(capsys):
    import runpy

    runpy.run_path(str(Path(__file__).parents[1] / "examples" / "two_link_dc_motors.py"), run_name="__main__")
    assert "M with motors − M = [[J_m*N**2, 0], [0, J_m*N**2]]" in capsys.readouterr().out


def motor_on_a_link():
    """One link (0.1 + 1 · 0.5² about the joint, 0.36 with the rotor) under a voltage feedback in q, q̇."""
    system = eg.System(gravity=(0, -9.81, 0))
    a = system.add_body("a", joint=eg.Revolute("phi"), mass=1, com=(0.5, 0, 0), inertia=sp.eye(3) * 0.1)
    (phi,), (phid,) = system.q, system.u
    L = sp.Symbol("L", positive=True)
    system.add_motor(a, resistance=1, inductance=L, torque_constant=0.05, rotor_inertia=0.01,
                     voltage=-5 * phi - 0.5 * phid)
    return system


@pytest.mark.parametrize("backend", ["numpy", "c"])
def test_rhs_bound_or_not_with_the_currents_from_x(backend, tmp_path, monkeypatch):
    monkeypatch.setenv("EOMGEN_CACHE", str(tmp_path))
    f = eg.codegen(eg.derive(motor_on_a_link()), backend=backend)
    phi, phid, i = 0.3, 0.5, 2.0
    expected = [phid, (0.05 * i - 9.81 * 0.5 * np.cos(phi)) / 0.36,
                (-5 * phi - 0.5 * phid - i - 0.05 * phid) / 0.01]
    bound = f.bind({"L": 0.01})  # the current is state: no bind gives it
    for rhs in (f.rhs(0.0, [phi, phid, i], params={"L": 0.01}), bound.rhs(0.0, (phi, phid, i))):
        np.testing.assert_allclose(rhs, expected, rtol=1e-14)
    np.testing.assert_allclose(bound.tau([phi], [phid], {"i_motor_phi": i}), [0.05 * i], rtol=1e-15)
    with pytest.raises(eg.ModelError, match=r"values missing for the parameters \['i_motor_phi'\]"):
        bound.tau([phi], [phid])
    with pytest.raises(eg.ModelError, match="bound"):
        bound.tau([phi], [phid], {"i_motor_phi": i, "L": 0.02})
    with pytest.raises(eg.ModelError, match=r"bind: \['i_motor_phi'\] are motor currents"):
        f.bind({"L": 0.01, "i_motor_phi": i})
    with pytest.raises(eg.ModelError, match=r"\['i_motor_phi'\] are motor currents, taken from the state x"):
        f.rhs(0.0, [phi, phid, i], params={"L": 0.01, "i_motor_phi": i})
    with pytest.raises(eg.ModelError, match=r"L = 0.0 \(must be > 0\)"):
        f.rhs(0.0, [phi, phid, i], params={"L": 0.0})
    with pytest.raises(eg.ModelError, match=r"x: expected \[q, u, i\] of shape \(3,\), got shape \(2,\)"):
        bound.rhs(0.0, [phi, phid])


def test_two_link_rhs_bound():
    fn = eg.codegen(eg.derive(two_link_arm(motors=True), method="lagrange"))
    x = np.array([-1.2, 0.4, 0.3, -0.7, 1.5, -2.0])
    np.testing.assert_array_equal(fn.bind(NUMBERS).rhs(0.0, x), fn.rhs(0.0, x, params=NUMBERS))
    with pytest.raises(eg.ModelError, match=r"x: expected \[q, u\] of shape \(4,\) or \(N, 4\), got"):
        eg.codegen(eg.derive(two_link_arm())).rhs(0.0, x)
