"""MJCF import against Pinocchio's model of the same file: the tree (M, b, g, frame Jacobians and J̇u of a
model with hinge, slide, ball and free joints and armature), and loops from `<equality>` connect and weld
against `constraintDynamics` with the rigid constraint models Pinocchio's parser built.

Frames: Pinocchio's constraint rows and forces λ are in the axes of the constraint's first frame
(joint1_placement, LOCAL), eomgen's in the world's. With R_1 that frame's rotation:
J_eomgen = blockdiag(R_1, R_1) J_Pinocchio and F_eomgen = blockdiag(R_1, R_1) λ (3 rows for a connect, 6
for a weld: force, then moment about the frame's origin), acting on the first frame's body."""
from __future__ import annotations

from importlib.resources import files
from pathlib import Path

import numpy as np
import pinocchio as pin
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from scipy.linalg import block_diag

import eomgen as eg
from eomgen.errors import ModelError

DATA = files("eomgen") / "data" / "mjcf"
TREE, SPATIAL, CASSIE = (Path(str(DATA / f)) for f in ("tree.xml", "spatial_loop.xml", "cassie_leg.xml"))
TREE_GRAVITY = [0.3, -0.2, -9.81]  # tree.xml's <option gravity>, which Pinocchio's parser does not read
LWA = pin.ReferenceFrame.LOCAL_WORLD_ALIGNED
SITE, BODY = pin.FrameType.OP_FRAME, pin.FrameType.BODY


def close(ours, ref, tol):
    np.testing.assert_allclose(ours, ref, rtol=0, atol=tol * max(1.0, np.abs(ref).max()))


def test_tree_equals_pinocchio():
    """M (crba), b = nle − g, g, and the frame Jacobians and J̇u of bodies and sites to 1e-12."""
    system = eg.from_mjcf(TREE)
    model = pin.buildModelFromMJCF(str(TREE))
    model.gravity.linear = np.array(TREE_GRAVITY)
    assert [j.name for j in system.joints] == list(model.names)[1:]
    assert [j.shortname() for j in model.joints[1:]] == [
        "JointModelFreeFlyer", "JointModelRevoluteUnaligned", "JointModelPrismaticUnaligned",
        "JointModelSpherical", "JointModelRY", "JointModelRY"]
    assert (system.nq, system.nv) == (model.nq, model.nv) and model.armature[6:].min() > 0
    f = eg.codegen(eg.derive(system))
    data = model.createData()
    q, u, _ = eg.random_states(system, 5, np.random.default_rng(3))
    for qk, uk in zip(q, u):
        M = pin.crba(model, data, qk)
        g = pin.computeGeneralizedGravity(model, data, qk)
        close(f.M(qk), np.triu(M) + np.triu(M, 1).T, 1e-12)
        close(f.g(qk), g, 1e-12)
        close(f.b(qk, uk), pin.nonLinearEffects(model, data, qk, uk) - g, 1e-12)
        pin.computeJointJacobiansTimeVariation(model, data, qk, uk)
        pin.updateFramePlacements(model, data)
        for name, kind in [("imu", SITE), ("palm", SITE), ("foot", SITE), ("hand", BODY), ("torso", BODY)]:
            frame = model.getFrameId(name, kind)
            close(f.jacobian(name, qk), pin.getFrameJacobian(model, data, frame, LWA), 1e-12)
            close(f.jacobian_dot_u(name, qk, uk),
                  pin.getFrameJacobianTimeVariation(model, data, frame, LWA) @ uk, 1e-11)


def test_floating_base_option(tmp_path):
    """None takes the file's free joint; True adds one above a fixed root body; False refuses a free one."""
    assert eg.from_mjcf(SPATIAL, floating_base=True).nv == eg.from_mjcf(SPATIAL).nv + 6
    assert eg.from_mjcf(TREE, floating_base=True).nv == eg.from_mjcf(TREE).nv
    with pytest.raises(ModelError, match="joint 'root' is a free joint, but floating_base=False"):
        eg.from_mjcf(TREE, floating_base=False)
    with pytest.raises(ModelError, match="floating_base must be None, False or True"):
        eg.from_mjcf(TREE, floating_base="euler")


def variant(tmp_path: Path, path: Path, old: str, new: str) -> Path:
    """A copy of the file with `old` replaced by `new`."""
    text = path.read_text()
    assert old in text
    out = tmp_path / path.name
    out.write_text(text.replace(old, new))
    return out


