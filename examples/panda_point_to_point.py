"""A Franka panda's point-to-point motion by direct collocation: eomgen's CasADi inverse dynamics and the
hand's placement "X:panda_hand_tcp" in a `casadi.Opti` problem solved by IPOPT, the optimal torques
replayed on the C backend.

The arm's seven joints (the fingers locked closed, `System.reduced`) start at rest in the "ready" pose and
must bring the hand's tool point to `GOAL`, a quarter turn to the side, pointing straight down (the third
column of its rotation (0, 0, −1): its first two entries zero, the third negative), at rest after T seconds,
within the joint ranges, speeds and torques of panda.urdf's limits, with the least effort
∫ Σ (τ_i / τ_max,i)² dt (collocation.py's Hermite–Simpson transcription). The torques found, applied
open-loop to the compiled C functions (`eg.simulate`), bring the tool point to the goal within `TOLERANCE`.

Run: python examples/panda_point_to_point.py [output folder]   (writes panda_point_to_point.png)"""
import sys
import warnings
from functools import cache
from pathlib import Path

import numpy as np

import eomgen as eg
from eomgen.numeric import NumericEoM
from eomgen.simulate import Simulation
from collocation import Collocation, Trajectory, figure

FINGERS = {"panda_finger_joint1": 0.0, "panda_finger_joint2": 0.0}
TAU_MAX = np.array([87.0, 87.0, 87.0, 87.0, 12.0, 12.0, 12.0])  # N m, panda.urdf's <limit effort>
Q_MIN = np.array([-2.8973, -1.7628, -2.8973, -3.0718, -2.8973, -0.0175, -2.8973])  # rad, its lower
Q_MAX = np.array([2.8973, 1.7628, 2.8973, -0.0698, 2.8973, 3.7525, 2.8973])  # and upper limits
U_MAX = np.array([2.175, 2.175, 2.175, 2.175, 2.61, 2.61, 2.61])  # rad/s, its <limit velocity>
READY = np.array([0.0, -np.pi / 4, 0.0, -3 * np.pi / 4, 0.0, np.pi / 2, np.pi / 4])
GOAL = np.array([0.0, 0.5, 0.3])  # m, the tool point's goal in the world (the arm's base) frame
TOOL, T = "panda_hand_tcp", 0.8  # the frame, the duration (s)
# the re-simulated end: the tool point's distance to the goal (m), its z-axis's to (0, 0, −1), the joints'
# speeds (rad/s); open-loop, the replay drifts from the optimum as the transcription's error, O(h⁴)
TOLERANCE = {"position": 1e-3, "axis": 1e-2, "speed": 0.2}


@cache
def arm() -> eg.EquationsOfMotion:
    """The panda's equations with its fingers locked (a mimic warning on loading: they are locked anyway)."""
    with warnings.catch_warnings():
        warnings.filterwarnings("ignore", message=".*mimic joints")
        system = eg.robots.load("panda")
    return eg.derive(system.reduced(FINGERS), method="recursive")


def solve(N: int = 25) -> Trajectory:
    """The least-effort motion on N Hermite–Simpson intervals (IPOPT's status in `.status`)."""
    f = eg.codegen(arm(), backend="casadi")
    problem = Collocation(f, T, N, TAU_MAX, weights=1 / TAU_MAX ** 2)
    opti, q = problem.opti, problem.X[:7, :]
    opti.subject_to(opti.bounded(Q_MIN[:, None], q, Q_MAX[:, None]))
    opti.subject_to(opti.bounded(-U_MAX[:, None], problem.X[7:, :], U_MAX[:, None]))
    X = f.casadi[f"X:{TOOL}"](q[:, -1])  # [R | p] at the end
    opti.subject_to(X[:, 3] == GOAL)
    opti.subject_to(X[:2, 2] == 0)
    opti.subject_to(X[2, 2] <= 0)
    problem.at_rest(0, READY)
    problem.at_rest(-1)
    problem.guess(READY, READY + np.array([np.arctan2(GOAL[1], GOAL[0]), 0, 0, 0, 0, 0, 0]))
    return problem.solve()


def replay(trajectory: Trajectory) -> tuple[NumericEoM, Simulation]:
    """The C functions and the optimal torques applied open-loop to them from the ready pose at rest."""
    f = eg.codegen(arm(), backend="c")
    sim = eg.simulate(f, (READY, np.zeros(7)), (0.0, T), tau=lambda t, q, u: trajectory.effort(t),
                      t_eval=np.linspace(0.0, T, 161))
    return f, sim


def main(folder: Path) -> None:
    trajectory = solve()
    f, sim = replay(trajectory)
    X = f.call(f"X:{TOOL}", sim.q[-1])
    print(f"IPOPT: {trajectory.status} after {trajectory.iterations} iterations; "
          f"max |τ_i| / τ_max,i = {np.abs(trajectory.tau / TAU_MAX).max():.3f}")
    print(f"re-simulated end: |p − goal| = {np.linalg.norm(X[:, 3] - GOAL):.2e} m, "
          f"|z − (0, 0, −1)| = {np.linalg.norm(X[:, 2] - [0, 0, -1]):.2e}, "
          f"max |u| = {np.abs(sim.u[-1]).max():.2e} rad/s (tolerances {TOLERANCE})")
    figure(trajectory, sim, "panda point to point", folder / "panda_point_to_point.png")


if __name__ == "__main__":
    main(Path(sys.argv[1]) if len(sys.argv) > 1 else Path("."))
