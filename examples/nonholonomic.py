"""Nonholonomic systems with Kane's method: the skate, a particle with a velocity
constraint, and the rolling disk; p equations for p independent speeds, no multipliers.

Run: python examples/nonholonomic.py"""
import sympy as sp
from scipy.integrate import solve_ivp

import eomgen as eg

m, I_x, I_y, I_z, a, l, R, g = sp.symbols("m I_x I_y I_z a l R g", positive=True)
F, tau_d, tau_s = sp.symbols("F tau_d tau_s")
u1, u2, u3, u4 = sp.symbols("u1 u2 u3 u4")


def _planar_base(system, names, mass_last=0):
    """Two massless prismatic joints along x and y."""
    px = system.add_body("rail_x", joint=eg.Prismatic(names[0], axis=(1, 0, 0)))
    return system.add_body("rail_y", parent=px, joint=eg.Prismatic(names[1], axis=(0, 1, 0)), mass=mass_last)


def skate(force_at=None, solved=True):
    """Runner through C = (x1, x2), heading x3; centre of mass at a, point P at l along the runner.
    Speeds: along the runner, turning rate, sideways (dependent, constrained to 0). force_at: a force F
    perpendicular to the runner at distance force_at from C. The kinematic equations solved for q̇
    (q̇ = W w: closed forms exist), or with solved=False as w = Wᵀ q̇ (Y = −Wᵀ: its pivots cos x3,
    sin x3 are not provably nonzero, so only the generated code, which solves numerically)."""
    system = eg.System(gravity=(0, 0, -g))
    base = _planar_base(system, ("x_1", "x_2"))
    body = system.add_body("skate", parent=base, joint=eg.Revolute("x_3", axis=(0, 0, 1)), mass=m,
                           com=(a, 0, 0), inertia=sp.diag(I_x, I_y, I_z))
    if force_at is not None:
        system.add_force(body, (0, F, 0), point=(force_at, 0, 0), in_body_frame=True)
    x1d, x2d, x3d = system.u
    x3 = system.q[2]
    c, s = sp.cos(x3), sp.sin(x3)
    kdes = ([x1d - (c * u1 - s * u3), x2d - (s * u1 + c * u3), x3d - u2] if solved else
            [u1 - (c * x1d + s * x2d), u2 - x3d, u3 - (-s * x1d + c * x2d)])
    return system, dict(speeds=[u1, u2, u3], kinematic_equations=kdes, nonholonomic=[u3], independent=[u1, u2])


def particle():
    """A particle (x, y, z) under gravity whose velocity obeys ż = x ẏ."""
    system = eg.System(gravity=(0, 0, -g))
    base = _planar_base(system, ("x", "y"))
    system.add_body("particle", parent=base, joint=eg.Prismatic("z", axis=(0, 0, 1)), mass=m)
    x = system.q[0]
    return system, dict(speeds=list(system.u), nonholonomic=[system.u[2] - x * system.u[1]],
                        independent=list(system.u[:2]))


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


def main() -> None:
    for name, (system, args) in {"skate": skate(force_at=l), "particle": particle(),
                                 "rolling disk": rolling_disk(torques=True)}.items():
        k = eg.kane(system, **args)
        print(f"\n{name}: n = {len(k.speeds)} speeds, m = {len(k.dependent)} constraints, "
              f"p = {len(k.independent)} equations in {k.independent}")
        print("  q̇ =", list(sp.simplify(k.qdot)))
        print("  dependent speeds", k.dependent, "=", list(sp.simplify(k.dependent_speeds)))
        print("  M̃ =", sp.simplify(k.mass_matrix).tolist())
        print("  f̃ =", list(sp.simplify(k.forcing)))

    print("\nskate equilibrium, a force F perpendicular to the runner:")
    for at, where in ((0, "through C"), (l, "through P")):
        system, args = skate(force_at=at)
        print(f"  {where}: F̃_r = {list(sp.simplify(eg.kane(system, **args).active_forces))}")

    system, args = rolling_disk()
    f = eg.codegen(eg.kane(system, **args))
    p = {"m": 1.3, "R": 0.3, "g": 9.81}
    sol = solve_ivp(lambda t, x: f.rhs(t, x, params=p), (0, 10), [0, 0, 0.2, 0, 0.5, 4.0], method="DOP853",
                    rtol=1e-12, atol=1e-12)
    x, y, theta, phi, theta_d, phi_d = sol.y[:, -1]
    print(f"\nrolling disk after 10 s: x = {x:.4f}, y = {y:.4f}, heading {theta:.4f}, spin rate {phi_d:.4f} "
          f"(a circle of radius R φ̇/θ̇ = {0.3 * 4.0 / 0.5:.2f} m)")


if __name__ == "__main__":
    main()
