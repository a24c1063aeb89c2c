"""The sympy.physics.mechanics twins of the systems in examples/nonholonomic.py."""
import sys
from pathlib import Path

import sympy as sp
import sympy.physics.mechanics as me

sys.path.insert(0, str(Path(__file__).parents[1] / "examples"))
from nonholonomic import F, I_x, I_y, I_z, R, a, g, l, m, particle, rolling_disk, skate, tau_d, tau_s  # noqa: E402,F401
from nonholonomic import u1, u2, u3  # noqa: E402,F401


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
