"""Flexible links by finite elements: element matrices, cantilever frequencies against
Euler-Bernoulli theory, the rigid limit, a mixed flexible-rigid chain, and energy in free vibration."""
import sys
from pathlib import Path

import numpy as np
import pytest
import scipy.linalg as sla
import sympy as sp
from scipy.integrate import solve_ivp

import eomgen as eg

sys.path.insert(0, str(Path(__file__).parents[1] / "examples"))
from flexible_link import simulate  # noqa: E402

BETA_L = np.array([1.8751040687, 4.6940911330, 7.8547574382])  # roots of cos βL cosh βL = −1


def _link(elements, EI=1.0, m=1.0, L=1.0, gravity=(0, 0, 0), stiffening=True):
    system = eg.System(gravity=gravity)
    system.add_body("link", joint=eg.FlexibleLink("theta", length=L, mass_per_length=m, EI=EI, elements=elements,
                                                  stiffening=stiffening))
    return system


def test_single_element_matrices():
    """For θ̇ = 0 the nodal block of M is the consistent mass matrix (m h / 420)[...] of the free node,
    and the elastic forces are −K d with K = (E I / h³)[[12, −6h], [−6h, 4h²]]."""
    m, L, EI = sp.symbols("m L EI", positive=True)
    system = _link(1, EI, m, L)
    eom = eg.derive(system, method="lagrange")
    q0 = {x: 0 for x in system.q}
    consistent = m * L / 420 * sp.Matrix([[156, -22 * L], [-22 * L, 4 * L**2]])
    assert sp.simplify(eom.M[1:, 1:].xreplace(q0) - consistent) == sp.zeros(2, 2)
    assert sp.simplify(eom.M[0, 0].xreplace(q0) - m * L**3 / 3) == 0  # the rigid rod about its end
    K = EI / L**3 * sp.Matrix([[12, -6 * L], [-6 * L, 4 * L**2]])
    d = sp.Matrix(system.q[1:])
    assert sp.simplify(eom.tau_of("elastic")[1:, :] + K * d) == sp.zeros(2, 1)


def _frequencies(elements):
    system = _link(elements, stiffening=False)  # at rest the foreshortening's terms vanish: the same K, M
    f = eg.codegen(eg.derive(system, method="lagrange"))
    n = system.nv
    M = f.M(np.zeros(n))[1:, 1:]
    K = np.column_stack([-f.tau_of("elastic", np.eye(n)[k], np.zeros(n))[1:] for k in range(1, n)])
    return np.sqrt(np.sort(sla.eigh(K, M, eigvals_only=True)))


def test_cantilever_frequencies_converge():
    """Joint locked: ω_k = (β_k L)² √(E I / (m L⁴)); 4 elements give the first within 0.01 % and the
    third within 1 %, and the error falls about as h⁴."""
    errors = {}
    print("\n elements   error ω1     error ω2     error ω3")
    for n in (1, 2, 3, 4, 6):
        w = _frequencies(n)[:3]
        errors[n] = np.abs(w / BETA_L[:len(w)] ** 2 - 1)
        print(f"{n:9d}   " + "   ".join(f"{e:10.3e}" for e in errors[n]))
    assert errors[4][0] < 1e-4 and errors[4][2] < 1e-2
    assert 12 < errors[2][0] / errors[4][0] < 20  # h⁴: 16
    assert 12 < errors[3][1] / errors[6][1] < 20


def test_rigid_limit():
    """As E I grows, the joint angle of the flexible link follows the rigid uniform rod."""
    rigid = eg.System(gravity=(0, -9.81, 0))
    rigid.add_body("rod", joint=eg.Revolute("theta"), mass=5.0, com=(0.5, 0, 0),
                   inertia=np.diag([0.0, 5.0 / 12, 5.0 / 12]).tolist())
    fr = eg.codegen(eg.derive(rigid))
    t = np.linspace(0, 0.5, 11)
    ref = solve_ivp(lambda _, x: np.r_[x[1], fr.forward_dynamics(x[:1], x[1:])], (0, 0.5), [0.0, 0.0],
                    rtol=1e-10, atol=1e-12, t_eval=t).y[0]
    gaps = []
    for EI in (1e2, 1e3, 1e4):
        sol, _ = simulate(EI, seconds=0.5, backend="c")  # compiled: EI = 1e4 takes 60,000 evaluations
        gaps.append(np.abs(np.interp(t, sol.t, sol.y[0]) - ref).max())
    print("\nmax |θ_flexible − θ_rigid| over 0.5 s for EI = 1e2, 1e3, 1e4:", gaps)
    assert gaps[0] > gaps[1] > gaps[2] and gaps[2] < 2e-4, gaps


def test_free_vibration_conserves_energy():
    sol, energy = simulate(50.0, seconds=1.5, elements=2, backend="c")
    assert sol.success and np.abs(sol.y[1]).max() > 1e-3  # it deflects
    scale = np.abs(energy - energy.min()).max()
    assert np.ptp(energy) < 1e-8 * max(scale, 1.0)


