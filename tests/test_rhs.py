"""f.rhs(t, x, tau): against Pinocchio's aba on a floating-base robot (q̇ of the quaternion by hand), the
four-bar loop's free-body diagrams, sympy's KanesMethod with specified forces and torques, and the
cart-pendulum's closed form (NumPy and C); tau as values or a function, batches, refused inputs."""

import numpy as np
import pinocchio as pin
import pytest
import sympy.physics.mechanics as me

import eomgen as eg
import kane_systems as K
from models import cart_pendulum
from test_loops import closed_form, hand, newton_euler, numeric

CART = {"m_c": 1.3, "m_p": 0.4, "l": 0.6, "g": 9.81}


def quaternion_rate(quat, omega) -> np.ndarray:
    """d/dt (x, y, z, w) = ½ quat ⊗ (ω, 0), ω in the body's axes."""
    x, y, z, w = quat
    Q = np.array([[w, -z, y], [z, w, -x], [-y, x, w], [-x, -y, -z]])
    return 0.5 * Q @ omega


def test_free_flyer_equals_aba():
    """solo12 at 5 random states and efforts: u̇ = aba(q, u, Sᵀ τ_a) to 1e-9 (relative to its size), q̇ of
    the base: ṗ = R v, the quaternion's ½ q ⊗ ω; of the joints u; a function of (t, q, u) as tau."""
    system = eg.robots.load("solo12")
    f = eg.codegen(eg.derive(system, method="recursive"))
    model = system.pinocchio_model
    data = model.createData()
    rng = np.random.default_rng(5)
    q, u, _ = eg.random_states(system, 5, rng)
    tau = rng.uniform(-2, 2, (5, len(f.S)))
    for k in range(5):
        x = np.r_[q[k], u[k]]
        rates = f.rhs(0.3, x, tau[k])
        expected = pin.aba(model, data, q[k], u[k], np.r_[np.zeros(6), tau[k]])
        np.testing.assert_allclose(
            rates[system.nq :], expected, rtol=0, atol=1e-9 * max(1, np.abs(expected).max())
        )
        R = pin.Quaternion(q[k][6], *q[k][3:6]).toRotationMatrix()
        np.testing.assert_allclose(rates[:3], R @ u[k][:3], atol=1e-13)
        np.testing.assert_allclose(rates[3:7], quaternion_rate(q[k][3:7], u[k][3:6]), atol=1e-13)
        np.testing.assert_allclose(rates[7 : system.nq], u[k][6:], atol=0)

        def controller(t, qq, uu, k=k):  # called with this t, q and u, else NaN (refused)
            return tau[k] if t == 0.3 and np.array_equal(np.r_[qq, uu], x) else np.nan

        np.testing.assert_array_equal(f.rhs(0.3, x, controller), rates)


@pytest.mark.parametrize("theta,rate,torque", [(0.3, 2.0, 1.5), (2.0, -1.0, -3.0), (-1.2, 0.5, 0.0)])
def test_loop_equals_free_body_diagrams(theta, rate, torque):
    """The four-bar with a crank torque: u̇ of rhs = the crank's θ̈ of the hand-derived mechanism and the
    other links' rates from the closure, u̇ = [θ̈, (k2 − 1) θ̈ + k2' θ̇², k3 θ̈ + k3' θ̇²]; q̇ = u;
    the power τ θ̇."""
    _, f, _ = numeric()
    acc, _, u = newton_euler(theta, rate, torque)
    q = closed_form(theta)
    h = hand()
    angles = (q[0], q[0] + q[1], q[2])
    k2, k3, dk2, dk3 = (h[k](*angles) for k in ("k2", "k3", "dk2", "dk3"))
    expected = [acc, (k2 - 1) * acc + dk2 * rate**2, k3 * acc + dk3 * rate**2]
    rates = f.rhs(0.0, np.r_[q, u], [torque])
    np.testing.assert_allclose(rates[:3], u, atol=1e-14)
    np.testing.assert_allclose(rates[3:], expected, rtol=1e-9, atol=1e-9)
    assert f.power(0.0, np.r_[q, u], [torque]) == pytest.approx(torque * rate, rel=1e-12, abs=1e-12)
    with_gains = f.rhs(0.0, np.r_[q, u], [torque], baumgarte=(10.0, 10.0))  # closed and J u = 0: the same
    np.testing.assert_allclose(with_gains, rates, rtol=1e-9, atol=1e-9)


