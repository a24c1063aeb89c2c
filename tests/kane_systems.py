"""The sympy.physics.mechanics twins of the systems in examples/nonholonomic.py; planar bodies with
constraints that defeat symbolic pivoting; a Whipple-like bicycle (five nonholonomic constraints); a
planar four-bar with holonomic constraints, its sympy twin and its pose by hand."""
import sys
from pathlib import Path

import numpy as np
import sympy as sp

import eomgen as eg
from eomgen.model.loads import Point
import sympy.physics.mechanics as me

sys.path.insert(0, str(Path(__file__).parents[1] / "examples"))
from nonholonomic import F, I_x, I_y, I_z, R, a, g, l, m, particle, rolling_disk, skate, tau_d, tau_s  # noqa: E402,F401
from nonholonomic import u1, u2, u3  # noqa: E402,F401


def _skate_frame(force_at):
    """The skate in sympy: (N, x1, x2, x3, body, loads) with the velocity of C = (ẋ1, ẋ2)."""
    x1, x2, x3 = me.dynamicsymbols("x_1 x_2 x_3")
    N = me.ReferenceFrame("N")
    A = N.orientnew("A", "Axis", [x3, N.z])
    C = me.Point("C")
    C.set_vel(N, x1.diff() * N.x + x2.diff() * N.y)
    G = C.locatenew("G", a * A.x)
    G.v2pt_theory(C, N, A)
    body = me.RigidBody("skate", G, A, m, (me.inertia(A, I_x, I_y, I_z), G))
    loads = []
    if force_at is not None:
        P = C.locatenew("P", force_at * A.x)
        P.v2pt_theory(C, N, A)
        loads.append((P, F * A.y))
    return N, x1, x2, x3, body, loads


def skate_sympy(force_at=None):
    N, x1, x2, x3, body, loads = _skate_frame(force_at)
    w1, w2, w3 = me.dynamicsymbols("u1 u2 u3")
    kdes = [w1 - (sp.cos(x3) * x1.diff() + sp.sin(x3) * x2.diff()), w2 - x3.diff(),
            w3 - (-sp.sin(x3) * x1.diff() + sp.cos(x3) * x2.diff())]
    km = me.KanesMethod(N, q_ind=[x1, x2, x3], u_ind=[w1, w2], u_dependent=[w3], kd_eqs=kdes,
                        velocity_constraints=[w3])
    km.kanes_equations([body], loads)
    return km, [x1, x2, x3], [w1, w2]


def particle_sympy():
    x, y, z = me.dynamicsymbols("x y z")
    ux, uy, uz = me.dynamicsymbols("xdot ydot zdot")
    N = me.ReferenceFrame("N")
    P = me.Point("P")
    P.set_vel(N, ux * N.x + uy * N.y + uz * N.z)
    km = me.KanesMethod(N, q_ind=[x, y, z], u_ind=[ux, uy], u_dependent=[uz],
                        kd_eqs=[x.diff() - ux, y.diff() - uy, z.diff() - uz], velocity_constraints=[uz - x * uy])
    km.kanes_equations([me.Particle("p", P, m)], [(P, -m * g * N.z)])
    return km, [x, y, z], [ux, uy]


F_x, F_y = sp.symbols("F_x F_y")


def rolling_disk_sympy(torques=False, forces=False):
    """torques: the drive τ_d about the axle (reaction on the heading frame) and the steer τ_s about the
    vertical; forces: F_x, F_y on the centre along the ground's axes."""
    x, y, th, ph = me.dynamicsymbols("x y theta phi")
    ux, uy, uth, uph = me.dynamicsymbols("xdot ydot thetadot phidot")
    N = me.ReferenceFrame("N")
    A = N.orientnew("A", "Axis", [th, N.z])
    D = A.orientnew("D", "Axis", [ph, A.y])
    A.set_ang_vel(N, uth * N.z)
    D.set_ang_vel(A, uph * A.y)
    G = me.Point("G")
    G.set_vel(N, ux * N.x + uy * N.y)
    disk = me.RigidBody("disk", G, D, m, (me.inertia(D, m * R**2 / 4, m * R**2 / 2, m * R**2 / 4), G))
    loads = [(G, -m * g * N.z)]
    if torques:
        loads += [(D, tau_d * A.y), (A, -tau_d * A.y + tau_s * N.z)]
    if forces:
        loads[0] = (G, -m * g * N.z + F_x * N.x + F_y * N.y)
    km = me.KanesMethod(N, q_ind=[x, y, th, ph], u_ind=[uth, uph], u_dependent=[ux, uy],
                        kd_eqs=[x.diff() - ux, y.diff() - uy, th.diff() - uth, ph.diff() - uph],
                        velocity_constraints=[ux - R * uph * sp.cos(th), uy - R * uph * sp.sin(th)])
    km.kanes_equations([disk], loads)
    return km, [x, y, th, ph], [uth, uph]