def test_flexible_and_rigid_links_in_one_chain():
    """A rigid link on the tip of a flexible one: at zero deflection its rigid block of M equals the
    two-link arm with a uniform first rod."""
    m, L = 2.0, 0.8
    chain = eg.System(gravity=(0, -9.81, 0))
    flex = chain.add_body("flex", joint=eg.FlexibleLink("q_1", length=L, mass_per_length=m / L, EI=30.0, elements=2))
    chain.add_body("rigid", parent=flex, joint=eg.Revolute("q_2"), mass=1.0, com=(0.3, 0, 0),
                   inertia=np.diag([0.01, 0.02, 0.03]).tolist())
    arm = eg.System(gravity=(0, -9.81, 0))
    rod = arm.add_body("rod", joint=eg.Revolute("q_1"), mass=m, com=(L / 2, 0, 0),
                       inertia=np.diag([0.0, m * L**2 / 12, m * L**2 / 12]).tolist())
    arm.add_body("rigid", parent=rod, joint=eg.Revolute("q_2"), mass=1.0, com=(0.3, 0, 0),
                 inertia=np.diag([0.01, 0.02, 0.03]).tolist(), placement=eg.Placement(translation=(L, 0, 0)))
    fc, fa = eg.codegen(eg.derive(chain, method="lagrange")), eg.codegen(eg.derive(arm))
    idx = [0, chain.nv - 1]  # q_1 and q_2 (the nodal coordinates sit between them)
    for q1, q2 in [(0.3, -0.7), (1.1, 0.4)]:
        qc = np.zeros(chain.nv)
        qc[idx] = q1, q2
        np.testing.assert_allclose(fc.M(qc)[np.ix_(idx, idx)], fa.M([q1, q2]), rtol=1e-12, atol=1e-12)
        np.testing.assert_allclose(fc.g(qc)[idx], fa.g([q1, q2]), rtol=1e-12, atol=1e-12)


def test_flexible_link_errors():
    with pytest.raises(eg.ModelError, match="elements must be a positive integer"):
        eg.FlexibleLink("theta", length=1, mass_per_length=1, EI=1, elements=0)
    with pytest.raises(eg.ModelError, match="EI must be positive"):
        eg.FlexibleLink("theta", length=1, mass_per_length=1, EI=-2)
    with pytest.raises(eg.ModelError, match="does not handle flexible links"):
        eg.derive(_link(1), method="projected_newton_euler")


def test_example_runs(tmp_path, monkeypatch):
    import runpy

    monkeypatch.setattr(sys, "argv", ["flexible_link.py", "--out", str(tmp_path / "plot.png")])
    runpy.run_path(str(Path(__file__).parents[1] / "examples" / "flexible_link.py"), run_name="__main__")
    assert (tmp_path / "plot.png").stat().st_size > 10_000


def test_the_mass_matrix_stays_positive_definite_with_stiffening():
    """The foreshortening kept whole (not truncated at second order, whose T lost the positive u_x² terms
    and made M indefinite at slopes of 5 % on two elements): M is a Gram matrix of the centre line's
    motion, positive definite at deflections and slopes up to 0.25."""
    system = _link(2, EI=3.0, m=2.0, gravity=(0, -9.81, 0))
    f = eg.codegen(eg.derive(system))
    rng = np.random.default_rng(4)
    q = np.c_[rng.uniform(-np.pi, np.pi, 200), rng.uniform(-0.25, 0.25, (200, system.nq - 1))]
    assert np.linalg.eigvalsh(f.M(q)).min() > 0


def test_jacobians_beyond_a_flexible_link_are_refused(tmp_path):
    """A body on the tip moves with the nodes (through the tip's deflection, slope and foreshortening), which
    the Jacobians' columns do not hold: J and J̇ u of such a body are refused by name, not given wrong; the
    written module's default frames leave it out (its equations are written)."""
    import importlib.util

    chain = _link(2, gravity=(0, -9.81, 0))
    flex = chain.body("link")
    chain.add_body("hand", parent=flex, joint=eg.Revolute("q_2"), mass=1.0, com=(0.1, 0, 0))
    eom = eg.derive(chain)
    f = eg.codegen(eom)
    spec = importlib.util.spec_from_file_location("chain", eg.write_module(eom, tmp_path / "chain.py"))
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    q = np.random.default_rng(1).uniform(-0.1, 0.1, chain.nq)
    np.testing.assert_allclose(module.M(q), f.M(q), rtol=1e-13, atol=1e-13)
    q, u = np.zeros(chain.nq), np.zeros(chain.nv)
    assert f.jacobian("link", q).shape == (6, chain.nv)  # the link frame itself sits on the joint
    for call in (lambda: f.jacobian("hand", q), lambda: f.jacobian_dot_u("hand", q, u)):
        with pytest.raises(eg.ModelError, match="body 'hand' sits beyond flexible link 'theta'"):
            call()
