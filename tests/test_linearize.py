"""eg.linearize of equations of motion without constraints: the cart-pole about the upright against a hand
derivation and sympy's KanesMethod linearizer, and an LQR from it that brings the nonlinear simulation back
upright; a pendulum's load and model parameters as inputs and a DC motor's voltage, by hand; a free flyer
with a ball and a planar joint (quaternions, tangent coordinates) against finite differences along
eg.integrate; bad input refused."""

import numpy as np
import pytest
import sympy as sp
import sympy.physics.mechanics as me
from scipy.integrate import solve_ivp
from scipy.linalg import solve_continuous_are

import eomgen as eg

m_c, m_p, l, g = sp.symbols("m_c m_p l g", positive=True)
CART_POLE = {"m_c": 1.0, "m_p": 0.3, "l": 0.7, "g": 9.81}


def cart_pole() -> eg.EquationsOfMotion:
    """A cart (x, pushed by its actuated joint) carrying a point mass m_p on a massless pole of length l,
    angle phi about z from the upright (the mass at (x − l sin phi, l cos phi)); gravity −y."""
    system = eg.System(gravity=(0, -g, 0))
    cart = system.add_body("cart", joint=eg.Prismatic("x", axis=(1, 0, 0)), mass=m_c)
    system.add_body(
        "pole",
        parent=cart,
        joint=eg.Revolute("phi", axis=(0, 0, 1), actuated=False),
        mass=m_p,
        com=(0, l, 0),
    )
    return eg.derive(system, method="recursive")


def cart_pole_by_hand() -> tuple[sp.Matrix, sp.Matrix]:
    """(m_c + m_p) ẍ − m_p l cos φ φ̈ + m_p l sin φ φ̇² = F, −m_p l cos φ ẍ + m_p l² φ̈ − m_p g l sin φ = 0;
    at φ = 0: m_c ẍ = F + m_p g φ, m_c l φ̈ = F + (m_c + m_p) g φ."""
    A = sp.zeros(4, 4)
    A[0, 2] = A[1, 3] = 1
    A[2, 1], A[3, 1] = m_p * g / m_c, (m_c + m_p) * g / (m_c * l)
    return A, sp.Matrix([0, 0, 1 / m_c, 1 / (m_c * l)])


def cart_pole_sympy() -> tuple[sp.Matrix, sp.Matrix]:
    """sympy's KanesMethod linearizer on the same cart-pole (written independently)."""
    q1, q2, u1, u2, F = me.dynamicsymbols("q1 q2 u1 u2 F")
    N = me.ReferenceFrame("N")
    O = me.Point("O")
    O.set_vel(N, 0)
    P = O.locatenew("P", q1 * N.x)
    P.set_vel(N, u1 * N.x)
    B = N.orientnew("B", "Axis", [q2, N.z])
    B.set_ang_vel(N, u2 * N.z)
    Q = P.locatenew("Q", l * B.y)
    Q.v2pt_theory(P, N, B)
    km = me.KanesMethod(N, q_ind=[q1, q2], u_ind=[u1, u2], kd_eqs=[q1.diff() - u1, q2.diff() - u2])
    km.kanes_equations(
        [me.Particle("cart", P, m_c), me.Particle("pole", Q, m_p)],
        [(P, F * N.x - m_c * g * N.y), (Q, -m_p * g * N.y)],
    )
    A, B, _ = km.linearize(op_point={q1: 0, q2: 0, u1: 0, u2: 0}, A_and_B=True)
    return A, B


def equal(X: sp.Matrix, Y: sp.Matrix) -> bool:
    return X.shape == Y.shape and sp.simplify(X - Y) == sp.zeros(*X.shape)