# --- planar bodies whose constraint matrices defeat symbolic pivoting (speeds q̇ = (ẋ1, ẋ2, ẋ3)) -------
b = sp.Symbol("b", positive=True)  # appears only in a constraint


def pythagoras(q, qd):
    """(cos²x3 + sin²x3 − 1) ẋ1 + ẋ2 − ẋ3 = 0, a ẋ1 − cos x3 ẋ3 = 0: ẋ1 = cos x3 ẋ3 / a, ẋ2 = ẋ3.
    The first entry is zero but not recognised as zero."""
    c, s = sp.cos(q[2]), sp.sin(q[2])
    return [(c**2 + s**2 - 1) * qd[0] + qd[1] - qd[2], a * qd[0] - c * qd[2]]


def pythagoras_sympy_form(q, qd):
    """The same constraints as sympy is given them: ẋ2 − ẋ3 = 0, a ẋ1 − cos x3 ẋ3 = 0."""
    return [qd[1] - qd[2], a * qd[0] - sp.cos(q[2]) * qd[2]]


def rotation(q, qd):
    """C_dep = [[sin x3, cos x3], [cos x3, −sin x3]] (a rotation with its rows swapped):
    sin x3 ẋ1 + cos x3 ẋ2 = 0, cos x3 ẋ1 − sin x3 ẋ2 − b ẋ3 = 0; by hand (C_dep⁻¹ = C_dep)
    ẋ1 = b cos x3 ẋ3, ẋ2 = −b sin x3 ẋ3."""
    c, s = sp.cos(q[2]), sp.sin(q[2])
    return [s * qd[0] + c * qd[1], c * qd[0] - s * qd[1] - b * qd[2]]


def elementary(q, qd):
    """Constraints with tan, exp and atan2 (code for each in every backend):
    ẋ1 − b cos x3 ẋ3 = 0, ẋ2 − tan(x3) ẋ1 − exp(−x1²) atan2(x2, 2) ẋ3 = 0; by hand
    ẋ1 = b cos x3 ẋ3, ẋ2 = (b sin x3 + exp(−x1²) atan2(x2, 2)) ẋ3."""
    return [qd[0] - b * sp.cos(q[2]) * qd[2],
            qd[1] - sp.tan(q[2]) * qd[0] - sp.exp(-q[0]**2) * sp.atan2(q[1], 2) * qd[2]]


def constrained_skate(constraints, force_at=None):
    """The skate's body and loads with speeds q̇, `constraints(q, q̇)` and ẋ3 independent."""
    system, _ = skate(force_at)
    return system, dict(nonholonomic=constraints(system.q, system.u), independent=[system.u[2]])


def constrained_skate_sympy(constraints, force_at=None):
    """sympy's KanesMethod for `constrained_skate`: (km, q, w_ind) with speeds q̇ (ẋ1, ẋ2 dependent)."""
    N, x1, x2, x3, body, loads = _skate_frame(force_at)
    q = [x1, x2, x3]
    u = me.dynamicsymbols("v_1 v_2 v_3")
    km = me.KanesMethod(N, q_ind=q, u_ind=[u[2]], u_dependent=u[:2],
                        kd_eqs=[qi.diff() - ui for qi, ui in zip(q, u)],
                        velocity_constraints=constraints(q, u))
    km.kanes_equations([body], loads)
    return km, q, [u[2]]


# --- a Whipple-like bicycle: five nonholonomic constraints, a dense trigonometric 5 × 5 C_dep -------------
m_b, g_b = sp.symbols("m_b g", positive=True)
BIKE = dict(R=sp.Float(0.3), wheelbase=sp.Float(1.02), trail=sp.Float(0.08), tilt=sp.Float(0.314))


