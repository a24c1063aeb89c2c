"""Denavit-Hartenberg tables (`eg.from_dh`): the Puma 560 and the Stanford arm against Pinocchio built
here from the same tables (each DH transform an SE3 product), the symbolic planar arm against its
textbook closed form, standard and modified tables of one robot, bad input, random tables."""
from __future__ import annotations

import math

import mpmath
import numpy as np
import pinocchio as pin
import pytest
import sympy as sp
from hypothesis import HealthCheck, Phase, given, settings
from hypothesis import strategies as st

import eomgen as eg
import strategies as S
from eomgen.model import dh, dh_tables
from models import matrices_trig_equal, random_inertia


# --- the same table in Pinocchio ----------------------------------------------------------------
def rz(t):
    return pin.SE3(pin.utils.rotate("z", t), np.zeros(3))


def rx(t):
    return pin.SE3(pin.utils.rotate("x", t), np.zeros(3))


def tz(d):
    return pin.SE3(np.eye(3), np.array([0.0, 0.0, d]))


def tx(a):
    return pin.SE3(np.eye(3), np.array([a, 0.0, 0.0]))


def se3(placement) -> pin.SE3:
    if placement is None:
        return pin.SE3.Identity()
    return pin.SE3(np.array(placement.rotation.tolist(), float),
                   np.array(placement.translation.tolist(), float).ravel())


def floats_of(link: eg.DHLink) -> dict:
    """The link's fields as floats; the variable (θ or d) at q = 0, i.e. its offset."""
    f = {k: float(getattr(link, k) if getattr(link, k) is not None else link.offset)
         for k in ("d", "a", "alpha", "theta")}
    inertia = np.zeros((3, 3)) if link.inertia is None else np.array(sp.Matrix(link.inertia).tolist(), float)
    f.update(m=float(link.mass), c=np.array(link.com, float).ravel(), I=inertia,
             armature=float(link.armature) + float(link.gear_ratio) ** 2 * float(link.motor_inertia))
    return f


class PinocchioDH:
    """A DH table built with Pinocchio's API. Standard: joint i turns (RZ) or slides (PZ) DH frame i−1
    and carries DH frame i at Rz(θ) Tz(d) Tx(a) Rx(α) (θ, d at q = 0); the next joint sits there.
    Modified: joint i sits at Rx(α) Tx(a) Rz(θ) Tz(d) in DH frame i−1 and is DH frame i itself."""

    def __init__(self, links, convention="standard", base=None, tool=None, gravity=(0, 0, -9.81)):
        model = pin.Model()
        model.gravity.linear = np.array(gravity, float)
        parent, previous = 0, se3(base)  # previous: DH frame i−1 in the frame of joint `parent`
        self.frames = {}
        for i, link in enumerate(links, start=1):
            f = floats_of(link)
            joint = pin.JointModelRZ() if link.kind == "revolute" else pin.JointModelPZ()
            if convention == "standard":
                placement, dh_frame = previous, rz(f["theta"]) * tz(f["d"]) * tx(f["a"]) * rx(f["alpha"])
            else:
                placement = previous * rx(f["alpha"]) * tx(f["a"]) * rz(f["theta"]) * tz(f["d"])
                dh_frame = pin.SE3.Identity()
            parent = model.addJoint(parent, joint, placement, f"joint{i}")
            model.appendBodyToJoint(parent, pin.Inertia(f["m"], f["c"], f["I"]), dh_frame)
            model.armature[model.joints[parent].idx_v] = f["armature"]
            self.frames[f"dh{i}"] = model.addFrame(pin.Frame(f"dh{i}", parent, dh_frame,
                                                             pin.FrameType.OP_FRAME))
            previous = dh_frame
        if tool is not None:
            self.frames["tool"] = model.addFrame(pin.Frame("tool", parent, previous * se3(tool),
                                                           pin.FrameType.OP_FRAME))
        self.model, self.data = model, model.createData()

    def dynamics(self, q, u):
        n = self.model.nv
        M = pin.crba(self.model, self.data, q).reshape(n, n)
        M = np.triu(M) + np.triu(M, 1).T
        g = pin.computeGeneralizedGravity(self.model, self.data, q).reshape(n)
        return M, pin.nonLinearEffects(self.model, self.data, q, u).reshape(n) - g, g.copy()

    def jacobian(self, frame, q):
        pin.computeJointJacobians(self.model, self.data, q)
        pin.updateFramePlacements(self.model, self.data)
        J = pin.getFrameJacobian(self.model, self.data, self.frames[frame], pin.LOCAL_WORLD_ALIGNED)
        return J.reshape(6, self.model.nv)


