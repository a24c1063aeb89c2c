"""Kane's method on every joint type but the free flyer (issue 14): against the recursive method and
Pinocchio; a heavy top against sympy.physics.mechanics.KanesMethod; the quaternion top simulated; a
skate on a planar joint, constrained in the joint's own speeds, against the hand derivation and the
skate of examples/nonholonomic.py (rails and a revolute with kinematic equations); a ball rolling on a
ball joint (constraints in the quaternion and ω) conserving its energy."""
import numpy as np
import pinocchio as pin
import pytest
import sympy as sp
import sympy.physics.mechanics as me
from scipy.integrate import solve_ivp
from scipy.spatial.transform import Rotation

import eomgen as eg
import kane_systems as K
from models import JOINTS, joint_chain
from eomgen.model.rotations import quaternion_rotation
from eomgen.model.urdf import pinocchio_configuration
from eomgen.verify import to_pinocchio

def accelerations(f, q, w, params=None) -> np.ndarray:
    """ẇ from Kane's M̃ ẇ = f̃ (batched)."""
    return np.linalg.solve(f.mass_matrix(q, w, params), f.forcing(q, w, params)[..., None])[..., 0]


@pytest.mark.parametrize("name", JOINTS)
def test_joint_equals_recursive_and_pinocchio(name):
    """u̇ of Kane's equations (w = u) = the recursive method's forward dynamics = Pinocchio's ABA (a mimic:
    M⁻¹ (−nle) by CRBA, as Pinocchio 4.1's aba refuses mimic joints); and q̇ = qdot(q, w) is the rate of
    Pinocchio's configuration (central differences of pin.integrate)."""
    system = joint_chain(JOINTS[name]())
    k = eg.kane(system)
    f, recursive = eg.codegen(k), eg.codegen(eg.derive(system, method="recursive"))
    model = to_pinocchio(system)
    q, u, _ = eg.random_states(system, 5, np.random.default_rng(14))
    ours = accelerations(f, q, u)
    assert f.qdot(q, u).shape == q.shape and f.joint_speeds(q, u).shape == u.shape
    h = 1e-6
    for qi, ui, udi in zip(q, u, ours):
        np.testing.assert_allclose(udi, recursive.forward_dynamics(qi, ui), rtol=1e-10, atol=1e-10)
        qp = pinocchio_configuration(system, qi)
        data = model.createData()  # afresh: with a mimic joint, Pinocchio 4.1's crba on used data is wrong
        if name == "mimic":
            M = pin.crba(model, data, qp)
            reference = np.linalg.solve(M, -pin.nonLinearEffects(model, data, qp, ui))
        else:
            reference = pin.aba(model, data, qp, ui, np.zeros(model.nv))
        np.testing.assert_allclose(udi, reference, rtol=1e-10, atol=1e-10)
        qd = f.qdot(qi, ui)
        rate = (pin.integrate(model, qp, h * ui) - pin.integrate(model, qp, -h * ui)) / (2 * h)
        moved = [pinocchio_configuration(system, qi + sign * h * qd) for sign in (1, -1)]
        np.testing.assert_allclose((moved[0] - moved[1]) / (2 * h), rate, atol=1e-8)


# --- the heavy symmetric top: a ball joint at the fixed point O, centre of mass at L along the body z ----
TOP = {"m": 2.0, "L": 0.4, "A": 0.05, "C": 0.08, "g": 9.81}


def top(parametrization: str) -> eg.System:
    s = eg.System(gravity=(0, 0, -TOP["g"]))
    s.add_body("top", joint=eg.Spherical("s", parametrization), mass=TOP["m"], com=(0, 0, TOP["L"]),
               inertia=sp.diag(TOP["A"], TOP["A"], TOP["C"]))
    return s


def body_rates(yaw, pitch, roll, rates) -> list:
    """ω in body axes of body-fixed ZYX angles, by hand:
    (φ̇ − sθ ψ̇, cφ θ̇ + sφ cθ ψ̇, −sφ θ̇ + cφ cθ ψ̇)."""
    dy, dp, dr = rates
    c, s = sp.cos, sp.sin
    return [dr - s(pitch) * dy, c(roll) * dp + s(roll) * c(pitch) * dy,
            -s(roll) * dp + c(roll) * c(pitch) * dy]


