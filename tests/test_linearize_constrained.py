"""eg.linearize with constraints, in the independent coordinates and speeds: the four-bar as Kane's equations
with holonomic constraints and as equations of motion with a loop, against each other, a hand closed form
(the pose by circle intersection, J(θ) and V(θ) differentiated by sympy) and finite differences of the
generated right-hand sides (a parameter of the loop included); an arm held at its tip by a contact against
differences of eg.reduce; the rolling disk (Kane's, nonholonomic, and
as equations of motion with add_rolling) about upright rolling against its hand linearization, symbolic in
the spin rate, the eigenvalues' real parts crossing zero at ω² = g/(3R); the Whipple bicycle's published
eigenvalues, weave and capsize speeds (tests/test_bicycle.py) without finite differences."""

import sys
from pathlib import Path

import mpmath
import numpy as np
import pytest
import sympy as sp

import eomgen as eg
import kane_systems as K

sys.path.insert(0, str(Path(__file__).parents[1] / "examples"))
import rolling_disk as disk  # noqa: E402
import whipple_bicycle as bike  # noqa: E402
from test_bicycle import CAPSIZE, SPEEDS, WEAVE, published_eigenvalues  # noqa: E402

d = sp.Symbol("d", positive=True)


def four_bar_by_hand(theta0: float, rate: float) -> tuple[np.ndarray, np.ndarray]:
    """A, B (input: a torque on the crank) of J(θ) θ̈ + ½ J'(θ) θ̇² + V'(θ) = τ + τ_load, the crank angle θ:
    the pose by circle intersection (K.four_bar_pose) in sympy, J = Σ m |∂G/∂θ|² + I (∂a/∂θ)², V = Σ m g y_G
    (their derivatives in θ by mpmath);
    θ̈ = (τ + τ_load − ½ J' θ̇² − V')/J, ∂θ̈/∂θ̇ = −J' θ̇/J, ∂θ̈/∂θ = (−½ J'' θ̇² − V'' − J' θ̈)/J, B = 1/J.
    """
    t = sp.Symbol("theta")
    b = {k: sp.Float(v) for k, v in K.BAR.items()}
    P1, P3 = b["l1"] * sp.Matrix([sp.cos(t), sp.sin(t)]), sp.Matrix([b["d"], 0])
    e = P3 - P1
    L = sp.sqrt(e.dot(e))
    a = (L**2 + b["l2"] ** 2 - b["l3"] ** 2) / (2 * L)
    P2 = P1 + a * e / L + sp.sqrt(b["l2"] ** 2 - a**2) * sp.Matrix([-e[1], e[0]]) / L
    angles = [t, sp.atan2(*(P2 - P1)[::-1]), sp.atan2(*(P3 - P2)[::-1])]
    starts = [sp.zeros(2, 1), P1, P2]
    J = V = 0
    for i, (angle, start) in enumerate(zip(angles, starts), 1):
        G = start + b[f"l{i}"] / 2 * sp.Matrix([sp.cos(angle), sp.sin(angle)])
        dG = G.diff(t)
        J += b[f"m{i}"] * dG.dot(dG) + b[f"I{i}"] * angle.diff(t) ** 2
        V += b[f"m{i}"] * b["g"] * G[1]
    mpmath.mp.dps = 30  # J', J'', V', V'' by mpmath's differentiation at 30 digits
    J, V = (sp.lambdify(t, x, "mpmath") for x in (J, V))
    J0, J1, J2 = (float(mpmath.diff(J, mpmath.mpf(theta0), k)) for k in range(3))
    V1, V2 = (float(mpmath.diff(V, mpmath.mpf(theta0), k)) for k in (1, 2))
    acceleration = (b["tau"] - J1 * rate**2 / 2 - V1) / J0
    A = np.array(
        [[0, 1], [(-J2 * rate**2 / 2 - V2 - J1 * acceleration) / J0, -J1 * rate / J0]], dtype=float
    )
    return A, np.array([[0], [1 / J0]])


