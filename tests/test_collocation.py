"""The trajectory-optimisation examples (examples/cart_pole_swing_up.py, examples/panda_point_to_point.py) on
small grids: IPOPT converges ("Solve_Succeeded", its "Optimal Solution Found") within the limits, and the
optimal efforts replayed open-loop on the C backend reach the goal: the cart-pole upright at rest (the
state 0), the panda's tool point where Pinocchio's forward kinematics of the URDF puts it, pointing down."""
import sys
from pathlib import Path

import numpy as np
import pinocchio as pin

from eomgen.model.robots import paths

sys.path.insert(0, str(Path(__file__).parents[1] / "examples"))
import cart_pole_swing_up as cart_pole  # noqa: E402
import panda_point_to_point as panda  # noqa: E402

SLACK = 1e-6  # IPOPT's interior point may pass a bound by its tolerance


def test_cart_pole_swings_up():
    trajectory = cart_pole.solve(N=30)
    assert trajectory.status == "Solve_Succeeded"
    assert np.abs(trajectory.tau).max() <= cart_pole.F_MAX * (1 + SLACK)
    assert np.abs(trajectory.x[:, 0]).max() <= cart_pole.X_MAX * (1 + SLACK)
    sim = cart_pole.replay(trajectory)
    np.testing.assert_allclose(sim.q[0], [0.0, np.pi])
    assert np.abs(np.concatenate([sim.q[-1], sim.u[-1]])).max() < cart_pole.TOLERANCE
    assert np.abs(sim.balance).max() < 1e-6  # the replay keeps E − E0 = W: the integrator's accuracy


def test_panda_reaches_the_goal_with_torques_within_the_limits():
    trajectory = panda.solve(N=25)
    assert trajectory.status == "Solve_Succeeded"
    assert np.all(np.abs(trajectory.tau) <= panda.TAU_MAX * (1 + SLACK))
    assert np.all(np.abs(trajectory.x[:, 7:]) <= panda.U_MAX * (1 + SLACK))
    _, sim = panda.replay(trajectory)
    model = pin.buildModelFromUrdf(str(paths("panda")[0]))
    data = model.createData()
    pin.framesForwardKinematics(model, data, np.concatenate([sim.q[-1], np.zeros(2)]))  # fingers closed
    tool = data.oMf[model.getFrameId(panda.TOOL)]
    assert np.linalg.norm(tool.translation - panda.GOAL) < panda.TOLERANCE["position"]
    assert np.linalg.norm(tool.rotation[:, 2] - [0, 0, -1]) < panda.TOLERANCE["axis"]
    assert np.abs(sim.u[-1]).max() < panda.TOLERANCE["speed"]
    assert np.all(sim.q >= panda.Q_MIN - 1e-3) and np.all(sim.q <= panda.Q_MAX + 1e-3)
