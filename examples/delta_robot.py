"""A Delta parallel robot: three arms on actuated revolute shoulders around a fixed base, forearms on
universal joints at the elbows, a translating platform; each forearm's wrist joined to the platform by a
point loop (a ball joint). 12 coordinates, 9 loop rows, 3 degrees of freedom: the shoulder angles.
Assembled for given shoulder angles, reduced to them, and simulated holding the platform in place.

Run: python examples/delta_robot.py"""
import numpy as np

import eomgen as eg

BASE, PLATFORM, ARM, FOREARM = 0.2, 0.05, 0.3, 0.8  # base and platform radii, arm and forearm lengths
MASSES = dict(arm=0.4, forearm=0.2, platform=0.5)
ANGLES = (0.0, 2 * np.pi / 3, 4 * np.pi / 3)  # the arms' directions about z


def turn_z(angle: float) -> np.ndarray:
    c, s = np.cos(angle), np.sin(angle)
    return np.array([[c, -s, 0], [s, c, 0], [0, 0, 1]])


def delta_robot() -> eg.System:
    """Arm i at the base radius in direction γ_i, turning about the tangent (body y; θ > 0 down); its
    forearm hangs along its −z at the elbow on a universal joint (axes y, then x); the platform moves on
    a Translation joint (platform_x, _y, _z) and carries the ball joints at the platform radius."""
    system = eg.System(gravity=(0, 0, -9.81))
    platform = system.add_body("platform", joint=eg.Translation("platform", actuated=False),
                               mass=MASSES["platform"], inertia=np.eye(3) * 1e-3)
    for i, gamma in enumerate(ANGLES, start=1):
        radial = np.array([np.cos(gamma), np.sin(gamma), 0])
        arm = system.add_body(f"arm{i}", joint=eg.Revolute(f"shoulder{i}", axis=(0, 1, 0)),
                              placement=eg.Placement(rotation=turn_z(gamma), translation=BASE * radial),
                              mass=MASSES["arm"], com=(ARM / 2, 0, 0),
                              inertia=np.diag([1e-4, 1, 1]) * MASSES["arm"] * ARM**2 / 12)
        forearm = system.add_body(f"forearm{i}", parent=arm, placement=eg.Placement(translation=(ARM, 0, 0)),
                                  joint=eg.Universal(f"elbow{i}", axis1=(0, 1, 0), axis2=(1, 0, 0),
                                                     actuated=False),
                                  mass=MASSES["forearm"], com=(0, 0, -FOREARM / 2),
                                  inertia=np.diag([1, 1, 1e-4]) * MASSES["forearm"] * FOREARM**2 / 12)
        system.add_frame(f"wrist{i}", forearm, eg.Placement(translation=(0, 0, -FOREARM)))
        system.add_frame(f"ball{i}", platform, eg.Placement(translation=PLATFORM * radial))
        system.add_loop(f"wrist{i}", f"ball{i}", kind="point", name=f"leg{i}")
    return system


SHOULDERS = ["shoulder1", "shoulder2", "shoulder3"]


def guess(theta) -> np.ndarray:
    """A q near the working pose: forearms hanging straight down, the platform below the elbows."""
    q = np.zeros(12)
    q[2] = -FOREARM + ARM * -np.sin(np.mean(theta))
    for k, t in enumerate(theta):
        q[3 + 3 * k], q[4 + 3 * k] = t, -t  # shoulder, elbow's first axis undoes it
    return q


def main() -> None:
    system = delta_robot()
    f = eg.codegen(eom := eg.derive(system, method="recursive"))
    print("coordinates:", [str(x) for x in system.q])
    reduced = eg.reduce(eom, independent=SHOULDERS)
    for theta in ([0.3, 0.3, 0.3], [0.1, 0.5, 0.4]):
        q = eg.assemble(f, guess(theta), fixed=SHOULDERS)
        residual = np.linalg.norm(f.closure_residual(q))
        print(f"θ = {theta}: platform at {np.round(q[:3], 6)}; ‖r‖ = {residual:.1e}")
        print("  reduced M:\n", np.round(reduced.M(q), 6))
        print("  shoulder torques holding it still (g_r):", np.round(reduced.g(q), 6))
    q0 = eg.assemble(f, guess([0.3, 0.3, 0.3]), fixed=SHOULDERS)
    hold = reduced.g(q0)
    sim = eg.simulate(f, (q0, np.zeros(12)), (0, 1), tau=hold)
    print(f"1 s with the holding torques: platform moved {np.linalg.norm(sim.q[-1, :3] - q0[:3]):.1e} m; "
          f"max ‖r‖ {sim.closure_drift.max():.1e}, max ‖J_c u‖ {sim.velocity_drift.max():.1e}")


if __name__ == "__main__":
    main()
