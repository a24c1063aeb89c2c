"""URDF mimic, planar and floating joints, and every joint type of Pinocchio's model, against Pinocchio:
its model of the same file (mimic=True) or the one it builds from a System is the reference for M, b,
g, frame Jacobians and J̇u. Files Pinocchio's parser cannot follow (it stops with a terse message, or
drops the mimic silently) are refused with the joints named, before the parser sees them."""
from __future__ import annotations

from pathlib import Path

import numpy as np
import pinocchio as pin
import pytest

import eomgen as eg
from eomgen.errors import ModelError
from eomgen.model.robots import robots_folder
from eomgen.model.urdf import from_pinocchio, pinocchio_configuration
from eomgen.model.urdf_check import check_urdf
from eomgen.state import random_states
from eomgen.verify import to_pinocchio

METHODS = ["recursive", "projected_newton_euler", "free_cut", "lagrange"]
LIMIT = '<limit lower="-1" upper="1" effort="10" velocity="1"/>'


def link(name: str, mass: float = 1.0, com: str = "0.05 0.02 0.1",
         inertia: str = "0.02 0.001 0 0.03 0.002 0.025") -> str:
    values = dict(zip(("ixx", "ixy", "ixz", "iyy", "iyz", "izz"), inertia.split()))
    return (f'<link name="{name}"><inertial><origin xyz="{com}"/><mass value="{mass}"/>'
            f'<inertia {" ".join(f"{k}={v!r}" for k, v in values.items())}/></inertial></link>')


def joint(name: str, parent: str, child: str, kind: str = "revolute", axis: str = "0 0 1", extra: str = "",
          origin: str = '<origin xyz="0.1 0.05 0.2" rpy="0.1 -0.2 0.3"/>') -> str:
    axis = f'<axis xyz="{axis}"/>' if axis else ""
    limit = LIMIT if kind in ("revolute", "prismatic") else ""
    return (f'<joint name="{name}" type="{kind}"><parent link="{parent}"/><child link="{child}"/>'
            f"{origin}{axis}{limit}{extra}</joint>")


def mimic(driver: str | None, **numbers) -> str:
    """A <mimic> element: mimic("a", multiplier="2") (None: no joint attribute)."""
    attributes = ({} if driver is None else {"joint": driver}) | numbers
    return "<mimic " + " ".join(f'{k}="{v}"' for k, v in attributes.items()) + "/>"


def write(folder: Path, *joints: str, root: str = "base", name: str = "r.urdf") -> Path:
    """A URDF of the joints, a link of mass for every child link they name."""
    children = sorted({j.split('<child link="')[1].split('"')[0] for j in joints})
    path = folder / name
    links = "".join(link(c, 1 + 0.1 * k) for k, c in enumerate(children))
    path.write_text(f'<robot name="r"><link name="{root}"/>{links}{"".join(joints)}</robot>')
    return path


A = joint("a", "base", "l1")


def jb(kind: str = "revolute", **numbers) -> str:
    """Joint b below a (l1 → l2), mimicking numbers["joint"] if given."""
    driver = numbers.pop("joint", "-")
    return joint("b", "l1", "l2", kind, extra="" if driver == "-" else mimic(driver, **numbers))


