"""Flexible links in 3D: bending in the link's x-y plane (E I = E I_z) and x-z plane (E I_y), torsion (GJ,
ρI_x) and the cross-sections' rotary inertia. Checked against the textbook element matrices, the
clamped-free frequencies of Euler-Bernoulli beams and of a shaft (with the exact eigenvalues of the
linear-element shaft), the published flapwise frequencies of a spinning cantilever, a rigid arm built in
Pinocchio, and energy in free vibration."""
from __future__ import annotations

import numpy as np
import pinocchio as pin
import pytest
import scipy.linalg as sla
import sympy as sp
from scipy.integrate import solve_ivp

import eomgen as eg

BETA_L = np.array([1.8751040687, 4.6940911330, 7.8547574382])  # roots of cos βL cosh βL = −1
PUBLISHED = [3.5160, 3.6816, 4.1373, 4.7973, 5.5850]  # first flapwise frequency at γ = 0 … 4 (Wright 1982)


def clamped(elements: int, stiffening: bool = False, motion=0, **values) -> eg.System:
    """A 3D flexible link whose angle is prescribed (held at 0 by default)."""
    system = eg.System(gravity=(0, 0, 0))
    link = eg.FlexibleLink("beam", elements=elements, stiffening=stiffening, motion=motion,
                           **{"length": 1, "mass_per_length": 1, "EI": 1, **values})
    system.add_body("beam", joint=link, mass=0)
    return system


def test_one_element_equals_the_textbook_matrices():
    """At rest, the free node's mass matrix is the consistent one, m h/420 [[156, −22h], [−22h, 4h²]], plus
    the rotary inertia's ρI/(30 h) [[36, −3h], [−3h, 4h²]] in each bending plane, and ρI_x h/3 for the twist;
    the elastic forces are −K d with (E I/h³)[[12, −6h], [−6h, 4h²]] in each plane and GJ/h for the twist
    (Przemieniecki, Theory of Matrix Structural Analysis, ch. 10–11)."""
    m, L, EI, EI_y, GJ, Jx, Jy, Jz = sp.symbols("m L EI EI_y GJ J_x J_y J_z", positive=True)
    system = clamped(1, length=L, mass_per_length=m, EI=EI, EI_y=EI_y, GJ=GJ, rotary_inertia=(Jx, Jy, Jz))
    eom = eg.derive(system)
    at_rest = {x: 0 for x in system.q}
    consistent = m * L / 420 * sp.Matrix([[156, -22 * L], [-22 * L, 4 * L**2]])
    rotary = sp.Matrix([[36, -3 * L], [-3 * L, 4 * L**2]]) / (30 * L)
    expected = sp.diag(consistent + Jz * rotary, consistent + Jy * rotary, Jx * L / 3)
    assert sp.simplify(eom.M.xreplace(at_rest) - expected) == sp.zeros(5, 5)
    bending = sp.Matrix([[12, -6 * L], [-6 * L, 4 * L**2]]) / L**3
    K = sp.diag(EI * bending, EI_y * bending, GJ / L)
    assert sp.simplify(eom.tau_of("elastic") + K * sp.Matrix(system.q)) == sp.zeros(5, 1)


def _frequencies(f, rows, n, params) -> np.ndarray:
    M = f.M(np.zeros(n), params=params)[np.ix_(rows, rows)]
    K = np.column_stack([-f.tau_of("elastic", e, np.zeros(n), params=params)[rows] for e in np.eye(n)[rows]])
    return np.sqrt(np.sort(sla.eigh(K, M, eigvals_only=True)))


