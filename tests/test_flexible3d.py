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


@pytest.mark.parametrize("elements", [4, 8])
def test_bending_in_both_planes_and_torsion_equal_the_analytic_frequencies(elements):
    """Clamped-free, m = L = 1: bending ω_k = (β_k L)² √(E I/m) with E I_z = 1 and E I_y = 4 (h⁴
    convergence of Hermite elements); torsion ω_k = (2k − 1)(π/2) √(GJ/ρI_x), whose linear elements give
    exactly ω_j² = (6 GJ/(ρI_x h²))(1 − cos μ_j)/(2 + cos μ_j), μ_j = (2j − 1)π/(2n) (the discrete shaft's
    eigenvectors sin(k μ_j))."""
    GJ, Jx, n = 0.5, 0.02, elements
    system = clamped(n, EI_y=4.0, GJ=GJ, rotary_inertia=(Jx, 0, 0))
    f, nv = eg.codegen(eg.derive(system)), system.nv
    blocks = {"y": range(0, 2 * n), "z": range(2 * n, 4 * n), "x": range(4 * n, 5 * n)}
    w = {field: _frequencies(f, list(rows), nv, {}) for field, rows in blocks.items()}
    tolerance = {4: (1e-4, 1e-2), 8: (1e-5, 1e-3)}[n]
    for field, EI in (("y", 1.0), ("z", 4.0)):
        error = np.abs(w[field][:3] / (BETA_L**2 * np.sqrt(EI)) - 1)
        assert error[0] < tolerance[0] and error[2] < tolerance[1], (field, error)
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
        params, h, k = {"W": float(gamma), "t": 0.0}, 1e-6, len(z)

        def force(x):
            q = np.zeros(nv)
            q[z] = x
            rest = np.zeros(nv)
            return (f.nle(q, rest, params=params) - f.tau_of("elastic", q, rest, params=params))[z]
        K = np.column_stack([(force(h * e) - force(-h * e)) / (2 * h) for e in np.eye(k)])
        M = f.M(np.zeros(nv), params=params)[np.ix_(z, z)]
        first = np.sqrt(sla.eigh((K + K.T) / 2, M, eigvals_only=True).min())
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


def test_free_vibration_of_the_3d_arm_conserves_energy(arm):
    """Released bent and twisted under gravity, no damping: T + U stays constant to the integrator's
    tolerance while every field moves."""
    arm, f = arm
    n = arm.nv
    q0 = np.zeros(n)
    q0[1:11] = 0.02  # the first link's deflections, slopes and twists
    sol = solve_ivp(lambda _, x: np.r_[x[n:], f.forward_dynamics(x[:n], x[n:])], (0, 0.1),
                    np.r_[q0, np.zeros(n)], method="DOP853", rtol=1e-11, atol=1e-12,
                    t_eval=np.linspace(0, 0.1, 21))
    assert sol.success and np.ptp(sol.y[:n], axis=1).min() > 1e-4  # every coordinate moves
    energy = np.array([f.T(x[:n], x[n:]) + f.U(x[:n]) for x in sol.y.T])
    assert np.ptp(energy) < 1e-8 * np.abs(energy).max()


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