# an arm of two revolute joints, a palm on a fixed wrist, a prismatic driving joint, and two fingers
# following it: a prismatic one along an unaligned axis (multiplier −1), a revolute one (2.5, offset 0.3)
GRIPPER = f"""<?xml version="1.0"?>
<robot name="gripper">
 <link name="base"/>
 {link("upper", 2, "0 0 0.2", "0.05 0.001 0 0.045 0.002 0.01")}
 {link("fore", 1.5, "0.15 0 0", "0.01 0 0.001 0.03 0 0.03")}
 {link("palm", 0.4, "0 0 0.03", "0.001 0 0 0.001 0 0.0005")}
 {link("driver", 0.1, "0 0.01 0.02", "0.0002 0 0 0.0001 0 0.0001")}
 {link("left", 0.12, "0 0.01 0.04", "0.00025 0 0 0.0002 0.00001 0.0001")}
 {link("right", 0.11, "0 -0.01 0.04", "0.00025 0 0 0.0002 0 0.0001")}
 {joint("shoulder", "base", "upper", axis="0 1 0", origin='<origin xyz="0 0 0.1"/>')}
 {joint("elbow", "upper", "fore", axis="1 0 0", origin='<origin xyz="0 0 0.4" rpy="0 0.3 0"/>')}
 {joint("wrist", "fore", "palm", "fixed", "", origin='<origin xyz="0.3 0 0" rpy="0 1.5707963 0"/>')}
 {joint("grip", "palm", "driver", "prismatic", "0 1 0", origin='<origin xyz="0 0.02 0.05"/>')}
 {joint("left_finger", "palm", "left", "prismatic", "0 0.6 0.8", '<mimic joint="grip" multiplier="-1"/>',
        '<origin xyz="0 0.03 0.06"/>')}
 {joint("right_finger", "palm", "right", "revolute", "1 0 0",
        '<mimic joint="grip" multiplier="2.5" offset="0.3"/>', '<origin xyz="0 -0.03 0.06"/>')}
</robot>
"""


@pytest.fixture
def gripper(tmp_path) -> Path:
    path = tmp_path / "gripper.urdf"
    path.write_text(GRIPPER)
    return path


@pytest.mark.parametrize("method", METHODS)
def test_gripper_fingers_follow_the_driving_joint(gripper, method):
    system = eg.from_urdf(gripper)
    reference = pin.buildModelFromUrdf(str(gripper), mimic=True)
    assert (system.nq, system.nv) == (reference.nq, reference.nv) == (3, 3)
    assert len(reference.mimicking_joints) == 2
    fingers = {b.joint.name: b.joint.mimic for b in system.bodies if getattr(b.joint, "mimic", None)}
    assert {n: (m.driver.name, float(m.multiplier), float(m.offset)) for n, m in fingers.items()} == \
        {"left_finger": ("grip", -1.0, 0.0), "right_finger": ("grip", 2.5, 0.3)}
    system.pinocchio_model = reference
    report = eg.verify(system, method=method, states=5)
    assert any(k.startswith("J left") for k in report.errors) and report.ok(1e-12), str(report)


def test_gripper_mimic_independent_or_refused(gripper):
    with pytest.warns(UserWarning, match=r"\['left_finger', 'right_finger'\] imported as independent"):
        system = eg.from_urdf(gripper, mimic="independent")
    assert system.nv == pin.buildModelFromUrdf(str(gripper)).nv == 5
    assert eg.verify(system, method="recursive", states=3).ok(1e-12)
    with pytest.raises(ModelError, match=r"'left_finger' mimics joint 'grip': .*mimic='mimic'\) follows"):
        eg.from_urdf(gripper, mimic="refuse")
    with pytest.raises(ModelError, match="mimic must be one of"):
        eg.from_urdf(gripper, mimic="follow")


def reference_model(name: str) -> pin.Model:
    """Pinocchio's model of a robot of example-robot-data with its mimic joints, armature from the SRDF."""
    urdf, srdf, floating = eg.robots.paths(name)
    model = pin.buildModelFromUrdf(str(urdf), *([pin.JointModelFreeFlyer()] if floating else []), mimic=True)
    if srdf:
        pin.loadRotorParameters(model, str(srdf), False)
        model.armature = model.rotorInertia * model.rotorGearRatio**2
    return model


def pinocchio_eom(model: pin.Model, q, u) -> tuple:
    """M, b, g of Pinocchio (a new Data each time: Pinocchio 4.1's crba is wrong with a reused one when
    a mimic joint sits below its driver)."""
    data = model.createData()
    M = pin.crba(model, data, q)
    g = pin.computeGeneralizedGravity(model, data, q)
    return np.triu(M) + np.triu(M, 1).T, pin.nonLinearEffects(model, data, q, u) - g, g


def assert_close(ours, ref):
    for a, r in zip(ours, ref):
        np.testing.assert_allclose(a, r, rtol=0, atol=1e-12 * max(1.0, np.abs(r).max()))


