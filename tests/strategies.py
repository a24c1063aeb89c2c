"""Hypothesis strategies: random numeric trees with adversarial names, and the same tree built with
Pinocchio's own API (the independent truth).

A drawn `Tree` is plain data (it prints as a reproduction): bodies with revolute, prismatic or fixed
joints on random unit axes, random placements, physical inertias, masses and coms; frames; loads (a
spring between two points, a force, a torque). Names of bodies, joints, frames and loads come from
`NAMES`: keywords, sympy names, the names eomgen generates itself, unicode, punctuation, newlines.
Bodies and frames share one namespace, joints another, loads a third (the library's rule); nothing
else is kept apart, so a joint named 'adot' beside a joint 'a' is fair game."""
from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
import pinocchio as pin
from hypothesis import strategies as st

import eomgen as eg

# --- names ------------------------------------------------------------------------------------
KEYWORDS = ["lambda", "def", "int", "return", "class", "import", "None", "True", "if", "for", "while",
            "double", "const", "void", "struct", "static", "include", "main", "out", "q", "u", "ud", "p",
            "sin", "cos", "sqrt", "math", "numpy", "np", "exp", "log", "pow"]
SYMPY = ["sin", "cos", "E", "I", "S", "N", "O", "Q", "pi", "beta", "gamma", "zeta", "oo", "nan", "zoo",
         "Symbol", "Integer", "Float", "Matrix", "x", "y", "z", "t", "Abs", "re", "im", "sign", "Heaviside"]
# names eomgen makes itself (speeds, accelerations, free-flyer coordinates, intermediates, code
# variables, actuator torques, motor currents, free-cut unknowns, flexible-link symbols)
EOMGEN = ["a", "adot", "addot", "adotdot", "q_1", "qdot_1", "qddot_1", "q", "qdot", "qddot", "phi", "phidot",
          "root_joint", "root_joint_vx", "root_joint_x", "root_joint_qw", "root_joint_vxdot",
          "_ξ0", "_ξ1", "_ξ2", "_ξ10", "_x0", "_x1", "_q0", "_q1", "_u0", "_ud0", "_p0", "_p1", "_sin_q0",
          "_cos_q0", "_c0", "_s0", "tau_a", "tau_q_1", "tau_link", "i_motor", "U_motor", "F_link_x", "T_link_1",
          "a_link_x", "alpha_link_y", "link", "xi", "h", "x0", "w2_link", "fixed", "link_fixed", "world",
          "universe", "spring0", "force0", "torque0"]
UNICODE = ["φ", "θ₁", "ω̇", "ξ", "関節", "腕", "e\u0301", "\u00e9", "Å", "A\u030a", "ﬁ", "fi", "𝑥", "x²",
           "\u200b", "a\u200db", "\u202eevil", "🤖", "Ω", "µ", "μ"]
PUNCTUATION = ["upper arm, left", "a b", " lead", "trail ", "a,b", "x=1", "a'b", 'a"b', "'''", '"""', "\\",
               "a\\nb", "*/", "/*", "// c", "#", "a\nb", "\n", "\r\n", "\t", "%s", "{0}", "{}", "$x", "a;b",
               "1", "0", "-1", "1e3", "1.5", "(", ")", "[0]", "a.b", "a:b", "<tag>", "&amp;", "\x00", "\x7f"]
ALPHABET = KEYWORDS + SYMPY + EOMGEN + UNICODE + PUNCTUATION


# Families of names that collide with each other through eomgen's own naming, drawn together in one
# tree so that the collisions happen: speeds and accelerations, intermediates, code variables,
# torques and currents, free-cut unknowns, sympy's splitting of names at spaces and commas,
# NFKC-equal spellings.
CLUSTERS = [
    ["a", "adot", "addot", "adotdot", "adot_1", "a_1", "adot_1", "ad", "add", "addd"],
    ["q_1", "qdot_1", "qddot_1", "q", "qdot", "qddot", "q_1_1", "qdot_1_1", "q_", "qdot_"],
    ["_ξ0", "_ξ1", "_ξ2", "_ξ3", "_ξ5", "_ξ8", "_ξ10", "_ξ20"],
    ["_x0", "_x1", "_x3", "_q0", "_q1", "_u0", "_u1", "_ud0", "_p0", "_sin_q0", "_cos_q1"],
    ["root_joint", "root_joint_vx", "root_joint_x", "root_joint_qw", "root_joint_wz"],
    ["a", "tau_a", "tau_tau_a", "i_a", "U_a", "motor_a"],
    ["link", "F_link_x", "F_link_1", "T_link_1", "T_link_x", "a_link_x", "alpha_link_y", "link_fixed"],
    ["t", "xi", "h", "x0", "T", "U", "w2_a", "s2_a"],
    ["sin", "cos", "sqrt", "pi", "E", "I", "S", "N", "oo", "nan"],
    ["upper arm, left", "upper arm", "left", "a b", "a,b", "a", "b", "a_a", "a_b", "x y", "a:b", "a:2"],
    ["e\u0301", "\u00e9", "Å", "A\u030a", "ﬁ", "fi", "𝑥", "x", "µ", "μ"],
]