STANCE = '<connect name="stance" body1="foot" anchor="0.01 0 -0.03"/>'  # the foot held to the world
WELD = ('<connect name="tips" body1="b2" body2="a3" anchor="0.334 0.025 -0.005"/>',
        '<weld name="tips" body1="b2" body2="a3"/>')


def pinocchio_loops(path: Path):
    model, constraints = pin.buildModelAndLegacyConstraintsFromMJCF(str(path))
    data, datas = model.createData(), [c.createData() for c in constraints]
    pin.initConstraintDynamics(model, data, constraints, datas)
    return model, data, constraints, datas


def to_world(model, data, constraints, q) -> np.ndarray:
    """blockdiag(R_1, …) over the constraints' rows: Pinocchio's LOCAL rows in world axes."""
    pin.forwardKinematics(model, data, q)
    blocks = []
    for c in constraints:
        R = (data.oMi[c.joint1_id] * c.joint1_placement).rotation
        blocks += [R] * (2 if c.type == pin.ContactType.CONTACT_6D else 1)
    return block_diag(*blocks)


def assembled(model, data, constraints, datas, q, steps: int = 30) -> np.ndarray:
    """q moved onto the closure by Gauss-Newton on Pinocchio's residual (minimum-norm steps)."""
    for _ in range(steps):
        r = np.concatenate([residual(model, data, c, q) for c in constraints])
        if np.abs(r).max() < 1e-14:
            break
        q = pin.integrate(model, q, -np.linalg.lstsq(jacobian(model, data, constraints, datas, q), r,
                                                     rcond=None)[0])
    return q


def jacobian(model, data, constraints, datas, q) -> np.ndarray:
    """getConstraintJacobian of every constraint at q, stacked (LOCAL rows)."""
    pin.computeJointJacobians(model, data, q)
    for c, cd in zip(constraints, datas):
        c.calc(model, data, cd)  # the constraint's frames at q
    return np.vstack([pin.getConstraintJacobian(model, data, c, cd) for c, cd in zip(constraints, datas)])


def residual(model, data, c, q) -> np.ndarray:
    """Pinocchio's frames 1 and 2 of a constraint: p_1 − p_2 (frame 1's axes), and for a weld the
    rotation vector log(R_2ᵀ R_1) (whose rate is ω_1 − ω_2, as the rows of its Jacobian)."""
    pin.forwardKinematics(model, data, q)
    A, B = data.oMi[c.joint1_id] * c.joint1_placement, data.oMi[c.joint2_id] * c.joint2_placement
    r = A.rotation.T @ (A.translation - B.translation)
    if c.type == pin.ContactType.CONTACT_3D:
        return r
    return np.concatenate([r, pin.log3(B.rotation.T @ A.rotation)])


def compare(f, system, model, data, constraints, datas, q, u, tau):
    """u̇, F, J_c against constraintDynamics (1e-8) and getConstraintJacobian (1e-12); the residual
    against Pinocchio's frames: p_1 − p_2, and for a weld
    2 vee(E − Eᵀ) / (1 + tr E) = −R_1 2 tan(|ω|/2) ω/|ω| with E = R_1 R_2ᵀ, ω = log(R_1ᵀ R_2)."""
    u_dot, F = f.constrained_dynamics(q, u, tau)
    a = pin.constraintDynamics(model, data, q, u, tau, constraints, datas)
    W = to_world(model, data, constraints, q)
    close(u_dot, a, 1e-8)
    close(F, W @ data.lambda_c, 1e-8)
    close(f.contact_jacobian(q), W @ jacobian(model, data, constraints, datas, q), 1e-12)
    rows, k = f.closure_residual(q), 0
    for c in constraints:
        n = 6 if c.type == pin.ContactType.CONTACT_6D else 3
        pin.forwardKinematics(model, data, q)
        A, B = data.oMi[c.joint1_id] * c.joint1_placement, data.oMi[c.joint2_id] * c.joint2_placement
        close(rows[k:k + 3], A.translation - B.translation, 1e-12)
        if n == 6:
            w = pin.log3(A.rotation.T @ B.rotation)
            angle = np.linalg.norm(w)
            turn = 2 * np.tan(angle / 2) / angle * w if angle else w
            close(rows[k + 3:k + 6], -A.rotation @ turn, 1e-12)
        k += n
    assert f.constraint_rows[:3] == [f"{system.loops[0].name}.{a}" for a in "xyz"]