@pytest.mark.parametrize("name, mimics", [("talos", 0), ("pr2", 10), ("tiago_pro", 10), ("baxter", 2),
                                          ("panda", 1)])
def test_robots_with_mimic_joints(name, mimics):
    """talos' 24 <mimic> sit on fixed joints (its grippers are locked in talos_reduced): nothing follows."""
    system = eg.robots.load(name, mimic="mimic")
    model = reference_model(name)
    assert len(model.mimicking_joints) == mimics
    assert sum(getattr(b.joint, "mimic", None) is not None for b in system.bodies) == mimics
    assert system.nv == model.nv
    f = eg.codegen(eg.derive(system, method="recursive"))
    q, u, _ = random_states(system, 3, np.random.default_rng(4))
    for qk, uk in zip(q, u):
        qp = pinocchio_configuration(system, qk)
        assert qp.shape == (model.nq,)
        assert_close((f.M(qk), f.b(qk, uk), f.g(qk)), pinocchio_eom(model, qp, uk))


@pytest.mark.parametrize("method", METHODS)
def test_mimic_below_its_driver(tmp_path, method):
    """a → b (mimics a: q_b = 2 q_a + 0.1) → c: equal to Pinocchio's model with independent joints
    reduced by u_full = G u, M = Gᵀ M_full G, b = Gᵀ b_full, g = Gᵀ g_full, and to its mimic model."""
    path = write(tmp_path, A, jb(joint="a", multiplier=2, offset=0.1), joint("c", "l2", "l3", axis="1 0 0"))
    f = eg.codegen(eg.derive(eg.from_urdf(path), method=method))
    full, model = pin.buildModelFromUrdf(str(path)), pin.buildModelFromUrdf(str(path), mimic=True)
    G = np.array([[1.0, 0.0], [2.0, 0.0], [0.0, 1.0]])
    for q, u in np.random.default_rng(5).uniform(-2, 2, (3, 2, 2)):
        M, b, g = pinocchio_eom(full, G @ q + [0, 0.1, 0], G @ u)
        reduced = G.T @ M @ G, G.T @ b, G.T @ g
        assert_close(reduced, pinocchio_eom(model, q, u))
        assert_close((f.M(q), f.b(q, u), f.g(q)), reduced)


def test_robots_load_keeps_mimic_joints_independent_by_default():
    with pytest.warns(UserWarning, match=r"mimic joints \[.*'r_gripper_r_finger_joint'"):
        system = eg.robots.load("pr2")
    assert system.nv == pin.buildModelFromUrdf(str(eg.robots.paths("pr2")[0])).nv == 30


MIMIC_FILES = sorted(p for p in robots_folder().rglob("*.urdf") if b"<mimic" in p.read_bytes())


@pytest.mark.parametrize("path", MIMIC_FILES, ids=[p.name for p in MIMIC_FILES])
def test_refused_exactly_where_pinocchio_cannot_follow(path):
    """On every file of example-robot-data with <mimic>: Pinocchio's parser stops (talos_full, romeo:
    a finger met before the hand joint it follows; alex: a mimic of an unknown joint) exactly where
    the check refuses."""
    try:
        pin.buildModelFromUrdf(str(path), mimic=True)
    except ValueError:
        with pytest.raises(ModelError, match="mimics"):
            check_urdf(path, "mimic")
    else:
        check_urdf(path, "mimic")


def test_robot_pinocchio_cannot_follow_is_refused_by_name():
    with pytest.raises(ModelError, match="joint 'gripper_left_inner_double_joint' mimics "
                                         "'gripper_left_joint', which Pinocchio's parser adds after it"):
        eg.robots.load("talos_full", mimic="mimic")