def close(actual, expected, what, rtol=1e-12):
    expected = np.asarray(expected, float)
    atol = rtol * max(1.0, np.abs(expected).max())
    np.testing.assert_allclose(actual, expected, rtol=0, atol=atol, err_msg=what)


def states(links, n, rng):
    for _ in range(n):
        q = np.array([rng.uniform(-np.pi, np.pi) if link.kind == "revolute" else rng.uniform(-1, 1)
                      for link in links])
        yield q, rng.uniform(-2, 2, len(links))


def assert_equal_to_pinocchio(system, reference, links, frames, n=10, seed=0, rtol=1e-12):
    f = eg.codegen(eg.derive(system, frames=frames), backend="numpy")
    for q, u in states(links, n, np.random.default_rng(seed)):
        M, b, g = reference.dynamics(q, u)
        close(f.M(q), M, "M", rtol)
        close(f.b(q, u), b, "b", rtol)
        close(f.g(q), g, "g", rtol)
        for frame in frames:
            close(f.jacobian(frame, q), reference.jacobian(frame, q), f"J {frame}", rtol)


# --- 1. the shipped robots ----------------------------------------------------------------------
@pytest.mark.parametrize("name", ["puma560", "stanford"])
def test_shipped_robot_equals_pinocchio(name):
    links = getattr(dh_tables, name)()
    system = eg.robots.load(name)
    assert system.name == name and [b.name for b in system.bodies] == [f"link{i}" for i in range(1, 7)]
    assert [j.name for j in system.joints] == [f"q{i}" for i in range(1, 7)]
    assert [type(j) for j in system.joints] == [eg.Prismatic if link.kind == "prismatic" else eg.Revolute
                                                for link in links]
    assert any(link.kind == "prismatic" for link in links) == (name == "stanford")
    assert_equal_to_pinocchio(system, PinocchioDH(links), links, ["dh6", "dh3"])


@pytest.mark.parametrize("name", ["puma560", "stanford"])
def test_shipped_robot_verify(name):
    report = eg.verify(eg.robots.load(name), states=5, seed=3)
    assert any(k.startswith("J dh6") for k in report.errors)
    assert report.ok(1e-10), str(report)


