"""The Whipple bicycle built from its parts: a rear frame on a free-flying base, the rear wheel, the front
frame on the tilted steer axis, the front wheel, and two rolling contacts (`bicycle_on_rails`: the same
bicycle with the rear frame on rails, yaw and roll about the rear contact line, sympy's and Moore's
formulation, its rear wheel grounded by the tree); the benchmark parameters of
Meijaard, Papadopoulos, Ruina and Schwab (2007). Linearized about upright running at speed v by finite
differences of the generated right-hand side: the eigenvalues at v = 0 … 10 m/s and the weave and
capsize speeds.

Run: python examples/whipple_bicycle.py"""
from __future__ import annotations

import numpy as np
import sympy as sp
from scipy.optimize import brentq

import eomgen as eg

# Meijaard et al. 2007, Table 1: axes x forward, y right, z down, origin at the rear contact;
# the inertia matrices of the rear body B and the front handlebar assembly H about their mass centres.
BENCHMARK = {"w": 1.02, "c": 0.08, "lam": np.pi / 10, "g": 9.81,
             "r_R": 0.3, "m_R": 2.0, "I_Rxx": 0.0603, "I_Ryy": 0.12,
             "x_B": 0.3, "z_B": -0.9, "m_B": 85.0, "I_Bxx": 9.2, "I_Byy": 11.0, "I_Bzz": 2.8, "I_Bxz": 2.4,
             "x_H": 0.9, "z_H": -0.7, "m_H": 4.0, "I_Hxx": 0.05892, "I_Hyy": 0.06, "I_Hzz": 0.00708,
             "I_Hxz": -0.00756,
             "r_F": 0.35, "m_F": 3.0, "I_Fxx": 0.1405, "I_Fyy": 0.28}
SIGNED = ("x_B", "z_B", "x_H", "z_H", "I_Bxz", "I_Hxz")  # the others positive: g > 0, the ground faces −z
P = {name: sp.Symbol(name, real=True) if name in SIGNED else sp.Symbol(name, positive=True)
     for name in BENCHMARK}


def derivative(f, x0, h: float = 0.05, levels: int = 5) -> np.ndarray:
    """J = ∂f/∂x at x0: central differences D(h) = (f(x0 + h e_k) − f(x0 − h e_k)) / 2h at h, h/2, …,
    Richardson-extrapolated (D(h) = J + a h² + b h⁴ + …)."""
    x0 = np.asarray(x0, dtype=float)
    columns = []
    for k in range(len(x0)):
        e = np.eye(len(x0))[k]
        table: list[list[np.ndarray]] = []
        for i in range(levels):
            step = h / 2**i
            row = [(np.asarray(f(x0 + step * e)) - np.asarray(f(x0 - step * e))) / (2 * step)]
            for j in range(1, i + 1):
                row.append(row[j - 1] + (row[j - 1] - table[i - 1][j - 1]) / (4**j - 1))
            table.append(row)
        columns.append(table[-1][-1])
    return np.column_stack(columns)


def state_matrix(accelerations, v: float) -> np.ndarray:
    """A of ẋ = A x, x = (roll φ, steer δ, φ̇, δ̇), about upright running at speed v: accelerations(x, v)
    gives (φ̈, δ̈) at the state x."""
    return np.vstack([np.eye(4)[2:], derivative(lambda x: accelerations(x, v), np.zeros(4))])


def stable_speeds(eigenvalues) -> tuple[float, float]:
    """The weave and capsize speeds: where the largest real part of eigenvalues(v) crosses zero, downwards
    (weave, between 4 and 5 m/s) and upwards (capsize, between 5 and 7 m/s)."""
    def abscissa(v):
        return eigenvalues(v).real.max()
    return brentq(abscissa, 4.0, 5.0, xtol=1e-14), brentq(abscissa, 5.0, 7.0, xtol=1e-14)


def inertia(body: str) -> sp.Matrix:
    """The inertia matrix of the rear body "B" or the front assembly "H" (symmetric about the xz plane)."""
    I = {k: P[f"I_{body}{k}"] for k in ("xx", "yy", "zz", "xz")}
    return sp.Matrix([[I["xx"], 0, I["xz"]], [0, I["yy"], 0], [I["xz"], 0, I["zz"]]])


def wheels_and_fork(system: eg.System, rear: eg.Body) -> None:
    """Onto the rear frame `rear` (origin at the rear wheel's centre, axes as the benchmark's at upright):
    the rear wheel R spinning about its axle y, the front frame H steering about the axis tilted back by
    λ through the point at trail c ahead of the front contact, the front wheel F, and both rolling disks."""
    p = P
    rear_wheel = system.add_body("rear_wheel", parent=rear, joint=eg.Revolute("spin_R", axis=(0, 1, 0)),
                                 mass=p["m_R"], inertia=sp.diag(p["I_Rxx"], p["I_Ryy"], p["I_Rxx"]))
    steer = eg.Revolute("steer", axis=(sp.sin(p["lam"]), 0, sp.cos(p["lam"])))  # down the steer axis
    at_ground = eg.Placement(translation=(p["w"] + p["c"], 0, p["r_R"]))  # the steer axis meets the ground
    front = system.add_body("front_frame", parent=rear, joint=steer, mass=p["m_H"], placement=at_ground,
                            com=(p["x_H"] - p["w"] - p["c"], 0, p["z_H"]),
                            inertia=inertia("H"))
    front_wheel = system.add_body("front_wheel", parent=front, joint=eg.Revolute("spin_F", axis=(0, 1, 0)),
                                  placement=eg.Placement(translation=(-p["c"], 0, -p["r_F"])),
                                  mass=p["m_F"], inertia=sp.diag(p["I_Fxx"], p["I_Fyy"], p["I_Fxx"]))
    system.add_rolling(rear_wheel, radius=p["r_R"])
    system.add_rolling(front_wheel, radius=p["r_F"])


