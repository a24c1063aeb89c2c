"""Modal reduction of flexible links (FlexibleLink(modes=k)): the modes against the textbook element
matrices, the reduced model's frequencies against the full finite-element model's and Euler-Bernoulli
theory, the reduced equations as the full ones projected on the modes, energy in free vibration, the
random states, and the refusals."""
import numpy as np
import pytest
import scipy.linalg as sla
import sympy as sp
from hypothesis import given, settings, strategies as st
from scipy.integrate import solve_ivp

import eomgen as eg
from eomgen.model.beam_modes import clamped_modes
from eomgen.state import random_states

BETA_L = np.array([1.8751040687, 4.6940911330, 7.8547574382])  # roots of cos βL cosh βL = −1
m, EI, L, N = 5.0, 50.0, 1.0, 3


def _textbook(m, EI, L, n):
    """The nodal (M, K) of n elements from the textbook consistent mass (m h / 420)[...] and bending
    stiffness (E I / h³)[...] matrices, node 1 clamped."""
    h = L / n
    Me = m * h / 420 * np.array([[156, 22 * h, 54, -13 * h], [22 * h, 4 * h**2, 13 * h, -3 * h**2],
                                 [54, 13 * h, 156, -22 * h], [-13 * h, -3 * h**2, -22 * h, 4 * h**2]])
    Ke = EI / h**3 * np.array([[12, 6 * h, -12, 6 * h], [6 * h, 4 * h**2, -6 * h, 2 * h**2],
                               [-12, -6 * h, 12, -6 * h], [6 * h, 2 * h**2, -6 * h, 4 * h**2]])
    M, K = np.zeros((2 * n + 2,) * 2), np.zeros((2 * n + 2,) * 2)
    for e in range(n):
        M[2 * e:2 * e + 4, 2 * e:2 * e + 4] += Me
        K[2 * e:2 * e + 4, 2 * e:2 * e + 4] += Ke
    return M[2:, 2:], K[2:, 2:]


def _link(modes, elements=N, gravity=(0, -9.81, 0), child=False):
    system = eg.System(gravity=gravity)
    joint = eg.FlexibleLink("theta", length=L, mass_per_length=m, EI=EI, elements=elements, modes=modes)
    link = system.add_body("link", joint=joint)
    if child:
        system.add_body("hand", parent=link, joint=eg.Revolute("q_2"), mass=0.5, com=(0.2, 0, 0),
                        inertia=np.diag([0.01, 0.02, 0.03]).tolist())
    return system, joint


@pytest.fixture(scope="module")
def models():
    """The link (3 elements) with k = 1, 2, 3 modes, generated once."""
    out = {}
    for k in (1, 2, 3):
        system, joint = _link(k)
        out[k] = system, joint, eg.codegen(eg.derive(system, method="lagrange"))
    return out


@settings(max_examples=10, deadline=None)
@given(st.floats(0.1, 10), st.floats(0.1, 100), st.floats(0.2, 3), st.integers(1, 5), st.data())
def test_modes_are_the_textbook_eigenvectors(m, EI, L, n, data):
    """Φᵀ M Φ = 1, Φᵀ K Φ = diag ω², ω the first k of the textbook matrices' eigenfrequencies."""
    k = data.draw(st.integers(1, 2 * n))
    Phi, omega = clamped_modes(L, m, EI, n, k)
    M, K = _textbook(m, EI, L, n)
    np.testing.assert_allclose(Phi.T @ M @ Phi, np.eye(k), atol=1e-10)
    reference = np.sqrt(sla.eigh(K, M, eigvals_only=True)[:k])
    np.testing.assert_allclose(omega, reference, rtol=1e-10)
    np.testing.assert_allclose(Phi.T @ K @ Phi, np.diag(omega**2), atol=1e-9 * omega[-1] ** 2)
    assert np.all(Phi[-2] > 0)  # each mode signed by its tip deflection


def test_modal_frequencies_are_the_full_models(models):
    """Joint locked (θ's row and column removed): the k-mode model's frequencies equal the first k of the
    full 3-element model (textbook matrices) to 1e-10, near (β_k L)² √(E I / (m L⁴))."""
    M_full, K_full = _textbook(m, EI, L, N)
    full = np.sqrt(sla.eigh(K_full, M_full, eigvals_only=True))
    analytic = BETA_L**2 * np.sqrt(EI / (m * L**4))
    print("\n k   ω (reduced)                       error vs full       error vs analytic")
    for k, (system, _, f) in models.items():
        n = system.nv
        M = f.M(np.zeros(n))[1:, 1:]
        K = np.column_stack([-f.tau_of("elastic", np.eye(n)[j], np.zeros(n))[1:] for j in range(1, n)])
        w = np.sqrt(np.sort(sla.eigh(K, M, eigvals_only=True)))
        print(f" {k}   {w}   {np.abs(w / full[:k] - 1).max():.1e}   {np.abs(w / analytic[:k] - 1)}")
        np.testing.assert_allclose(w, full[:k], rtol=1e-10)
        np.testing.assert_allclose(w, analytic[:k], rtol=3e-2)  # 3 elements: the discretisation error