BAD = {  # joints, error
    "unknown": ([A, jb(joint="zz")], "joint 'b' mimics the unknown joint 'zz'"),
    "self": ([A, jb(joint="b")], "joint 'b' mimics itself"),
    "loop": ([joint("a", "base", "l1", extra=mimic("b")), jb(joint="a")],
             r"joints \['a', 'b'\] mimic each other in a loop: 'a' → 'b' → 'a'"),
    "chain": ([A, jb(joint="a", multiplier=2), joint("c", "l2", "l3", extra=mimic("b", multiplier=3))],
              "joint 'c' mimics 'b', which mimics 'a': a mimic of a mimic"),
    "word": ([A, jb(joint="a", multiplier="two")], "joint 'b': mimic multiplier='two' is not a number"),
    "nan": ([A, jb(joint="a", multiplier="nan")], "joint 'b': mimic multiplier='nan' must be finite"),
    "comma": ([A, jb(joint="a", offset="0,1")], "joint 'b': mimic offset='0,1' is not a number"),
    "no driver": ([A, jb(joint=None, multiplier=2)], "joint 'b': <mimic> has no joint"),
    "of fixed": ([joint("a", "base", "l1", "fixed"), jb(joint="a")], "joint 'b' mimics 'a', a fixed joint"),
    "of continuous": ([joint("a", "base", "l1", "continuous"), jb(joint="a")],
                      "joint 'b' mimics 'a', a continuous joint"),
    "continuous": ([A, jb("continuous", joint="a")], "joint 'b', a continuous joint, mimics 'a'"),
    "planar": ([A, jb("planar", joint="a")], "joint 'b', a planar joint, mimics 'a'"),  # Pinocchio drops it
    "driver later": ([joint("b", "base", "l1"), joint("a", "base", "l2", extra=mimic("b"))],
                     "joint 'a' mimics 'b', which Pinocchio's parser adds after it"),
}


@pytest.mark.parametrize("case", BAD)
def test_mimics_pinocchio_cannot_follow_are_refused(tmp_path, case):
    joints, message = BAD[case]
    path = write(tmp_path, *joints)
    try:
        assert len(pin.buildModelFromUrdf(str(path), mimic=True).mimicking_joints) == 0
    except ValueError:
        pass  # "does not contain a valid URDF model", "not in the kinematic tree", "different sizes"
    with pytest.raises(ModelError, match=f"r.urdf: {message}"):
        eg.from_urdf(path)


def test_mimic_order_is_pinocchio_s(tmp_path):
    """Siblings by name (byte order: 'B' before 'a'), a driver in an earlier branch is fine."""
    for joints in ([A, joint("b", "base", "l2", extra=mimic("a"))],
                   [joint("B", "base", "l1"), joint("a", "base", "l2", extra=mimic("B"))],
                   [A, joint("a2", "l1", "l3"), joint("b", "base", "l2", extra=mimic("a2", multiplier=-2))]):
        path = write(tmp_path, *joints)
        system = eg.from_urdf(path)
        assert system.nv == pin.buildModelFromUrdf(str(path), mimic=True).nv == len(joints) - 1


def test_mimic_on_a_fixed_joint_moves_nothing_but_its_numbers_are_read(tmp_path):
    path = write(tmp_path, A, jb("fixed", joint="zz", multiplier="-1.0"))
    assert eg.from_urdf(path).nv == pin.buildModelFromUrdf(str(path), mimic=True).nv == 1
    path = write(tmp_path, A, jb("fixed", joint="a", multiplier="1 "))
    with pytest.raises(ValueError):
        pin.buildModelFromUrdf(str(path))
    with pytest.raises(ModelError, match="joint 'b': mimic multiplier='1 ' is not a number"):
        eg.from_urdf(path)


def test_zero_multiplier_refused(tmp_path):
    path = write(tmp_path, A, jb(joint="a", multiplier=0, offset=0.5))
    assert len(pin.buildModelFromUrdf(str(path), mimic=True).mimicking_joints) == 1
    with pytest.raises(ModelError, match="joint 'b' mimics 'a' with multiplier 0, 0 to 1e-14: it does not"):
        eg.from_urdf(path)


ELBOW = joint("elbow", "body", "arm", axis="0 1 0", origin='<origin xyz="0.3 0 0"/>')


@pytest.mark.parametrize("method", METHODS)
def test_planar_joint(tmp_path, method):
    path = write(tmp_path, joint("slide", "world", "body", "planar", "0 0 2"), ELBOW, root="world")
    system = eg.from_urdf(path)
    model = pin.buildModelFromUrdf(str(path))
    assert type(system.joints[0]) is eg.Planar and (system.nv, system.nq + 1) == (model.nv, model.nq)
    report = eg.verify(system, method=method, states=5)
    assert report.ok(1e-12), str(report)