def bicycle():
    """Rear contact (x, y) on rails, yaw ψ, roll φ about the heading, the rear frame pitching θ about the
    rear axle (height R), the rear wheel spinning on the frame, the steer δ about an axis tilted back by
    λ through the point `trail` ahead of the front contact, the front wheel spinning on the fork.
    Speeds q̇; independent φ̇, rear spin, δ̇. Constraints: no slip of the rear wheel at the rails'
    point (x, y) and of the front wheel at its lowest point (x, y, z; z is the derivative of the
    holonomic contact condition). Upright (q = 0) both wheels touch the ground.
    Returns (system, kane arguments, front contact height(q) as an expression)."""
    R, wb, c, lam = BIKE["R"], BIKE["wheelbase"], BIKE["trail"], BIKE["tilt"]
    system = eg.System(gravity=(0, 0, -g_b))
    rail = system.add_body("rail_x", joint=eg.Prismatic("x", axis=(1, 0, 0)))
    base = system.add_body("rail_y", parent=rail, joint=eg.Prismatic("y", axis=(0, 1, 0)))
    yaw = system.add_body("yaw", parent=base, joint=eg.Revolute("psi", axis=(0, 0, 1)))
    roll = system.add_body("roll", parent=yaw, joint=eg.Revolute("phi", axis=(1, 0, 0)))
    frame = system.add_body("frame", parent=roll, joint=eg.Revolute("theta", axis=(0, 1, 0)), mass=m_b,
                            com=(0.3, 0, 0.6), inertia=sp.diag(9.2, 11, 2.8),
                            placement=eg.Placement(translation=(0, 0, R)))
    rear = system.add_body("rear_wheel", parent=frame, joint=eg.Revolute("theta_r", axis=(0, 1, 0)), mass=2,
                           inertia=sp.diag(0.0603, 0.12, 0.0603))
    steer_at = wb + c - R * sp.tan(lam)  # on the steer axis, at the height of the front axle
    steer = eg.Revolute("delta", axis=(-sp.sin(lam), 0, sp.cos(lam)))
    fork = system.add_body("fork", parent=frame, joint=steer,
                           mass=4, com=(0.02, 0, 0.5), inertia=sp.diag(0.05, 0.06, 0.02),
                           placement=eg.Placement(translation=(steer_at, 0, 0)))
    front = system.add_body("front_wheel", parent=fork, joint=eg.Revolute("theta_f", axis=(0, 1, 0)), mass=3,
                            inertia=sp.diag(0.1405, 0.28, 0.1405),
                            placement=eg.Placement(translation=(wb - steer_at, 0, 0)))
    kin = eg.Kinematics(system)
    closed = kin.sub.inline

    def slip(wheel, contact_offset):  # velocity of the wheel's material point at the contact
        v, w = closed(kin.velocity(Point(wheel, sp.zeros(3, 1)))), closed(kin.omega(wheel))
        return v + w.cross(contact_offset)
    down_r = -R * closed(kin.R[roll][:, 2])
    axle = closed(kin.R[front][:, 1])
    z = sp.Matrix([0, 0, 1])
    in_plane = z - axle[2] * axle  # ẑ projected on the wheel plane
    down_f = -R * in_plane / sp.sqrt(1 - axle[2] ** 2)
    rear_slip, front_slip = slip(rear, down_r), slip(front, down_f)
    height = closed(kin.p[front])[2] + down_f[2]
    qd = system.u
    return system, dict(nonholonomic=[*rear_slip[:2], *front_slip], independent=[qd[3], qd[5], qd[6]]), height


# --- a planar four-bar: crank, coupler and rocker on revolutes about z, the rocker's tip pinned at (d, 0) --
BAR = dict(l1=0.2, l2=0.5, l3=0.4, d=0.45, m1=0.3, m2=0.8, m3=0.6, I1=0.002, I2=0.02, I3=0.01, tau=0.5,
           g=9.81)


def closure(q, l1=BAR["l1"], l2=BAR["l2"], l3=BAR["l3"], d=BAR["d"]):
    """The tip of the rocker at (d, 0): l1 c1 + l2 c12 + l3 c123 − d = 0, l1 s1 + l2 s12 + l3 s123 = 0."""
    a1, a2, a3 = q[0], q[0] + q[1], q[0] + q[1] + q[2]
    return [l1 * sp.cos(a1) + l2 * sp.cos(a2) + l3 * sp.cos(a3) - d,
            l1 * sp.sin(a1) + l2 * sp.sin(a2) + l3 * sp.sin(a3)]


def four_bar(speeds="rates"):
    """The four-bar (gravity −y, torque τ on the crank), q = relative angles; speeds "rates" (w = q̇) or
    "absolute" (w = the links' absolute angular rates, by kinematic equations); q2, q3 dependent."""
    system = eg.System(gravity=(0, -BAR["g"], 0))
    parent, at = None, 0
    for i in (1, 2, 3):
        length = BAR[f"l{i}"]
        parent = system.add_body(f"link{i}", parent=parent, joint=eg.Revolute(f"q{i}", axis=(0, 0, 1)),
                                 mass=BAR[f"m{i}"], com=(length / 2, 0, 0),
                                 inertia=sp.diag(0.001, BAR[f"I{i}"], BAR[f"I{i}"]),
                                 placement=eg.Placement(translation=(at, 0, 0)))
        at = length
    system.add_torque("link1", (0, 0, BAR["tau"]))
    q, u = system.q, system.u
    args = dict(holonomic=closure(q), dependent_coordinates=[q[1], q[2]])
    if speeds == "rates":
        return system, {**args, "independent": [u[0]]}
    w = sp.symbols("w1:4")
    return system, {**args, "speeds": w, "independent": [w[0]],
                    "kinematic_equations": [w[0] - u[0], w[1] - u[0] - u[1], w[2] - u[0] - u[1] - u[2]]}


