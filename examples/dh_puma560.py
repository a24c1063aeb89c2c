"""The Puma 560 from its DH table (issue 14): derive M, b, g, generate NumPy code, compare with
Pinocchio at random states, and print the table, M at the zero pose and the gravity torques.

The table (standard DH, dynamics of Corke & Armstrong-Hélouvry 1994) ships as
`eg.robots.load("puma560")`; tests/test_dh.py also checks it against the Robotics Toolbox's own results.

Run: python examples/dh_puma560.py"""
import numpy as np
import sympy as sp

import eomgen as eg
from eomgen.model import dh_tables


def print_table(links) -> None:
    print(f"{'link':>4s} {'d [m]':>8s} {'a [m]':>8s} {'alpha':>7s} {'m [kg]':>7s} {'G':>9s} "
          f"{'Jm [kg m²]':>11s} {'armature G² Jm':>15s}")
    for i, link in enumerate(links, start=1):
        alpha = sp.nsimplify(link.alpha / sp.pi)
        armature = float(link.gear_ratio) ** 2 * float(link.motor_inertia)
        print(f"{i:4d} {float(link.d):8.4f} {float(link.a):8.4f} {str(alpha) + 'π':>7s} "
              f"{float(link.mass):7.2f} {float(link.gear_ratio):9.4f} {float(link.motor_inertia):11.2e} "
              f"{armature:15.4f}")


def main() -> None:
    links = dh_tables.puma560()
    print("Puma 560, standard DH (Corke & Armstrong-Hélouvry 1994):")
    print_table(links)

    system = eg.robots.load("puma560")
    print(f"\nbodies {[b.name for b in system.bodies]}, frames {list(system.frames)}")
    f = eg.codegen(eg.derive(system, frames=["dh6"]), backend="numpy")
    print(eg.verify(system, states=20))  # Pinocchio built from the System, at 20 random states

    qz, qn = np.zeros(6), np.array([0, np.pi / 4, np.pi, 0, np.pi / 4, 0])
    np.set_printoptions(precision=4, suppress=True, linewidth=110)
    print("\nM(qz), qz = 0 (armature included):")
    print(f.M(qz))
    print(f"g(qn), qn = (0, π/4, π, 0, π/4, 0): {f.g(qn)} N m")
    print("Jacobian [J_P; J_R] of DH frame 6 at qn (world axes):")
    print(f.jacobian("dh6", qn))


if __name__ == "__main__":
    main()