def test_bending_in_both_planes_and_torsion_equal_the_analytic_frequencies():
    """Clamped-free, m = L = 1, 4 elements: bending ω_k = (β_k L)² √(E I/m) with E I_z = 1 and E I_y = 4
    (the first within 1e-4, the third within 1e-2, as the planar link's); torsion ω_k = (2k − 1)(π/2)
    √(GJ/ρI_x), whose linear elements give exactly ω_j² = (6 GJ/(ρI_x h²))(1 − cos μ_j)/(2 + cos μ_j),
    μ_j = (2j − 1)π/(2n) (the discrete shaft's eigenvectors sin(k μ_j))."""
    GJ, Jx, n = 0.5, 0.02, 4
    system = clamped(n, EI_y=4.0, GJ=GJ, rotary_inertia=(Jx, 0, 0))
    f, nv = eg.codegen(eg.derive(system)), system.nv
    blocks = {"y": range(0, 2 * n), "z": range(2 * n, 4 * n), "x": range(4 * n, 5 * n)}
    w = {field: _frequencies(f, list(rows), nv, {}) for field, rows in blocks.items()}
    for field, EI in (("y", 1.0), ("z", 4.0)):
        error = np.abs(w[field][:3] / (BETA_L**2 * np.sqrt(EI)) - 1)
        assert error[0] < 1e-4 and error[2] < 1e-2, (field, error)
    mu = (2 * np.arange(1, n + 1) - 1) * np.pi / (2 * n)
    exact = np.sqrt(6 * GJ / (Jx / n**2) * (1 - np.cos(mu)) / (2 + np.cos(mu)))
    np.testing.assert_allclose(w["x"], exact, rtol=1e-10)
    continuum = (2 * np.arange(1, 3) - 1) * np.pi / 2 * np.sqrt(GJ / Jx)
    assert np.all(np.abs(w["x"][:2] / continuum - 1) < (np.pi / n) ** 2 / 8)  # O(h²)


def test_flapwise_frequencies_of_a_spinning_3d_link_equal_the_published_values():
    """The link spins about its joint's z axis at Ω (prescribed θ = Ω t) and bends out of the plane of
    rotation in its x-z plane: the first frequency of the z rows, linearized about the straight link (the
    foreshortening stiffens it), is 3.5160 … 5.5850 at γ = Ω = 0 … 4 (L = m = E I_y = 1)."""
    W = sp.Symbol("W")
    n = 5
    system = clamped(n, stiffening=True, motion=W * eg.t, EI_y=1, EI=2)
    f, nv = eg.codegen(eg.derive(system)), system.nv
    z = list(range(2 * n, 4 * n))
    for gamma, published in zip(range(5), PUBLISHED):
        first = _linearized(f, z, nv, {"W": float(gamma), "t": 0.0})[0]
        assert abs(first / published - 1) < 2e-4, (gamma, first)


def _arm(gravity=(0, 0, -9.81), stiffening=True) -> eg.System:
    """Two 3D flexible links (2 and 1 elements) and a rigid body, the second link's joint turned to the
    first's −y axis: a spatial arm."""
    arm = eg.System(gravity=gravity)
    l1 = arm.add_body("l1", joint=eg.FlexibleLink("q1", length=1.0, mass_per_length=2.0, EI=50.0, elements=2,
                                                   EI_y=70.0, GJ=30.0, rotary_inertia=(0.01, 0.005, 0.006),
                                                   stiffening=stiffening))
    l2 = arm.add_body("l2", parent=l1, placement=eg.Placement(rotation=[[1, 0, 0], [0, 0, -1], [0, 1, 0]]),
                      joint=eg.FlexibleLink("q2", length=0.8, mass_per_length=1.5, EI=40.0, elements=1,
                                            EI_y=30.0, GJ=20.0, rotary_inertia=(0.01, 0.004, 0.005),
                                            stiffening=stiffening))
    arm.add_body("tool", parent=l2, joint=eg.Revolute("q3", axis=(1, 0, 0)), mass=0.7, com=(0.1, 0.02, -0.03),
                 inertia=[[0.01, 0.001, 0.0], [0.001, 0.02, 0.002], [0.0, 0.002, 0.015]])
    return arm


