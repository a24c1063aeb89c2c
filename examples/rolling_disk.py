"""A uniform thin disk rolling without slip, built from its parts: the centre on rails x, y, z, the
heading (yaw), the lean and the spin on revolute joints, and `add_rolling` for the contact with the
ground; Kane's equations take the rolling disk's height (z dependent) and its no-slip rows. Upright
rolling is stable above the critical spin rate ω² = g/(3R): a small lean stays small at 1.2 times it
and grows (the disk falls) at 0.8 times it.

Run: python examples/rolling_disk.py"""
import numpy as np
import sympy as sp
from scipy.integrate import solve_ivp

import eomgen as eg

m, R, g = sp.symbols("m R g", positive=True)
VALUES = {"m": 1.0, "R": 0.3, "g": 9.81}
LEAN = 4  # the lean angle's index in q = (x, y, z, yaw, lean, spin)


def rolling_disk() -> tuple[eg.System, eg.KaneEquations]:
    """The disk (I = m R²/4 about a diameter, m R²/2 about the axle y) and its Kane's equations in the
    yaw, lean and spin rates; ẋ, ẏ, ż follow from rolling, z from the contact."""
    system = eg.System(gravity=(0, 0, -g))
    parent = None
    for name, axis in (("x", (1, 0, 0)), ("y", (0, 1, 0)), ("z", (0, 0, 1))):
        parent = system.add_body(f"rail_{name}", parent=parent, joint=eg.Prismatic(name, axis=axis))
    for name, axis in (("yaw", (0, 0, 1)), ("lean", (1, 0, 0))):
        parent = system.add_body(name, parent=parent, joint=eg.Revolute(name, axis=axis))
    disk = system.add_body("disk", parent=parent, joint=eg.Revolute("spin", axis=(0, 1, 0)), mass=m,
                           inertia=sp.diag(m * R**2 / 4, m * R**2 / 2, m * R**2 / 4))
    system.add_rolling(disk, radius=R, axis=(0, 1, 0))
    k = eg.kane(system, dependent_coordinates=[system.q[2]], independent=list(system.u[3:]))
    return system, k


def critical_spin(values: dict = VALUES) -> float:
    """ω_c = √(g / (3 R))."""
    return float(np.sqrt(values["g"] / (3 * values["R"])))


def roll(f, factor: float, lean: float = 0.02, seconds: float = 6.0, values: dict = VALUES):
    """Rolling upright at `factor` × ω_c with a small initial lean (q assembled: z = R cos lean); stops
    if the disk leans past 1 rad. Returns scipy's solution."""
    q = f.assemble(np.array([0, 0, values["R"], 0, lean, 0]), values)
    x0 = np.r_[q, 0.0, 0.0, factor * critical_spin(values)]
    fell = lambda t, x: abs(x[LEAN]) - 1.0  # noqa: E731
    fell.terminal = True
    return solve_ivp(lambda t, x: f.rhs(t, x, params=values), (0, seconds), x0, method="DOP853", rtol=1e-10,
                     atol=1e-10, events=fell, max_step=0.05)


if __name__ == "__main__":
    system, k = rolling_disk()
    f = eg.codegen(k)
    print(f"critical spin rate √(g/(3R)) = {critical_spin():.4f} rad/s (R = {VALUES['R']} m)")
    for factor in (1.2, 0.8):
        sol = roll(f, factor)
        lean = np.abs(sol.y[LEAN])
        fate = f"fell (|lean| > 1 rad) at t = {sol.t[-1]:.2f} s" if sol.status == 1 else "stayed up"
        print(f"{factor} × ω_c: lean 0.02 rad → largest |lean| {lean.max():.4f} rad over {sol.t[-1]:.1f} s: "
              f"{fate}; height residual {np.abs(f.holonomic_residual(sol.y[:6].T, VALUES)).max():.1e}")