def four_bar_loop() -> eg.EquationsOfMotion:
    """K.four_bar built as a tree with a revolute loop from the rocker's tip to a world frame at (d, 0)."""
    system, _ = K.four_bar()
    system.add_frame("tip", "link3", eg.Placement(translation=(K.BAR["l3"], 0, 0)))
    system.add_frame("pin", None, eg.Placement(translation=(d, 0, 0)))
    system.add_loop("tip", "pin", kind="revolute")
    return eg.derive(system, method="recursive")


def derivative(function, x0, h=1e-4) -> np.ndarray:
    """∂function/∂x at x0, fourth-order central differences."""

    def along(e):
        return (
            8 * (function(x0 + h * e) - function(x0 - h * e))
            - (function(x0 + 2 * h * e) - function(x0 - 2 * h * e))
        ) / (12 * h)

    return np.column_stack([along(e) for e in np.eye(len(x0))])


@pytest.mark.parametrize("theta0, rate", [(0.7, 1.3), (-2.0, -0.4)])
def test_four_bar_kane_and_loop_equal_hand_and_differences(theta0, rate):
    """x = [q1, q̇1] (q2, q3 dependent): Kane's equations with holonomic constraints and the equations of
    motion with a loop give the same A, B (Kane's also in the links' absolute rates), equal to the hand
    closed form to 1e-9 and to differences of Kane's generated rhs (q2, q3 assembled; with the crank's
    effort) to 1e-8; ∂ẋ/∂d (the pin's distance, a parameter of the loop) equals differences of the reduced
    forward dynamics with q assembled for d ± h."""
    system, args = K.four_bar()
    kane = eg.kane(system, **args)
    q0 = np.array(K.four_bar_pose(theta0))
    by_kane = eg.linearize(kane, (q0, [rate]), inputs=["tau_q1"])
    loop = four_bar_loop()
    by_loop = eg.linearize(
        loop, (q0, [rate]), inputs=["tau_q1", "d"], independent=["q1"], params={"d": K.BAR["d"]}
    )
    assert by_kane.states == by_loop.states == ("q1", "q1dot")
    A, B = four_bar_by_hand(theta0, rate)
    np.testing.assert_allclose(by_kane.A, A, rtol=1e-9, atol=1e-9)
    np.testing.assert_allclose(by_kane.B, B, rtol=1e-9)
    other, in_w = K.four_bar("absolute")  # w = the links' absolute rates, by kinematic equations; w1 = q̇1
    by_absolute = eg.linearize(eg.kane(other, **in_w), (q0, [rate]), inputs=["tau_q1"])
    assert by_absolute.states == ("q1", "w1")
    np.testing.assert_allclose(by_absolute.A, by_kane.A, rtol=1e-11, atol=1e-11)
    np.testing.assert_allclose(by_loop.A, by_kane.A, rtol=1e-11, atol=1e-11)
    np.testing.assert_allclose(by_loop.B[:, :1], by_kane.B, rtol=1e-11)
    f = eg.codegen(kane)

    def rhs(x, tau=(0.0, 0.0, 0.0)):
        q = f.assemble(np.r_[x[0], K.four_bar_pose(x[0])[1:]] + [0, 1e-3, -1e-3])
        return f.rhs(0, np.r_[q, x[1]], tau)[[0, 3]]

    x0 = np.array([theta0, rate])
    np.testing.assert_allclose(by_kane.A, derivative(rhs, x0), rtol=1e-8, atol=1e-8)
    np.testing.assert_allclose(
        by_kane.B, derivative(lambda t: rhs(x0, [t[0], 0, 0]), np.zeros(1)), rtol=1e-8
    )
    g = eg.codegen(loop)
    reduced = eg.reduce(g, ["q1"])

    def along_d(x):
        params = {"d": x[0]}
        q = eg.assemble(g, q0, fixed=["q1"], params=params)
        return np.r_[rate, reduced.forward_dynamics(q, [rate], params=params)[0]]

    np.testing.assert_allclose(by_loop.B[:, 1:], derivative(along_d, np.array([K.BAR["d"]])), rtol=1e-7)