def test_reduced_equations_are_the_projected_full_ones():
    """d = Φ η is a linear map T = diag(1, Φ, 1) of the coordinates, so the reduced equations are the full
    ones projected: M_r(q) = Tᵀ M(T q) T, g_r = Tᵀ g(T q), b_r = Tᵀ b(T q, T u) — the energies, the
    foreshortening and the child on the tip frame all through Φ η. Two elements, two modes."""
    reduced, joint = _link(2, elements=2, child=True)
    full, _ = _link(None, elements=2, child=True)
    fr, ff = (eg.codegen(eg.derive(s, method="lagrange")) for s in (reduced, full))
    T = sla.block_diag(1.0, joint.shapes, 1.0)
    q, u, _ = random_states(reduced, 5, np.random.default_rng(1))
    for qr, ur in zip(q, u):
        np.testing.assert_allclose(fr.M(qr), T.T @ ff.M(T @ qr) @ T, rtol=1e-10, atol=1e-12)
        np.testing.assert_allclose(fr.g(qr), T.T @ ff.g(T @ qr), rtol=1e-10, atol=1e-10)
        np.testing.assert_allclose(fr.b(qr, ur), T.T @ ff.b(T @ qr, T @ ur), rtol=1e-10, atol=1e-10)


def _release(system, f, seconds, rtol):
    """A free swing released at rest from the horizontal, undeformed (DOP853, 101 samples)."""
    n = system.nv
    return solve_ivp(lambda _, x: np.r_[x[n:], f.forward_dynamics(x[:n], x[n:])], (0, seconds),
                     np.zeros(2 * n), method="DOP853", rtol=rtol, atol=rtol / 100,
                     t_eval=np.linspace(0, seconds, 101))


def test_free_vibration_with_modes_conserves_energy(models):
    """Released at rest from the horizontal, two modes, 0.5 s."""
    system, _, f = models[2]
    n = system.nv
    sol = _release(system, f, 0.5, rtol=1e-11)
    energy = np.array([f.T(x[:n], x[n:]) + f.U(x[:n]) for x in sol.y.T])
    assert sol.success and np.abs(sol.y[1]).max() > 1e-3  # it deflects
    assert np.ptp(energy) < 1e-8 * max(np.abs(energy).max(), 1.0)


def _swing(system, f, shapes, seconds=1.0):
    """The tip deflection over a free swing released at rest from the horizontal."""
    sol = _release(system, f, seconds, rtol=1e-9)
    assert sol.success
    return (shapes @ sol.y[1:system.nv])[-2]


@pytest.mark.slow
def test_tip_deflection_converges_with_modes(models):
    """A 1 s free swing: the tip deflection of k = 1, 2, 3 modes against all the nodal coordinates of
    the same 3 elements (stiff: its highest frequency ~ 50 ω1, hence slow), the error falling with k."""
    full, _ = _link(None)
    reference = _swing(full, eg.codegen(eg.derive(full, method="lagrange")), np.eye(2 * N))
    errors = {k: np.abs(_swing(s, f, joint.shapes) - reference).max() for k, (s, joint, f) in models.items()}
    print(f"\nmax |tip − tip_full| (max |tip_full| = {np.abs(reference).max():.3e} m):", errors)
    assert errors[1] > errors[2] > errors[3] and errors[3] < 0.05 * np.abs(reference).max()


def test_random_modal_amplitudes_deflect_like_nodes(models):
    """Each mode alone moves no node by more than 0.05 (the nodal coordinates' range), and the draws use
    that range."""
    system, joint, _ = models[3]
    q, _, _ = random_states(system, 2000, np.random.default_rng(0))
    per_mode = np.abs(joint.shapes[:, None, :] * q[None, :, 1:])
    assert per_mode.max() <= 0.05 + 1e-12 and per_mode.max(axis=(0, 1)).min() > 0.045


@pytest.mark.parametrize("changes, field", [
    ({"EI": sp.Symbol("EI", positive=True), "modes": 2}, "EI"),
    ({"length": sp.Symbol("L"), "modes": 1}, "length"),
    ({"modes": 0}, "modes"), ({"modes": 5}, "modes"), ({"modes": 1.5}, "modes"), ({"modes": True}, "modes"),
])
def test_modes_refusals_name_the_joint_and_field(changes, field):
    """A symbolic m, E I or L with modes (Φ needs numbers); k not an integer in 1 … 2n (2 elements: 4)."""
    values = {"length": 1.0, "mass_per_length": 1.0, "EI": 1.0, "elements": 2, **changes}
    with pytest.raises(eg.ModelError, match=rf"joint 'arm'.*{field}"):
        eg.FlexibleLink("arm", **values)
