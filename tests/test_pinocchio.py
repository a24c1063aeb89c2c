"""Against Pinocchio: the same numeric robots built with its own API (Model.addJoint,
appendBodyToJoint); M, b, g at random states equal crba, nonLinearEffects − g and
computeGeneralizedGravity."""
import numpy as np
import pinocchio as pin
import pytest

import eomgen as eg
from models import ARM6, numeric_arm


def pinocchio_model(system, spec):
    model = pin.Model()
    model.gravity.linear = np.array([float(x) for x in system.gravity])
    ids = []
    for i, s in enumerate(spec):
        principal = {(1, 0, 0): "X", (0, 1, 0): "Y", (0, 0, 1): "Z"}.get(tuple(s["axis"]))
        if s["kind"] is eg.Revolute:
            joint = getattr(pin, f"JointModelR{principal}")() if principal else pin.JointModelRevoluteUnaligned(s["axis"])
        else:
            joint = getattr(pin, f"JointModelP{principal}")() if principal else pin.JointModelPrismaticUnaligned(s["axis"])
        parent = 0 if s["parent"] < 0 else ids[s["parent"]]
        jid = model.addJoint(parent, joint, pin.SE3(s["R"], s["p"]), f"q_{i}")
        model.appendBodyToJoint(jid, pin.Inertia(s["m"], s["c"], s["I"]), pin.SE3.Identity())
        ids.append(jid)
    return model, ids


@pytest.mark.parametrize("method", ["projected_newton_euler", "lagrange", "recursive"])
@pytest.mark.parametrize("branch_at", [None, 1])
def test_against_pinocchio(method, branch_at):
    rng = np.random.default_rng(7 if branch_at is None else 8)
    system, spec = numeric_arm(rng, ARM6, branch_at=branch_at)
    model, _ = pinocchio_model(system, spec)
    data = model.createData()
    eom = eg.derive(system, method=method)
    f = eg.codegen(eom)
    for _ in range(20):
        q, u = rng.uniform(-3, 3, 6), rng.uniform(-3, 3, 6)
        M = pin.crba(model, data, q)
        M = np.triu(M) + np.triu(M, 1).T
        g = pin.computeGeneralizedGravity(model, data, q)
        b = pin.nonLinearEffects(model, data, q, u) - g
        np.testing.assert_allclose(f.M(q), M, rtol=0, atol=1e-12 * max(1, np.abs(M).max()))
        np.testing.assert_allclose(f.g(q), g, rtol=0, atol=1e-12 * max(1, np.abs(g).max()))
        np.testing.assert_allclose(f.b(q, u), b, rtol=0, atol=1e-12 * max(1, np.abs(b).max()))
