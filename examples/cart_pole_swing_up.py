"""Swinging a cart-pole up by direct collocation: eomgen's CasADi inverse dynamics in a `casadi.Opti`
problem solved by IPOPT, the optimal force replayed on the C backend.

The cart-pole of cart_pole_lqr.py (the pole's angle φ from the upward vertical) starts hanging at rest,
(x, φ) = (0, π), and must stand upright at rest, (0, 0), after T seconds, pushed by a force |F| ≤ F_max on a
rail |x| ≤ x_max, with the least effort ∫ F² dt. The Hermite–Simpson transcription is collocation.py's.
The force found is then applied open-loop, interpolated as the transcription assumes, to the compiled C
functions (`eg.simulate`): the pole arrives upright within `TOLERANCE`, which shows that the optimum is a
motion of the equations and not an artefact of the grid.

Run: python examples/cart_pole_swing_up.py [output folder]   (writes cart_pole_swing_up.png)"""
import sys
from pathlib import Path

import numpy as np

import eomgen as eg
from eomgen.simulate import Simulation
from cart_pole_lqr import cart_pole
from collocation import Collocation, Trajectory, figure

T, F_MAX, X_MAX = 2.0, 10.0, 1.0  # s, N, m
HANGING, UPRIGHT = np.array([0.0, np.pi]), np.zeros(2)
TOLERANCE = 0.05  # the re-simulated end: |x|, |φ| (m, rad) and |ẋ|, |φ̇| (m/s, rad/s)


def solve(N: int = 40) -> Trajectory:
    """The least-effort swing-up on N Hermite–Simpson intervals (IPOPT's status in `.status`)."""
    f = eg.codegen(eg.derive(cart_pole(), method="recursive"), backend="casadi")
    problem = Collocation(f, T, N, F_MAX)
    problem.opti.subject_to(problem.opti.bounded(-X_MAX, problem.X[0, :], X_MAX))
    problem.at_rest(0, HANGING)
    problem.at_rest(-1, UPRIGHT)
    problem.guess(HANGING, UPRIGHT)
    return problem.solve()


def replay(trajectory: Trajectory) -> Simulation:
    """The optimal force applied open-loop to the C backend's cart-pole from the hanging rest."""
    f = eg.codegen(eg.derive(cart_pole(), method="recursive"), backend="c")
    return eg.simulate(f, (HANGING, np.zeros(2)), (0.0, T), tau=lambda t, q, u: trajectory.effort(t),
                       t_eval=np.linspace(0.0, T, 201))


def main(folder: Path) -> None:
    trajectory = solve()
    sim = replay(trajectory)
    print(f"IPOPT: {trajectory.status} after {trajectory.iterations} iterations; "
          f"max |F| = {np.abs(trajectory.tau).max():.2f} N (limit {F_MAX} N)")
    print(f"re-simulated end: x = {sim.q[-1, 0]:.2e} m, φ = {sim.q[-1, 1]:.2e} rad, "
          f"ẋ = {sim.u[-1, 0]:.2e} m/s, φ̇ = {sim.u[-1, 1]:.2e} rad/s (tolerance {TOLERANCE})")
    figure(trajectory, sim, "cart-pole swing-up", folder / "cart_pole_swing_up.png")


if __name__ == "__main__":
    main(Path(sys.argv[1]) if len(sys.argv) > 1 else Path("."))