def test_puma_equals_robotics_toolbox():
    """The Robotics Toolbox for Python's own results for its Puma560 at qn (its tests/test_DHRobot.py,
    printed to 4 decimals or 6 figures; no friction terms): inertia (M with G² J_m), gravload, rne at
    q̇ = 0, q̈ = 1 (M·1 + g), itorque and coriolis (C q̇ = b). Catches a wrong number in the table."""
    f = eg.codegen(eg.derive(eg.robots.load("puma560")), backend="numpy")
    qn = np.array([0, np.pi / 4, np.pi, 0, np.pi / 4, 0])
    inertia = [[3.6594, -0.4044, 0.1006, -0.0025, 0.0000, -0.0000],
               [-0.4044, 4.4137, 0.3509, 0.0000, 0.0024, 0.0000],
               [0.1006, 0.3509, 0.9378, 0.0000, 0.0015, 0.0000],
               [-0.0025, 0.0000, 0.0000, 0.1925, 0.0000, 0.0000],
               [0.0000, 0.0024, 0.0015, 0.0000, 0.1713, 0.0000],
               [-0.0000, 0.0000, 0.0000, 0.0000, 0.0000, 0.1941]]
    coriolis = [[-0.1735, -2.0494, -0.1178, -0.0002, -0.0045, 0.0001],
                [0.6274, 1.1572, 1.9287, -0.0015, -0.0003, -0.0000],
                [-0.3608, -0.7734, -0.0018, -0.0009, -0.0064, -0.0000],
                [0.0011, 0.0005, -0.0001, 0.0002, 0.0002, -0.0001],
                [-0.0002, 0.0028, 0.0046, -0.0002, -0.0000, -0.0000],
                [0.0001, 0.0000, 0.0000, 0.0000, 0.0000, 0]]
    qd = np.array([1.0, 2, 3, 1, 2, 3])
    M, g = f.M(qn), f.g(qn)
    np.testing.assert_allclose(M, inertia, rtol=0, atol=6e-5)
    np.testing.assert_allclose(g, [-0.0000, 31.6399, 6.0351, 0.0000, 0.0283, 0], rtol=0, atol=6e-5)
    np.testing.assert_allclose(M @ np.ones(6) + g, [3.35311, 36.0025, 7.42596, 0.190043, 0.203441, 0.194133],
                               rtol=0, atol=6e-5)
    np.testing.assert_allclose(M @ qd, [3.1500, 9.4805, 3.6189, 0.1901, 0.3519, 0.5823], rtol=0, atol=6e-5)
    np.testing.assert_allclose(f.b(qn, qd), np.array(coriolis) @ qd, rtol=0, atol=5e-5 * qd.sum())


def test_puma_armature_is_reflected_motor_inertia():
    """armature = G² J_m, e.g. joint 2: 107.815² · 200e-6 (Pinocchio's M_ii term)."""
    system = eg.robots.load("puma560")
    expected = [G**2 * Jm for G, Jm in [(-62.6111, 200e-6), (107.815, 200e-6), (-53.7063, 200e-6),
                                        (76.0364, 33e-6), (71.923, 33e-6), (76.686, 33e-6)]]
    np.testing.assert_allclose([float(j.armature) for j in system.joints], expected, rtol=1e-14)


def test_unknown_robot_lists_dh_robots():
    with pytest.raises(eg.ModelError, match="puma560, stanford"):
        eg.robots.load("puma561")


# --- 2. the symbolic planar arm ----------------------------------------------------------------
@pytest.mark.parametrize("convention", ["standard", "modified"])
def test_planar_arm_closed_form(convention):
    """Spong's two-link arm: com at l_ci along the link, I_i about z, gravity along −y of frame 0."""
    l1, l2, lc1, lc2, m1, m2, I1, I2, g = sp.symbols("l1 l2 lc1 lc2 m1 m2 I1 I2 g", positive=True)
    if convention == "standard":  # frame i at the distal end of link i
        links = [eg.DHLink(d=0, a=l1, alpha=0, mass=m1, com=(-(l1 - lc1), 0, 0), inertia=sp.diag(0, 0, I1)),
                 eg.DHLink(d=0, a=l2, alpha=0, mass=m2, com=(-(l2 - lc2), 0, 0), inertia=sp.diag(0, 0, I2))]
    else:  # frame i at the joint of link i
        links = [eg.DHLink(d=0, a=0, alpha=0, mass=m1, com=(lc1, 0, 0), inertia=sp.diag(0, 0, I1)),
                 eg.DHLink(d=0, a=l1, alpha=0, mass=m2, com=(lc2, 0, 0), inertia=sp.diag(0, 0, I2))]
    system = eg.from_dh(links, convention=convention, gravity=(0, -g, 0))
    q1, q2 = system.q
    u1, u2 = system.u
    assert str(u1) == "q1dot"
    eom = eg.derive(system)
    c2 = sp.cos(q2)
    M12 = I2 + m2 * (lc2**2 + l1 * lc2 * c2)
    M = sp.Matrix([[I1 + I2 + m1 * lc1**2 + m2 * (l1**2 + lc2**2 + 2 * l1 * lc2 * c2), M12],
                   [M12, I2 + m2 * lc2**2]])
    h = -m2 * l1 * lc2 * sp.sin(q2)
    b = sp.Matrix([h * u2 * (2 * u1 + u2), -h * u1**2])
    G = sp.Matrix([(m1 * lc1 + m2 * l1) * g * sp.cos(q1) + m2 * lc2 * g * sp.cos(q1 + q2),
                   m2 * lc2 * g * sp.cos(q1 + q2)])
    for got, want in ((eom.M, M), (eom.b, b), (eom.g, G)):
        assert sp.simplify(got - want) == sp.zeros(*want.shape)
        assert matrices_trig_equal(sp.expand_trig(got), sp.expand_trig(want), [q1, q2])