def test_contact_rows_against_differences_of_reduce():
    """A planar three-link arm whose tip is held by a point contact (rows x, y; velocity constraints, no
    closure: every coordinate stays a state), th1 independent, at a state with speed and efforts: A, B equal
    differences of ẋ = [R(q) u_i, u̇_i] (eg.reduce's R and forward dynamics) to 1e-8."""
    system = eg.System(gravity=(0, -9.81, 0))
    parent, at = None, 0.0
    for i, (length, mass) in enumerate([(0.5, 1.0), (0.4, 0.8), (0.3, 0.5)], 1):
        parent = system.add_body(
            f"link{i}",
            parent=parent,
            joint=eg.Revolute(f"th{i}"),
            mass=mass,
            com=(length / 2, 0, 0),
            inertia=sp.diag(0, 1, 1) * mass * length**2 / 12,
            placement=eg.Placement(translation=(at, 0, 0)),
        )
        at = length
    system.add_frame("tip", parent, eg.Placement(translation=(at, 0, 0)))
    system.add_contact("tip")
    eom = eg.derive(system, method="recursive")
    q0, tau0 = np.array([0.3, 0.9, -1.1]), np.array([0.4, -0.2, 0.1])
    L = eg.linearize(eom, (q0, [0.7], tau0), independent=["th1"])
    assert L.states == ("th1", "th2", "th3", "th1dot") and L.inputs == ("tau_th1", "tau_th2", "tau_th3")
    reduced = eg.reduce(eg.codegen(eom), ["th1"])

    def xdot(x, tau=tau0):
        q, u = x[:3], x[3:]
        return np.r_[reduced.R(q) @ u, reduced.forward_dynamics(q, u, tau)[0]]

    x0 = np.r_[q0, 0.7]
    np.testing.assert_allclose(L.A, derivative(xdot, x0), rtol=1e-8, atol=1e-8)
    np.testing.assert_allclose(L.B, derivative(lambda t: xdot(x0, t), tau0), rtol=1e-8, atol=1e-8)
    np.testing.assert_allclose(L.xdot0, xdot(x0), rtol=1e-13)


def disk_by_hand(w, g, R) -> sp.Matrix:
    """Upright rolling along x at spin rate w (axle y; I = m R²/4, J = m R²/2), x = (x, y, yaw ψ, lean φ,
    spin, their independent rates ψ̇, φ̇, θ̇): the contact point moves at R θ̇ along the heading and the
    centre is R above it in the lean frame, so ẋ = R θ̇, ẏ = R w ψ − R φ̇; I ψ̈ = −J w φ̇ (ψ̈ = −2 w φ̇);
    (I + m R²) φ̈ = m g R φ + (J + m R²) w ψ̇ (φ̈ = 4 g φ/(5 R) + 6 w ψ̇/5); θ̈ = 0."""
    A = sp.zeros(8, 8)
    A[0, 7], A[1, 2], A[1, 6] = R, R * w, -R
    A[2, 5] = A[3, 6] = A[4, 7] = 1
    A[5, 6], A[6, 3], A[6, 5] = -2 * w, 4 * g / (5 * R), 6 * w / 5
    return A


