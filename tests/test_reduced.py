"""Modelling only what a scene needs: locked joints against Pinocchio's buildReducedModel, and
derivations of only the requested quantities."""
import numpy as np
import pinocchio as pin
import pytest

import eomgen as eg


@pytest.mark.parametrize("name,lock", [("ur5", {"shoulder_lift_joint": 0.4, "wrist_2_joint": -1.1}),
                                       ("panda", {"panda_joint3": 0.7, "panda_finger_joint1": 0.01})])
def test_locked_joints_equal_pinocchio_reduced_model(name, lock):
    system = eg.robots.load(name)
    model = system.pinocchio_model
    reduced = system.reduced(lock)
    assert reduced.nq == system.nq - len(lock)
    q_ref = pin.neutral(model)
    for joint, value in lock.items():
        q_ref[model.joints[model.getJointId(joint)].idx_q] = value
    ref = pin.buildReducedModel(model, [model.getJointId(j) for j in lock], q_ref)
    data = ref.createData()
    f = eg.codegen(eg.derive(reduced, method="recursive"))
    q, u, _ = eg.random_states(reduced, 10, np.random.default_rng(14))
    for k in range(10):
        M = pin.crba(ref, data, q[k])
        g = pin.computeGeneralizedGravity(ref, data, q[k])
        np.testing.assert_allclose(f.M(q[k]), np.triu(M) + np.triu(M, 1).T, rtol=0, atol=1e-10)
        np.testing.assert_allclose(f.g(q[k]), g, rtol=0, atol=1e-10 * max(1, np.abs(g).max()))
        np.testing.assert_allclose(f.b(q[k], u[k]), pin.nonLinearEffects(ref, data, q[k], u[k]) - g, rtol=0, atol=1e-10)


def test_only_the_requested_quantities():
    system = eg.robots.load("talos")
    eom = eg.derive(system, method="recursive", quantities=("g",))
    assert "M" not in eom.compact and "b" not in eom.compact
    f = eg.codegen(eom)
    full = eg.codegen(eg.derive(system, method="recursive"))
    q, _, _ = eg.random_states(system, 5, np.random.default_rng(15))
    np.testing.assert_allclose(f.g(q), full.g(q), rtol=1e-13, atol=1e-12)
    with pytest.raises(eg.ModelError, match="M was not derived"):
        f.M(q[0])
    with pytest.raises(eg.ModelError, match="M was not derived"):
        eom.M
    with pytest.raises(eg.ModelError, match="quantities"):
        eg.derive(system, quantities=("g",))  # only the recursive method filters
    with pytest.raises(eg.ModelError, match="reduced: unknown joints"):
        system.reduced({"no_joint": 0.0})