def test_symbolic_table_keeps_parameters_and_exact_angles():
    """Symbolic d, a, α, offset, armature: the placements are the DH transforms in those symbols."""
    d1, a1, a2, al2, off, Jm, N, A = sp.symbols("d1 a1 a2 alpha2 theta_off J_m N A")
    system = eg.from_dh([eg.DHLink(d=d1, a=a1, alpha=sp.pi / 2, offset=off, mass=1, armature=A,
                                   gear_ratio=N, motor_inertia=Jm),
                         eg.DHLink(theta=0, a=a2, alpha=al2, kind="prismatic", mass=1)])
    link1, link2 = system.bodies
    assert link1.joint.armature == A + N**2 * Jm
    assert link1.placement.rotation == sp.Matrix([[sp.cos(off), -sp.sin(off), 0],
                                                  [sp.sin(off), sp.cos(off), 0], [0, 0, 1]])
    assert list(link1.placement.translation) == [0, 0, d1]
    # link 2 hangs at Tx(a1) Rx(π/2) (exact) and then Rz(0) Tz(0)
    assert link2.placement.rotation == sp.Matrix([[1, 0, 0], [0, 0, -1], [0, 1, 0]])
    assert list(link2.placement.translation) == [a1, 0, 0]
    assert system.frames["dh2"].placement.rotation == sp.Matrix(
        [[1, 0, 0], [0, sp.cos(al2), -sp.sin(al2)], [0, sp.sin(al2), sp.cos(al2)]])
    assert system.parameters == {d1, a1, a2, al2, off, Jm, N, A}


def test_float_quarter_turns_are_exact():
    """α = math.pi / 2 gives exact 0, ±1 (not 6e-17); 1.5708 is kept as it is."""
    system = eg.from_dh([eg.DHLink(d=0, a=0, alpha=math.pi / 2, offset=-math.pi, mass=1),
                         eg.DHLink(d=0, a=0, alpha=1.5708, mass=1)])
    assert system.frames["dh1"].placement.rotation == sp.Matrix([[1, 0, 0], [0, 0, -1], [0, 1, 0]])
    assert system.bodies[0].placement.rotation == sp.diag(-1, -1, 1)
    R = system.frames["dh2"].placement.rotation
    assert R[1, 1] == sp.cos(sp.Float(1.5708)) and R[1, 1] != 0


