"""The multibody system: bodies in a tree, joints, frames, loads, gravity. Building computes nothing."""
from __future__ import annotations

import warnings
from contextlib import contextmanager
from dataclasses import dataclass

import numpy as np
import sympy as sp

from ..errors import ModelError
from ..symbols import Generated, user_symbols
from .constraints import Contact, Loop, Rolling, default_ground, loop, unit
from .free_flyer import FreeFlyer
from .joints import Fixed, Joint, Placement, Revolute
from .loads import Actuator, Damper, Force, Motor, Point, Spring, Torque
from .values import is_numeric, matrix3, nonnegative, scalar, vector3


@dataclass(eq=False)
class Body:
    """A rigid body of a `System` (made by `System.add_body`): parent, joint, mass, com and inertia
    (body frame), placement of the joint frame on the parent; `index` and `q_index` are the
    positions of the joint's first speed in u and first coordinate in q (None for a joint without
    coordinates: fixed, or a mimic); `speed_indices` are the speeds of the joint's motion subspace
    columns (its own, or a mimic's driver's)."""

    name: str
    parent: "Body | None"
    joint: Joint
    mass: sp.Expr
    com: sp.Matrix
    inertia: sp.Matrix
    placement: Placement
    index: int  # position of its (first) speed in u, or None for a fixed joint
    q_index: int  # position of its (first) coordinate in q, or None
    speed_indices: list  # u index of each column of the joint's motion subspace

    def __repr__(self) -> str:
        parent = self.parent.name if self.parent else "world"
        return f"Body({self.name!r}, parent={parent!r}, joint={self.joint!r})"


@dataclass(eq=False)
class Frame:
    """A named frame fixed on a body (made by `System.add_frame`), placed on the body's frame, or fixed
    in the world (body None)."""

    name: str
    body: Body | None
    placement: Placement