def test_cart_pole_equals_hand_and_sympy_linearizer():
    """About the upright (q = 0, u = 0): symbolic A, B equal the hand derivation and sympy's; the numeric
    ones equal them at numbers; states x, phi, xdot, phidot and the input tau_x."""
    eom = cart_pole()
    L = eg.linearize(eom, (np.zeros(2), np.zeros(2)), symbolic=True)
    A, B = cart_pole_by_hand()
    assert equal(L.A, A) and equal(L.B, B)
    A_s, B_s = cart_pole_sympy()
    assert equal(L.A, A_s) and equal(L.B, B_s)
    assert L.states == ("x", "phi", "xdot", "phidot") and L.inputs == ("tau_x",)
    assert L.xdot0 == sp.zeros(4, 1)
    numeric = eg.linearize(eom, {"x": 0.3, "phi": 0}, params=CART_POLE)  # x is ignorable
    at = {sp.Symbol(k, positive=True): v for k, v in CART_POLE.items()}
    np.testing.assert_allclose(numeric.A, np.array(A.subs(at), dtype=float), rtol=1e-14, atol=1e-14)
    np.testing.assert_allclose(numeric.B, np.array(B.subs(at), dtype=float), rtol=1e-14)
    np.testing.assert_allclose(numeric.x0, [0.3, 0, 0, 0])


def test_no_inputs_symbolic_gives_an_empty_B():
    """inputs=[]: B has no columns (n × 0) and r0 no entries, symbolic as numeric; A is the hand one's."""
    eom = cart_pole()
    L = eg.linearize(eom, (np.zeros(2), np.zeros(2)), inputs=[], symbolic=True)
    A, _ = cart_pole_by_hand()
    assert equal(L.A, A) and L.B.shape == (4, 0) and L.inputs == ()
    assert eg.linearize(eom, (np.zeros(2), np.zeros(2)), inputs=[], params=CART_POLE).B.shape == (4, 0)


def test_lqr_from_the_linearization_holds_the_pole_up():
    """K from the continuous Riccati equation (Q = 1, R = 1) of the numeric A, B; the nonlinear cart-pole
    (the generated forward dynamics, solve_ivp) from a 0.2 rad tilt is upright within 1e-3 rad after 8 s and
    at rest at the start within 1e-2 after 10 s under τ = −K x; it falls without it."""
    eom = cart_pole()
    L = eg.linearize(eom, (np.zeros(2), np.zeros(2)), params=CART_POLE)
    P = solve_continuous_are(L.A, L.B, np.eye(4), np.eye(1))
    K = L.B.T @ P
    f = eg.codegen(eom, params=CART_POLE)

    def rhs(t, x, gain):
        return np.r_[x[2:], f.forward_dynamics(x[:2], x[2:], -gain @ x)]

    x0 = np.array([0, 0.2, 0, 0])
    held = solve_ivp(rhs, (0, 10), x0, args=(K,), rtol=1e-10, atol=1e-10)
    assert held.success and np.abs(held.y[:, -1]).max() < 1e-2
    assert np.abs(held.y[1][held.t > 8]).max() < 1e-3 and np.abs(held.y[1]).max() < 0.25
    fallen = solve_ivp(rhs, (0, 3), x0, args=(0 * K,), rtol=1e-10, atol=1e-10)
    assert np.abs(fallen.y[1]).max() > 1.5


def pendulum(motor: bool = False):
    """A point mass m at distance l below a revolute joint about z (angle from the downward vertical),
    a torque T on it (a load parameter); with `motor` a DC motor drives the joint instead."""
    m, T = sp.symbols("m T", positive=True)
    system = eg.System(gravity=(0, -g, 0))
    body = system.add_body(
        "bob", joint=eg.Revolute("th", axis=(0, 0, 1), actuated=False), mass=m, com=(0, -l, 0)
    )
    if motor:
        R, Lm, k, J, f, N = sp.symbols("R L_m k J_m f N", positive=True)
        system.add_motor(
            body, resistance=R, inductance=Lm, torque_constant=k, rotor_inertia=J, friction=f, gear_ratio=N
        )
    else:
        system.add_torque(body, (0, 0, T), name="torque")
    return eg.derive(system, method="recursive")