def test_names_base_and_tool():
    base = eg.Placement(translation=(0, 0, 0.5))
    tool = eg.Placement(translation=(0, 0, 0.1))
    system = eg.from_dh([eg.DHLink(d=0.3, a=0, alpha=0, name="shoulder", mass=1),
                         eg.DHLink(theta=0, a=0, alpha=0, kind="prismatic", name=sp.Symbol("s"), mass=1)],
                        base=base, tool=tool)
    assert [j.name for j in system.joints] == ["shoulder", "s"] and system.q[1] == sp.Symbol("s")
    assert [b.name for b in system.bodies] == ["link1", "link2"]
    assert sorted(system.frames) == ["dh1", "dh2", "tool"]
    f = eg.codegen(eg.derive(system, frames=["tool"]), backend="numpy")
    J = f.jacobian("tool", np.array([0.4, 0.2]))
    np.testing.assert_allclose(J[:, 1], [0, 0, 1, 0, 0, 0], atol=1e-15)  # slides along z


# --- 3. standard and modified tables of one robot ----------------------------------------------
def to_modified(links, tool):
    """Craig's row i = (α_{i−1}, a_{i−1}, θ_i, d_i); modified frame i = standard frame i ·
    (Tx(a_i) Rx(α_i))⁻¹, so com and inertia pass through Tx(a_i) Rx(α_i); the last tail goes
    to the tool."""
    out, a_prev, alpha_prev = [], 0, 0
    for link in links:
        f = floats_of(link)
        T = tx(f["a"]) * rx(f["alpha"])
        fields = dict(theta=link.theta) if link.kind == "prismatic" else dict(d=link.d)
        out.append(eg.DHLink(kind=link.kind, a=a_prev, alpha=alpha_prev, offset=link.offset, mass=link.mass,
                             com=tuple(T.act(f["c"])), inertia=(T.rotation @ f["I"] @ T.rotation.T).tolist(),
                             armature=link.armature, gear_ratio=link.gear_ratio,
                             motor_inertia=link.motor_inertia, **fields))
        a_prev, alpha_prev = link.a, link.alpha
    tail = tx(float(a_prev)) * rx(float(alpha_prev)) * se3(tool)
    return out, eg.Placement(rotation=tail.rotation.tolist(), translation=tuple(tail.translation))


def spatial_arm(rng):
    """Revolute, prismatic, revolute; offsets, a twist that is not a quarter turn, full inertias."""
    def dyn():
        return dict(mass=rng.uniform(0.5, 3), com=tuple(rng.uniform(-0.3, 0.3, 3)),
                    inertia=random_inertia(rng).tolist(), motor_inertia=rng.uniform(0, 1e-3),
                    gear_ratio=rng.uniform(10, 100))
    return [eg.DHLink(d=0.4, a=0.1, alpha=sp.pi / 2, offset=0.3, **dyn()),
            eg.DHLink(kind="prismatic", theta=-0.7, a=0.25, alpha=0.4, offset=0.2, **dyn()),
            eg.DHLink(d=0.05, a=0.3, alpha=-sp.pi / 2, offset=-1.1, **dyn())]


@pytest.mark.filterwarnings("ignore:.*triangle inequality")
@pytest.mark.parametrize("robot", ["puma560", "spatial_arm"])
def test_standard_equals_modified(robot):
    links = dh_tables.puma560() if robot == "puma560" else spatial_arm(np.random.default_rng(4))
    tool = eg.Placement(rotation=sp.Matrix([[0, -1, 0], [1, 0, 0], [0, 0, 1]]),
                        translation=(0.01, 0.02, 0.1))
    modified, modified_tool = to_modified(links, tool)
    base = eg.Placement(translation=(0.1, -0.2, 0.3))
    standard = eg.from_dh(links, base=base, tool=tool, strict=False)
    craig = eg.from_dh(modified, convention="modified", base=base, tool=modified_tool, strict=False)
    f = eg.codegen(eg.derive(standard, frames=["tool"]), backend="numpy")
    h = eg.codegen(eg.derive(craig, frames=["tool"]), backend="numpy")
    for q, u in states(links, 10, np.random.default_rng(5)):
        close(h.M(q), f.M(q), "M")
        close(h.b(q, u), f.b(q, u), "b")
        close(h.g(q), f.g(q), "g")
        close(h.jacobian("tool", q), f.jacobian("tool", q), "J tool")
    # and the modified one against Pinocchio built from the modified table
    assert_equal_to_pinocchio(craig, PinocchioDH(modified, "modified", base, modified_tool), modified,
                              ["tool", "dh2"], n=3)


