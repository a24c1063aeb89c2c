"""Contacts on floating-base robots against Pinocchio's constraintDynamics, the support null-space
projector, and a robot standing still."""
import warnings

import numpy as np
import pinocchio as pin
import pytest

import eomgen as eg
from eomgen.numeric.contacts import contact_dynamics
from eomgen.verify import random_states

SOLO_FEET = ["FL_FOOT", "FR_FOOT", "HL_FOOT", "HR_FOOT"]
TALOS_FEET = ["left_sole_link", "right_sole_link"]


def _contacts(frames, kind):
    return [(f, kind) for f in frames]


def _with_contacts(name, frames, kind=None):
    """The robot with contacts at `frames` (of `kind`, or (frame, kind) pairs) and its numeric equations."""
    system = eg.robots.load(name)
    for f, k in (_contacts(frames, kind) if kind else frames):
        system.add_contact(f, k)
    return system, eg.codegen(eg.derive(system, method="recursive"))


def _pinocchio_constraints(model, contacts):
    models, datas = pin.StdVec_RigidConstraintModel(), pin.StdVec_RigidConstraintData()
    for f, kind in contacts:
        frame = model.frames[model.getFrameId(f)]
        c = pin.RigidConstraintModel(pin.ContactType.CONTACT_3D if kind == "point" else pin.ContactType.CONTACT_6D,
                                     model, frame.parentJoint, frame.placement, pin.ReferenceFrame.LOCAL_WORLD_ALIGNED)
        models.append(c)
        datas.append(c.createData())
    return models, datas


@pytest.mark.parametrize("name,contacts", [
    ("solo12", _contacts(SOLO_FEET, "point")),
    ("talos", _contacts(TALOS_FEET, "frame")),
    ("talos", _contacts(TALOS_FEET, "frame") + [("gripper_right_base_link", "point")]),  # a hand on a wall
])
def test_constrained_dynamics_equals_pinocchio(name, contacts):
    """Contact forces and accelerations at random states whose speeds respect the contacts
    (J_c u = 0, where the classical and spatial contact accelerations coincide), to 1e-8."""
    system, f = _with_contacts(name, contacts)
    model = system.pinocchio_model
    data = model.createData()
    models, datas = _pinocchio_constraints(model, contacts)
    pin.initConstraintDynamics(model, data, models, datas)
    rng = np.random.default_rng(6)
    q, u, _ = random_states(system, 5, rng)
    for k in range(5):
        J = f.contact_jacobian(q[k])
        assert J.shape == (sum(3 if kind == "point" else 6 for _, kind in contacts), system.nv)
        uk = u[k] - np.linalg.pinv(J) @ (J @ u[k])
        tau = rng.uniform(-2, 2, system.nv - 6)
        ud, F = f.constrained_dynamics(q[k], uk, tau)
        a = pin.constraintDynamics(model, data, q[k], uk, np.concatenate([np.zeros(6), tau]), models, datas,
                                   pin.ProximalSettings(1e-14, 1e-12, 1))
        np.testing.assert_allclose(F, data.lambda_c, rtol=0, atol=1e-8 * max(1, np.abs(F).max()))
        np.testing.assert_allclose(ud, a, rtol=0, atol=1e-8 * max(1, np.abs(a).max()))


def test_support_projector_and_support_consistent_dynamics():
    system, f = _with_contacts("solo12", SOLO_FEET, "point")
    q, u, _ = random_states(system, 3, np.random.default_rng(7))
    for k in range(3):
        N = f.support_projector(q[k])
        J = f.contact_jacobian(q[k])
        assert np.abs(J @ N).max() < 1e-10
        assert np.abs(N @ N - N).max() < 1e-10
        tau = np.linspace(-1, 1, 12)
        ud, _ = f.constrained_dynamics(q[k], u[k], tau)
        assert np.abs(f.support_consistent_residual(q[k], u[k], ud, tau)).max() < 1e-9


def test_standing_still_carries_the_weight():
    """Joint torques that hold the robot still (N_cᵀ (g − Sᵀ τ) = 0): the accelerations vanish and the
    contact forces sum to the weight."""
    system, f = _with_contacts("solo12", SOLO_FEET, "point")
    model = system.pinocchio_model
    q = pin.neutral(model)
    q[2] = 0.3
    q[7:] = np.tile([0.0, 0.8, -1.6], 4)
    N = f.support_projector(q)
    S = np.array(system.S.tolist(), float)
    tau = np.linalg.lstsq(N.T @ S.T, N.T @ f.g(q), rcond=None)[0]
    ud, F = f.constrained_dynamics(q, np.zeros(system.nv), tau)
    assert np.abs(ud).max() < 1e-9
    weight = sum(inertia.mass for inertia in model.inertias) * 9.81
    np.testing.assert_allclose(F.reshape(4, 3).sum(axis=0), [0, 0, weight], atol=1e-9 * weight)


def test_redundant_contacts_warn_and_name_the_rows():
    """A quadruped on four 6D feet: 24 constraints on 18 speeds; at rest the feet hold it still."""
    system, f = _with_contacts("solo12", SOLO_FEET, "frame")
    q, _, _ = random_states(system, 1, np.random.default_rng(8))
    with pytest.warns(UserWarning, match=r"rank-deficient contact set: \[.*'HR_FOOT.rz'\] repeat"):
        ud, F = f.constrained_dynamics(q[0], np.zeros(18), np.linspace(-1, 1, 12))
    assert np.abs(ud).max() < 1e-8 and np.isfinite(F).all()


def _ur5_at(q5):
    """ur5 with its tool flange held (6 rows on 6 joints), at wrist angle q5 (singular at q5 = 0)."""
    system, f = _with_contacts("ur5", ["tool0"], "frame")
    return system, f, np.array([0.3, -1.0, 1.2, 0.5, q5, 0.7])