@pytest.mark.parametrize("symbolic", [False, True])
def test_pendulum_load_and_model_parameters_as_inputs(symbolic):
    """θ̈ = (T − m g l sin θ)/(m l²) at θ0 = 0.6, θ̇0 = 0.4, T0 = 0.5 by hand: A = [[0, 1], [−g cos θ/l, 0]],
    ∂θ̈/∂T = 1/(m l²), ∂/∂g = −sin θ/l, ∂/∂l = g sin θ/l² − 2T/(m l³), ∂/∂m = −T/(m² l²); ẋ0 the rates."""
    eom = pendulum()
    values = {"m": 1.3, "l": 0.8, "g": 9.81, "T": 0.5}
    th, thd = 0.6, 0.4
    L = eg.linearize(
        eom,
        (np.array([th]), [thd]),
        inputs=["T", "g", "l", "m"],
        params=None if symbolic else values,
        symbolic=symbolic,
    )
    m, T = sp.symbols("m T", positive=True)
    s, c = sp.sin(th), sp.cos(th)
    A = sp.Matrix([[0, 1], [-g * c / l, 0]])
    B = sp.Matrix(
        [[0, 0, 0, 0], [1 / (m * l**2), -s / l, g * s / l**2 - 2 * T / (m * l**3), -T / (m**2 * l**2)]]
    )
    xdot0 = sp.Matrix([thd, (T - m * g * l * s) / (m * l**2)])
    at = {sp.Symbol(k, positive=True): v for k, v in values.items()}
    if symbolic:
        assert equal(L.A, A) and equal(L.B, B) and equal(L.xdot0, xdot0) and L.r0 == sp.Matrix([T, g, l, m])
    for got, want in ((L.A, A), (L.B, B), (L.xdot0, xdot0)):
        np.testing.assert_allclose(
            np.array(sp.Matrix(got).subs(at), dtype=float).reshape(np.shape(want)),
            np.array(want.subs(at), dtype=float),
            rtol=1e-13,
            atol=1e-15,
        )


def test_dc_motor_voltage_input():
    """State [θ, θ̇, i]: (m l² + N² J_m) θ̈ = N k i − N² f θ̇ − m g l sin θ, L di/dt = U − R i − k N θ̇ by
    hand; the input U_motor_th gives B = [0, 0, 1/L]; ẋ0 equals the generated rhs."""
    eom = pendulum(motor=True)
    values = {
        "m": 1.3,
        "l": 0.8,
        "g": 9.81,
        "R": 2.0,
        "L_m": 0.05,
        "k": 0.3,
        "J_m": 0.01,
        "f": 0.02,
        "N": 5.0,
        "U_motor_th": 1.5,
    }
    th, thd, i = 0.6, 0.4, 0.7
    L = eg.linearize(eom, {"th": th, "thdot": thd, "i_motor_th": i}, inputs="U_motor_th", params=values)
    v = values
    J = v["m"] * v["l"] ** 2 + v["N"] ** 2 * v["J_m"]
    A = [
        [0, 1, 0],
        [-v["m"] * v["g"] * v["l"] * np.cos(th) / J, -v["N"] ** 2 * v["f"] / J, v["N"] * v["k"] / J],
        [0, -v["k"] * v["N"] / v["L_m"], -v["R"] / v["L_m"]],
    ]
    np.testing.assert_allclose(L.A, A, rtol=1e-13, atol=1e-15)
    np.testing.assert_allclose(L.B, [[0], [0], [1 / v["L_m"]]], rtol=1e-14, atol=1e-15)
    assert L.states == ("th", "thdot", "i_motor_th") and L.inputs == ("U_motor_th",)
    f = eg.codegen(eom)
    np.testing.assert_allclose(L.xdot0, f.rhs(0, [th, thd, i], params=values), rtol=1e-13)


def floating_system() -> eg.System:
    """A free-flyer base (quaternion), a ball joint (quaternion) and a planar joint: every group."""
    s, parent = eg.System(gravity=(0, 0, -9.81)), None
    base_inertia = sp.Matrix([[0.3, 0.01, 0.02], [0.01, 0.4, 0.03], [0.02, 0.03, 0.5]])
    for name, joint, mass, com, inertia, at in [
        ("base", eg.FreeFlyer("root"), 2.0, (0.1, 0.2, 0.3), base_inertia, (0, 0, 0)),
        ("arm", eg.Spherical("ball"), 0.7, (0.2, 0, 0.1), sp.diag(0.1, 0.2, 0.15), (0.3, -0.1, 0.2)),
        ("tip", eg.Planar("pl"), 0.4, (0.1, 0.05, 0), sp.diag(0.01, 0.02, 0.03), (0.2, 0, 0)),
    ]:
        parent = s.add_body(name, parent=parent, joint=joint, mass=mass, com=com, inertia=inertia,
                            placement=eg.Placement(translation=at))
    return s


