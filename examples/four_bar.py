"""A planar four-bar linkage: crank, coupler and rocker on revolute joints, the coupler's end joined to
the rocker's end by a loop closure. Assembled at a crank angle, reduced to the crank's equation
J(θ) θ̈ + ½ J'(θ) θ̇² + V'(θ) = τ, its loop force, and simulated for 10 s with each stabilisation.

Run: python examples/four_bar.py"""
import numpy as np

import eomgen as eg

LENGTHS = (0.3, 1.0, 0.8, 0.9)  # crank a, coupler b, rocker c, ground d (Grashof: the crank turns fully)
MASSES = (1.0, 2.0, 1.5)


def rod(mass: float, length: float) -> dict:
    """A uniform thin rod along x from the body origin: mass, centre of mass, inertia about it."""
    return dict(mass=mass, com=(length / 2, 0, 0), inertia=np.diag([0, 1, 1]) * mass * length**2 / 12)


def four_bar(lengths=LENGTHS, masses=MASSES, kind: str = "revolute") -> eg.System:
    """Crank th1 from the world at the origin, coupler th2 (relative to the crank) at its end, rocker th3
    from the world at (d, 0, 0); gravity along −y; the loop (`kind`) joins the coupler's end to the rocker's
    end. Only the crank is actuated."""
    a, b, c, d = lengths
    system = eg.System(gravity=(0, -9.81, 0))
    crank = system.add_body("crank", joint=eg.Revolute("th1"), **rod(masses[0], a))
    coupler = system.add_body("coupler", parent=crank, joint=eg.Revolute("th2", actuated=False),
                              placement=eg.Placement(translation=(a, 0, 0)), **rod(masses[1], b))
    rocker = system.add_body("rocker", joint=eg.Revolute("th3", actuated=False),
                             placement=eg.Placement(translation=(d, 0, 0)), **rod(masses[2], c))
    system.add_frame("coupler_end", coupler, eg.Placement(translation=(b, 0, 0)))
    system.add_frame("rocker_end", rocker, eg.Placement(translation=(c, 0, 0)))
    system.add_loop("coupler_end", "rocker_end", kind=kind, name="loop")
    return system


def main() -> None:
    f = eg.codegen(eom := eg.derive(four_bar(), method="recursive"))
    reduced = eg.reduce(eom, independent=["th1"])
    print(" θ1     th2      th3      J(θ)     V'(θ)   loop force (θ̇ = 1, τ = 0)")
    q = np.array([0.0, 1.2, 1.5])
    for k, theta in enumerate(np.linspace(0, 2 * np.pi, 37)[:-1]):  # in 10° steps: on one branch
        q = eg.assemble(f, np.r_[theta, q[1:]], fixed=["th1"])
        if k % 6:
            continue
        u = reduced.R(q) @ [1.0]
        F = f.constraint_forces(q, u)["loop"]
        print(f"{theta:5.2f} {q[1]:8.4f} {q[2]:8.4f} {reduced.M(q)[0, 0]:8.4f} {reduced.g(q)[0]:8.3f}   "
              f"({F[0]:8.3f}, {F[1]:8.3f})")
    q0 = eg.assemble(f, [0.3, 1.2, 1.5], fixed=["th1"])
    u0 = reduced.R(q0) @ [2.0]
    print("\n10 s from θ1 = 0.3, θ̇1 = 2 (no load): max ‖r‖, max ‖J_c u‖, energy spread")
    for rtol in (1e-6, 1e-10):
        for stabilization in ("projection", "baumgarte", None):
            sim = eg.simulate(f, (q0, u0), (0, 10), stabilization=stabilization, rtol=rtol, atol=rtol)
            print(f"rtol {rtol:.0e} {str(stabilization):>10}: {sim.closure_drift.max():.1e}  "
                  f"{sim.velocity_drift.max():.1e}  {np.ptp(sim.energy):.1e}")


if __name__ == "__main__":
    main()