@pytest.mark.parametrize("q5,warning", [
    (1e-8, r"near-singular contact set: cond\(J_c M⁻¹ J_cᵀ\) = \d\.\d\de\+17 > 1e\+08 "
           r"at contacts \['tool0'\]; rows in the weak directions .*tool0\.y .*damping μ"),
    (0.0, r"rank-deficient contact set: \['tool0\.rz'\] repeat"),
])
def test_wrist_singularity_warns_and_keeps_the_residual_bounded(q5, warning):
    """At the wrist singularity the forces stay bounded and the constraint residual J u̇ + J̇ u no larger
    than with no contact forces at all (J M⁻¹ h + J̇ u); on the exact singularity, the minimum-norm
    forces."""
    _, f, q = _ur5_at(q5)
    rng = np.random.default_rng(3)
    u, tau = rng.uniform(-1, 1, 6), rng.uniform(-2, 2, 6)
    with pytest.warns(UserWarning, match=warning):
        ud, F = f.constrained_dynamics(q, u, tau)
    J, Jdot_u = f.contact_jacobian(q), f.contact_jacobian_dot_u(q, u)
    free = J @ f.forward_dynamics(q, u, tau) + Jdot_u
    assert np.linalg.norm(J @ ud + Jdot_u) <= np.linalg.norm(free)
    assert np.linalg.norm(F) < 1e3  # ~50 N at these torques; 4e15 N undamped at q5 = 1e-8


def test_near_wrist_singularity_equals_pinocchio():
    """Slightly away from the singularity (cond(J M⁻¹ Jᵀ) ≈ 4e5, forces ~10× the regular ones), the exact
    solution, no warning (a regression guard: the damping stays off)."""
    system, f, q = _ur5_at(1e-2)
    model = system.pinocchio_model
    data = model.createData()
    models, datas = _pinocchio_constraints(model, [("tool0", "frame")])
    pin.initConstraintDynamics(model, data, models, datas)
    tau = np.random.default_rng(4).uniform(-2, 2, 6)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        ud, F = f.constrained_dynamics(q, np.zeros(6), tau)  # J u = 0 holds only for u = 0 (J is square)
    a = pin.constraintDynamics(model, data, q, np.zeros(6), tau, models, datas,
                               pin.ProximalSettings(1e-14, 1e-12, 1))
    np.testing.assert_allclose(F, data.lambda_c, rtol=0, atol=1e-7 * np.abs(F).max())
    np.testing.assert_allclose(ud, a, rtol=0, atol=1e-7 * max(1, np.abs(a).max()))


def test_support_projector_at_the_wrist_singularity():
    _, f, q = _ur5_at(1e-8)
    with pytest.warns(UserWarning, match=r"near-singular contact set: cond.*N_c removes them exactly"):
        N = f.support_projector(q)
    assert np.abs(N @ N - N).max() < 1e-10
    assert np.abs(f.contact_jacobian(q) @ N).max() < 1e-10


def test_singularity_is_judged_relative_to_the_mass_scale():
    """Scaling every mass and inertia (M, h) by c leaves the verdicts and u̇ unchanged and scales F by c."""
    system, f, _ = _ur5_at(0.0)
    names = system.constraint_rows()
    rng = np.random.default_rng(5)
    expected = {0.0: "rank-deficient", 1e-8: "near-singular", 3e-4: "near-singular", 1e-3: None, 0.3: None}
    for q5, verdict in expected.items():
        q = np.array([0.3, -1.0, 1.2, 0.5, q5, 0.7])
        u, tau = rng.uniform(-1, 1, 6), rng.uniform(-2, 2, 6)
        M, J, Jdot_u = f.M(q), f.contact_jacobian(q), f.contact_jacobian_dot_u(q, u)
        h = M @ f.forward_dynamics(q, u, tau)
        results = []
        for c in (1.0, 1e6, 1e-6):
            with warnings.catch_warnings(record=True) as caught:
                warnings.simplefilter("always")
                results.append(contact_dynamics(c * M, c * h, J, Jdot_u, names))
            verdicts = [str(w.message).split(" contact set")[0] for w in caught]
            assert verdicts == ([verdict] if verdict else []), (q5, c)
        for (ud, F), c in zip(results, (1.0, 1e6, 1e-6)):
            np.testing.assert_allclose(ud, results[0][0], rtol=0, atol=1e-6 * np.abs(results[0][0]).max())
            np.testing.assert_allclose(F / c, results[0][1], rtol=0, atol=1e-6 * np.abs(results[0][1]).max())


def test_contact_errors():
    system = eg.robots.load("solo12")
    with pytest.raises(eg.ModelError, match="unknown frame 'FOOT'"):
        system.add_contact("FOOT")
    with pytest.raises(eg.ModelError, match="kind must be 'point' or 'frame'"):
        system.add_contact("FL_FOOT", kind="line")
    f = eg.codegen(eg.derive(system, method="recursive"))
    with pytest.raises(eg.ModelError, match="no contacts"):
        f.contact_forces(np.r_[0, 0, 0.3, 0, 0, 0, 1, np.zeros(12)], np.zeros(18))


def test_example_runs(capsys):
    import runpy
    from pathlib import Path

    runpy.run_path(str(Path(__file__).parents[1] / "examples" / "quadruped_contact.py"), run_name="__main__")
    out = capsys.readouterr().out
    line = next(x for x in out.splitlines() if x.startswith("sum of contact forces"))
    weight = float(out.split("weight ")[1].split(" N")[0])
    assert abs(float(line.split("[")[1].split("]")[0].split()[2]) - weight) < 1e-3
    assert "ZYX Euler angles are singular" in out