def four_bar_sympy(speeds="rates"):
    """sympy's KanesMethod of `four_bar`, written independently: (km, q, u)."""
    q = me.dynamicsymbols("q1:4")
    u = me.dynamicsymbols("u1:4")
    N = me.ReferenceFrame("N")
    frames, points, bodies, loads = [N], [me.Point("O")], [], []
    points[0].set_vel(N, 0)
    for i in range(3):
        frame = frames[-1].orientnew(f"L{i}", "Axis", [q[i], frames[-1].z])
        if speeds == "rates":
            frame.set_ang_vel(frames[-1], u[i] * frames[-1].z)
        else:
            frame.set_ang_vel(N, u[i] * N.z)
        length, mass = BAR[f"l{i + 1}"], BAR[f"m{i + 1}"]
        G = points[-1].locatenew(f"G{i}", length / 2 * frame.x)
        G.v2pt_theory(points[-1], N, frame)
        tip = points[-1].locatenew(f"P{i}", length * frame.x)
        tip.v2pt_theory(points[-1], N, frame)
        I = BAR[f"I{i + 1}"]
        bodies.append(me.RigidBody(f"link{i}", G, frame, mass, (me.inertia(frame, 0.001, I, I), G)))
        loads.append((G, -mass * BAR["g"] * N.y))
        frames.append(frame)
        points.append(tip)
    loads.append((frames[1], BAR["tau"] * N.z))
    rates = [x.diff() for x in q]
    if speeds == "rates":
        kd, qd = [ui - r for ui, r in zip(u, rates)], dict(zip(rates, u))
    else:
        kd = [u[0] - rates[0], u[1] - rates[0] - rates[1], u[2] - sum(rates)]
        qd = {rates[0]: u[0], rates[1]: u[1] - u[0], rates[2]: u[2] - u[1]}
    f = closure(q)
    km = me.KanesMethod(N, q_ind=[q[0]], q_dependent=q[1:], configuration_constraints=f, u_ind=[u[0]],
                        u_dependent=u[1:], velocity_constraints=[e.diff().subs(qd) for e in f], kd_eqs=kd)
    km.kanes_equations(bodies, loads)
    return km, q, u


def four_bar_pose(q1: float) -> list[float]:
    """(q1, q2, q3) of the four-bar by hand: the coupler-rocker joint P2 where the circles about P1 (radius
    l2) and about (d, 0) (radius l3) meet, on the side above the line P1-(d, 0)."""
    l1, l2, l3, d = (BAR[k] for k in ("l1", "l2", "l3", "d"))
    P1, P3 = l1 * np.array([np.cos(q1), np.sin(q1)]), np.array([d, 0.0])
    e = P3 - P1
    L = np.linalg.norm(e)
    a = (L**2 + l2**2 - l3**2) / (2 * L)
    P2 = P1 + a * e / L + np.sqrt(l2**2 - a**2) * np.array([-e[1], e[0]]) / L
    a2 = np.arctan2(*(P2 - P1)[::-1])
    a3 = np.arctan2(*(P3 - P2)[::-1])
    return [q1, a2 - q1, a3 - a2]


def number(expr, values) -> np.ndarray:
    """A sympy.physics.mechanics matrix at `values` (30 digits, then float)."""
    return np.array(me.msubs(expr, values).evalf(30).tolist(), dtype=float)


def sympy_residuals(km, p: int, values: dict, wd: np.ndarray) -> np.ndarray:
    """sympy's F_r + F*_r at `values` for independent rates ẇ_ind = wd (its mass matrix and forcing
    over all speeds, the last rows the constraints' derivatives, give the dependent rates)."""
    M_s, F_s = number(km.mass_matrix, values), number(km.forcing, values)[:, 0]
    wd_dep = np.linalg.solve(M_s[p:, p:], F_s[p:] - M_s[p:, :p] @ wd) if len(F_s) > p else []
    return F_s[:p] - M_s[:p] @ np.r_[wd, wd_dep]