# --- 4. bad input ------------------------------------------------------------------------------
@pytest.mark.parametrize("links,kwargs,match", [
    ([eg.DHLink(a=0, alpha=0)], {}, r"DH link 1: field 'd' is missing"),
    ([eg.DHLink(d=0, a=0, alpha=0), eg.DHLink(d=0, alpha=0, name="elbow")], {},
     r"DH link 2 \('elbow'\): field 'a' is missing"),
    ([eg.DHLink(kind="prismatic", a=0, alpha=0)], {}, r"DH link 1: field 'theta' is missing"),
    ([eg.DHLink(d=0, a=0, alpha=0, theta=0.3, name="q")], {},
     r"DH link 1 \('q'\): field 'theta' is the joint variable of a revolute link"),
    ([eg.DHLink(d=0.1, theta=0, a=0, alpha=0, kind="prismatic")], {},
     r"DH link 1: field 'd' is the joint variable of a prismatic link"),
    ([eg.DHLink(d=0, a=0, alpha=0, kind="spherical")], {}, r"DH link 1: field 'kind' must be 'revolute' or"),
    ([eg.DHLink(d=0, a=0, alpha=0, kind=None)], {}, r"DH link 1: field 'kind'"),
    ([eg.DHLink(d=0, a="0.5", alpha=0, name="x")], {},
     r"DH link 1 \('x'\): field 'a'.*strings are not parsed"),
    ([eg.DHLink(d=0, a=0, alpha=0, mass=1, com=(0, "1", 0))], {}, r"DH link 1: field 'com'\[1\].*strings"),
    ([eg.DHLink(d=0, a=0, alpha=0, inertia="I")], {}, r"DH link 1: field 'inertia'"),
    ([eg.DHLink(d=0, a=0, alpha=0, mass=-1)], {}, r"DH link 1: .*mass must be non-negative"),
    ([eg.DHLink(d=0, a=0, alpha=0, name="")], {}, r"DH link 1 \(''\): field 'name'"),
    ([eg.DHLink(d=0, a=0, alpha=0, name="j"), eg.DHLink(d=0, a=0, alpha=0, name="j")], {},
     r"DH link 2 \('j'\): .*coordinate 'j' is used by another joint"),
    ([(0, 0, 0)], {}, r"DH link 1: expected an eomgen.DHLink, got tuple"),
    ([], {}, r"from_dh: links must be a non-empty list"),
    ([eg.DHLink(d=0, a=0, alpha=0)], {"convention": "craig"},
     r"convention must be 'standard' or 'modified'"),
    ([eg.DHLink(d=0, a=0, alpha=0)], {"tool": (0, 0, 1)}, r"from_dh: tool must be an eomgen.Placement"),
])
def test_bad_tables(links, kwargs, match):
    with pytest.raises(eg.ModelError, match=match):
        eg.from_dh(links, **kwargs)


# --- 5. random tables against Pinocchio ---------------------------------------------------------
QUARTERS = [k * math.pi / 2 for k in range(-2, 3)]


def angles():
    return st.one_of(st.sampled_from(QUARTERS), S._floats(-math.pi, math.pi))


@st.composite
def dh_links(draw):
    kind = draw(st.sampled_from(["revolute", "revolute", "prismatic"]))
    mass = draw(st.one_of(st.just(0.0), S._floats(0.1, 5.0)))
    fields = dict(theta=draw(angles())) if kind == "prismatic" else dict(d=draw(S._floats(-0.5, 0.5)))
    return eg.DHLink(kind=kind, a=draw(st.one_of(st.just(0.0), S._floats(-0.5, 0.5))), alpha=draw(angles()),
                     offset=draw(st.one_of(st.just(0.0), angles())), mass=mass,
                     com=draw(S.vectors(-0.3, 0.3)),
                     inertia=[list(r) for r in draw(S.inertias(mass))], armature=draw(S._floats(0, 0.1)),
                     gear_ratio=draw(S._floats(-100, 100)), motor_inertia=draw(S._floats(0, 1e-4)), **fields)