@pytest.mark.parametrize("backend", ["numpy", "c"])
def test_kane_equals_sympy_with_efforts(backend, tmp_path, monkeypatch):
    """The rolling disk (Kane, two no-slip constraints) with all four joints actuated: rhs with
    τ_a = (F_x, F_y, τ_s, τ_d) = sympy's KanesMethod with those forces on the centre, the steer torque on
    the heading and the drive torque between heading and disk: [q̇; ẇ_ind] from its full mass matrix and
    forcing, at random states; and the power Fᵀ v + τ_s θ̇ + τ_d φ̇."""
    monkeypatch.setenv("EOMGEN_CACHE", str(tmp_path))
    system, args = K.rolling_disk()
    f = eg.codegen(eg.kane(system, **args), backend=backend)
    km, qs, _ = K.rolling_disk_sympy(torques=True, forces=True)
    values = {"m": 1.3, "R": 0.3, "g": 9.81}
    rng = np.random.default_rng(7)
    for _ in range(3):
        q, w, efforts = rng.uniform(-1.5, 1.5, 4), rng.uniform(-2, 2, 2), rng.uniform(-1, 1, 4)
        ux, uy = values["R"] * w[1] * np.cos(q[2]), values["R"] * w[1] * np.sin(q[2])
        numbers = {
            K.m: values["m"],
            K.R: values["R"],
            K.g: values["g"],
            **dict(zip([K.F_x, K.F_y, K.tau_s, K.tau_d], efforts)),
            **dict(zip(qs, q)),
            **dict(zip(km.u, [*w, ux, uy])),
        }
        M = np.array(me.msubs(km.mass_matrix_full, numbers).evalf(30).tolist(), dtype=float)
        F = np.array(me.msubs(km.forcing_full, numbers).evalf(30).tolist(), dtype=float)[:, 0]
        expected = np.linalg.solve(M, F)[:6]  # q̇ (4), then the independent speeds' rates
        rates = f.rhs(0.0, np.r_[q, w], efforts, params=values)
        np.testing.assert_allclose(rates, expected, rtol=1e-11, atol=1e-11)
        power = efforts[:2] @ [ux, uy] + efforts[2] * w[0] + efforts[3] * w[1]
        assert f.power(0.0, np.r_[q, w], efforts, params=values) == pytest.approx(
            power, rel=1e-12, abs=1e-12
        )
    batch = rng.uniform(-1, 1, (4, 6))
    np.testing.assert_allclose(
        f.rhs(0.0, batch, efforts, params=values)[2],
        f.rhs(0.0, batch[2], efforts, params=values),
        rtol=1e-14,
    )


@pytest.mark.parametrize("backend", ["numpy", "c"])
def test_cart_pendulum_closed_form(backend, tmp_path, monkeypatch):
    """The cart-pendulum (bob at l below the pivot) by hand: (m_c + m_p) ẍ + m_p l cos φ φ̈ − m_p l sin φ φ̇²
    = F, m_p l cos φ ẍ + m_p l² φ̈ + m_p g l sin φ = τ; one state, N states at once, tau a function."""
    monkeypatch.setenv("EOMGEN_CACHE", str(tmp_path))
    system, _ = cart_pendulum()
    f = eg.codegen(eg.derive(system), backend=backend).bind(CART)
    mc, mp, l, g = CART.values()
    x = np.random.default_rng(8).uniform(-2, 2, (6, 4))
    tau = np.array([0.7, -0.3])
    for state in x:
        phi, xd, phid = state[1:]
        M = np.array([[mc + mp, mp * l * np.cos(phi)], [mp * l * np.cos(phi), mp * l**2]])
        rhs = tau + [mp * l * np.sin(phi) * phid**2, -mp * g * l * np.sin(phi)]
        np.testing.assert_allclose(
            f.rhs(0.0, state, tau), np.r_[xd, phid, np.linalg.solve(M, rhs)], rtol=1e-13, atol=1e-13
        )
    np.testing.assert_allclose(f.rhs(0.0, x, tau)[4], f.rhs(0.0, x[4], tau), rtol=1e-14, atol=1e-14)
    np.testing.assert_allclose(
        f.rhs(0.0, x, lambda t, q, u: np.tile(tau, (len(q), 1))), f.rhs(0.0, x, tau), rtol=1e-15
    )


def test_bad_inputs():
    """A mapping as tau (the old positional params), x of the wrong size, a batch where constraints are held
    one state at a time, Baumgarte's gains without constraints, efforts of the wrong length."""
    system, _ = cart_pendulum()
    f = eg.codegen(eg.derive(system))
    with pytest.raises(eg.ModelError, match="tau: expected the actuator efforts .* got a mapping"):
        f.rhs(0.0, np.zeros(4), CART)
    with pytest.raises(
        eg.ModelError, match=r"x: expected \[q, u\] of shape \(4,\) or \(N, 4\), got shape \(3,\)"
    ):
        f.rhs(0.0, np.zeros(3), params=CART)
    with pytest.raises(
        eg.ModelError, match="baumgarte: the system has no contacts, loops or rolling disks"
    ):
        f.rhs(0.0, np.zeros(4), params=CART, baumgarte=(1, 1))
    with pytest.raises(eg.ModelError, match=r"tau_a: expected 2 finite values"):
        f.rhs(0.0, np.zeros(4), [1.0], params=CART)
    _, loop, _ = numeric()
    with pytest.raises(
        eg.ModelError, match=r"x: expected \[q, u\] of shape \(6,\), got shape \(2, 6\) \(one state"
    ):
        loop.rhs(0.0, np.zeros((2, 6)))
    kane = eg.codegen(eg.kane(*K.rolling_disk()[:1], **K.rolling_disk()[1]))
    with pytest.raises(eg.ModelError, match=r"x: expected \[q, w_ind\] of shape \(6,\)"):
        kane.rhs(0.0, np.zeros(7), params={"m": 1, "R": 0.3, "g": 9.81})