def derivative(function, h: float = 1e-3):
    """d/dt function(t) at 0, the fourth-order central difference."""
    return (8 * (function(h) - function(-h)) - (function(2 * h) - function(-2 * h))) / (12 * h)


def test_quaternion_and_planar_joints_against_finite_differences_along_integrate():
    """x = [δ, u] with q = q0 ⊕ δ: ẋ(δ, u) = [d/dt (q ⊖ q0) along q̇ = u (eg.integrate, eg.difference), the
    forward dynamics at q0 ⊕ δ]; A and B equal its finite differences to 1e-9 at random states (the
    tangent coordinates' −½ ad(u0) is in A: without it the kinematic rows differ by about |u0|); Kane's
    equations of the same system give the same."""
    system = floating_system()
    eom = eg.derive(system, method="recursive")
    f = eg.codegen(eom)
    nv, rng = system.nv, np.random.default_rng(1)
    q, u, _ = eg.random_states(system, 2, rng)
    for q0, u0 in zip(q, u):
        tau0 = rng.normal(size=system.S.shape[0])
        L = eg.linearize(eom, (q0, u0, tau0))

        def xdot(x, tau):
            at = eg.integrate(system, q0, x[:nv], 1.0)
            rate = derivative(lambda t: eg.difference(system, q0, eg.integrate(system, at, x[nv:], t)))
            return np.r_[rate, f.forward_dynamics(at, x[nv:], tau)]

        x0 = np.r_[np.zeros(nv), u0]
        A = np.column_stack([derivative(lambda t: xdot(x0 + t * e, tau0)) for e in np.eye(2 * nv)])
        B = np.column_stack([derivative(lambda t: xdot(x0, tau0 + t * e)) for e in np.eye(len(tau0))])
        np.testing.assert_allclose(L.A, A, atol=1e-9 * np.abs(A).max())
        np.testing.assert_allclose(L.B, B, atol=1e-9 * np.abs(B).max())
        assert np.abs(L.A[:nv, :nv]).max() > 0.1  # the drift of the tangent coordinates
    by_kane = eg.linearize(eg.kane(system), (q0, u0, tau0))  # w = u, the same tangent coordinates
    assert by_kane.states == L.states
    np.testing.assert_allclose(by_kane.A, L.A, atol=1e-11)
    np.testing.assert_allclose(by_kane.B, L.B, atol=1e-11)
    assert L.states[:3] == ("delta_root_vx", "delta_root_vy", "delta_root_vz") and "pl_theta" in L.states
    assert L.inputs[:3] == ("tau_ball_wx", "tau_ball_wy", "tau_ball_wz")


