"""How each body moves: rotation R, origin p, joint axes, Jacobians J_P, J_R and the bias terms J̇ u.

Computed once per system and shared by every method, each body's placement when a method first reads it
(`placements`: the body-frame recursions read none). Every quantity is kept as named intermediates
(see `Subexpressions`). Time derivatives use the chain rule with q̇ = q̇(q, u) of the joints (u but for
a body twist's speeds): the general `time_derivative` (d/dt f(q) = Σ_k ∂f/∂q_k q̇_k, through the
intermediates) and, for J̇ u, the same rule applied along the tree (ė = Ω × e for a vector fixed in a
body), which costs O(n) instead of O(n²) per body; a test checks the two against each other.
Inside, 3-vectors and rotations are tuples of the engine's scalars (`linalg`, `engine`: sympy or
symengine); what the methods read is an `sp.Matrix` of sympy expressions, converted once per quantity."""
from __future__ import annotations

from collections.abc import Callable, Iterator, Mapping
from functools import partial

import sympy as sp

from .constraint_rows import constraint_rows
from .errors import ModelError
from .grounded import grounded
from .linalg import IDENTITY, ZERO, add, apply, compose, cross, dot, matmul, scale, subtract, total
from .model import FlexibleLink, Placement
from .model.loads import Point
from .model.system import Body, Frame, System
from .placements import Field, Placements, World, columns_in_sympy
from .subexpressions import Subexpressions
from .symbols import t

TIME = "t"


class InSympy(Mapping):
    """A read-only view of a mapping of the engine's values, each converted to sympy once, when first read."""

    def __init__(self, values: Mapping, convert: Callable) -> None:
        self._values, self._convert, self._converted = values, convert, {}

    def __getitem__(self, key):
        if key not in self._converted:
            self._converted[key] = self._convert(self._values[key])
        return self._converted[key]

    def __iter__(self) -> Iterator:
        return iter(self._values)

    def __len__(self) -> int:
        return len(self._values)