def name_strategy(cluster: list[str] | None = None) -> st.SearchStrategy[str]:
    """Any non-blank string: most often one of the adversarial names (of `cluster`, if given), or
    two of them joined, or any text."""
    fixed = st.sampled_from(ALPHABET)
    joined = st.tuples(fixed, st.sampled_from(["", "_", " ", "dot", "_1", "\n"]), fixed).map("".join)
    choices = [fixed, fixed, joined, st.text(min_size=1, max_size=8)]
    if cluster:
        choices = [st.sampled_from(cluster)] * 6 + choices
    return st.one_of(*choices).filter(lambda s: s.strip() != "")


@st.composite
def unique_names(draw, n: int, taken: set | None = None, cluster: list[str] | None = None) -> list[str]:
    taken = set() if taken is None else taken
    out = []
    for _ in range(n):
        name = draw(name_strategy(cluster).filter(lambda s: s not in taken))
        taken.add(name)
        out.append(name)
    return out


# --- numbers ----------------------------------------------------------------------------------
def _floats(lo, hi):
    return st.floats(lo, hi, allow_nan=False, allow_infinity=False)


@st.composite
def unit_vectors(draw, principal: bool = True) -> tuple:
    if principal and draw(st.integers(0, 3)) == 0:
        return draw(st.sampled_from([(1, 0, 0), (0, 1, 0), (0, 0, 1), (0, 0, -1), (0, -1, 0)]))
    v = np.array(draw(st.tuples(_floats(-1, 1), _floats(-1, 1), _floats(-1, 1)).filter(
        lambda v: np.linalg.norm(v) > 0.2)))
    return tuple(float(x) for x in v / np.linalg.norm(v))


