"""Projected Newton-Euler and Lagrange II are separate derivations: they must agree."""
import numpy as np
import pytest
import sympy as sp

import eomgen as eg
from models import assert_methods_agree, double_pendulum, matrices_trig_equal, numeric_arm, spatial_arm_3dof


def _both(system):
    return [eg.derive(system, method=m) for m in ("projected_newton_euler", "lagrange")]


@pytest.mark.parametrize("method", ["lagrange", "recursive"])
@pytest.mark.parametrize("build", [double_pendulum, spatial_arm_3dof])
def test_symbolic_agreement(build, method):
    """Double pendulum; spatial arm with skew axes, offset and rotated placements, full symbolic
    inertias and a prismatic joint."""
    assert_methods_agree(build(), method)


def test_double_pendulum_textbook_M11():
    """The textbook M11 of the double pendulum with rods (an independent closed form)."""
    system = double_pendulum()
    q = list(system.q)
    m1, m2, l1, l2, I1, I2 = sp.symbols("m1 m2 l1 l2 I1 I2", positive=True)
    M11 = I1 + I2 + m1 * l1**2 / 4 + m2 * (l1**2 + l2**2 / 4 + l1 * l2 * sp.cos(q[1]))
    assert sp.simplify(eg.derive(system).M[0, 0] - M11) == 0


def test_numeric_6dof_arm_with_loads():
    rng = np.random.default_rng(1)
    system, _ = numeric_arm(rng)
    F, T_a, k, c, f = sp.symbols("F T_a k c f")
    system.add_force("link5", (F, 2 * F, -F), point=(0.1, 0.2, 0.0), in_body_frame=True)
    system.add_torque("link3", (0, T_a, 0))
    system.add_actuator("link4", torque=(T_a, 0, 0), force=f, point=(0.1, 0, 0), reaction_point=(0, 0.1, 0.2),
                        in_body_frame=True)
    system.add_spring((None, (0.3, 0.2, 0.1)), ("link5", (0.0, 0.1, 0.1)), stiffness=k, rest_length=0.2)
    system.add_spring("link1", "link4", stiffness=k)
    system.add_damper((None, (0.0, 0.4, 0.0)), ("link2", (0.1, 0.0, 0.0)), damping=c)
    fs = [eg.codegen(e) for e in _both(system)]
    params = {"F": 1.7, "T_a": -0.4, "k": 30.0, "c": 2.5, "f": 0.9}
    for _ in range(5):
        q, u = rng.uniform(-2, 2, 6), rng.uniform(-2, 2, 6)
        for fn in ("M", "g", "U"):
            np.testing.assert_allclose(getattr(fs[0], fn)(q, params), getattr(fs[1], fn)(q, params),
                                       rtol=1e-12, atol=1e-12)
        for fn in ("b", "tau", "T"):
            np.testing.assert_allclose(getattr(fs[0], fn)(q, u, params), getattr(fs[1], fn)(q, u, params),
                                       rtol=1e-12, atol=1e-12)


@pytest.mark.parametrize("method", ["projected_newton_euler", "lagrange"])
def test_jdot_u_equals_literal_chain_rule(method):
    """Kinematics' J̇u (chain rule through sub-results) against Σ_k ∂J/∂q_k u_k on closed forms."""
    system = spatial_arm_3dof()
    kin = eg.Kinematics(system)
    q, u = system.q, system.u
    J = kin.sub.inline(kin.jacobian("link3"))
    Jdot_u = sum((J.diff(qk) * uk for qk, uk in zip(q, u)), sp.zeros(6, 3)) * u
    got = kin.sub.inline(kin.jacobian_dot_u("link3"))
    assert matrices_trig_equal(got, Jdot_u, list(q))
