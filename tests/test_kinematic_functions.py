"""Frame placements, centre of mass, its Jacobian and the centroidal momentum matrix as generated functions,
against Pinocchio: `updateFramePlacements` (oMf), `centerOfMass`, `jacobianCenterOfMass`, `ccrba` on robots
of example-robot-data and on random trees with every joint type built with Pinocchio's own API."""
import numpy as np
import pinocchio as pin
import pytest
from hypothesis import HealthCheck, Phase, given, settings

import eomgen as eg
import strategies as S
from eomgen.model import pinocchio_configuration
from eomgen.verify import to_pinocchio


def pinocchio_values(model, data, qp, u):
    c = pin.centerOfMass(model, data, qp)
    J_com = pin.jacobianCenterOfMass(model, data, qp).reshape(3, model.nv)
    A_G = pin.ccrba(model, data, qp, u).reshape(6, model.nv).copy()
    pin.framesForwardKinematics(model, data, qp)
    return c, J_com, A_G


@pytest.mark.parametrize("name, backend", [("ur5", "numpy"), ("panda", "numpy"), ("solo12", "numpy"),
                                           ("ur5", "c")])
def test_robots_equal_pinocchio(name, backend):
    system = eg.robots.load(name)
    f = eg.codegen(eg.derive(system, method="recursive", quantities=()), backend=backend)
    model = to_pinocchio(system)
    data = model.createData()
    q, u, _ = eg.random_states(system, 4, np.random.default_rng(1))
    frames = [system.bodies[-1].name, list(system.frames)[-1]]
    for k in range(len(q)):
        c, J_com, A_G = pinocchio_values(model, data, pinocchio_configuration(system, q[k]), u[k])
        np.testing.assert_allclose(f.com(q[k]), c, atol=1e-13)
        np.testing.assert_allclose(f.com_jacobian(q[k]), J_com, atol=1e-13)
        np.testing.assert_allclose(f.centroidal_momentum_matrix(q[k]), A_G, atol=1e-12)
        np.testing.assert_allclose(f.centroidal_momentum(q[k], u[k]), A_G @ u[k], atol=1e-12)
        for frame in frames:
            R, p = f.placement(frame, q[k])
            oMf = data.oMf[model.getFrameId(frame)]
            np.testing.assert_allclose(R, oMf.rotation, atol=1e-13)
            np.testing.assert_allclose(p, oMf.translation, atol=1e-13)
    batch = f.com(q)  # N states at once
    assert batch.shape == (len(q), 3) and np.allclose(batch[1], f.com(q[1]), atol=1e-15)


@settings(max_examples=25, deadline=None, derandomize=True, suppress_health_check=list(HealthCheck),
          phases=[Phase.generate])
@given(tree=S.trees(max_bodies=5, loads=False))
def test_random_trees_equal_pinocchio(tree):
    """Every joint type; the Pinocchio model built with its own API (speeds permuted into eomgen's order)."""
    f = eg.codegen(eg.derive(S.eomgen_system(tree), method="recursive", quantities=()))
    ref = S.PinocchioTree(tree)
    model, data = ref.model, ref.data
    q, u = S.random_state(tree, np.random.default_rng(0))
    qp, up = ref.configuration(q), np.asarray(u, float)[ref.perm]
    c, J_com, A_G = pinocchio_values(model, data, qp, up)
    J, A = np.zeros_like(J_com), np.zeros_like(A_G)
    J[:, ref.perm], A[:, ref.perm] = J_com, A_G
    np.testing.assert_allclose(f.com(q), c, atol=1e-12)
    np.testing.assert_allclose(f.com_jacobian(q), J, atol=1e-12)
    np.testing.assert_allclose(f.centroidal_momentum_matrix(q), A, atol=1e-11)
    for i, b in enumerate(tree.bodies):
        R, p = f.placement(b.name, q)
        oMf = data.oMf[ref.frame_ids[("body", i)]]
        np.testing.assert_allclose(R, oMf.rotation, atol=1e-12)
        np.testing.assert_allclose(p, oMf.translation, atol=1e-12)


def test_bad_requests_are_refused():
    system = eg.System()
    system.add_body("arm", joint=eg.Revolute("q", axis=(0, 0, 1)), mass=1, inertia=np.eye(3))
    f = eg.codegen(eg.derive(system, method="recursive", quantities=()))
    with pytest.raises(eg.ModelError, match="unknown frame 'hand'"):
        f.placement("hand", np.zeros(1))
    moving = eg.System()  # a body fixed to the world is part of it, as in Pinocchio
    moving.add_body("stand", mass=5, inertia=np.eye(3))
    moving.add_body("arm", parent="stand", joint=eg.Revolute("q", axis=(0, 0, 1)))
    moving.add_body("tip", parent="arm", mass=0, inertia=np.eye(3))
    g = eg.codegen(eg.derive(moving, method="recursive", quantities=()))
    with pytest.raises(eg.ModelError, match="moving bodies have no mass"):
        g.com(np.zeros(1))