def top_sympy(speeds: str):
    """sympy's KanesMethod of the top, body-fixed ZYX angles (ψ, θ, φ); speeds "rates" (u = the angle
    rates) or "body" (u = ω in body axes). Returns (km, q, u)."""
    m, L, A, C, g = (sp.Float(TOP[k]) for k in ("m", "L", "A", "C", "g"))
    q = me.dynamicsymbols("psi theta phi")
    u = me.dynamicsymbols("u1:4")
    N = me.ReferenceFrame("N")
    B = N.orientnew("B", "Body", q, "ZYX")
    O = me.Point("O")
    O.set_vel(N, 0)
    G = O.locatenew("G", L * B.z)
    G.v2pt_theory(O, N, B)
    rates = [x.diff() for x in q]
    kd = [ui - r for ui, r in zip(u, rates if speeds == "rates" else body_rates(*q, rates))]
    km = me.KanesMethod(N, q_ind=q, u_ind=u, kd_eqs=kd)
    km.kanes_equations([me.RigidBody("top", G, B, m, (me.inertia(B, A, A, C), G))], [(G, -m * g * N.z)])
    return km, q, u


def _number(expr, values) -> np.ndarray:
    return np.array(me.msubs(expr, values).evalf(30).tolist(), dtype=float)


@pytest.mark.parametrize("case", ["zyx", "quaternion", "zyx_body_rates", "quaternion_world_rates"])
def test_top_equals_sympy_kanes_method(case):
    """M̃ and f̃ equal sympy's M_s, f_s at random states: ZYX angles with their rates; the quaternion with
    ω in body axes (the joint speeds; ZYX angles of the same rotation for sympy); ZYX angles with new
    speeds w = ω in body axes through kinematic equations; the quaternion with w = ω in world axes,
    u = Rᵀ w (then u̇ = Rᵀ ẇ as Ṙ u = R (ω × ω) = 0, so M̃ = R M_s Rᵀ and f̃ = R f_s with sympy's body
    speeds). With w = u the closed forms too."""
    system = top(case.split("_")[0])
    w = sp.symbols("w1:4")
    R = quaternion_rotation(*system.q) if case == "quaternion_world_rates" else sp.eye(3)
    if case == "zyx_body_rates":
        k = eg.kane(system, speeds=w, kinematic_equations=[wi - r for wi, r in
                                                             zip(w, body_rates(*system.q, system.u))])
    elif case == "quaternion_world_rates":
        k = eg.kane(system, speeds=w, kinematic_equations=list(system.u - R.T * sp.Matrix(w)))
    else:
        k = eg.kane(system)
    f = eg.codegen(k)
    km, q_s, u_s = top_sympy("rates" if case == "zyx" else "body")
    rotation = sp.lambdify([system.q], R)
    q, u, _ = eg.random_states(system, 4, np.random.default_rng(7))
    for qi, ui in zip(q, u):
        angles = Rotation.from_quat(qi).as_euler("ZYX") if case.startswith("quaternion") else qi
        values = {**dict(zip(q_s, angles)), **dict(zip(u_s, ui))}
        Ri, wi = rotation(qi), rotation(qi) @ ui
        np.testing.assert_allclose(f.mass_matrix(qi, wi), Ri @ _number(km.mass_matrix, values) @ Ri.T,
                                   rtol=1e-12, atol=1e-12)
        np.testing.assert_allclose(f.forcing(qi, wi), Ri @ _number(km.forcing, values)[:, 0], rtol=1e-12,
                                   atol=1e-12)
    if k.speeds_are_qdot:  # Y = 1: closed forms (the quaternion's not simplified by |q| = 1)
        values = {**dict(zip(system.q, qi)), **dict(zip(k.independent, wi))}
        for key in ("mass_matrix", "forcing"):
            ours = getattr(f, key)(qi, wi)
            closed = np.array(getattr(k, key).xreplace(values).evalf(30).tolist(), dtype=float)
            np.testing.assert_allclose(closed.reshape(ours.shape), ours, rtol=1e-12, atol=1e-12)
    if case == "quaternion":  # w = u = ω, q̇ = ½ q ⊗ (ω, 0), M̃ = I_O
        assert k.joint_speeds == system.u and k.qdot == system.qdot
        I_O = np.diag([TOP["A"] + TOP["m"] * TOP["L"] ** 2] * 2 + [TOP["C"]])
        np.testing.assert_allclose(f.mass_matrix(q, u), np.broadcast_to(I_O, (4, 3, 3)), rtol=1e-13,
                                   atol=1e-14)