class Kinematics:
    """World-frame kinematics of every body of `system`, as named sub-results in `self.sub`."""

    def __init__(self, system: System, engine: str | None = None) -> None:
        self.system = system
        self.version = system.version  # the model these kinematics describe
        self.q, self.u = list(system.q), list(system.u)
        self.n = len(self.u)
        self.sub = Subexpressions(engine=engine)
        self._u = self.sub.vector(self.u)
        self.time_seeds = dict(zip(self.q, system.qdot))  # q̇(q, u): u but for a free-flyer base
        for joint in system.prescribed:  # θ, θ̇, θ̈ of t, named: d/dt θ = θ̇, d/dt θ̇ = θ̈
            theta, rate, acceleration = joint.driven
            for symbol, n in zip(joint.driven, range(3)):
                self.sub.define(symbol, sp.diff(joint.prescribed, t, n))
            self.time_seeds.update({theta: rate, rate: acceleration})
        # the world placements, formed on first reading (`placements`), by field; the same in sympy,
        # converted on first reading (the recursions read the tuples alone; partials, not lambdas: the
        # equations are pickled, `sweep`)
        placed = Placements(self.sub, system.bodies)
        self._R, self._p, self._columns, self._axes, self.chain = (Field(placed, f) for f in World._fields)
        self.R = InSympy(self._R, partial(self.sub.matrix, cols=3))
        self.p = InSympy(self._p, self.sub.matrix)
        self.columns = InSympy(self._columns, partial(columns_in_sympy, self.sub))
        self.on_tip: dict[Body, str] = {}  # bodies beyond a flexible link: the link's joint
        for body in system.bodies:
            parent = body.parent
            if parent is not None and (isinstance(parent.joint, FlexibleLink) or parent in self.on_tip):
                self.on_tip[body] = self.on_tip.get(parent, parent.joint.name)
        self._cache: dict = {}

    # --- positions ---------------------------------------------------------------------------
    def position(self, point: Point) -> sp.Matrix:
        """r = p + R r_local, world coordinates of a point."""
        if point.body is None:
            return point.offset
        return self._cached(("r", point.body, tuple(point.offset)),
                            lambda: self.sub.matrix(self._position(point)))

    def _position(self, point: Point) -> tuple:
        body = point.body
        offset = self.sub.vector(point.offset)
        return offset if body is None else self._cached(
            ("_r", body, tuple(point.offset)),
            lambda: self.sub.add_matrix(add(self._p[body], apply(self._R[body], offset))))

    def com(self, body: Body) -> sp.Matrix:
        """World coordinates of the body's centre of mass."""
        return self.position(Point(body, body.com))

    def frame_placement(self, name: str) -> tuple[sp.Matrix, sp.Matrix]:
        """(R, r) of a named frame in the world."""
        f = self._frame(name)
        R_body = self._R[f.body] if f.body else IDENTITY
        R = self._cached(("R", name), lambda: self.sub.matrix(
            self.sub.add_matrix(compose(R_body, self.sub.vector(f.placement.rotation))), 3))
        return R, self.position(Point(f.body, f.placement.translation))

    def inertia_world(self, body: Body) -> sp.Matrix:
        """Θ in world axes: R Θ Rᵀ (about the centre of mass)."""
        return self._cached(("Theta", body), lambda: self.sub.matrix(self._inertia_world(body), 3))

    def _inertia_world(self, body: Body) -> tuple:
        def build():
            R = self._R[body]
            RI = compose(R, self.sub.vector(body.inertia))
            Theta = [None] * 9
            for i in range(3):
                for j in range(i, 3):  # symmetric: the upper triangle, mirrored
                    entry = dot(RI[3 * i:3 * i + 3], R[3 * j:3 * j + 3])
                    Theta[3 * i + j] = Theta[3 * j + i] = self.sub.add(entry)
            return tuple(Theta)
        return self._cached(("_Theta", body), build)

    # --- Jacobians (3 × n, world axes) --------------------------------------------------------
    def rigid(self, body: Body | None) -> None:
        """Refuse, naming it, a body beyond a flexible link: its Jacobians' columns of the link's nodes
        (which move it through the tip) are not formed (J u and J̇ u would miss the bending)."""
        if body in self.on_tip:
            raise ModelError(f"body '{body.name}' sits beyond flexible link '{self.on_tip[body]}': its "
                             "Jacobians (J, J̇ u, contact rows) are not formed (its placement and the "
                             "equations of motion are)")

    def J_P(self, point: Point) -> sp.Matrix:
        """Translational Jacobian of a point: column i is Σ v_k + ω_k × (r − p_k) over the joints k
        on the way whose motion has u_i (one joint, or a driver and its mimics)."""
        self.rigid(point.body)

        def build():
            if point.body is None:
                return sp.zeros(3, self.n)
            J, r = [[0] * self.n for _ in range(3)], self._position(point)
            for k in self.chain[point.body]:
                arm = self.sub.add_matrix(subtract(r, self._p[k]))
                for i, v, w in self._columns[k]:
                    for row, x in enumerate(add(v, self.sub.add_matrix(cross(w, arm)))):
                        J[row][i] += x
            return self._rows(J)
        return self._cached(("J_P", point.body, tuple(point.offset)), build)

    def J_R(self, body: Body | None) -> sp.Matrix:
        """Rotational Jacobian: column i is Σ ω_k over the joints on the way whose motion has u_i."""
        self.rigid(body)
        J = [[0] * self.n for _ in range(3)]
        for k in self.chain.get(body, []):
            for i, _, w in self._columns[k]:
                for row, x in enumerate(w):
                    J[row][i] += x
        return self._rows(J)

    def _rows(self, J: list[list]) -> sp.Matrix:
        """The sympy matrix of a 3 × n list of the engine's scalars."""
        return self.sub.matrix([x for row in J for x in row], self.n) if self.n else sp.zeros(3, 0)

    def jacobian(self, name: str) -> sp.Matrix:
        """6 × n Jacobian [J_P; J_R] of a named frame's origin in world-aligned axes."""
        f = self._frame(name)
        return self.J_P(Point(f.body, f.placement.translation)).col_join(self.J_R(f.body))

    # --- velocities and bias accelerations ----------------------------------------------------
    def velocity(self, point: Point) -> sp.Matrix:
        """v = J_P u."""
        return self._cached(("v", point.body, tuple(point.offset)),
                            lambda: self.sub.add_matrix(matmul(self.J_P(point), sp.Matrix(self.u))))

    def omega(self, body: Body | None) -> sp.Matrix:
        """Ω = J_R u, built along the chain: Ω_i = Ω_parent + Σ_k ω_k u_k."""
        if body is None:
            return sp.zeros(3, 1)
        return self._cached(("w", body), lambda: self.sub.matrix(self._omega(body)))

    def _omega(self, body: Body | None) -> tuple:
        if body is None:
            return ZERO
        return self._cached(("_w", body), lambda: self.sub.add_matrix(add(self._omega(body.parent),
                                                                          self.relative(body)[1])))

    def time_derivative(self, expr: sp.Matrix) -> sp.Matrix:
        """d/dt by the chain rule, q̇ = u and u held fixed (so d/dt (J u) = J̇ u)."""
        return expr.applyfunc(lambda e: self.sub.add(self.sub.derivative(e, self.time_seeds, TIME)))

    def relative(self, body: Body) -> tuple[tuple, tuple]:
        """(V, W): the velocity of the body origin and the angular velocity relative to the joint frame,
        world axes, Σ_k (v_k, ω_k) u_k."""
        def build():
            V = total(scale(self._u[i], v) for i, v, _ in self._columns[body])
            W = total(scale(self._u[i], w) for i, _, w in self._columns[body])
            return self.sub.add_matrix(V), self.sub.add_matrix(W)
        return self._cached(("rel", body), build)

    def _bias(self, body: Body | None) -> tuple[tuple, tuple]:
        """(α_i, a_i): angular acceleration and acceleration of the body origin when u̇ = 0.

        The chain rule along the tree, with ė = Ω × e for every vector fixed in a moving body,
        d = p_i − p_p, (V, W) the joint's relative motion (`relative`) and (a_rel, α_rel) its bias:
        α_i = α_p + Ω_p × W + R α_rel,
        a_i = a_p + α_p × d + Ω_p × (Ω_p × d) + 2 Ω_p × V + R a_rel,
        with R the axes the joint writes its subspace in (`Joint.bias`, `Joint.joint_frame_subspace`)."""
        if body is None:
            return ZERO, ZERO

        def build():
            parent = body.parent
            alpha_p, a_p = self._bias(parent)
            Omega_p = self._omega(parent)
            d = self.sub.add_matrix(subtract(self._p[body], self._p[parent] if parent else ZERO))
            a = add(add(a_p, cross(alpha_p, d)), cross(Omega_p, self.sub.add_matrix(cross(Omega_p, d))))
            alpha = alpha_p
            if self._columns[body]:
                V, W = self.relative(body)
                a_rel, alpha_rel = self._joint_bias(body)
                alpha = add(add(alpha, cross(Omega_p, W)), apply(self._axes[body], alpha_rel))
                a = add(add(a, scale(2, cross(Omega_p, V))), apply(self._axes[body], a_rel))
            return self.sub.add_matrix(alpha), self.sub.add_matrix(a)
        return self._cached(("bias", body), build)

    def _joint_bias(self, body: Body) -> tuple[tuple, tuple]:
        """The joint's (a_rel, α_rel) in the axes of its subspace (a mimic's columns are constant: 0)."""
        joint = body.joint
        bias = joint.bias() if joint.joint_frame_subspace() is None else joint.joint_frame_bias()
        return tuple(self.sub.add_matrix(self.sub.vector(x)) for x in bias)

    def Jdot_u_P(self, point: Point) -> sp.Matrix:
        """J̇_P u: the acceleration of a point when u̇ = 0, a_i + α_i × c + Ω_i × (Ω_i × c), c = r − p_i."""
        self.rigid(point.body)
        if point.body is None:
            return sp.zeros(3, 1)

        def build():
            alpha, a = self._bias(point.body)
            Omega = self._omega(point.body)
            c = self.sub.add_matrix(apply(self._R[point.body], self.sub.vector(point.offset)))
            return self.sub.matrix(self.sub.add_matrix(add(add(a, cross(alpha, c)),
                                                  cross(Omega, self.sub.add_matrix(cross(Omega, c))))))
        return self._cached(("a", point.body, tuple(point.offset)), build)

    def Jdot_u_R(self, body: Body | None) -> sp.Matrix:
        """J̇_R u: the angular acceleration of a body when u̇ = 0."""
        self.rigid(body)
        return self.sub.matrix(self._bias(body)[0])

    def jacobian_dot_u(self, name: str) -> sp.Matrix:
        """6 × 1 J̇ u of a named frame, rows [linear; angular]."""
        f = self._frame(name)
        return self.Jdot_u_P(Point(f.body, f.placement.translation)).col_join(self.Jdot_u_R(f.body))

    def constraint_jacobian(self) -> tuple[sp.Matrix, sp.Matrix]:
        """(J_c, J̇_c u): the rows of every contact, loop and rolling disk stacked (`System.constraint_rows`;
        see `constraint_rows`)."""
        rows = self._cached("constraints", lambda: constraint_rows(self))
        return rows.J, rows.Jdot_u

    def closure_residual(self) -> sp.Matrix:
        """The position residuals of the loops and rolling disks (`System.closure_rows`), 0 when closed."""
        return self._cached("constraints", lambda: constraint_rows(self)).residual

    def grounded_disks(self) -> list:
        """The rolling disks whose tree keeps them on the ground (`grounded`): their height residual and
        normal row are zero at every state with the centre above the ground."""
        def build():
            disks, r = self.system.rolling, self.closure_residual()
            return grounded(self, dict(zip(disks, r[r.rows - len(disks):, 0])))
        return self._cached("grounded", build)

    # --- helpers ------------------------------------------------------------------------------
    def _frame(self, name: str):
        if name in self.system.frames:
            return self.system.frames[name]
        if isinstance(name, str) and any(b.name == name for b in self.system.bodies):
            body = self.system.body(name)
            return Frame(name, body, Placement())
        raise ModelError(f"unknown frame {name!r}; frames are {sorted(self.system.frames)} "
                         f"and bodies {[b.name for b in self.system.bodies]}")

    def _cached(self, key, build):
        if key not in self._cache:
            self._cache[key] = build()
        return self._cache[key]