def rear_frame(system: eg.System, parent, joint: eg.Joint, placement: eg.Placement | None = None) -> eg.Body:
    """The rear frame B (origin at the rear wheel's centre) on `joint`."""
    p = P
    return system.add_body("rear_frame", parent=parent, joint=joint, placement=placement, mass=p["m_B"],
                           com=(p["x_B"], 0, p["z_B"] + p["r_R"]), inertia=inertia("B"))


def bicycle() -> tuple[eg.System, eg.KaneEquations]:
    """The bicycle from its parts, in the benchmark's axes (x forward, y right, z down; gravity +z):
    the rear frame B on a free-flying base (x, y, z, yaw, pitch, roll; origin at the rear wheel's
    centre), then `wheels_and_fork`. Kane's equations in the roll, steer and rear spin rates; z and the
    pitch follow from the wheels' contacts (holonomic), the other speeds from rolling without slip."""
    system = eg.System(gravity=(0, 0, P["g"]))
    wheels_and_fork(system, rear_frame(system, None, eg.FreeFlyer("rear", parametrization="euler")))
    x, y, z, yaw, pitch, roll, spin_R, delta, spin_F = system.q
    u = dict(zip(system.q, system.u))
    k = eg.kane(system, dependent_coordinates=[z, pitch], independent=[u[roll], u[delta], u[spin_R]])
    return system, k


def bicycle_on_rails() -> tuple[eg.System, eg.KaneEquations]:
    """The same bicycle in sympy's and Moore's formulation: rails x, y (the rear contact point), the yaw,
    the roll about the rear contact line, the rear wheel's centre r_R above the contact along the leaned
    frame's up axis (−z), the rear frame's pitch about the rear axle, then `wheels_and_fork`. The tree
    keeps the rear wheel on the ground (its disk is grounded); only the front wheel's height is a
    holonomic constraint, with the pitch dependent."""
    system = eg.System(gravity=(0, 0, P["g"]))
    parent = None
    for name, axis in (("x", (1, 0, 0)), ("y", (0, 1, 0))):
        parent = system.add_body(f"rail_{name}", parent=parent, joint=eg.Prismatic(name, axis=axis))
    system.add_body("yawed", parent=parent, joint=eg.Revolute("yaw", axis=(0, 0, 1)))
    system.add_body("leaned", parent="yawed", joint=eg.Revolute("roll", axis=(1, 0, 0)))
    rear = rear_frame(system, "leaned", eg.Revolute("pitch", axis=(0, 1, 0)),
                      eg.Placement(translation=(0, 0, -P["r_R"])))
    wheels_and_fork(system, rear)
    x, y, yaw, roll, pitch, spin_R, delta, spin_F = system.q
    u = dict(zip(system.q, system.u))
    k = eg.kane(system, dependent_coordinates=[pitch], independent=[u[roll], u[delta], u[spin_R]])
    return system, k


def accelerations(f, values: dict = BENCHMARK):
    """(φ̈, δ̈)(x, v) of the generated equations `f` (either builder) at x = (roll φ, steer δ, φ̇, δ̇),
    rolling at speed v: q assembled from φ, δ and zeros (the dependent coordinates from the contacts),
    w = (φ̇, δ̇, rear spin −v/r_R). Roll and steer are the coordinates of the first two independent
    speeds (u = q̇ on both trees)."""
    k = f.kane
    roll, steer = (list(k.system.u).index(speed) for speed in k.independent[:2])

    def at(x, v):
        phi, delta, phid, deltad = x
        guess = np.zeros(f.nq)
        guess[[roll, steer]] = phi, delta
        q = f.assemble(guess, values)
        return f.rhs(0.0, np.r_[q, phid, deltad, -v / values["r_R"]], params=values)[-3:-1]
    return at


def eigenvalues(f, v: float) -> np.ndarray:
    """The eigenvalues of the linearized bicycle at speed v, sorted (numpy.sort_complex)."""
    return np.sort_complex(np.linalg.eigvals(state_matrix(accelerations(f), v)))


def main() -> None:
    system, k = bicycle()
    f = eg.codegen(k)
    print(f"{len(system.q)} coordinates {list(system.q)}; Kane's equations in {k.independent}, dependent "
          f"speeds {k.dependent}, dependent coordinates {k.dependent_coordinates}")
    print(f"\n{'v [m/s]':>7s}  eigenvalues of the linearized bicycle (roll, steer, their rates)")
    for v in range(11):
        print(f"{v:7d}  " + "  ".join(f"{e.real:+.10f}{e.imag:+.10f}i" for e in eigenvalues(f, float(v))))
    weave, capsize = stable_speeds(lambda v: eigenvalues(f, v))
    print(f"\nweave speed {weave:.12f} m/s, capsize speed {capsize:.12f} m/s: self-stable in between")


if __name__ == "__main__":
    main()