@pytest.mark.parametrize("path, extra", [(SPATIAL, None), (CASSIE, None), (CASSIE, STANCE)],
                         ids=["spatial", "cassie", "cassie-stance"])
def test_loops_equal_pinocchio(tmp_path, path, extra):
    """Random states (not closed; speeds free and with J_c u = 0), then closed ones: accelerations and
    loop forces equal constraintDynamics, J_c equals getConstraintJacobian in world axes."""
    if extra:
        path = variant(tmp_path, path, "</equality>", f"  {extra}\n  </equality>")
    system = eg.from_mjcf(path)
    model, data, constraints, datas = pinocchio_loops(path)
    assert [loop.kind for loop in system.loops] == ["point"] * len(constraints)
    assert [loop.name for loop in system.loops] == ["achilles", "stance"][:len(constraints)] \
        if path.stem == "cassie_leg" else ["tips"]
    f = eg.codegen(eg.derive(system))
    rng = np.random.default_rng(8)
    q, u, _ = eg.random_states(system, 3, rng)
    for qk, uk in zip(q, u):
        J = f.contact_jacobian(qk)
        for speed in (uk, uk - np.linalg.pinv(J) @ (J @ uk)):
            compare(f, system, model, data, constraints, datas, qk, speed, rng.uniform(-2, 2, system.nv))
    for _ in range(3):
        qk = assembled(model, data, constraints, datas,
                       pin.integrate(model, pin.neutral(model), rng.uniform(-0.2, 0.2, model.nv)))
        np.testing.assert_allclose(f.closure_residual(qk), 0, atol=1e-12)
        J = f.contact_jacobian(qk)
        uk = rng.uniform(-2, 2, system.nv)
        compare(f, system, model, data, constraints, datas, qk, uk - np.linalg.pinv(J) @ (J @ uk),
                rng.uniform(-2, 2, system.nv))


def test_weld_loop_equals_pinocchio(tmp_path):
    """The two arms welded at their tips (1 degree of freedom left), at closed states: a weld's 6 rows
    are Pinocchio's 6D constraint (force, then moment) in world axes. At open states the linear rows
    differ by ω_2 × (p_1 − p_2): eomgen takes each body's velocity at its own frame's origin, Pinocchio
    both at frame 1's."""
    path = variant(tmp_path, SPATIAL, *WELD)
    system = eg.from_mjcf(path)
    assert [(loop.name, loop.kind) for loop in system.loops] == [("tips", "frame")]
    model, data, constraints, datas = pinocchio_loops(path)
    f = eg.codegen(eg.derive(system))
    rng = np.random.default_rng(9)
    c = constraints[0]
    for q in eg.random_states(system, 3, rng)[0]:  # open: Pinocchio's force rows are at frame 1's origin
        J = to_world(model, data, constraints, q) @ jacobian(model, data, constraints, datas, q)
        A, B = data.oMi[c.joint1_id] * c.joint1_placement, data.oMi[c.joint2_id] * c.joint2_placement
        J_w2 = pin.getJointJacobian(model, data, c.joint2_id, LWA)[3:]
        close(f.contact_jacobian(q), J + np.vstack([np.cross(J_w2.T, A.translation - B.translation).T,
                                                    np.zeros_like(J_w2)]), 1e-12)
    for _ in range(3):
        q = assembled(model, data, constraints, datas,
                      pin.integrate(model, pin.neutral(model), rng.uniform(-0.2, 0.2, model.nv)))
        assert np.abs(residual(model, data, constraints[0], q)).max() < 1e-13
        np.testing.assert_allclose(f.closure_residual(q), 0, atol=1e-12)
        J = f.contact_jacobian(q)
        u = rng.uniform(-2, 2, system.nv)
        compare(f, system, model, data, constraints, datas, q, u - np.linalg.pinv(J) @ (J @ u),
                rng.uniform(-2, 2, system.nv))