def _pinocchio_arm():
    """The same arm rigid: uniform rods with the cross-sections' inertia, ρI_a L about their axes."""
    model = pin.Model()
    rods = [(2.0, 1.0, (0.01, 0.005, 0.006)), (1.5, 0.8, (0.01, 0.004, 0.005))]
    turned = np.array([[1, 0, 0], [0, 0, -1], [0, 1, 0]], float)
    placements = [pin.SE3.Identity(), pin.SE3(turned, np.array([1.0, 0, 0]))]
    parent = 0
    for (m, L, J), placement in zip(rods, placements):
        parent = model.addJoint(parent, pin.JointModelRZ(), placement, f"j{parent}")
        inertia = np.diag(J) * L + np.diag([0, 1, 1]) * m * L * L**2 / 12
        rod = pin.Inertia(m * L, np.array([L / 2, 0, 0]), inertia)
        model.appendBodyToJoint(parent, rod, pin.SE3.Identity())
    tool = model.addJoint(parent, pin.JointModelRX(), pin.SE3(np.eye(3), np.array([0.8, 0, 0])), "tool")
    model.appendBodyToJoint(tool, pin.Inertia(0.7, np.array([0.1, 0.02, -0.03]), np.array(
        [[0.01, 0.001, 0.0], [0.001, 0.02, 0.002], [0.0, 0.002, 0.015]])), pin.SE3.Identity())
    return model


@pytest.fixture(scope="module")
def arm():
    system = _arm()
    return system, eg.codegen(eg.derive(system))


def test_a_two_link_flexible_arm_at_zero_deflection_equals_the_rigid_arm(arm):
    """M, the nonlinear effects and g on the rigid coordinates, at zero deflection and nodal rates, equal
    Pinocchio's for the rigid arm at random angles and speeds."""
    arm, f = arm
    rigid = [list(arm.q).index(sp.Symbol(name)) for name in ("q1", "q2", "q3")]
    model = _pinocchio_arm()
    data = model.createData()
    rng = np.random.default_rng(7)
    for _ in range(5):
        angles, speeds = rng.uniform(-np.pi, np.pi, 3), rng.uniform(-2, 2, 3)
        q, u = np.zeros(arm.nv), np.zeros(arm.nv)
        q[rigid], u[rigid] = angles, speeds
        M = pin.crba(model, data, angles)
        M = np.triu(M) + np.triu(M, 1).T
        np.testing.assert_allclose(f.M(q)[np.ix_(rigid, rigid)], M, atol=1e-12)
        np.testing.assert_allclose(f.nle(q, u)[rigid], pin.nonLinearEffects(model, data, angles, speeds),
                                   atol=1e-11)
        g = pin.computeGeneralizedGravity(model, data, angles)
        np.testing.assert_allclose(f.g(q)[rigid], g, atol=1e-11)


def _rotation(axis: int, angle: float) -> np.ndarray:
    c, s, (j, k) = np.cos(angle), np.sin(angle), [(1, 2), (2, 0), (0, 1)][axis]
    R = np.eye(3)
    R[j, j], R[j, k], R[k, j], R[k, k] = c, -s, s, c
    return R


def test_children_sit_on_the_bent_twisted_tip(arm):
    """The tool's placement at a deflected state: each link's tip at (L + u_x(L), y_L, z_L) in its frame with
    u_x(L) = −½ ∫ (y'² + z'²) (by quadrature of the Hermite slopes), turned by R_z(y'_L) R_y(−z'_L)
    R_x(φ_L)."""
    arm, f = arm
    rng = np.random.default_rng(5)
    q = rng.uniform(-1, 1, arm.nv)
    q[1:11] *= 0.1
    q[12:17] *= 0.1
    R, p = np.eye(3), np.zeros(3)
    links = [(q[0], q[1:5], q[5:9], q[9:11], 1.0, 2, np.eye(3)),
             (q[11], q[12:14], q[14:16], q[16:17], 0.8, 1, np.array([[1, 0, 0], [0, 0, -1], [0, 1, 0]]))]
    for angle, y, z, phi, L, n, placement in links:
        R = R @ placement @ _rotation(2, angle)
        h, shortening = L / n, 0.0
        y, z = np.r_[0, 0, y], np.r_[0, 0, z]
        for e in range(n):
            t, w = _gauss(0, h)
            dN = _hermite(t, h)[1]
            shortening -= 0.5 * np.sum(w * ((y[2 * e:2 * e + 4] @ dN) ** 2 + (z[2 * e:2 * e + 4] @ dN) ** 2))
        p = p + R @ np.array([L + shortening, y[-2], z[-2]])
        R = R @ _rotation(2, y[-1]) @ _rotation(1, -z[-1]) @ _rotation(0, phi[-1])
    R = R @ _rotation(0, q[17])
    R_tool, p_tool = f.placement("tool", q)
    np.testing.assert_allclose(p_tool, p, atol=1e-13)
    np.testing.assert_allclose(R_tool, R, atol=1e-13)