def rotation_from_quaternion(qv) -> np.ndarray:
    w, x, y, z = np.asarray(qv, float) / np.linalg.norm(qv)
    return np.array([[1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
                     [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
                     [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)]])


@st.composite
def rotations(draw) -> tuple:
    """A proper rotation (sometimes exactly the identity), as nested tuples."""
    if draw(st.integers(0, 4)) == 0:
        return ((1, 0, 0), (0, 1, 0), (0, 0, 1))
    qv = draw(st.tuples(*[_floats(-1, 1)] * 4).filter(lambda v: np.linalg.norm(v) > 0.2))
    return tuple(tuple(float(x) for x in row) for row in rotation_from_quaternion(qv))


def vectors(lo=-0.5, hi=0.5):
    return st.tuples(_floats(lo, hi), _floats(lo, hi), _floats(lo, hi))


@st.composite
def inertias(draw, mass: float) -> tuple:
    """Inertia about the com of a solid box (principal moments obey the triangle inequality; a flat
    box meets it with equality), rotated; zero for a point mass."""
    shape = draw(st.sampled_from(["box", "box", "flat", "point"]))
    if shape == "point" or mass == 0:
        return ((0.0,) * 3,) * 3
    a, b, c = draw(vectors(0.02, 0.6))
    if shape == "flat":
        c = 0.0
    D = np.diag([b * b + c * c, a * a + c * c, a * a + b * b]) * mass / 12
    R = np.array(draw(rotations()), float)
    I = R @ D @ R.T
    I = (I + I.T) / 2
    return tuple(tuple(float(x) for x in row) for row in I)


# --- the tree ---------------------------------------------------------------------------------
@dataclass
class BodySpec:
    name: str
    parent: int  # index of an earlier body, -1 for the world
    kind: str  # "revolute", "prismatic", "fixed" or one of JOINTS
    joint: str
    axis: tuple
    rotation: tuple  # placement of the joint frame in the parent's body frame
    translation: tuple
    mass: float
    com: tuple
    inertia: tuple  # about the com, body axes
    axis2: tuple = (0.0, 1.0, 0.0)  # universal joint: second axis
    pitch: float = 0.0  # helical joint


# the other joint types: (number of coordinates, of speeds)
JOINTS = {"spherical": (4, 3), "zyx": (3, 3), "universal": (2, 2), "planar": (3, 3), "cylindrical": (2, 2),
          "translation": (3, 3), "helical": (1, 1)}
SIZE = {"revolute": (1, 1), "prismatic": (1, 1), "fixed": (0, 0), **JOINTS}


@dataclass
class FrameSpec:
    name: str
    body: int
    rotation: tuple
    translation: tuple


@dataclass
class LoadSpec:
    kind: str  # "spring", "force", "torque"
    name: str
    body: int = -1  # force, torque; spring: end a (-1 = world)
    point: tuple = (0.0, 0.0, 0.0)  # force: point; spring: offset of end a
    vector: tuple = (0.0, 0.0, 0.0)  # force or torque
    in_body_frame: bool = False
    body_b: int = -1  # spring: end b
    point_b: tuple = (0.0, 0.0, 0.0)
    stiffness: float = 0.0
    rest_length: float = 0.0


@dataclass
class Tree:
    gravity: tuple
    bodies: list = field(default_factory=list)
    frames: list = field(default_factory=list)
    loads: list = field(default_factory=list)

    @property
    def moving(self) -> list[int]:
        return [i for i, b in enumerate(self.bodies) if b.kind != "fixed"]


@st.composite
def trees(draw, max_bodies: int = 6, loads: bool = True, fixed: bool = True, frames: int = 2) -> Tree:
    n = draw(st.integers(1, max_bodies))
    gravity = draw(st.sampled_from([(0.0, 0.0, -9.81), None]))
    gravity = gravity or draw(vectors(-10, 10))
    cluster = draw(st.sampled_from(CLUSTERS))
    body_names = draw(unique_names(n, cluster=cluster))
    joint_names = draw(unique_names(n, cluster=cluster))
    tree = Tree(gravity=gravity)
    for i in range(n):
        kinds = ["revolute", "revolute", "prismatic", "other"] + (["fixed"] if fixed and i > 0 else [])
        kind = draw(st.sampled_from(kinds))
        if i == n - 1 and not tree.moving:
            kind = draw(st.sampled_from(["revolute", "prismatic", "other"]))  # at least one moving joint
        if kind == "other":
            kind = draw(st.sampled_from(sorted(JOINTS)))
        axis = draw(unit_vectors())
        axis2 = np.array(draw(unit_vectors()))
        if np.linalg.norm(np.cross(axis, axis2)) < 0.2:  # a universal joint's axes are not parallel
            axis2 = np.cross(axis, (1.0, 0.0, 0.0) if abs(axis[0]) < 0.9 else (0.0, 1.0, 0.0))
            axis2 /= np.linalg.norm(axis2)
        mass = draw(st.one_of(st.just(0.0), _floats(0.05, 5.0), _floats(0.05, 5.0), _floats(0.05, 5.0)))
        if i == n - 1 and all(b.mass == 0 for b in tree.bodies) and mass == 0:
            mass = 1.0  # total mass > 0
        tree.bodies.append(BodySpec(
            name=body_names[i], parent=draw(st.integers(-1, i - 1)), kind=kind, joint=joint_names[i],
            axis=axis, rotation=draw(rotations()), translation=draw(vectors()),
            mass=mass, com=draw(vectors(-0.3, 0.3)) if mass else (0.0, 0.0, 0.0), inertia=draw(inertias(mass)),
            axis2=tuple(float(x) for x in axis2), pitch=draw(_floats(-0.3, 0.3))))
    frame_names = draw(unique_names(draw(st.integers(0, frames)), taken=set(body_names), cluster=cluster))
    for name in frame_names:
        tree.frames.append(FrameSpec(name, draw(st.integers(0, n - 1)), draw(rotations()), draw(vectors())))
    if loads:
        kinds = draw(st.lists(st.sampled_from(["spring", "force", "torque"]), max_size=3))
        load_names = draw(unique_names(len(kinds), cluster=cluster))
        for kind, name in zip(kinds, load_names):
            body = draw(st.integers(0, n - 1))
            if kind == "spring":
                tree.loads.append(LoadSpec("spring", name, body=body, point=draw(vectors()),
                                           body_b=draw(st.integers(-1, n - 1)), point_b=draw(vectors()),
                                           stiffness=draw(_floats(0.1, 50.0)),
                                           rest_length=draw(st.sampled_from([0.0, 0.0, 0.3]))))
            else:
                tree.loads.append(LoadSpec(kind, name, body=body, point=draw(vectors()) if kind == "force" else (0.0,) * 3,
                                           vector=draw(vectors(-5, 5)), in_body_frame=draw(st.booleans())))
    return tree


# --- the tree in eomgen -----------------------------------------------------------------------
def eomgen_system(tree: Tree) -> eg.System:
    """The tree built with eomgen's API, as a user would."""
    system = eg.System(gravity=tree.gravity)
    bodies = []
    for b in tree.bodies:
        joint = {"revolute": lambda: eg.Revolute(b.joint, axis=b.axis),
                 "prismatic": lambda: eg.Prismatic(b.joint, axis=b.axis),
                 "fixed": lambda: eg.Fixed(b.joint),
                 "spherical": lambda: eg.Spherical(b.joint),
                 "zyx": lambda: eg.Spherical(b.joint, parametrization="zyx"),
                 "universal": lambda: eg.Universal(b.joint, b.axis, b.axis2),
                 "planar": lambda: eg.Planar(b.joint),
                 "cylindrical": lambda: eg.Cylindrical(b.joint, b.axis),
                 "translation": lambda: eg.Translation(b.joint),
                 "helical": lambda: eg.Helical(b.joint, b.axis, b.pitch)}[b.kind]()
        bodies.append(system.add_body(b.name, parent=bodies[b.parent] if b.parent >= 0 else None, joint=joint,
                                      mass=b.mass, com=b.com, inertia=[list(r) for r in b.inertia],
                                      placement=eg.Placement(rotation=[list(r) for r in b.rotation],
                                                             translation=b.translation)))
    for f in tree.frames:
        system.add_frame(f.name, bodies[f.body], eg.Placement(rotation=[list(r) for r in f.rotation],
                                                              translation=f.translation))
    for load in tree.loads:
        if load.kind == "spring":
            a = (bodies[load.body] if load.body >= 0 else None, load.point)
            b = (bodies[load.body_b] if load.body_b >= 0 else None, load.point_b)
            system.add_spring(a, b, load.stiffness, load.rest_length, name=load.name)
        elif load.kind == "force":
            system.add_force(bodies[load.body], load.vector, load.point, in_body_frame=load.in_body_frame,
                             name=load.name)
        else:
            system.add_torque(bodies[load.body], load.vector, in_body_frame=load.in_body_frame, name=load.name)
    return system


# --- the same tree in Pinocchio ---------------------------------------------------------------
class PinocchioTree:
    """The tree built with Pinocchio's API (no eomgen code involved): joints with unaligned axes,
    bodies appended to their joints (a fixed body to the joint that carries it), an operational frame
    at every body origin, every named frame and every load point. Names are Pinocchio's own."""

    def __init__(self, tree: Tree) -> None:
        self.tree = tree
        model = pin.Model()
        model.gravity.linear = np.array(tree.gravity, float)
        # Pinocchio's algorithms need each joint's subtree contiguous in v (depth-first order); eomgen
        # numbers joints in the order they were added. perm[k] = eomgen's index of Pinocchio's k-th speed.
        children = {i: [j for j, b in enumerate(tree.bodies) if b.parent == i] for i in range(-1, len(tree.bodies))}
        order, stack = [], list(reversed(children[-1]))
        while stack:
            i = stack.pop()
            order.append(i)
            stack += reversed(children[i])
        q_at, u_at, nq, nv = {}, {}, 0, 0  # eomgen's first coordinate and speed of each body's joint
        for i in tree.moving:
            q_at[i], u_at[i] = nq, nv
            nq, nv = nq + SIZE[tree.bodies[i].kind][0], nv + SIZE[tree.bodies[i].kind][1]
        moving = [i for i in order if i in q_at]
        self.perm = np.array([u_at[i] + k for i in moving for k in range(SIZE[tree.bodies[i].kind][1])], dtype=int)
        self.joints_q = [(tree.bodies[i].kind, q_at[i]) for i in moving]
        carrier = {}  # per body: (Pinocchio joint id, placement of the body frame in that joint's frame)
        for i in order:
            b = tree.bodies[i]
            parent_joint, parent_offset = carrier[b.parent] if b.parent >= 0 else (0, pin.SE3.Identity())
            placement = parent_offset * pin.SE3(np.array(b.rotation, float), np.array(b.translation, float))
            if b.kind == "fixed":
                carrier[i] = (parent_joint, placement)
            else:
                carrier[i] = (model.addJoint(parent_joint, _pinocchio_joint(b), placement, f"joint{i}"),
                              pin.SE3.Identity())
            jid, offset = carrier[i]
            inertia = pin.Inertia(b.mass, np.array(b.com, float), np.array(b.inertia, float))
            model.appendBodyToJoint(jid, inertia, offset)
        self.carrier = carrier
        self.frame_ids: dict = {}

        def add(key, body: int, placement: pin.SE3):
            jid, offset = carrier[body] if body >= 0 else (0, pin.SE3.Identity())
            fid = model.addFrame(pin.Frame(f"frame{len(self.frame_ids)}", jid, offset * placement,
                                           pin.FrameType.OP_FRAME))
            self.frame_ids[key] = fid

        for i in range(len(tree.bodies)):
            add(("body", i), i, pin.SE3.Identity())
        for k, f in enumerate(tree.frames):
            add(("frame", k), f.body, pin.SE3(np.array(f.rotation, float), np.array(f.translation, float)))
        for k, load in enumerate(tree.loads):
            add(("load", k, "a"), load.body, pin.SE3(np.eye(3), np.array(load.point, float)))
            if load.kind == "spring":
                add(("load", k, "b"), load.body_b, pin.SE3(np.eye(3), np.array(load.point_b, float)))
        self.model = model
        self.data = model.createData()

    def configuration(self, q) -> np.ndarray:
        """Pinocchio's q: the joints in its order, a planar joint's angle as (cos θ, sin θ)."""
        parts = []
        for kind, k in self.joints_q:
            x = list(np.asarray(q, float)[k:k + SIZE[kind][0]])
            parts += x[:2] + [np.cos(x[2]), np.sin(x[2])] if kind == "planar" else x
        return np.array(parts)

    def dynamics(self, q, u):
        """(M, b, g) as Pinocchio computes them: crba (upper triangle mirrored), nonLinearEffects − g,
        computeGeneralizedGravity."""
        model, data, perm, n = self.model, self.data, self.perm, self.model.nv
        q, u = self.configuration(q), np.asarray(u, float)[perm]
        Mp = pin.crba(model, data, q).reshape(n, n)
        Mp = np.triu(Mp) + np.triu(Mp, 1).T
        gp = pin.computeGeneralizedGravity(model, data, q).reshape(n)
        bp = pin.nonLinearEffects(model, data, q, u).reshape(n) - gp
        M, b, g = np.zeros((n, n)), np.zeros(n), np.zeros(n)
        M[np.ix_(perm, perm)], b[perm], g[perm] = Mp, bp, gp
        return M, b, g

    def energies(self, q, u) -> tuple[float, float]:
        """(T, U) as Pinocchio computes them (computeKineticEnergy, computePotentialEnergy: −Σ m g⃗ · c over
        the moving joints), U with −m g⃗ · c of the bodies welded to the world (Pinocchio's universe inertia,
        which its sum leaves out) and ½ k (ℓ − l0)² of each spring."""
        springs = [load for load in self.tree.loads if load.kind == "spring"]
        elastic = sum(load.stiffness * (length - load.rest_length) ** 2 / 2
                      for load, length in zip(springs, self.spring_lengths(q)))
        q, u = self.configuration(q), np.asarray(u, float)[self.perm]
        world = self.model.inertias[0]
        U = pin.computePotentialEnergy(self.model, self.data, q) + elastic \
            - world.mass * self.model.gravity.linear @ world.lever
        return pin.computeKineticEnergy(self.model, self.data, q, u), U

    def jacobians(self, q) -> dict:
        """[J_P; J_R] (LOCAL_WORLD_ALIGNED) of every body origin and named frame, keyed by eomgen name."""
        pin.computeJointJacobians(self.model, self.data, self.configuration(q))
        pin.updateFramePlacements(self.model, self.data)
        out = {}
        for i, b in enumerate(self.tree.bodies):
            out[b.name] = self._jacobian(("body", i))
        for k, f in enumerate(self.tree.frames):
            out[f.name] = self._jacobian(("frame", k))
        return out

    def _jacobian(self, key):
        """A frame's Jacobian with its columns in eomgen's order."""
        Jp = pin.getFrameJacobian(self.model, self.data, self.frame_ids[key],
                                  pin.ReferenceFrame.LOCAL_WORLD_ALIGNED).reshape(6, self.model.nv)
        J = np.zeros_like(Jp)
        J[:, self.perm] = Jp
        return J

    def load_forces(self, q) -> dict:
        """The generalized force of each load, from Pinocchio's frame Jacobians and placements:
        Jᵀ F for a force, J_Rᵀ T for a torque, (J_a − J_b)ᵀ F_a for a spring (F_a = −k (ℓ − l0) d/ℓ)."""
        pin.computeJointJacobians(self.model, self.data, self.configuration(q))
        pin.updateFramePlacements(self.model, self.data)
        out = {}
        for k, load in enumerate(self.tree.loads):
            Ja = self._jacobian(("load", k, "a"))
            Ra = self.data.oMf[self.frame_ids[("load", k, "a")]].rotation
            if load.kind == "force":
                F = Ra @ np.array(load.vector) if load.in_body_frame else np.array(load.vector)
                out[load.name] = Ja[:3].T @ F
            elif load.kind == "torque":
                T = Ra @ np.array(load.vector) if load.in_body_frame else np.array(load.vector)
                out[load.name] = Ja[3:].T @ T
            else:
                Jb = self._jacobian(("load", k, "b"))
                pa = self.data.oMf[self.frame_ids[("load", k, "a")]].translation
                pb = self.data.oMf[self.frame_ids[("load", k, "b")]].translation
                d = pa - pb
                length = np.linalg.norm(d)
                F = -load.stiffness * (length - load.rest_length) * d / length
                out[load.name] = (Ja[:3] - Jb[:3]).T @ F
        return out

    def spring_lengths(self, q) -> list[float]:
        pin.framesForwardKinematics(self.model, self.data, self.configuration(q))
        return [float(np.linalg.norm(self.data.oMf[self.frame_ids[("load", k, "a")]].translation
                                     - self.data.oMf[self.frame_ids[("load", k, "b")]].translation))
                for k, load in enumerate(self.tree.loads) if load.kind == "spring"]


def _pinocchio_joint(b: BodySpec):
    """Pinocchio's joint model of a body's joint, by Pinocchio's names."""
    axis = np.array(b.axis, float)
    if b.kind == "cylindrical":
        composite = pin.JointModelComposite(pin.JointModelPrismaticUnaligned(axis))
        composite.addJoint(pin.JointModelRevoluteUnaligned(axis))
        return composite
    return {"revolute": lambda: pin.JointModelRevoluteUnaligned(axis),
            "prismatic": lambda: pin.JointModelPrismaticUnaligned(axis),
            "spherical": pin.JointModelSpherical, "zyx": pin.JointModelSphericalZYX,
            "universal": lambda: pin.JointModelUniversal(axis, np.array(b.axis2, float)),
            "planar": pin.JointModelPlanar, "translation": pin.JointModelTranslation,
            "helical": lambda: pin.JointModelHelicalUnaligned(axis, b.pitch)}[b.kind]()


def random_state(tree: Tree, rng):
    """q (angles in [−π, π], ZYX pitch within ±1.3, slides in [−1, 1], unit quaternions) and u in [−2, 2],
    in eomgen's layout."""
    q = []
    for i in tree.moving:
        kind = tree.bodies[i].kind
        if kind == "spherical":
            quat = rng.normal(size=4)
            q += list(quat / np.linalg.norm(quat))
        else:
            angular = {"revolute": [1], "helical": [1], "universal": [1, 1], "zyx": [1, 0.4, 1], "planar": [0, 0, 1],
                       "cylindrical": [0, 1]}.get(kind, [0] * SIZE[kind][0])
            q += [rng.uniform(-np.pi, np.pi) * a if a else rng.uniform(-1, 1) for a in angular]
    return np.array(q), rng.uniform(-2, 2, sum(SIZE[tree.bodies[i].kind][1] for i in tree.moving))