def mjcf(tmp_path: Path, body: str = "", equality: str = "", top: str = "", name: str = "m.xml") -> Path:
    """A file of two bodies (a: hinge, b: hinge below a; sites sa, sb) with `body` inside b."""
    path = tmp_path / name
    path.write_text(f"""<mujoco model="m">{top}<worldbody><body name="a"><joint name="ja" axis="1 0 0"/>
      <inertial pos="0 0 0.1" mass="1" diaginertia="0.01 0.01 0.01"/><site name="sa" pos="0 0 0.2"/>
      <body name="b" pos="0 0 0.3"><joint name="jb" axis="0 1 0"/><site name="sb" pos="0.1 0 0"/>
      <inertial pos="0 0 0.1" mass="1" diaginertia="0.01 0.01 0.01"/>{body}</body></body></worldbody>
      <equality>{equality}</equality></mujoco>""")
    return path


def test_equalities_keep_their_names_and_placements(tmp_path):
    """Named and unnamed, body and site, connect and weld, to the world: each loop is named after its
    equality and its frames sit where the file says, in the order of Pinocchio's constraint models."""
    path = mjcf(tmp_path, equality="""<connect name="z" body1="b" anchor="0.1 0.2 0.3"/>
        <connect body1="b" body2="a" anchor="0.1 0.2 0.31"/><connect site1="sb" site2="sa"/>
        <weld name="w" body1="a" body2="b" relpose="0.3 0.2 0.1 1 0 0 0"/><weld body1="b"/>""")
    system = eg.from_mjcf(path)
    _, constraints = pin.buildModelAndLegacyConstraintsFromMJCF(str(path))
    sizes = {pin.ContactType.CONTACT_3D: "point", pin.ContactType.CONTACT_6D: "frame"}
    assert [loop.kind for loop in system.loops] == [sizes[c.type] for c in constraints]
    loops = {loop.name: loop for loop in system.loops}
    assert sorted(loops) == ["b-a", "b-world", "sb-sa", "w", "z"]
    expected = {"z_1": ("b", [0.1, 0.2, 0.3]), "b-a_1": ("b", [0.1, 0.2, 0.31]),
                "sb-sa_1": ("b", [0.1, 0, 0]), "sb-sa_2": ("a", [0, 0, 0.2]), "w_1": ("a", [0.3, 0.2, 0.1]),
                "w_2": ("b", [0, 0, 0])}
    for name, (body, translation) in expected.items():
        frame = system.frames[name]
        assert frame.body.name == body
        np.testing.assert_allclose(np.array(frame.placement.translation, float).ravel(), translation,
                                   atol=1e-15)
    assert system.frames["z_2"].body is None and system.frames["b-world_2"].body is None
    assert [loops[n].kind for n in ("z", "b-a", "sb-sa", "w", "b-world")] == ["point"] * 3 + ["frame"] * 2


ANCHOR = st.lists(st.floats(-2, 2, allow_subnormal=False), min_size=3, max_size=3)


@settings(max_examples=25, deadline=None, derandomize=True, database=None,
          suppress_health_check=[HealthCheck.function_scoped_fixture])
@given(anchor=ANCHOR, relpose=ANCHOR)
def test_anchors_as_written(tmp_path, anchor, relpose):
    """Any anchor and relpose, as Python writes the floats: the loops' frames sit there, to the 1e-14
    within which eomgen takes a number for 0 or ±1 (the equalities are told apart among Pinocchio's
    constraints by these numbers)."""
    a, r = " ".join(map(repr, anchor)), " ".join(map(repr, relpose))
    system = eg.from_mjcf(mjcf(tmp_path, equality=f"""<connect name="c" body1="b" body2="a" anchor="{a}"/>
        <connect name="d" body1="b" body2="a" anchor="{r}"/>
        <weld name="w" body1="a" body2="b" relpose="{r} 0.6 0 0.8 0"/>"""))
    for frame, where in (("c_1", anchor), ("d_1", relpose), ("w_1", relpose)):
        np.testing.assert_allclose(np.array(system.frames[frame].placement.translation, float).ravel(),
                                   where, rtol=1e-15, atol=1e-14)