def test_free_vibration_of_the_3d_arm_conserves_energy(arm):
    """Released bent and twisted under gravity, no damping: T + U stays constant to 1e-9 of itself (the
    integrator's tolerance 1e-10; measured 1e-10) while every field moves."""
    arm, f = arm
    n = arm.nv
    q0 = np.zeros(n)
    q0[1:11] = 0.02  # the first link's deflections, slopes and twists
    sol = solve_ivp(lambda _, x: np.r_[x[n:], f.forward_dynamics(x[:n], x[n:])], (0, 0.1),
                    np.r_[q0, np.zeros(n)], method="DOP853", rtol=1e-10, atol=1e-11,
                    t_eval=np.linspace(0, 0.1, 21))
    assert sol.success and np.ptp(sol.y[:n], axis=1).min() > 1e-4  # every coordinate moves
    energy = np.array([f.T(x[:n], x[n:]) + f.U(x[:n]) for x in sol.y.T])
    assert np.ptp(energy) < 1e-9 * np.abs(energy).max()


def test_modes_of_a_3d_link_keep_each_fields_first_frequencies():
    """modes=k keeps the first k modes of each bending plane and of the twist: the reduced link's
    frequencies are the full link's first k of each field."""
    values = {"EI_y": 3.0, "GJ": 0.5, "rotary_inertia": (0.02, 0, 0)}
    full, reduced = clamped(3, **values), clamped(3, modes=2, **values)
    f_full, f_reduced = (eg.codegen(eg.derive(s)) for s in (full, reduced))
    blocks = {"y": range(0, 6), "z": range(6, 12), "x": range(12, 15)}
    for i, (field, rows) in enumerate(blocks.items()):
        w_full = _frequencies(f_full, list(rows), full.nv, {})
        w_reduced = _frequencies(f_reduced, [2 * i, 2 * i + 1], reduced.nv, {})
        np.testing.assert_allclose(w_reduced, w_full[:2], rtol=1e-10)


def test_3d_link_values_are_refused_by_name():
    link = {"length": 1, "mass_per_length": 1, "EI": 1}
    with pytest.raises(eg.ModelError, match="joint 'b': EI_y must be positive"):
        eg.FlexibleLink("b", **link, EI_y=-1)
    with pytest.raises(eg.ModelError, match="joint 'b': torsion .GJ. needs rotary_inertia"):
        eg.FlexibleLink("b", **link, GJ=1)
    with pytest.raises(eg.ModelError, match="joint 'b': torsion .GJ. needs rotary_inertia"):
        eg.FlexibleLink("b", **link, GJ=1, rotary_inertia=(0, 1, 1))
    with pytest.raises(eg.ModelError, match="joint 'b': rotary_inertia must be three values"):
        eg.FlexibleLink("b", **link, rotary_inertia=(1, 1))
    with pytest.raises(eg.ModelError, match="joint 'b': rotary_inertia must not be negative"):
        eg.FlexibleLink("b", **link, rotary_inertia=(1, -1, 1))
    with pytest.raises(eg.ModelError, match="joint 'b': modes must be an integer from 1 to 2 .the nodal "
                                            "coordinates of the twist"):
        eg.FlexibleLink("b", **link, elements=2, GJ=1, rotary_inertia=(1, 0, 0), modes=3)
    with pytest.raises(eg.ModelError, match="joint 'b': modes needs a numeric GJ"):
        eg.FlexibleLink("b", **link, GJ=sp.Symbol("GJ"), rotary_inertia=(1, 0, 0), modes=1)