@pytest.mark.parametrize("axis", [None, "1 0 0", "0 1 0", "0 0 -1", "0.6 0 0.8"])
def test_planar_joint_out_of_the_xy_plane_refused(tmp_path, axis):
    """Pinocchio's parser ignores a planar joint's axis (the plane's normal, 1 0 0 if left out)."""
    path = write(tmp_path, joint("slide", "world", "body", "planar", axis), ELBOW, root="world")
    xy = write(tmp_path, joint("slide", "world", "body", "planar", "0 0 1"), ELBOW, root="world",
               name="xy.urdf")
    q = np.array([0.1, 0.2, np.cos(0.3), np.sin(0.3), 0.4])
    M = [pin.crba(m, m.createData(), q) for m in map(pin.buildModelFromUrdf, (str(path), str(xy)))]
    np.testing.assert_array_equal(*M)
    with pytest.raises(ModelError, match="'slide': a planar joint moves in the plane normal to its axis"):
        eg.from_urdf(path)


@pytest.mark.parametrize("method", METHODS)
def test_floating_joint_at_the_root(tmp_path, method):
    path = write(tmp_path, joint("base", "world", "body", "floating", ""), ELBOW, root="world")
    system = eg.from_urdf(path)
    model = pin.buildModelFromUrdf(str(path))
    assert type(system.joints[0]) is eg.FreeFlyer
    assert (system.nq, system.nv) == (model.nq, model.nv) == (8, 7)
    report = eg.verify(system, method=method, states=5)
    assert report.ok(1e-12), str(report)


def test_floating_joint_below_the_root_refused(tmp_path):
    path = write(tmp_path, joint("base", "world", "body", "revolute"), ELBOW,
                 joint("loose", "arm", "box", "floating", ""), root="world")
    assert pin.buildModelFromUrdf(str(path)).joints[3].shortname() == "JointModelFreeFlyer"
    with pytest.raises(ModelError, match="joint 'loose': a floating joint below joint 'elbow'"):
        eg.from_urdf(path)
    path = write(tmp_path, joint("base", "world", "body", "floating", ""), ELBOW, root="world")
    with pytest.raises(ModelError, match="joint 'base': a floating joint below joint 'root_joint'"):
        eg.from_urdf(path, floating_base=True)


# --- every joint type through Pinocchio's model and back ------------------------------------------------
INERTIA = [[0.02, 0.001, 0], [0.001, 0.03, 0.002], [0, 0.002, 0.025]]
CHAINS = {
    "free flyer": [eg.FreeFlyer("base"), eg.Revolute("r", (0, 1, 0))],
    "spherical": [eg.Spherical("s"), eg.Spherical("z", "zyx", armature=0.2)],
    "universal, translation": [eg.Universal("u", (1, 0, 0), (0, 0.6, 0.8)), eg.Translation("t")],
    "planar, helical": [eg.Planar("p"), eg.Helical("h", (0, 0, 1), 0.05),
                        eg.Helical("h2", (0.6, 0, 0.8), -0.1)],
    "cylindrical": [eg.Cylindrical("c", (0, 0.6, 0.8)), eg.Prismatic("pr", (1, 0, 0), armature=0.3)],
    "mimic": [eg.Revolute("a"), eg.Prismatic("b", (1, 0, 0), mimic=("a", -2, 0.1)),
              eg.Revolute("c", (0, 0.6, 0.8), mimic=("a", 0.5, 0.2))],
}


def chain(joints) -> eg.System:
    system, parent = eg.System(), None
    for k, j in enumerate(joints):
        placement = None if parent is None else eg.Placement(translation=[0.1, 0.05, 0.2])
        parent = system.add_body(f"b{k}", parent=parent, joint=j, mass=1 + 0.1 * k,
                                 com=[0.05, 0.02 * k, 0.1], inertia=INERTIA, placement=placement)
    return system