def test_rolling_disk_in_new_speeds_against_differences():
    """The disk in the speeds of tests/test_rolling_disk.py (ẋ, ẏ, ż, ψ̇, φ̇ and ω along the axle,
    θ̇ + ψ̇ sin φ: kinematic equations, u = −Y⁻¹ (K w + k0) depends on q) at a leaning, turning state: A
    equals differences of the generated rhs (z assembled) to 1e-8, ẋ0 the rhs."""
    system, _ = disk.rolling_disk()
    w = sp.symbols("w1:7")
    u, lean = system.u, system.q[4]
    kinematic = [w[i] - u[i] for i in range(5)] + [w[5] - u[5] - u[3] * sp.sin(lean)]
    k = eg.kane(
        system,
        speeds=w,
        kinematic_equations=kinematic,
        dependent_coordinates=[system.q[2]],
        independent=w[3:],
    )
    f, v = eg.codegen(k), disk.VALUES
    x0 = np.array([0.1, -0.2, 0.4, 0.3, 0.5, 0.7, -0.4, 5.0])  # x, y, yaw, lean, spin, w4, w5, w6

    def xdot(x):
        q = f.assemble(np.r_[x[:2], v["R"], x[2:5]], v)
        return f.rhs(0, np.r_[q, x[5:]], params=v)[[0, 1, 3, 4, 5, 6, 7, 8]]

    L = eg.linearize(k, (f.assemble(np.r_[x0[:2], v["R"], x0[2:5]], v), x0[5:]), inputs=[], params=v)
    assert L.states == ("x", "y", "yaw", "lean", "spin", "w4", "w5", "w6") and L.B.shape == (8, 0)
    np.testing.assert_allclose(L.A, derivative(xdot, x0), rtol=1e-8, atol=1e-8)
    np.testing.assert_allclose(L.xdot0, xdot(x0), rtol=1e-13)


def test_rolling_disk_symbolic_equals_hand():
    """Kane's equations of the disk (examples/rolling_disk.py) linearized in closed form, the spin rate a
    symbol: A equals the hand linearization; x = (x, y, yaw, lean, spin, yawdot, leandot, spindot); the same
    from the equations of motion with add_rolling (z the coordinate the height fixes, chosen by pivoting).
    """
    system, k = disk.rolling_disk()
    w, R, g = sp.Symbol("omega", real=True), sp.Symbol("R", positive=True), sp.Symbol("g", positive=True)
    L = eg.linearize(k, {**dict.fromkeys(map(str, system.q), 0), "z": R, "spindot": w}, symbolic=True)
    assert L.states == ("x", "y", "yaw", "lean", "spin", "yawdot", "leandot", "spindot")
    assert L.A == disk_by_hand(w, g, R) and L.B.shape == (8, 6)
    assert L.xdot0 == sp.Matrix([R * w, 0, 0, 0, w, 0, 0, 0])
    eom = eg.derive(system, method="recursive")
    by_eom = eg.linearize(
        eom,
        {**dict.fromkeys(map(str, system.q), 0), "z": R, "spindot": w},
        independent=["yaw", "lean", "spin"],
        symbolic=True,
    )
    assert by_eom.A == L.A and by_eom.states == L.states


@pytest.mark.parametrize("factor", [0.5, 0.9, 1.0, 1.1, 2.0])
def test_rolling_disk_eigenvalues_cross_zero_at_the_critical_spin(factor):
    """Numerically at factor × ω_c, ω_c² = g/(3R): A equals the hand linearization to 1e-13; its eigenvalues
    are 0 (six) and ±√(4/5 (g/R − 3ω²)): real, one positive, below ω_c; on the imaginary axis above; the
    same from the equations of motion with add_rolling in the same independent speeds (z dependent)."""
    system, k = disk.rolling_disk()
    v = disk.VALUES
    w = factor * disk.critical_spin()
    op = (np.array([0, 0, v["R"], 0, 0, 0]), [0, 0, w])
    L = eg.linearize(k, op, params=v)
    np.testing.assert_allclose(L.A, np.array(disk_by_hand(w, v["g"], v["R"]), dtype=float), atol=1e-13)
    pair = np.sqrt(complex(4 / 5 * (v["g"] / v["R"] - 3 * w**2)))
    lean = L.select(["yawdot", "lean", "leandot"]).eigenvalues()
    expected = [-pair, 0, pair]
    tol = 1e-4 if factor == 1 else 1e-12  # at ω_c a triple root 0: float64 round-off ε^(1/3)
    assert np.abs(lean[:, None] - expected).min(axis=0).max() < tol
    if factor < 1:
        assert L.eigenvalues().real.max() > 0.9 * pair.real
    elif factor > 1:
        assert np.abs(L.eigenvalues().real).max() < 1e-12
    eom = eg.derive(system, method="recursive")
    by_eom = eg.linearize(eom, op, independent=["yaw", "lean", "spin"], params=v)
    assert by_eom.states == L.states
    np.testing.assert_allclose(by_eom.A, L.A, atol=1e-12)
    np.testing.assert_allclose(by_eom.B[5:], L.B[5:], atol=1e-12)