def _hermite(xi, h):
    """Hermite cubics and their first two derivatives at ξ on an element of length h."""
    s = xi / h
    N = np.array([1 - 3 * s**2 + 2 * s**3, h * (s - 2 * s**2 + s**3), 3 * s**2 - 2 * s**3,
                  h * (-s**2 + s**3)])
    dN = np.array([(-6 * s + 6 * s**2) / h, 1 - 4 * s + 3 * s**2, (6 * s - 6 * s**2) / h, -2 * s + 3 * s**2])
    ddN = np.array([(-6 + 12 * s) / h**2, (-4 + 6 * s) / h, (6 - 12 * s) / h**2, (-2 + 6 * s) / h])
    return N, dN, ddN


def _gauss(a, b):
    """12-point Gauss-Legendre points and weights on [a, b]."""
    t, w = np.polynomial.legendre.leggauss(12)
    return a + (t + 1) * (b - a) / 2, w * (b - a) / 2


def test_energies_equal_a_quadrature_of_the_bent_twisted_link():
    """T and U of a 3D link on a moving parent, at random deflected states, against Gauss quadrature of
    m |ṙ|²/2 with r = p + R((x + u_x) e_x + y e_y + z e_z), u_x = −½ ∫ (y'² + z'²) (itself by quadrature),
    ṙ by central differences in time, the sections' ρI_a ω_s,a²/2 with their exact angular velocity, gravity
    and the strain energy ½ ∫ (E I_z y''² + E I_y z''² + GJ φ'²): U exact, T to third order in the
    deformation (ω_s is kept to second order: halving a small deformation divides the gap by about 8)."""
    n, L, m, EI, EI_y, GJ, J = 2, 1.2, 1.5, 3.0, 4.0, 2.0, np.array([0.03, 0.01, 0.02])
    system = eg.System(gravity=(0, 0, -9.81))
    base = system.add_body("base", joint=eg.Revolute("q0", axis=(1, 0, 0)), mass=0.5, com=(0.1, 0, 0),
                           inertia=np.diag([0.01, 0.02, 0.03]).tolist())  # on the axis: T = ½ 0.01 q̇0²
    system.add_body("beam", parent=base, placement=eg.Placement(translation=(0.3, 0.0, 0.1)), mass=0,
                    joint=eg.FlexibleLink("theta", length=L, mass_per_length=m, EI=EI, elements=n, EI_y=EI_y,
                                          GJ=GJ, rotary_inertia=tuple(J)))
    f = eg.codegen(eg.derive(system))
    h = L / n
    xi, weights = _gauss(0, h)

    def frame(q):
        c0, s0, c, s = np.cos(q[0]), np.sin(q[0]), np.cos(q[1]), np.sin(q[1])
        R0 = np.array([[1, 0, 0], [0, c0, -s0], [0, s0, c0]])
        return R0 @ np.array([[c, -s, 0], [s, c, 0], [0, 0, 1]]), R0 @ [0.3, 0.0, 0.1]

    def link(q):
        """Per element, at the Gauss points: the world positions, (y', z', φ), and the strain energy."""
        d = {"y": np.r_[0, 0, q[2:2 + 2 * n]], "z": np.r_[0, 0, q[2 + 2 * n:2 + 4 * n]],
             "x": np.r_[0, q[2 + 4 * n:]]}
        R, p = frame(q)
        positions, turns, strain, start = [], [], 0.0, 0.0
        for e in range(n):
            N, dN, ddN = _hermite(xi, h)
            y, z = (d[a][2 * e:2 * e + 4] for a in "yz")

            def shortening(b):
                t, w = _gauss(0, b)
                return -0.5 * np.sum(w * ((y @ _hermite(t, h)[1]) ** 2 + (z @ _hermite(t, h)[1]) ** 2))
            along = e * h + xi + start + np.array([shortening(b) for b in xi])
            positions.append(p[:, None] + R @ np.array([along, y @ N, z @ N]))
            turns.append(np.array([d["x"][e] + (d["x"][e + 1] - d["x"][e]) * xi / h, y @ dN, z @ dN]))
            strain += np.sum(weights * (EI * (y @ ddN) ** 2 + EI_y * (z @ ddN) ** 2)) / 2
            strain += GJ * (d["x"][e + 1] - d["x"][e]) ** 2 / h / 2
            start += shortening(h)
        return positions, turns, strain

    def energies(q, u, eps=1e-6):
        """(T of the centre line and the base, T of the sections' turning with the exact ω_s, U)."""
        (r_plus, turn_plus, _), (r_minus, turn_minus, _) = link(q + eps * u), link(q - eps * u)
        W = frame(q)[0].T @ (frame(q + eps * u)[0] - frame(q - eps * u)[0]) / (2 * eps)
        Omega = np.array([W[2, 1], W[0, 2], W[1, 0]])
        T, T_turn = 0.5 * 0.01 * u[0] ** 2, 0.0
        for e, (phi, y_slope, z_slope) in enumerate(link(q)[1]):
            v = (r_plus[e] - r_minus[e]) / (2 * eps)
            phi_dot, y_slope_dot, z_slope_dot = (turn_plus[e] - turn_minus[e]) / (2 * eps)
            T += np.sum(weights * m * np.sum(v**2, axis=0)) / 2
            for k in range(len(xi)):  # D = R_z(y') R_y(−z') R_x(φ); ω_s = Dᵀ Ω + ω_D in section axes
                Rx, Ry = _rotation(0, phi[k]), _rotation(1, -z_slope[k])
                D = _rotation(2, y_slope[k]) @ Ry @ Rx
                omega = D.T @ Omega + Rx.T @ Ry.T @ [0, 0, y_slope_dot[k]] + Rx.T @ [0, -z_slope_dot[k], 0] \
                    + [phi_dot[k], 0, 0]
                T_turn += weights[k] * J @ omega**2 / 2
        positions, _, strain = link(q)
        return T, T_turn, sum(np.sum(weights * m * 9.81 * r[2]) for r in positions) + strain

    rng = np.random.default_rng(3)
    for _ in range(3):
        q, u = rng.uniform(-1, 1, system.nv), rng.uniform(-2, 2, system.nv)
        gaps = []
        for scale in (0.05, 0.025):  # deflections, slopes, twists and their rates
            q_s, u_s = np.r_[q[:2], scale * q[2:]], np.r_[u[:2], scale * u[2:]]
            T, T_turn, U = energies(q_s, u_s)
            gaps.append(abs(f.T(q_s, u_s) - T - T_turn))
            assert abs(f.U(q_s) - U) < 1e-10 * max(1.0, abs(U)), (f.U(q_s), U)
        assert gaps[0] < 1e-2 * T_turn and 5.5 < gaps[0] / gaps[1] < 11, gaps  # third order


