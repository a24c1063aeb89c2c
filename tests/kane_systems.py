"""The systems of SEEDS.md §2, built twice: with eomgen, and with sympy.physics.mechanics."""
import sympy as sp
import sympy.physics.mechanics as me

import eomgen as eg

m, I_x, I_y, I_z, a, l, R, g = sp.symbols("m I_x I_y I_z a l R g", positive=True)
F, tau_d, tau_s = sp.symbols("F tau_d tau_s")
u1, u2, u3, u4 = sp.symbols("u1 u2 u3 u4")


def _planar_base(system, names, mass_last=0):
    """Two massless prismatic joints along x and y."""
    px = system.add_body("rail_x", joint=eg.Prismatic(names[0], axis=(1, 0, 0)))
    return system.add_body("rail_y", parent=px, joint=eg.Prismatic(names[1], axis=(0, 1, 0)), mass=mass_last)


def skate(force_at=None):
    """Runner through C = (x1, x2), heading x3; centre of mass at a, point P at l along the runner.
    Speeds: along the runner, turning rate, sideways (dependent, constrained to 0). force_at: a force F
    perpendicular to the runner at distance force_at from C."""
    system = eg.System(gravity=(0, 0, -g))
    base = _planar_base(system, ("x_1", "x_2"))
    body = system.add_body("skate", parent=base, joint=eg.Revolute("x_3", axis=(0, 0, 1)), mass=m,
                           com=(a, 0, 0), inertia=sp.diag(I_x, I_y, I_z))
    if force_at is not None:
        system.add_force(body, (0, F, 0), point=(force_at, 0, 0), in_body_frame=True)
    x1d, x2d, x3d = system.u
    x3 = system.q[2]
    kdes = [u1 - (sp.cos(x3) * x1d + sp.sin(x3) * x2d), u2 - x3d, u3 - (-sp.sin(x3) * x1d + sp.cos(x3) * x2d)]
    return system, dict(speeds=[u1, u2, u3], kinematic_equations=kdes, nonholonomic=[u3], independent=[u1, u2])


def skate_sympy(force_at=None):
    x1, x2, x3 = me.dynamicsymbols("x_1 x_2 x_3")
    w1, w2, w3 = me.dynamicsymbols("u1 u2 u3")
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
    kdes = [w1 - (sp.cos(x3) * x1.diff() + sp.sin(x3) * x2.diff()), w2 - x3.diff(),
            w3 - (-sp.sin(x3) * x1.diff() + sp.cos(x3) * x2.diff())]
    km = me.KanesMethod(N, q_ind=[x1, x2, x3], u_ind=[w1, w2], u_dependent=[w3], kd_eqs=kdes,
                        velocity_constraints=[w3])
    km.kanes_equations([body], loads)
    return km, [x1, x2, x3], [w1, w2]


def particle():
    """A particle (x, y, z) under gravity whose velocity obeys ż = x ẏ."""
    system = eg.System(gravity=(0, 0, -g))
    base = _planar_base(system, ("x", "y"))
    system.add_body("particle", parent=base, joint=eg.Prismatic("z", axis=(0, 0, 1)), mass=m)
    x = system.q[0]
    return system, dict(speeds=list(system.u), nonholonomic=[system.u[2] - x * system.u[1]],
                        independent=list(system.u[:2]))


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


def rolling_disk(torques=False):
    """An upright disk of radius R rolling without slip: contact (x, y), heading θ, spin φ about the
    axle; the speeds q̇, with ẋ and ẏ dependent: ẋ = R φ̇ cos θ, ẏ = R φ̇ sin θ."""
    system = eg.System(gravity=(0, 0, -g))
    base = _planar_base(system, ("x", "y"))
    heading = system.add_body("heading", parent=base, joint=eg.Revolute("theta", axis=(0, 0, 1)))
    disk = system.add_body("disk", parent=heading, joint=eg.Revolute("phi", axis=(0, 1, 0)), mass=m,
                           inertia=sp.diag(m * R**2 / 4, m * R**2 / 2, m * R**2 / 4),
                           placement=eg.Placement(translation=(0, 0, R)))
    if torques:
        system.add_actuator(disk, torque=(0, tau_d, 0), reaction=heading, in_body_frame=True, name="drive")
        system.add_torque(heading, (0, 0, tau_s), name="steer")
    xd, yd, thd, phd = system.u
    theta = system.q[2]
    return system, dict(speeds=list(system.u), independent=[thd, phd],
                        nonholonomic=[xd - R * phd * sp.cos(theta), yd - R * phd * sp.sin(theta)])


def rolling_disk_sympy(torques=False):
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
    km = me.KanesMethod(N, q_ind=[x, y, th, ph], u_ind=[uth, uph], u_dependent=[ux, uy],
                        kd_eqs=[x.diff() - ux, y.diff() - uy, th.diff() - uth, ph.diff() - uph],
                        velocity_constraints=[ux - R * uph * sp.cos(th), uy - R * uph * sp.sin(th)])
    km.kanes_equations([disk], loads)
    return km, [x, y, th, ph], [uth, uph]
