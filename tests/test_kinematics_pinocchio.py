"""Frame Jacobians and J̇u against Pinocchio (getFrameJacobian and getFrameJacobianTimeVariation,
LOCAL_WORLD_ALIGNED), on a tree with a rotated tool frame."""
import numpy as np
import pinocchio as pin

import eomgen as eg
from models import ARM6, numeric_arm
from test_pinocchio import pinocchio_model


def test_frame_jacobians():
    rng = np.random.default_rng(11)
    system, spec = numeric_arm(rng, ARM6, branch_at=2)
    R_tool = np.array([[0, -1, 0], [1, 0, 0], [0, 0, 1]], float)
    p_tool = np.array([0.1, -0.05, 0.2])
    system.add_frame("tool", "link4", eg.Placement(rotation=R_tool.tolist(), translation=tuple(p_tool)))
    model, ids = pinocchio_model(system, spec)
    model.addFrame(pin.Frame("tool", ids[4], pin.SE3(R_tool, p_tool), pin.FrameType.OP_FRAME))
    for i in range(6):
        model.addFrame(pin.Frame(f"link{i}", ids[i], pin.SE3.Identity(), pin.FrameType.BODY))
    data = model.createData()
    f = eg.codegen(eg.derive(system))
    LWA = pin.ReferenceFrame.LOCAL_WORLD_ALIGNED
    for _ in range(20):
        q, u = rng.uniform(-3, 3, 6), rng.uniform(-3, 3, 6)
        pin.computeJointJacobiansTimeVariation(model, data, q, u)
        pin.updateFramePlacements(model, data)
        for name in ["tool", "link5", "link1"]:
            fid = model.getFrameId(name)
            J = pin.getFrameJacobian(model, data, fid, LWA)
            Jdot = pin.getFrameJacobianTimeVariation(model, data, fid, LWA)
            np.testing.assert_allclose(f.jacobian(name, q), J, rtol=0, atol=1e-12)
            np.testing.assert_allclose(f.jacobian_dot_u(name, q, u), Jdot @ u, rtol=0, atol=1e-11)