def _stiffness(f, rows, nv, params):
    h = 1e-6

    def force(x):
        q = np.zeros(nv)
        q[rows] = x
        rest = np.zeros(nv)
        return (f.nle(q, rest, params=params) - f.tau_of("elastic", q, rest, params=params))[rows]
    return np.column_stack([(force(h * e) - force(-h * e)) / (2 * h) for e in np.eye(len(rows))])


def _linearized(f, rows, nv, params):
    """Frequencies of the rows about the straight link: K from (nle − τ_elastic), M at rest."""
    K = _stiffness(f, rows, nv, params)
    M = f.M(np.zeros(nv), params=params)[np.ix_(rows, rows)]
    return np.sqrt(np.sort(sla.eigh((K + K.T) / 2, M, eigvals_only=True)))


def test_twist_of_a_spinning_link_feels_the_propeller_moment():
    """A link spinning at Ω about its joint's z axis, twisted by φ: its sections turn at
    (φ̇, Ω sin φ, Ω cos φ) in their own axes, T_rot = ½ ∫ (ρI_x φ̇² + ρI_y Ω² sin²φ + ρI_z Ω² cos²φ), so
    ρI_x φ̈ − GJ φ'' + (ρI_z − ρI_y) Ω² φ = 0 (the propeller moment of a spinning blade). On the linear
    elements (mass and this stiffness share ∫ L_k L_l) every twist frequency shifts exactly:
    ω² = ω₀² + Ω² (ρI_z − ρI_y)/ρI_x. A thin blade (ρI_y ≈ 0, ρI_z ≈ ρI_x): ω² = ω₀² + Ω²."""
    W, n = sp.Symbol("W"), 3
    Jx, Jy, Jz = 0.02, 0.001, 0.019
    system = clamped(n, stiffening=True, motion=W * eg.t, GJ=0.5, rotary_inertia=(Jx, Jy, Jz))
    f, nv = eg.codegen(eg.derive(system)), system.nv
    twist = list(range(2 * n, 3 * n))
    w0 = _linearized(f, twist, nv, {"W": 0.0, "t": 0.0})
    Omega = 4.0
    w = _linearized(f, twist, nv, {"W": Omega, "t": 0.0})
    np.testing.assert_allclose(w**2 - w0**2, Omega**2 * (Jz - Jy) / Jx, rtol=1e-4)