def test_quaternion_top_simulation():
    """rhs(t, x), x = [quaternion, ω]: 3 s of a spinning top (DOP853, tolerances 1e-12) conserve the energy
    ½ ωᵀ I_O ω + m g z_G (by hand, with scipy's rotation of the quaternion) to 1e-8 and the quaternion's
    norm to 1e-9 without renormalising; the C backend's rhs equals NumPy's."""
    system = top("quaternion")
    k = eg.kane(system)
    f = eg.codegen(k)
    assert (f.nq, f.n) == (4, 3)
    x0 = np.r_[Rotation.from_euler("ZYX", [0.3, 0.5, -0.2]).as_quat(), 0.4, -0.3, 25.0]
    assert f.rhs(0, x0).shape == (7,)
    sol = solve_ivp(f.rhs, (0, 3), x0, method="DOP853", rtol=1e-12, atol=1e-12, t_eval=np.linspace(0, 3, 61))
    assert sol.success
    m, L, g = TOP["m"], TOP["L"], TOP["g"]
    I_O = np.diag([TOP["A"] + m * L**2] * 2 + [TOP["C"]])
    quaternions, omegas = sol.y[:4].T, sol.y[4:].T
    heights = Rotation.from_quat(quaternions).apply([0, 0, L])[:, 2]
    energies = 0.5 * np.einsum("ni,ij,nj->n", omegas, I_O, omegas) + m * g * heights
    assert np.ptp(energies) < 1e-8 * abs(energies[0])
    assert np.max(abs(np.linalg.norm(quaternions, axis=1) - 1)) < 1e-9
    assert np.ptp(heights) > 1e-3  # it nutates
    compiled = eg.codegen(k, backend="c")
    x = np.c_[eg.random_states(system, 6, np.random.default_rng(2))[:2]]
    np.testing.assert_allclose(compiled.rhs(0, x), f.rhs(0, x), rtol=1e-13, atol=1e-13)
    np.testing.assert_allclose(compiled.rhs(0, x[0]), f.rhs(0, x[0]), rtol=1e-13, atol=1e-13)


def planar_skate() -> tuple[eg.System, eg.KaneEquations]:
    """The skate on a planar joint (q = x, y, θ; u = v_x, v_y, ω in the runner's axes), the force F at l
    across the runner, and no side slip v_y = 0 in the joint's own speeds."""
    system = eg.System(gravity=(0, 0, -K.g))
    body = system.add_body("skate", joint=eg.Planar("p"), mass=K.m, com=(K.a, 0, 0),
                           inertia=sp.diag(K.I_x, K.I_y, K.I_z))
    system.add_force(body, (0, K.F, 0), point=(K.l, 0, 0), in_body_frame=True)
    vx, vy, wz = system.u
    return system, eg.kane(system, nonholonomic=[vy], independent=[vx, wz])