def test_bicycle_published_eigenvalues_and_speeds():
    """The Whipple bicycle (Kane's, two rolling disks) upright at speed v: the roll-steer block [rear_roll,
    steer, their rates] of A has the published eigenvalues at v = 0 … 10 m/s to 1e-11, the weave and
    capsize speeds to 1e-12; the other states (x, y, yaw, the spins, the rear spin rate) do not drive it."""
    _, k = bike.bicycle()
    q = eg.codegen(k).assemble(np.zeros(9), bike.BENCHMARK)
    block = ["rear_roll", "steer", "reardot_roll", "steerdot"]

    def linearized(v):
        return eg.linearize(k, (q, [0, 0, -v / bike.BENCHMARK["r_R"]]), params=bike.BENCHMARK)

    for v in SPEEDS:
        L = linearized(float(v))
        assert np.abs(L.select(block).eigenvalues() - published_eigenvalues(v)).max() < 1e-11, v
        others = [i for i, s in enumerate(L.states) if s not in block]
        assert np.abs(L.A[np.ix_(L.index(block), others)]).max() < 1e-12
    weave, capsize = bike.stable_speeds(lambda v: linearized(v).select(block).eigenvalues())
    assert abs(weave - WEAVE) < 1e-12 and abs(capsize - CAPSIZE) < 1e-12


def test_bad_constrained_input():
    loop = four_bar_loop()
    q0 = np.array(K.four_bar_pose(0.7))
    with pytest.raises(
        eg.ModelError, match=r"independent: name the independent speeds .* constraints \['tip-pin.x'"
    ):
        eg.linearize(loop, (q0, [0]), params={"d": 0.45})
    with pytest.raises(
        eg.ModelError, match=r"q0 does not satisfy the holonomic constraints .* residuals are"
    ):
        eg.linearize(loop, (q0 + 0.01, [0]), independent=["q1"], params={"d": 0.45})
    with pytest.raises(eg.ModelError, match="the speeds differ from those the constraints allow"):
        eg.linearize(loop, (q0, [1, 1, 1]), independent=["q1"], params={"d": 0.45})
    system, args = K.four_bar()
    kane = eg.kane(system, **args)
    with pytest.raises(eg.ModelError, match="independent: Kane's equations fix their independent speeds"):
        eg.linearize(kane, (q0, [0]), independent=["q1"])
    with pytest.raises(
        eg.ModelError,
        match=r"inputs: unknown input 'U'; the inputs are the actuated efforts "
        r"\['tau_q1', 'tau_q2', 'tau_q3'\] and the parameters \[\]",
    ):
        eg.linearize(kane, (q0, [0]), inputs=["U"])
    with pytest.raises(eg.ModelError, match=r"q0 does not satisfy the holonomic constraints"):
        eg.linearize(kane, (q0 + 0.01, [0]))
    free = eg.System()
    body = free.add_body("disk", joint=eg.FreeFlyer("base"), mass=1, inertia=sp.diag(0.5, 0.25, 0.25))
    free.add_rolling(body, radius=0.3, axis=(1, 0, 0))
    k = eg.kane(free, dependent_coordinates=[free.q[2]], independent=list(free.u[3:]))
    with pytest.raises(eg.ModelError, match=r"dependent coordinates \['base_z'\] are no joint speed's"):
        eg.linearize(k, (np.r_[0, 0, 0.3, 0, 0, 0, 1], [0, 0, 0]))