def test_bad_input():
    eom = cart_pole()
    zero = (np.zeros(2), np.zeros(2))
    with pytest.raises(
        eg.ModelError,
        match="linearize: inputs: unknown input 'tau_phi'; the inputs are the "
        r"actuated efforts \['tau_x'\] and the parameters \['g', 'l'",
    ):
        eg.linearize(eom, zero, inputs=["tau_phi"], params=CART_POLE)
    with pytest.raises(eg.ModelError, match="linearize: inputs: 'g' is named twice"):
        eg.linearize(eom, zero, inputs=["g", "g"], params=CART_POLE)
    with pytest.raises(
        eg.ModelError, match=r"op_point: q0 \(the coordinates\): expected 2 values, got shape"
    ):
        eg.linearize(eom, (np.zeros(3), np.zeros(2)), params=CART_POLE)
    with pytest.raises(
        eg.ModelError, match=r"op_point: the speeds \['xdot', 'phidot'\] .*: expected 2 values"
    ):
        eg.linearize(eom, (np.zeros(2), np.zeros(1)), params=CART_POLE)
    with pytest.raises(
        eg.ModelError, match=r"op_point: unknown names \['theta'\]; coordinates missing: \['phi'\]"
    ):
        eg.linearize(eom, {"x": 0, "theta": 0}, params=CART_POLE)
    with pytest.raises(eg.ModelError, match="op_point: q0 .*: values must be finite"):
        eg.linearize(eom, ([0, np.nan], [0, 0]), params=CART_POLE)
    with pytest.raises(eg.ModelError, match="op_point: expected .q0, speeds"):
        eg.linearize(eom, np.zeros(4), params=CART_POLE)
    with pytest.raises(
        eg.ModelError, match=r"params: values missing for the parameters \['g', 'l', 'm_c', 'm_p'\]"
    ):
        eg.linearize(eom, zero)
    with pytest.raises(eg.ModelError, match=r"params: expected a mapping \{name: value\}, got list"):
        eg.linearize(eom, zero, params=[1.0, 0.3, 0.7, 9.81])
    with pytest.raises(eg.ModelError, match="params: unknown parameter 'mass'"):
        eg.linearize(eom, zero, params={**CART_POLE, "mass": 1})
    with pytest.raises(eg.ModelError, match="independent: the system has no contacts, loops or rolling"):
        eg.linearize(eom, zero, params=CART_POLE, independent=["x"])
    with pytest.raises(
        eg.ModelError, match="linearize: expected EquationsOfMotion or KaneEquations, got System"
    ):
        eg.linearize(eom.system, zero)
    with pytest.raises(eg.ModelError, match=r"the equations have only \['g'\]: derive M, b and g"):
        eg.linearize(eg.derive(eom.system, quantities=("g",)), zero)
    motor = pendulum(motor=True)
    with pytest.raises(eg.ModelError, match="inputs: 'i_motor_th' is a motor current, a state"):
        eg.linearize(motor, ([0], [0]), inputs=["i_motor_th"])
    with pytest.raises(
        eg.ModelError, match=r"params: \['i_motor_th'\] are motor currents, part of the state"
    ):
        eg.linearize(motor, ([0], [0]), params={"i_motor_th": 1.0})
    big = eg.derive(floating_system(), method="recursive")
    with pytest.raises(eg.ModelError, match="24 states: symbolic=True is for at most 12"):
        eg.linearize(
            big,
            (eg.random_states(big.system, 1, np.random.default_rng(0))[0][0], np.zeros(12)),
            symbolic=True,
        )
    L = eg.linearize(eom, zero, params=CART_POLE)
    eom.system.add_body("extra", parent="pole", joint=eg.Revolute("extra"), mass=1, inertia=sp.eye(3))
    with pytest.raises(eg.ModelError, match="the system changed after these equations were derived"):
        eg.linearize(eom, zero, params=CART_POLE)
    with pytest.raises(eg.ModelError, match=r"Linearization: unknown states \['theta'\]"):
        L.select(["theta"])
    with pytest.raises(eg.ModelError, match=r"Linearization: unknown inputs \['F'\]"):
        L.select(["phi"], inputs=["F"])


@pytest.mark.parametrize("lname", ["L", "u", "q", "w"])
def test_parameter_named_like_a_seed_family(lname):
    """A parameter named q, u or w is its own direction: B of a damped pendulum (point mass m at l) by hand,
    θ̈ = −(g/l) sin θ + (τ − c θ̇)/(m l²)."""
    l, c = sp.Symbol(lname, positive=True), sp.Symbol("C", nonnegative=True)
    system = eg.System(gravity=(0, -9.81, 0))
    system.add_body("bob", joint=eg.Revolute("th", axis=(0, 0, 1)), mass=2.0, com=(0, -l, 0))
    system.add_torque("bob", (0, 0, -c * system.u[0]), name="friction")
    eom = eg.derive(system, method="recursive")
    m, g, th0, w0, tau0, lv, cv = 2.0, 9.81, 0.4, 1.3, 0.5, 0.8, 0.3
    for _ in range(2):  # the memo of the first call must not spoil the second
        L = eg.linearize(eom, ([th0], [w0], [tau0]), inputs=["tau_th", lname], params={lname: lv, "C": cv})
        A = np.array([[0, 1], [-(g / lv) * np.cos(th0), -cv / (m * lv**2)]])
        B = np.array([[0, 0], [1 / (m * lv**2),
                               (g / lv**2) * np.sin(th0) - 2 * (tau0 - cv * w0) / (m * lv**3)]])
        np.testing.assert_allclose(L.A, A, atol=1e-12)
        np.testing.assert_allclose(L.B, B, atol=1e-12)