def test_flapwise_bending_of_a_spinning_link_feels_the_sections_inertia():
    """Spinning at Ω about the joint's z axis, a section tilted by the flapwise slope z' (R_y(−z')) turns at
    (Ω sin z', −ż', Ω cos z') in its own axes: T_rot holds ½ (ρI_x − ρI_z) Ω² z'², a stiffness
    −(ρI_x − ρI_z) Ω² ∫ z'² (the rotary-inertia softening of a rotating Rayleigh beam). So raising ρI_x
    by a changes the linearized flapwise stiffness by exactly −a Ω² G, G = Σ_e ∫ N' N'ᵀ (Hermite,
    assembled here by Gauss quadrature)."""
    W, n, a, Omega = sp.Symbol("W"), 2, 0.01, 3.0
    K = []
    for Jx in (0.0, a):
        system = clamped(n, stiffening=True, motion=W * eg.t, EI_y=1, rotary_inertia=(Jx, 0, 0))
        f = eg.codegen(eg.derive(system))
        K.append(_stiffness(f, list(range(2 * n, 4 * n)), system.nv, {"W": Omega, "t": 0.0}))
    h = 1 / n
    x, w = np.polynomial.legendre.leggauss(4)
    x, w = (x + 1) * h / 2, w * h / 2
    s = x / h
    dN = np.array([(-6 * s + 6 * s**2) / h, 1 - 4 * s + 3 * s**2, (6 * s - 6 * s**2) / h, -2 * s + 3 * s**2])
    G = np.zeros((2 * n + 2, 2 * n + 2))
    for e in range(n):
        G[2 * e:2 * e + 4, 2 * e:2 * e + 4] += (dN * w) @ dN.T
    np.testing.assert_allclose(K[1] - K[0], -a * Omega**2 * G[2:, 2:], atol=1e-6)


def _rest_frequencies(system):
    f, nv = eg.codegen(eg.derive(system)), system.nv
    return _frequencies(f, list(range(nv)), nv, {})


def test_modes_of_a_link_with_rotary_inertia_keep_the_full_models_first_frequencies():
    """With rotary inertia (a Rayleigh beam) the nodal mass is m ∫NNᵀ + ρI_z ∫N'N'ᵀ: the modes are those of
    that mass, so a stubby link (ρI_z = 0.01 m L²) reduced to 2 modes keeps its first 2 frequencies."""
    values = dict(elements=4, rotary_inertia=(0, 0, 0.01))
    full = _rest_frequencies(clamped(**values))
    reduced = _rest_frequencies(clamped(modes=2, **values))
    np.testing.assert_allclose(reduced, full[:2], rtol=1e-9)