class System:
    """Rigid bodies connected by joints in a tree rooted at the (inertial) world."""

    def __init__(self, gravity=(0, 0, -9.81), *, strict: bool = True) -> None:
        """`strict=False` turns physically impossible inertias into warnings (for imported files
        that Pinocchio accepts as they are)."""
        self.gravity = vector3(gravity, "gravity")
        self.strict = strict
        self.bodies: list[Body] = []
        self.frames: dict[str, Frame] = {}
        self.loads: list = []
        self.contacts: list[Contact] = []
        self.loops: list[Loop] = []
        self.rolling: list[Rolling] = []
        self.motors: list[Motor] = []
        self._bodies: dict[str, Body] = {}
        self._symbols: dict[str, tuple[sp.Symbol, str]] = {}  # name → (the user's symbol, where it entered)
        self._coordinates: set[sp.Symbol] = set()
        self._labels: dict[str, str] = {}  # label of an eomgen symbol (a speed, ...) → what it stands for
        self.version = 0  # counts the changes: equations derived before one are refused (see ClosedForms)
        self._register("gravity", self.gravity)

    # --- coordinates -------------------------------------------------------------------------
    @property
    def joints(self) -> list[Joint]:
        """The moving joints (not the fixed ones), in the order of q and u."""
        return [b.joint for b in self.bodies if b.index is not None]

    @property
    def prescribed(self) -> list[Joint]:
        """The joints driven by a prescribed motion of time (`motion=`), without coordinates of their own."""
        return [b.joint for b in self.bodies if b.joint.prescribed is not None]

    @property
    def q(self) -> sp.Matrix:
        """The coordinates q, a column of symbols (a free-flyer base has 7, or 6 in Euler angles)."""
        return sp.Matrix([x for j in self.joints for x in j.coordinates])

    @property
    def u(self) -> sp.Matrix:
        """The speeds u, a column of symbols (q̇ but for the twist of a quaternion base, a ball joint or a
        planar joint)."""
        return sp.Matrix([x for j in self.joints for x in j.speeds])

    @property
    def ud(self) -> sp.Matrix:
        """Symbols of the accelerations u̇."""
        return sp.Matrix([x for j in self.joints for x in j.accelerations])

    @property
    def qdot(self) -> sp.Matrix:
        """q̇(q, u): the kinematic differential equations (q̇ = u but for a quaternion base, a ball joint
        and a planar joint)."""
        return sp.Matrix([x for j in self.joints for x in j.qdot()])

    @property
    def nq(self) -> int:
        """Number of coordinates (7 for a free-flyer base)."""
        return sum(len(j.coordinates) for j in self.joints)

    @property
    def nv(self) -> int:
        """Number of speeds (degrees of freedom)."""
        return sum(j.dof for j in self.joints)

    @property
    def floating_base(self) -> bool:
        """True if the root body has a `FreeFlyer` joint."""
        return any(isinstance(j, FreeFlyer) for j in self.joints)

    @property
    def actuated(self) -> list[str]:
        """What each row of S drives: the joint's name, with [k] for its k-th speed if it has several."""
        return [j.name if j.efforts == 1 else f"{j.name}[{k}]" for j in self.joints if j.actuated
                for k in range(j.efforts)]

    @property
    def S(self) -> sp.Matrix:
        """Selection matrix: one row per speed of an actuated joint, τ_gen = Sᵀ τ (a floating base is not
        actuated; a mimic joint's effort is its driver's)."""
        rows = [b.index + k for b in self.bodies if b.index is not None and b.joint.actuated
                for k in range(b.joint.efforts)]
        S = sp.zeros(len(rows), self.nv)
        for r, i in enumerate(rows):
            S[r, i] = 1
        return S

    def fields(self) -> list[tuple[str, list]]:
        """(where, its values) of every value of the model: gravity, each body's and joint's, frame's,
        load's and motor's."""
        found = [("gravity", list(self.gravity))]
        for b in self.bodies:
            found.append((f"body '{b.name}'", [b.mass, *b.com, *b.inertia, *b.placement.rotation,
                                               *b.placement.translation]))
            found += [(f"joint '{b.joint.name}': {k}", [v]) for k, v in b.joint.constants().items()]
        found += [(f"frame '{name}'", [*f.placement.rotation, *f.placement.translation])
                  for name, f in self.frames.items()]
        found += [(f"load '{load.name}'", [x for v in vars(load).values() for x in _entries(v)])
                  for load in self.loads]
        found += [(f"motor '{m.name}'", [m.voltage, m.resistance, m.inductance, m.torque_constant,
                                         m.gear_ratio]) for m in self.motors]  # circuit and voltage
        return found

    @property
    def parameters(self) -> set[sp.Symbol]:
        """Symbols of the model that are neither coordinates nor speeds."""
        free = {s for _, values in self.fields() for e in values for s in sp.sympify(e).free_symbols}
        return free - set(self.q) - set(self.u)

    # --- building ----------------------------------------------------------------------------
    def _register(self, what: str, *values) -> None:
        """Parameters are given by name: two different symbols of one name (say Symbol('l') and
        Symbol('l', positive=True)) would be one name for two values, and a parameter labelled like
        one of eomgen's symbols (`phidot` beside the speed of joint `phi`) would be taken for it; both
        are refused here."""
        for value in values:
            self.check_symbols(what, value)
            for s in user_symbols(value):
                self._symbols.setdefault(s.name, (s, what))

    def check_symbols(self, what: str, value, own=()) -> None:
        """Refuse a user symbol of `value` (not in `own`) that has the name of another symbol of this
        system, or of one of eomgen's symbols (a speed, an acceleration, ...), naming `what`."""
        own_names = {s.name: s for s in own}
        for s in user_symbols(value) - set(own):
            if s not in self._coordinates and s.name in self._labels:
                raise ModelError(f"{what}: parameter '{s.name}' has the name of {self._labels[s.name]}, "
                                 "which is eomgen's own symbol (System.u, System.ud); use that symbol, or "
                                 "another name for a parameter")
            known, where = self._symbols.get(s.name, (own_names.get(s.name, s), what))
            if known != s:
                raise ModelError(f"{what}: symbol {sp.srepr(s)} differs from {sp.srepr(known)} of "
                                 f"{where}, with the same name; use one symbol per name")

    def _add_joint(self, joint: Joint) -> None:
        """Register a joint's coordinates (never a parameter already) and the labels of its speeds and
        accelerations (never a parameter's name)."""
        for s in user_symbols(sp.Matrix(joint.coordinates)):
            if s.name in self._symbols:
                raise ModelError(f"joint '{joint.name}': its coordinate '{s.name}' is a parameter of "
                                 f"{self._symbols[s.name][1]} already; name the joint otherwise")
            self._symbols[s.name] = (s, f"joint '{joint.name}'")
            self._coordinates.add(s)
        generated = [(kind, x) for kind, xs in (("coordinate", joint.coordinates), ("speed", joint.speeds),
                                                ("acceleration", joint.accelerations))
                     for x in xs if isinstance(x, Generated)]
        for kind, x in generated:
            if x.name in self._symbols and self._symbols[x.name][0] not in self._coordinates:
                raise ModelError(f"joint '{joint.name}': its {kind} is labelled '{x.name}', the name of a "
                                 f"parameter of {self._symbols[x.name][1]}; rename that parameter")
            self._labels[x.name] = f"the {kind} of joint '{joint.name}'"

    @contextmanager
    def _changing(self):
        """One change of the model: the registry is restored if the change is refused, and the
        version counted if it is made."""
        saved = dict(self._symbols), set(self._coordinates), dict(self._labels)
        try:
            yield
        except BaseException:
            self._symbols, self._coordinates, self._labels = saved
            raise
        self.version += 1

    def body(self, ref) -> Body:
        """The body given by name or object; a clear error if it is not part of this system."""
        if isinstance(ref, Body):
            if self._bodies.get(ref.name) is not ref:
                raise ModelError(f"body '{ref.name}' does not belong to this system")
            return ref
        if isinstance(ref, str) and ref in self._bodies:
            return self._bodies[ref]
        raise ModelError(f"unknown body {ref!r}; bodies are {sorted(self._bodies)}")

    def add_body(self, name: str, parent=None, joint: Joint | None = None, mass=0, com=(0, 0, 0),
                 inertia=None, placement: Placement | None = None) -> Body:
        """Attach a body to `parent` (a body or its name; None = world) through `joint`.
        `com` and `inertia` (about the com) are in the body frame, which is the joint frame moved by q."""
        if not isinstance(name, str) or not name:
            raise ModelError(f"body name must be a non-empty string, got {name!r}")
        if name in self._bodies or name in self.frames:
            raise ModelError(f"duplicate name '{name}': a body or frame of that name exists")
        swapped = [f"joint '{parent.name}' given as parent" if isinstance(parent, Joint) else "",
                   f"body '{joint.name}' given as joint" if isinstance(joint, Body) else ""]
        if any(swapped):
            raise ModelError(f"body '{name}': {' and '.join(filter(None, swapped))}; the order is "
                             "add_body(name, parent, joint): pass them as parent=..., joint=...")
        if parent is not None:
            if parent == name:
                raise ModelError(f"body '{name}' cannot be its own parent (a loop in the tree)")
            try:
                parent = self.body(parent)
            except ModelError:
                raise ModelError(f"body '{name}': unknown parent {getattr(parent, 'name', parent)!r}; "
                                 f"add the parent first (bodies are {sorted(self._bodies)})") from None
        joint = Fixed(f"{name}_fixed") if joint is None else joint
        if not isinstance(joint, Joint):
            raise ModelError(f"body '{name}': unsupported joint type {type(joint).__name__}; use an eomgen "
                             "joint (Revolute, Prismatic, Helical, Universal, Cylindrical, Planar, Translation, "
                             "Spherical, FreeFlyer, Fixed)")
        used = set(joint.coordinates) & set(self.q)
        if used:
            raise ModelError(f"body '{name}': coordinate '{used.pop()}' is used by another joint already")
        if any(b.joint.name == joint.name for b in self.bodies):
            raise ModelError(f"body '{name}': joint name '{joint.name}' is used by another joint already "
                             "(joint names identify reactions and results)")
        if isinstance(joint, FreeFlyer) and parent is not None:
            raise ModelError(f"body '{name}': a FreeFlyer joint must attach the root body to the world")
        mass = nonnegative(mass, f"body '{name}': mass")
        com = vector3(com, f"body '{name}': com")
        inertia = matrix3(sp.zeros(3) if inertia is None else inertia, f"body '{name}': inertia")
        check_inertia(inertia, f"body '{name}'", self.strict)
        inertia = (inertia + inertia.T) / 2  # exact for symmetric input, removes float round-off
        placement = Placement() if placement is None else placement
        if not isinstance(placement, Placement):
            raise ModelError(f"body '{name}': placement must be an eomgen.Placement")
        motion = set(self.q) | set(joint.coordinates)
        fields = {"mass": mass, "com": com, "inertia": inertia, "placement": placement.rotation.row_join(
            placement.translation), **{f"joint {k}": v for k, v in joint.constants().items()}}
        for field_name, value in fields.items():
            moving = sorted(str(s) for s in sp.sympify(value).free_symbols
                            if s in motion or isinstance(s, Generated))
            if moving:
                what = "a function of eg.t and parameters" if field_name == "joint motion" else \
                    "constant (a parameter or a number)"
                raise ModelError(f"body '{name}': {field_name} depends on the coordinates or speeds "
                                 f"{moving}; it must be {what}")
        with self._changing():
            self._add_joint(joint)
            for field_name, value in fields.items():
                self._register(f"body '{name}': {field_name}", value)
        speed_indices = list(range(self.nv, self.nv + joint.dof)) if joint.dof else self._mimic(name, joint)
        body = Body(name, parent, joint, mass, com, inertia, placement,
                    self.nv if joint.dof else None, self.nq if joint.dof else None, speed_indices)
        self.bodies.append(body)
        self._bodies[name] = body
        return body

    def _mimic(self, name: str, joint: Joint) -> list[int]:
        """A mimic joint bound to its driver, which must be in the system already: [the driver's speed]."""
        mimic = joint.mimic
        if mimic is None:
            return []
        drivers = {b.joint.name: b for b in self.bodies}
        if mimic.driver_name not in drivers:
            raise ModelError(f"body '{name}': joint '{joint.name}' mimics the unknown joint '{mimic.driver_name}'; "
                             f"add the driving joint first (joints are {sorted(drivers)})")
        driver = drivers[mimic.driver_name]
        if driver.joint.mimic is not None:
            raise ModelError(f"body '{name}': joint '{joint.name}' mimics '{driver.joint.name}', which mimics "
                             f"'{driver.joint.mimic.driver_name}' itself; mimic the driving joint directly")
        if len(driver.joint.coordinates) != 1 or driver.joint.qdot() != driver.joint.speeds:
            raise ModelError(f"body '{name}': joint '{joint.name}' mimics '{driver.joint.name}', which is not a "
                             "one-coordinate joint (a mimic follows a revolute, prismatic or helical joint)")
        joint.bind(driver.joint)
        return [driver.index]

    def add_frame(self, name: str, body=None, placement: Placement | None = None) -> Frame:
        """A named frame fixed on a body (a tool tip, a contact point, a URDF link merged away), or
        in the world (body None: a loop's anchor)."""
        if not isinstance(name, str) or not name:
            raise ModelError(f"frame name must be a non-empty string, got {name!r}")
        if name in self._bodies or name in self.frames:
            raise ModelError(f"duplicate name '{name}': a body or frame of that name exists")
        placement = Placement() if placement is None else placement
        if not isinstance(placement, Placement):
            raise ModelError(f"frame '{name}': placement must be an eomgen.Placement")
        with self._changing():
            self._register(f"frame '{name}': placement", placement.rotation, placement.translation)
        frame = Frame(name, None if body is None else self.body(body), placement)
        self.frames[name] = frame
        return frame

    def add_contact(self, frame: str, kind: str = "point") -> Contact:
        """A rigid contact at a frame or body origin: kind "point" (3D) or "frame" (6D)."""
        if kind not in ("point", "frame"):
            raise ModelError(f"contact at '{frame}': kind must be 'point' or 'frame', got {kind!r}")
        if frame not in self.frames and frame not in self._bodies:
            raise ModelError(f"contact: unknown frame {frame!r}; frames are {sorted(self.frames)}")
        self._new_constraint(frame, "contact at")
        contact = Contact(frame, kind)
        self.contacts.append(contact)
        self.version += 1
        return contact

    def add_loop(self, frame_a: str, frame_b: str, kind: str = "point", axis=None,
                 name: str | None = None) -> Loop:
        """A loop closure between two frames (or body origins; a world frame from add_frame(body=None)):
        kind "point" / "spherical" (origins coincide), "frame" (poses coincide) or "revolute" (origins
        coincide, relative rotation about `axis`, frame_a's axes, default z). Rows J = J_a − J_b (world
        axes)."""
        name = f"{frame_a}-{frame_b}" if name is None else name
        if not isinstance(name, str) or not name:
            raise ModelError(f"loop name must be a non-empty string, got {name!r}")
        self._new_constraint(name, "loop")
        bodies = []
        for frame in (frame_a, frame_b):
            if not isinstance(frame, str) or frame not in self.frames and frame not in self._bodies:
                raise ModelError(f"loop '{name}': unknown frame {frame!r}; frames are {sorted(self.frames)} "
                                 f"and bodies {sorted(self._bodies)}")
            bodies.append(self.frames[frame].body if frame in self.frames else self._bodies[frame])
        if frame_a == frame_b:
            raise ModelError(f"loop '{name}': a loop between frame '{frame_a}' and itself constrains "
                             "nothing")
        rigid = [self._moving_ancestor(b) for b in bodies]
        if rigid[0] is rigid[1]:
            where = "the world" if rigid[0] is None else f"body '{rigid[0].name}'"
            raise ModelError(f"loop '{name}': frames '{frame_a}' and '{frame_b}' are both fixed on {where} "
                             "(directly or through fixed joints); a loop joins two bodies that can move "
                             "relative to each other")
        closure = loop(name, frame_a, frame_b, kind, axis)
        with self._changing():
            self._register(f"loop '{name}': axis", closure.axis)
        self.loops.append(closure)
        return closure

    def add_rolling(self, body, radius, axis=(0, 1, 0), ground: Placement | None = None,
                    name: str | None = None) -> Rolling:
        """A thin disk (wheel) of `radius`, centred at the body origin with axle `axis` (body axes), rolling
        without slip on the xy plane of `ground` (its z axis the normal toward the disk; default the plane
        z = 0 facing against gravity). Rows: the no-slip conditions along ground x and y and the normal
        velocity of the contact point; residual: the height of the lowest point of the disk."""
        body = self.body(body)
        name = f"{body.name}_rolling" if name is None else name
        if not isinstance(name, str) or not name:
            raise ModelError(f"rolling disk name must be a non-empty string, got {name!r}")
        self._new_constraint(name, "rolling disk")
        radius = nonnegative(radius, f"rolling disk '{name}': radius")
        if radius.is_zero:
            raise ModelError(f"rolling disk '{name}': radius must be positive")
        axis = unit(vector3(axis, f"rolling disk '{name}': axis"), f"rolling disk '{name}': axis")
        ground = default_ground(self.gravity, name) if ground is None else ground
        if not isinstance(ground, Placement):
            raise ModelError(f"rolling disk '{name}': ground must be an eomgen.Placement (its xy plane)")
        e_n = (self._rotation_at_zero(body) * axis).dot(ground.rotation[:, 2])
        if e_n.is_number and abs(abs(float(e_n)) - 1) < 1e-9:
            raise ModelError(f"rolling disk '{name}': its axle is normal to the ground at q = 0 (the disk lies "
                             "flat: no single contact point); give the axle along the wheel's hub")
        with self._changing():
            self._register(f"rolling disk '{name}'", radius, axis, ground.rotation, ground.translation)
        disk = Rolling(name, body, radius, axis, ground)
        self.rolling.append(disk)
        return disk

    def _new_constraint(self, name: str, what: str) -> None:
        """Contacts (by frame), loops and rolling disks name their rows and forces: one namespace."""
        if any(c.name == name for c in (*self.contacts, *self.loops, *self.rolling)):
            raise ModelError(f"{what} '{name}': a contact, loop or rolling disk of that name exists already")

    @staticmethod
    def _moving_ancestor(body: Body | None) -> Body | None:
        """The body itself, or the first ancestor through fixed joints whose joint moves (None: the world)."""
        while body is not None and not body.speed_indices:
            body = body.parent
        return body

    @staticmethod
    def _rotation_at_zero(body: Body) -> sp.Matrix:
        """The body's rotation in the world at q = 0 (placements and joint rotations from the root)."""
        chain = []
        while body is not None:
            chain.append(body)
            body = body.parent
        R = sp.eye(3)
        for b in reversed(chain):
            R = R * b.placement.rotation * b.joint.motion()[0].xreplace({x: 0 for x in b.joint.coordinates})
        return R

    def constraint_rows(self) -> list[str]:
        """Names of the rows of J_c: the contacts', the loops', the rolling disks' (in that order)."""
        return [r for c in (*self.contacts, *self.loops, *self.rolling) for r in c.row_names]

    def closure_rows(self) -> list[str]:
        """Names of the position residuals: the loops' rows, then the rolling disks' heights."""
        return [r for c in (*self.loops, *self.rolling) for r in c.closure_names]

    def point(self, ref) -> Point:
        """A point from: a frame or body name, a Body (its origin), (body or None, offset), or None (the
        world origin)."""
        if ref is None:
            return Point(None, sp.zeros(3, 1))
        if isinstance(ref, str) and ref in self.frames:
            f = self.frames[ref]
            return Point(f.body, f.placement.translation)
        if isinstance(ref, (str, Body)):
            return Point(self.body(ref), sp.zeros(3, 1))
        if isinstance(ref, tuple) and len(ref) == 2:
            body = None if ref[0] is None else self.body(ref[0])
            return Point(body, vector3(ref[1], "point offset"))
        raise ModelError(f"cannot read a point from {ref!r}: give a frame or body name, a body, "
                         "(body or None, offset) or None")

    def _load_name(self, name, kind: str) -> str:
        if name is not None and (not isinstance(name, str) or not name):
            raise ModelError(f"{kind} name must be a non-empty string, got {name!r}")
        name = name or f"{kind}{sum(type(x).__name__.lower() == kind for x in self.loads)}"
        if any(x.name == name for x in self.loads):
            raise ModelError(f"duplicate load name '{name}'")
        return name

    def _add_load(self, load):
        """Append a load, its symbols registered (see `_register`)."""
        with self._changing():
            self._register(f"load '{load.name}'", *[x for v in vars(load).values() for x in _entries(v)])
        self.loads.append(load)
        return load

    def add_force(self, body, force, point=(0, 0, 0), *, in_body_frame=False, name=None) -> Force:
        """Force F at `point` (body coordinates); F in world axes unless in_body_frame."""
        load = Force(self._load_name(name, "force"), Point(self.body(body), vector3(point, "force point")),
                     vector3(force, "force"), in_body_frame)
        return self._add_load(load)

    def add_torque(self, body, torque, *, in_body_frame=False, name=None) -> Torque:
        """Pure torque T on a body, world axes unless in_body_frame."""
        load = Torque(self._load_name(name, "torque"), self.body(body), vector3(torque, "torque"),
                      in_body_frame)
        return self._add_load(load)

    def add_actuator(self, body, *, torque=None, force=None, reaction=None, point=(0, 0, 0),
                     reaction_point=(0, 0, 0), in_body_frame=False, name=None) -> Actuator:
        """An actuator acting on `body` with reaction on `reaction` (default: its parent):
        torque T on body and −T on reaction; force f along the line between the two points."""
        a = self.body(body)
        b = a.parent if reaction is None else self.body(reaction)
        if torque is None and force is None:
            raise ModelError(f"actuator on body '{a.name}': give a torque, a force or both")
        load = Actuator(self._load_name(name, "actuator"), Point(a, vector3(point, "actuator point")),
                        Point(b, vector3(reaction_point, "actuator reaction_point")),
                        None if torque is None else vector3(torque, "actuator torque"),
                        None if force is None else scalar(force, "actuator force"), in_body_frame)
        return self._add_load(load)

    def add_motor(self, body, *, resistance, inductance, torque_constant, rotor_inertia, friction=0,
                  gear_ratio=1, voltage=None, name=None) -> Motor:
        """A DC motor on the revolute joint of `body` (see `Motor`): adds N² J_m to the joint's
        armature and the torque N k i − N² f q̇ between the body and its parent. Its current
        i_<name> and voltage (default U_<name>) are parameters of the equations of motion."""
        b = self.body(body)
        if not isinstance(b.joint, Revolute) or b.joint.mimic is not None:
            raise ModelError(f"motor on body '{b.name}': a DC motor drives a revolute joint, "
                             f"not {type(b.joint).__name__}")
        if b.joint.prescribed is not None:
            raise ModelError(f"motor on body '{b.name}': joint '{b.joint.name}' has a prescribed motion; a "
                             "DC motor drives a free revolute joint")
        name = name or f"motor_{b.joint.name}"
        if any(m.name == name for m in self.motors):
            raise ModelError(f"duplicate motor name '{name}'")
        values = {k: nonnegative(v, f"motor '{name}': {k}") for k, v in dict(
            resistance=resistance, inductance=inductance, torque_constant=torque_constant,
            rotor_inertia=rotor_inertia, friction=friction).items()}
        N = scalar(gear_ratio, f"motor '{name}': gear_ratio")
        current = Generated(f"i_{name}", ("current", name))
        voltage = (Generated(f"U_{name}", ("voltage", name)) if voltage is None
                   else scalar(voltage, f"motor '{name}': voltage"))
        if values["inductance"].is_zero:
            raise ModelError(f"motor '{name}': inductance must be positive (L di/dt = U − R i − k N q̇)")
        with self._changing():
            self._register(f"motor '{name}'", N, voltage, *values.values())
        motor = Motor(name, b, current, voltage,
                      values["resistance"], values["inductance"], values["torque_constant"],
                      values["rotor_inertia"], values["friction"], N)
        b.joint.armature = b.joint.armature + N**2 * motor.rotor_inertia
        qdot = b.joint.speeds[0]
        torque = N * motor.torque_constant * current - N**2 * motor.friction * qdot
        self.add_actuator(b, torque=b.joint.axis * torque, in_body_frame=True, name=name)
        self.motors.append(motor)
        return motor

    def add_spring(self, a, b, stiffness, rest_length=0, *, name=None) -> Spring:
        """Linear spring between points a and b (see `point`)."""
        name = self._load_name(name, "spring")
        load = Spring(name, self.point(a), self.point(b),
                      nonnegative(stiffness, f"spring '{name}': stiffness"),
                      nonnegative(rest_length, f"spring '{name}': rest_length"))
        return self._add_load(load)

    def add_damper(self, a, b, damping, *, name=None) -> Damper:
        """Linear damper between points a and b (see `point`); its force acts along the line between them,
        so the two must not be the same point."""
        name = self._load_name(name, "damper")
        load = Damper(name, self.point(a), self.point(b), nonnegative(damping, f"damper '{name}': damping"))
        return self._add_load(load)

    def reduced(self, lock: dict) -> "System":
        """A copy with the joints in `lock` (joint name → value) welded at those values: the joint's
        motion becomes part of the body's placement (as Pinocchio's buildReducedModel does)."""
        if not isinstance(lock, dict):
            raise ModelError(f"reduced: lock must be a dict {{joint name: value}}, got {type(lock).__name__}")
        names = {j.name for j in self.joints}
        unknown = sorted(set(lock) - names)
        mimics = {b.joint.name: b.joint.mimic.driver_name for b in self.bodies if b.joint.mimic is not None}
        if set(lock) & set(mimics):
            raise ModelError(f"reduced: {sorted(set(lock) & set(mimics))} are mimic joints, without a "
                             "coordinate of their own; lock their driving joint instead")
        for mimic, driver in mimics.items():
            if driver in lock:
                raise ModelError(f"reduced: joint '{mimic}' mimics '{driver}'; it cannot follow a locked "
                                 "joint")
        if unknown:
            raise ModelError(f"reduced: unknown joints {unknown}; joints are {sorted(names)}")
        if self.loads or self.contacts or self.motors or self.loops or self.rolling:
            raise ModelError("reduced: loads, contacts, loops, rolling disks and motors are not carried over; "
                             "add them to the reduced system")

        def weld(b):
            joint = b.joint
            if joint.name not in lock:
                return {}
            if len(joint.coordinates) != 1:
                raise ModelError(f"reduced: joint '{joint.name}' has {len(joint.coordinates)} coordinates; "
                                 "only one-coordinate joints can be locked")
            value = scalar(lock[joint.name], f"reduced: value of joint '{joint.name}'")
            R_q, t_q = (m.xreplace({joint.q: value}) for m in joint.motion())
            P = b.placement
            return {"joint": Fixed(joint.name), "placement": Placement(rotation=P.rotation * R_q,
                                                                       translation=P.translation + P.rotation * t_q)}
        new = self.rebuilt(weld)
        if hasattr(self, "continuous"):
            new.continuous = [c for j, c in zip(self.joints, self.continuous) if j.name not in lock]
        return new

    def rebuilt(self, change) -> "System":
        """A copy of the bodies and frames with `change(body)` → overrides of add_body's arguments
        (joint, mass, com, inertia, placement); loads, contacts and motors are not carried over."""
        new = System(gravity=self.gravity, strict=self.strict)
        for b in self.bodies:
            args = dict(joint=b.joint, mass=b.mass, com=b.com, inertia=b.inertia, placement=b.placement)
            args.update(change(b))
            new.add_body(b.name, parent=b.parent.name if b.parent else None, **args)
        for f in self.frames.values():
            new.add_frame(f.name, f.body and f.body.name, f.placement)
        new.continuous = getattr(self, "continuous", [False] * len(new.joints))
        return new

    def __repr__(self) -> str:
        return f"System({len(self.bodies)} bodies, q={list(self.q)})"