def test_planar_skate_no_side_slip():
    """By hand (v_G = v_x e1 + a ω e2): M̃ = diag(m, I_z + m a²), f̃ = (m a ω², F l − m a v_x ω),
    F̃_r = (0, F l), q̇ = (cos θ v_x, sin θ v_x, ω); the worked solution shows u and q̇; and rhs equals
    that of the skate of examples/nonholonomic.py (rails and a revolute, speeds by kinematic equations)
    state for state."""
    system, k = planar_skate()
    vx, vy, wz = system.u
    theta = system.q[2]
    m, a, I_z, F, l = K.m, K.a, K.I_z, K.F, K.l
    assert sp.simplify(k.mass_matrix - sp.diag(m, I_z + m * a**2)) == sp.zeros(2, 2)
    assert sp.simplify(k.forcing - sp.Matrix([m * a * wz**2, F * l - m * a * vx * wz])) == sp.zeros(2, 1)
    assert sp.simplify(k.active_forces - sp.Matrix([0, F * l])) == sp.zeros(2, 1)
    assert k.dependent_speeds == sp.Matrix([0]) and k.joint_speeds == sp.Matrix([vx, 0, wz])
    assert sp.simplify(k.qdot - sp.Matrix([sp.cos(theta) * vx, sp.sin(theta) * vx, wz])) == sp.zeros(3, 1)
    sol = eg.solution(k)
    assert sol["joint speeds"] == sp.Matrix([vx, 0, wz]) and sol["qdot"] == k.qdot
    f = eg.codegen(k)
    reference_system, args = K.skate(force_at=K.l)
    reference = eg.codegen(eg.kane(reference_system, **args))
    x = np.random.default_rng(9).uniform(-1.5, 1.5, (8, 5))
    values = {"m": 1.3, "I_x": 0.05, "I_y": 0.05, "I_z": 0.1, "a": 0.4, "l": 0.7, "F": 0.6, "g": 9.81}
    expected = reference.rhs(0, x, params={str(s): values[str(s)] for s in reference.params})
    np.testing.assert_allclose(f.rhs(0, x, params={str(s): values[str(s)] for s in f.params}), expected,
                               rtol=1e-13, atol=1e-13)


def test_rolling_ball_quaternion():
    """A ball (radius r, centre of mass off the centre) on a ball joint above rails x, y rolls without
    slip: ẋ = r ω_y, ẏ = −r ω_x with ω = R(q) u in world axes, quaternion-dependent constraints in the
    joint speeds. 3 s from a spin: the constraints hold to 1e-10, the energy ½ m v_G² + ½ uᵀ Θ u + m g z_G
    (by hand) is conserved to 1e-9 relative, the quaternion stays unit to 1e-10 (not renormalised)."""
    r, m, c, Theta = 0.2, 1.5, np.array([0.01, 0, -0.05]), np.diag([0.02, 0.025, 0.03])
    system = eg.System(gravity=(0, 0, -9.81))
    rail_x = system.add_body("rail_x", joint=eg.Prismatic("x", axis=(1, 0, 0)))
    rail_y = system.add_body("rail_y", parent=rail_x, joint=eg.Prismatic("y", axis=(0, 1, 0)))
    system.add_body("ball", parent=rail_y, joint=eg.Spherical("b"), mass=m, com=tuple(c),
                    inertia=sp.Matrix(Theta), placement=eg.Placement(translation=(0, 0, r)))
    xd, yd, *omega = system.u
    wx, wy, _ = quaternion_rotation(*system.q[2:]) * sp.Matrix(omega)
    f = eg.codegen(eg.kane(system, nonholonomic=[xd - r * wy, yd + r * wx], independent=omega))
    x0 = np.r_[0, 0, Rotation.from_euler("ZYX", [0.1, 0.4, 0.2]).as_quat(), 1.0, -0.5, 3.0]
    sol = solve_ivp(f.rhs, (0, 3), x0, method="DOP853", rtol=1e-12, atol=1e-12, t_eval=np.linspace(0, 3, 31))
    assert sol.success
    q = sol.y[:6].T
    u = f.joint_speeds(q, sol.y[6:].T)
    R = Rotation.from_quat(q[:, 2:]).as_matrix()
    omega_world, c_world = R @ u[:, 2:, None], R @ c
    np.testing.assert_allclose(u[:, :2], r * np.c_[omega_world[:, 1], -omega_world[:, 0]], atol=1e-10)
    v_G = np.c_[u[:, :2], np.zeros(len(u))] + np.cross(omega_world[..., 0], c_world)
    energies = (0.5 * m * np.sum(v_G**2, axis=1) + 0.5 * np.einsum("ni,ij,nj->n", u[:, 2:], Theta, u[:, 2:])
                + m * 9.81 * (r + c_world[:, 2]))
    assert np.ptp(energies) < 1e-9 * abs(energies[0])
    assert np.max(abs(np.linalg.norm(q[:, 2:], axis=1) - 1)) < 1e-10
    assert min(np.ptp(q[:, 0]), np.ptp(q[:, 1])) > 0.1  # it rolled