def placements():
    def placement(R, p):
        return eg.Placement(rotation=[list(r) for r in R], translation=p)
    return st.one_of(st.none(), st.builds(placement, S.rotations(), S.vectors()))


@settings(max_examples=30, deadline=None, derandomize=True, database=None, print_blob=True,
          phases=[Phase.explicit, Phase.reuse, Phase.generate],  # shrinking re-derives hundreds of times
          suppress_health_check=[HealthCheck.too_slow, HealthCheck.data_too_large])
@given(links=st.lists(dh_links(), min_size=1, max_size=4).filter(lambda ls: sum(l.mass for l in ls) > 0),
       convention=st.sampled_from(["standard", "modified"]), base=placements(), tool=placements(),
       gravity=st.one_of(st.just((0.0, 0.0, -9.81)), S.vectors(-10, 10)))
def test_random_tables_equal_pinocchio(links, convention, base, tool, gravity):
    system = eg.from_dh(links, convention=convention, base=base, tool=tool, gravity=gravity)
    reference = PinocchioDH(links, convention, base, tool, gravity)
    frames = [f"dh{i}" for i in range(1, len(links) + 1)] + (["tool"] if tool else [])
    assert_equal_to_pinocchio(system, reference, links, frames, n=3, rtol=1e-11)


def test_example_runs(capsys):
    import runpy
    from pathlib import Path

    runpy.run_path(str(Path(__file__).parents[1] / "examples" / "dh_puma560.py"), run_name="__main__")
    out = capsys.readouterr().out
    assert "worst relative error" in out and ": OK (tolerance" in out and "J dh6" in out


def test_huge_float_angles_are_not_snapped():
    """alpha = 1e17 is no multiple of π/2 (its float64 cos is −0.886, numpy's): eomgen used to snap
    every angle above ~1e15 to one, here making Rx(alpha) the identity."""
    for alpha, offset in ((1e17, 0.0), (0.3, -2.5e15), (1e100, 1e-300)):
        system = eg.from_dh([eg.DHLink(d=0, a=0, alpha=alpha, offset=offset, mass=1)])
        R = np.array(system.frames["dh1"].placement.rotation, float)
        np.testing.assert_allclose(R, pin.utils.rotate("x", alpha), rtol=0, atol=1e-15)
        np.testing.assert_allclose(np.array(system.bodies[0].placement.rotation, float),
                                   pin.utils.rotate("z", offset), rtol=0, atol=1e-15)


@settings(max_examples=300, deadline=None)
@given(st.one_of(S._floats(-1.8e308, 1.8e308), S._floats(-1e20, 1e20), st.builds(
    lambda k, e: k * math.pi / 2 + e, st.integers(-10**6, 10**6), S._floats(-1e-9, 1e-9))))
def test_float_angles_give_float64_cos_and_sin(angle):
    """cos and sin of any float angle are numpy's (the float's own value) to within the snap tolerance:
    a float within 1e-12 of k π/2 gives the exact 0, ±1, any other its cos and sin."""
    c, s = dh.cos_sin(sp.Float(angle))
    assert abs(float(c) - np.cos(angle)) <= dh.SNAP and abs(float(s) - np.sin(angle)) <= dh.SNAP
    with mpmath.workprec(1200):  # above the largest float's exponent, 2^1024
        x = mpmath.mpf(angle)
        near = abs(x - mpmath.nint(2 * x / mpmath.pi) * mpmath.pi / 2) < dh.SNAP
    assert (c.is_Integer and s.is_Integer) == near
