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
    with pytest.raises(eg.ModelError, match=r"quantities: a subset of \('M', 'b', 'g'\); unknown \['tau'\]"):
        eg.derive(system, quantities=("g", "tau"))
    with pytest.raises(eg.ModelError, match="unknown frame 'no_frame'"):
        eg.derive(system, quantities=(), frames=["no_frame"])
    with pytest.raises(eg.ModelError, match="reduced: unknown joints"):
        system.reduced({"no_joint": 0.0})


@pytest.mark.parametrize("method", ["projected_newton_euler", "lagrange", "free_cut", "recursive"])
def test_each_method_derives_only_what_is_asked(method):
    """ur5: each single quantity alone equals Pinocchio (crba, nonLinearEffects − g,
    computeGeneralizedGravity) and costs fewer intermediates than the full set."""
    import pinocchio as pin

    system = eg.robots.load("ur5")
    model = system.pinocchio_model
    data = model.createData()
    q, u, _ = eg.random_states(system, 5, np.random.default_rng(21))
    full = len(eg.derive(system, method=method).subexpressions.definitions)
    for key in ("M", "b", "g"):
        eom = eg.derive(system, method=method, quantities=[key])
        assert eom.quantities == (key,)
        assert len(eom.subexpressions.definitions) < full, key
        f = eg.codegen(eom)
        for k in range(5):
            expected = {"M": lambda: pin.crba(model, data, q[k]),
                        "g": lambda: pin.computeGeneralizedGravity(model, data, q[k]),
                        "b": lambda: pin.nonLinearEffects(model, data, q[k], u[k])
                        - pin.computeGeneralizedGravity(model, data, q[k])}[key]()
            got = f.M(q[k]) if key == "M" else f.b(q[k], u[k]) if key == "b" else f.g(q[k])
            np.testing.assert_allclose(np.triu(got) if key == "M" else got, np.triu(expected) if key == "M" else expected,
                                       rtol=0, atol=1e-10, err_msg=f"{method} {key}")
    if method == "free_cut":
        with pytest.raises(eg.ModelError, match="free cut with all of M, b, g"):
            eg.derive(system, method=method, quantities=("M", "g")).reactions


@pytest.mark.parametrize("backend", ["numpy", "c"])
def test_contact_scene_derives_only_its_frames(backend, tmp_path, monkeypatch):
    """solo12 with its feet: quantities=() and frames= gives the foot Jacobians and J̇ u alone
    (= Pinocchio's LOCAL_WORLD_ALIGNED frame Jacobian and classical acceleration), built up front."""
    import pinocchio as pin

    from eomgen.model.urdf import pinocchio_configuration

    monkeypatch.setenv("EOMGEN_CACHE", str(tmp_path))
    system = eg.robots.load("solo12")
    feet = ["FL_FOOT", "HR_FOOT"]
    eom = eg.derive(system, method="recursive", quantities=(), frames=feet)
    assert eom.quantities == () and eom.frames == feet
    f = eg.codegen(eom, backend=backend)
    assert sorted(f.functions) == sorted(f"{k}:{foot}" for foot in feet for k in ("J", "Jdot_u"))
    model = system.pinocchio_model
    data = model.createData()
    q, u, _ = eg.random_states(system, 4, np.random.default_rng(22))
    qp = pinocchio_configuration(system, q)
    for k in range(4):
        pin.forwardKinematics(model, data, qp[k], u[k], np.zeros(model.nv))
        pin.computeJointJacobians(model, data, qp[k])
        pin.updateFramePlacements(model, data)
        for foot in feet:
            fid = model.getFrameId(foot)
            J = pin.getFrameJacobian(model, data, fid, pin.LOCAL_WORLD_ALIGNED)
            a = pin.getFrameClassicalAcceleration(model, data, fid, pin.LOCAL_WORLD_ALIGNED)
            np.testing.assert_allclose(f.jacobian(foot, q[k]), J, rtol=0, atol=1e-10)
            np.testing.assert_allclose(f.jacobian_dot_u(foot, q[k], u[k]), a.vector, rtol=0, atol=1e-10)
    with pytest.raises(eg.ModelError, match="M was not derived"):
        f.M(q[0])