def _entries(v):
    if isinstance(v, sp.MatrixBase):
        return list(v)
    if isinstance(v, Point):
        return list(v.offset)
    if isinstance(v, sp.Basic):
        return [v]
    return []


def check_inertia(I: sp.Matrix, owner: str, strict: bool = True) -> None:
    """Symmetric; when numeric: positive semidefinite and principal moments obeying the triangle
    inequality (λ_i ≤ λ_j + λ_k). Not strict: the last two only warn."""
    if not is_numeric(I):
        if any(sp.expand(I[i, j] - I[j, i]) != 0 for i in range(3) for j in range(i)):
            raise ModelError(f"{owner}: inertia must be symmetric, got {I.tolist()}")
        return
    A = np.array(I.tolist(), dtype=float)
    tol = 1e-9 * max(1e-12, float(np.abs(A).max()))
    if np.abs(A - A.T).max() > tol:
        raise ModelError(f"{owner}: inertia must be symmetric, got {I.tolist()}")
    lam = np.linalg.eigvalsh(A)
    problem = None
    if lam.min() < -tol:
        problem = f"{owner}: inertia must be positive semidefinite, eigenvalues {lam.tolist()}"
    elif lam[2] > lam[0] + lam[1] + tol:
        problem = (f"{owner}: principal moments {lam.tolist()} break the triangle inequality "
                   "(largest ≤ sum of the other two)")
    if problem and strict:
        raise ModelError(problem)
    if problem:
        warnings.warn(problem, stacklevel=3)