BAD = {
    "joint equality": (dict(equality='<joint joint1="ja" joint2="jb"/>'), "a joint equality is not handled"),
    "tendon equality": (dict(equality='<tendon tendon1="t"/>'), "a tendon equality is not handled"),
    "distance": (dict(equality='<distance name="d" geom1="x" geom2="y"/>'), "a distance equality"),
    "inactive": (dict(equality='<connect body1="b" anchor="0 0 0" active="false"/>'), "active='false'"),
    "mixture": (dict(equality='<connect body1="b" site2="sa" anchor="0 0 0"/>'), "not a mixture"),
    "unknown body": (dict(equality='<connect body1="c" anchor="0 0 0"/>'), "body1 'c' is not a body"),
    "unknown site": (dict(equality='<connect site1="nope" site2="sa"/>'), "site1 'nope' is not a site"),
    "world by name": (dict(equality='<weld body1="b" body2="world"/>'), "leave out body2 for the world"),
    "short anchor": (dict(equality='<connect body1="b" anchor="1 0"/>'), "anchor='1 0' must be 3 finite"),
    "same name": (dict(equality='<connect name="x" body1="b" anchor="0 0 0"/><weld name="x" body1="a"/>'),
                  "two equalities are named 'x'"),
    "unnamed pair": (dict(equality='<connect body1="b" body2="a" anchor="0 0 0"/>'
                                   '<weld body1="b" body2="a"/>'), "two equalities are named 'b-a'"),
    "anchor off the joint": (dict(body='<body name="c"><joint name="jc" pos="0.1 0 0"/><inertial '
                                       'pos="0 0 0" mass="1" diaginertia="1 1 1"/></body>',
                                  equality='<connect body1="c" anchor="0 0 0"/>'),
                             "state the equality with sites"),
    "tendon": (dict(top='<tendon><fixed name="t"><joint joint="ja" coef="1"/></fixed></tendon>'),
               "tendons are not"),
    "stiffness": (dict(top='<default><joint stiffness="2"/></default>'), "stiffness='2' is a MuJoCo force"),
    "damping": (dict(body='<body name="c"><joint name="jc" damping="0.5"/><inertial pos="0 0 0" mass="1" '
                          'diaginertia="1 1 1"/></body>'), "joint 'jc': damping 0.5"),
    "viscosity": (dict(top='<option viscosity="0.1"/>'), "<option>: viscosity"),
    "gravcomp": (dict(body='<body name="c" gravcomp="1"/>'), "body 'c': gravcomp"),
    "two joints": (dict(body='<body name="c"><joint name="j1"/><joint name="j2"/></body>'), "has 2 joints"),
    "frame": (dict(body='<frame pos="1 0 0"><body name="c"/></frame>'), "<frame> is not read"),
    "include": (dict(top='<include file="other.xml"/>'), "<include> is not read"),
    "axisangle": (dict(body='<site name="s" axisangle="1 1 0 30"/>'), "give a unit axis"),
    "eulerseq": (dict(top='<compiler eulerseq="XYZ"/>'), "upper case"),
}


@pytest.mark.parametrize("case", BAD, ids=list(BAD))
def test_refused(tmp_path, case):
    kwargs, message = BAD[case]
    with pytest.raises(ModelError, match=message):
        eg.from_mjcf(mjcf(tmp_path, **kwargs))


def test_bad_files(tmp_path):
    with pytest.raises(ModelError, match="MJCF file not found"):
        eg.from_mjcf(tmp_path / "none.xml")
    (tmp_path / "broken.xml").write_text("<mujoco><worldbody><body></worldbody></mujoco>")
    with pytest.raises(ModelError, match="cannot read MJCF .*broken.xml: mismatched tag"):
        eg.from_mjcf(tmp_path / "broken.xml")
    (tmp_path / "robot.xml").write_text('<robot name="r"><link name="a"/></robot>')
    with pytest.raises(ModelError, match="the root element is <robot>, not <mujoco>"):
        eg.from_mjcf(tmp_path / "robot.xml")
    two = mjcf(tmp_path).read_text().replace("</worldbody>", '<body name="c"/></worldbody>')
    (tmp_path / "two.xml").write_text(two)
    with pytest.raises(ModelError, match=r"<worldbody> holds 2 bodies \['a', 'c'\]"):
        eg.from_mjcf(tmp_path / "two.xml")
    fixed = mjcf(tmp_path).read_text().replace('<joint name="ja" axis="1 0 0"/>', "").replace(
        '<body name="a">', '<body name="a" pos="0 0 1" euler="90 0 0">')
    (tmp_path / "fixed.xml").write_text(fixed)
    with pytest.raises(ModelError, match="body 'a' is fixed to the world and has pos and euler"):
        eg.from_mjcf(tmp_path / "fixed.xml")