def describe(system: eg.System) -> list:
    return [(type(b.joint).__name__, b.joint.name, getattr(b.joint, "parametrization", None),
             float(b.joint.armature), getattr(getattr(b.joint, "mimic", None), "driver_name", None))
            for b in system.bodies if b.speed_indices]


@pytest.mark.parametrize("case", CHAINS)
def test_every_joint_type_through_pinocchio_and_back(case):
    system = chain(CHAINS[case])
    back = from_pinocchio(to_pinocchio(system))
    assert describe(back) == describe(system)
    for method in METHODS:
        report = eg.verify(back, method=method, states=3)
        assert report.ok(1e-12), str(report)


def test_pinocchio_joint_models_without_eomgen_twin():
    """HX, HY, HZ, an unbounded revolute, an unaligned prismatic: built with Pinocchio's API."""
    model = pin.Model()
    parent = 0
    joints = [pin.JointModelHX(0.1), pin.JointModelHY(-0.2), pin.JointModelHZ(0.05), pin.JointModelRUBY(),
              pin.JointModelPrismaticUnaligned(np.array([0.6, 0, 0.8]))]
    for k, jm in enumerate(joints):
        placement = pin.SE3(pin.rpy.rpyToMatrix(0.1 * k, -0.2, 0.3), np.array([0.1, 0.05 * k, 0.2]))
        parent = model.addJoint(parent, jm, placement, f"j{k}")
        inertia = pin.Inertia(1 + 0.1 * k, np.array([0.05, 0.02, 0.1]), np.array(INERTIA))
        model.appendBodyToJoint(parent, inertia, pin.SE3.Identity())
        model.addFrame(pin.Frame(f"b{k}", parent, pin.SE3.Identity(), pin.FrameType.BODY))
        model.armature[model.joints[parent].idx_v] = 0.1 * k
    system = from_pinocchio(model)
    assert [type(j).__name__ for j in system.joints] == ["Helical"] * 3 + ["Revolute", "Prismatic"]
    assert system.continuous == [False] * 3 + [True, False]
    for method in ("recursive", "lagrange"):
        report = eg.verify(system, method=method, states=3)
        assert report.ok(1e-12), str(report)


def two_joints(second, parent_of_second: int = 1) -> pin.Model:
    model = pin.Model()
    a = model.addJoint(0, pin.JointModelRZ(), pin.SE3.Identity(), "a")
    model.appendBodyToJoint(a, pin.Inertia(1, np.zeros(3), np.array(INERTIA)), pin.SE3.Identity())
    b = model.addJoint(parent_of_second, second, pin.SE3(np.eye(3), np.array([0.1, 0, 0])), "b")
    model.appendBodyToJoint(b, pin.Inertia(1, np.zeros(3), np.array(INERTIA)), pin.SE3.Identity())
    return model


def test_pinocchio_models_eomgen_cannot_take():
    screw = pin.JointModelHelicalUnaligned(np.array([0, 0.6, 0.8]), 0.1)
    helical = pin.transformJointIntoMimic(two_joints(screw), 1, 2, 2.0, 0.1)  # Pinocchio 4.1 crashes on it
    with pytest.raises(ModelError, match="joint 'b' mimics 'a' as a HelicalUnaligned"):
        from_pinocchio(helical)
    with pytest.raises(ModelError, match="joint 'b' mimics 'a' with multiplier 0"):
        from_pinocchio(pin.transformJointIntoMimic(two_joints(pin.JointModelRX()), 1, 2, 0.0, 0.3))
    composite = pin.JointModelComposite(pin.JointModelRX())
    composite.addJoint(pin.JointModelRY())
    with pytest.raises(ModelError, match="joint 'b': unsupported joint type JointModelComposite"):
        from_pinocchio(two_joints(composite))
    with pytest.raises(ModelError, match="joint 'b': a floating joint below joint 'a'"):
        from_pinocchio(two_joints(pin.JointModelFreeFlyer()))
    model = two_joints(pin.JointModelSpherical())
    model.armature[2] = 0.1
    with pytest.raises(ModelError, match=r"joint 'b': armature \[0.0, 0.1, 0.0\]"):
        from_pinocchio(model)
