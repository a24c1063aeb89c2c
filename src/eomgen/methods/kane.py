"""Kane's equations with generalized speeds and nonholonomic constraints.

The joint speeds u = system.u are the coordinate rates q̇ for most joints, but a quaternion ball joint's
are its angular velocity and a planar joint's its twist, both in child axes: q̇ = q̇(q, u) (`System.qdot`;
nq ≠ nv). The generalized speeds w are defined by kinematic equations linear in u and w, and split by
velocity constraints linear in w into p independent and m dependent ones:

    Y(q) u + K(q) w + k0(q) = 0,        C(q) w + c0(q) = 0,   C w = C_dep w_dep + C_ind w_ind.

Holonomic constraints f(q) = 0 (given, and the heights of the rolling disks) fix as many dependent
coordinates; their derivatives ḟ = ∂f/∂q q̇(q, u) are the first rows of C w + c0 = 0 (with u in w from
the kinematic equations), the rolling disks' no-slip rows the last.

The equations of motion in u, M(q) u̇ = h(q, u) (projected Newton-Euler: h = τ_loads − b − g, i.e.
Kane's F_r + F*_r with the holonomic partial velocities, the columns of J_P and J_R) are derived
symbolically, with Y, K, k0, C, c0 and their time derivatives at u̇ = 0, ẇ = 0 (ḟ(q) = ∂f/∂q q̇(q, u)).
Everything that needs a matrix inverse is left to the numbers (see `codegen.kane`), solved with pivoting:

    w_dep = −C_dep⁻¹ (C_ind w_ind + c0),   u = −Y⁻¹ (K w + k0),   q̇ = q̇(q, u),
    P = ∂u/∂w_ind = −Y⁻¹ K T,   T = ∂w/∂w_ind = [I; −C_dep⁻¹ C_ind],
    ẇ_dep,0 = −C_dep⁻¹ d/dt(C w + c0)|_(ẇ=0),   u̇₀ = −Y⁻¹ (K ẇ₀ + d/dt(Y u + K w + k0)|_(u̇=0, ẇ=0)),
    M̃ = Pᵀ M P,   f̃ = Pᵀ (h − M u̇₀),   F̃_r = Pᵀ (τ_loads − g)

and M̃ ẇ_ind = f̃ are Kane's p equations F̃_r + F̃*_r = 0. Invertibility of C_dep and Y is checked at
random states; the closed forms solve symbolically only on pivots proven nonzero."""
from __future__ import annotations

from dataclasses import dataclass, field
from functools import cached_property

import numpy as np
import sympy as sp

from ..display import kane_markdown, kane_math
from ..eom import ClosedForms, EquationsOfMotion
from ..errors import ModelError
from ..constraint_rows import rolling_rows, tilts
from ..kinematics import Kinematics
from ..model import FlexibleLink
from ..model.system import System
from ..model.values import scalar
from ..subexpressions import samples
from ..symbols import Generated
from . import projected_newton_euler
from .nonzero import NOTHING, Nonzero

SAMPLES = 5  # random states for the invertibility checks
COND_LIMIT = 1e12
NUMERIC = "eg.codegen(k) solves it numerically with pivoting"


@dataclass(eq=False)
class KaneEquations(ClosedForms):
    """Kane's equations M̃(q) ẇ_ind = f̃(q, w_ind) with q̇ = q̇(q, w_ind). `compact` holds the pieces in
    named intermediates (`subexpressions`), in q, the joint speeds u = system.u (n of them) and the
    speeds w: "M" (n × n), "h" ([h | τ_loads − g], n × 2), "Y" ([Y | K | k0], n × (2n + 1)),
    "C" ([C | c0], m × (n + 1)), "rates" ([d/dt(Y u + K w + k0); d/dt(C w + c0)] at u̇ = 0, ẇ = 0) and
    "qdot" (q̇(q, u), nq × 1, `System.qdot`) and "holonomic" ([f | ∂f/∂q_dep], k × (k + 1), the
    configuration constraints f(q) = 0 and their Jacobian in the dependent coordinates) and "tilt" (each
    rolling disk's ‖e × n‖, `constraint_rows.tilt`)."""

    system: System
    kinematics: Kinematics
    speeds: list  # all generalized speeds w
    independent: list  # w_ind (p of them)
    dependent: list  # w_dep (m = n − p)
    compact: dict = field(default_factory=dict)
    parameters: set = field(default_factory=set)  # the system's, constraints' and kinematic equations'
    eom: EquationsOfMotion | None = None  # the equations in the joint speeds u (M, b, g, τ, T, U)
    dependent_coordinates: list = field(default_factory=list)  # one per holonomic constraint
    grounded: list = field(default_factory=list)  # rolling disks kept on the ground by the tree: no height
    assume_nonzero: list = field(default_factory=list)  # stated: the closed forms hold where none is 0
    _closed: dict = field(default_factory=dict, repr=False)

    @cached_property
    def nonzero(self) -> Nonzero:
        """The stated expressions (`assume_nonzero`) that the closed forms' pivots may divide by."""
        return Nonzero(self.assume_nonzero)

    @property
    def speeds_are_qdot(self) -> bool:
        """True when w = u (no kinematic equations): the speeds are the joint speeds, the symbols of
        system.u (q̇ unless `joint_speeds_are_rates` is False)."""
        return self.speeds == list(self.system.u)

    @property
    def joint_speeds_are_rates(self) -> bool:
        """True when the joint speeds are the coordinate rates, u = q̇ (no quaternion ball or planar
        joint)."""
        return list(self.system.qdot) == list(self.system.u)

    @property
    def mass_matrix(self) -> sp.Matrix:
        """M̃ = Pᵀ M P (p × p), closed form (pivots proven nonzero, else ModelError)."""
        return self._solution()["mass_matrix"]

    @property
    def forcing(self) -> sp.Matrix:
        """f̃ = Pᵀ (h − M q̈₀), so that M̃ ẇ_ind = f̃; closed form."""
        return self._solution()["forcing"]

    @property
    def active_forces(self) -> sp.Matrix:
        """F̃_r = Pᵀ (τ_loads − g): the nonholonomic generalized active forces (equilibrium iff 0)."""
        return self._solution()["F_r"]

    @property
    def qdot(self) -> sp.Matrix:
        """The kinematic differential equations q̇ = q̇(q, u) with u = −Y⁻¹ (K w + k0), in q and w_ind
        (nq rows); closed form."""
        return self._solution()["qdot"]

    @property
    def joint_speeds(self) -> sp.Matrix:
        """The joint speeds u = −Y⁻¹ (K w + k0) in q and w_ind (n rows; q̇ but for quaternion ball and planar
        joints); closed form."""
        return self._solution()["u"]

    @property
    def kinematic_equations(self) -> sp.Matrix:
        """The kinematic equations' left sides Y u + K w + k0 (= 0), in q, u and w; closed form."""
        B = self._blocks()
        return B["Y"] * sp.Matrix(self.system.u) + B["K"] * sp.Matrix(self.speeds) + B["k0"]

    @property
    def velocity_constraints(self) -> sp.Matrix:
        """The velocity constraints' left sides C w + c0 (= 0): ḟ, then the nonholonomic ones, in q and w;
        closed form."""
        B, (dep, ind) = self._blocks(), self._indices()
        w = sp.Matrix(self.speeds)
        return B["C_dep"] * w[dep, :] + B["C_ind"] * w[ind, :] + B["c0"]

    @property
    def holonomic(self) -> sp.Matrix:
        """The holonomic constraints' residuals f(q) (= 0 on the constraint); closed form."""
        return self._closed_form("holonomic")[:, 0]

    @property
    def independent_coordinates(self) -> list:
        """The coordinates that are not dependent (held by `assemble` of the generated code)."""
        return [x for x in self.system.q if x not in self.dependent_coordinates]

    @property
    def dependent_speeds(self) -> sp.Matrix:
        """w_dep = −C_dep⁻¹ (C_ind w_ind + c0); closed form."""
        return self._speeds_closed()[0]

    def inertia_forces(self) -> sp.Matrix:
        """F̃*_r = −M̃ ẇ_ind + (f̃ − F̃_r), in the symbols of ẇ_ind (w + 'dot')."""
        wdot = sp.Matrix([Generated(f"{w.name}dot", ("dot", w)) for w in self.independent])
        return -self.mass_matrix * wdot + self.forcing - self.active_forces

    def _repr_markdown_(self) -> str:  # Jupyter
        return kane_markdown(self)

    def _repr_latex_(self) -> str:
        return f"$$ {kane_math(self)} $$"

    # --- closed forms ---------------------------------------------------------------------------
    def _blocks(self) -> dict[str, sp.Matrix]:
        """Y, K, k0, r_kin, C_dep, C_ind, c0, r_con, M, h, Q in closed form (q, u, w)."""
        if "blocks" not in self._closed:
            n, m = len(self.speeds), len(self.dependent)
            Yk, Cc, rates = (self.subexpressions.inline(self.compact[k]) for k in ("Y", "C", "rates"))
            C = Cc[:, :n]
            dep, ind = self._indices()
            hQ = self.subexpressions.inline(self.compact["h"])
            self._closed["blocks"] = {
                "Y": Yk[:, :n], "K": Yk[:, n:2 * n], "k0": Yk[:, 2 * n], "r_kin": rates[:n, 0],
                "C_dep": C[:, dep], "C_ind": C[:, ind], "c0": Cc[:, n], "r_con": rates[n:n + m, 0],
                "M": self.subexpressions.inline(self.compact["M"]), "h": hQ[:, 0], "Q": hQ[:, 1]}
        return self._closed["blocks"]

    def _indices(self) -> tuple[list[int], list[int]]:
        index = self.speeds.index
        return [index(s) for s in self.dependent], [index(s) for s in self.independent]

    def _speeds_closed(self) -> tuple[sp.Matrix, sp.Matrix, sp.Matrix]:
        """(w_dep, T = ∂w/∂w_ind, −C_dep⁻¹ r_con) with w_dep = −C_dep⁻¹ (C_ind w_ind + c0)."""
        if "speeds" not in self._closed:
            B = self._blocks()
            n, p, m = len(self.speeds), len(self.independent), len(self.dependent)
            X = solve_proven(B["C_dep"], -B["C_ind"].row_join(B["c0"]).row_join(B["r_con"]),
                             "the constraints' matrix of the dependent speeds C_dep", nonzero=self.nonzero)
            A = X[:, :p]
            w_dep = A * sp.Matrix(self.independent) + X[:, p] if m else sp.zeros(0, 1)
            dep, ind = self._indices()
            T = sp.zeros(n, p)
            for r, i in enumerate(ind):
                T[i, r] = 1
            for r, i in enumerate(dep):
                T[i, :] = A[r, :]
            self._closed["speeds"] = (w_dep, T, X[:, p + 1] if m else sp.zeros(0, 1))
        return self._closed["speeds"]

    def _solution(self) -> dict[str, sp.Matrix]:
        """The closed forms of u, q̇, M̃, f̃ and F̃_r in q and w_ind (see the module's formulas)."""
        if "solution" not in self._closed:
            B = self._blocks()
            w_dep, T, wd_dep = self._speeds_closed()
            n = len(self.speeds)
            X = solve_proven(B["Y"], -B["K"].row_join(B["k0"]).row_join(B["r_kin"]),
                             "the speed map Y = ∂(kinematic equations)/∂u", nonzero=self.nonzero)
            W = X[:, :n]  # u = W w + X_k0,  u̇₀ = W ẇ₀ + X_r
            on_w = dict(zip(self.dependent, w_dep))
            w = sp.Matrix(self.speeds).xreplace(on_w)
            u = W * w + X[:, n]
            state = {**dict(zip(self.system.u, u)), **on_w}
            wd0 = sp.zeros(n, 1)
            for r, i in enumerate(self._indices()[0]):
                wd0[i] = wd_dep[r]
            ud0 = (W * wd0 + X[:, n + 1]).xreplace(state)
            P = W * T
            M = B["M"]
            self._closed["solution"] = {
                "u": u, "qdot": self.compact["qdot"].xreplace(state), "mass_matrix": P.T * M * P,
                "forcing": P.T * (B["h"].xreplace(state) - M * ud0), "F_r": P.T * B["Q"].xreplace(state)}
        return self._closed["solution"]


class NoPivot(ModelError):
    """No pivot of column j of `what` is proven nonzero; `candidates`: its nonzero entries."""

    def __init__(self, what: str, j: int, candidates: list) -> None:
        self.candidates = candidates
        self.hint = f"eg.kane(..., assume_nonzero={candidates[:1]}) (valid where it does not vanish)"
        state = f"where the closed forms may divide by one, state it: {self.hint}, or " if candidates else ""
        super().__init__(f"kane: no closed form: {what}: no pivot in column {j} can be proven nonzero "
                         f"(candidates {candidates}); {state}{NUMERIC}")


def solve_proven(A: sp.Matrix, B: sp.Matrix, what: str, normal=None, nonzero=NOTHING) -> sp.Matrix:
    """X with A X = B by Gauss-Jordan elimination, pivoting only on entries proven nonzero
    (`is_zero is False`: numbers, positive symbols, ...), else by the stated assumptions (`nonzero`, a
    `Nonzero`); `NoPivot` naming `what` otherwise. `normal` (e.g. sympy's cancel) rewrites the entries of
    A and B first and after each elimination step."""
    A, B = ((X.applyfunc(normal) if normal else X).as_mutable() for X in (A, B))
    n = A.rows
    for j in range(n):
        pivot = next((i for i in range(j, n) if A[i, j].is_zero is False), None)
        if pivot is None:
            pivot = next((i for i in range(j, n) if nonzero.proves(A[i, j])), None)
        if pivot is None:
            raise NoPivot(what, j, [e for e in A[j:, j] if e != 0])
        A.row_swap(j, pivot)
        B.row_swap(j, pivot)
        for i in range(n):
            if i != j and A[i, j] != 0:
                factor = A[i, j] / A[j, j]
                A[i, :] = A[i, :] - factor * A[j, :]
                B[i, :] = B[i, :] - factor * B[j, :]
                A[i, j] = 0
                if normal:
                    A[i, :], B[i, :] = A[i, :].applyfunc(normal), B[i, :].applyfunc(normal)
    return sp.Matrix(n, B.cols, lambda i, k: (normal or (lambda e: e))(B[i, k] / A[i, i]))


def _linear(exprs, symbols, what: str) -> tuple[sp.Matrix, sp.Matrix]:
    """(C, c0) with exprs = C symbols + c0: linear iff no entry of ∂exprs/∂symbols has a symbol left."""
    exprs = sp.Matrix(exprs)
    C = exprs.jacobian(list(symbols))
    for i in range(exprs.rows):
        left = set().union(*(C[i, j].free_symbols for j in range(C.cols))) & set(symbols)
        if left:
            raise ModelError(f"kane: {what} {i} is not linear in {list(symbols)} "
                             f"(∂/∂ still has {sorted(left, key=str)}): {exprs[i]}")
    return C, exprs.xreplace({s: 0 for s in symbols})


def _symbols(values, what: str) -> list[sp.Symbol]:
    """A list of sympy Symbols (speeds), or a ModelError naming `what`."""
    if isinstance(values, (str, sp.Basic)) or not hasattr(values, "__iter__"):
        raise ModelError(f"kane: {what}: expected a list of sympy Symbols, got {values!r}")
    values = list(values)
    wrong = [v for v in values if not isinstance(v, sp.Symbol)]
    if wrong:
        raise ModelError(f"kane: {what}: expected sympy Symbols, got {wrong}")
    return values


def _expressions(system: System, exprs, what: str, speeds: list) -> list[sp.Expr]:
    """Checked expressions (see `model.values.scalar`) whose symbols are the system's, the speeds or new
    parameters with names of their own (never the label of a speed: `Symbol("xdot")` is not ẋ)."""
    if isinstance(exprs, (str, sp.Basic)) or not hasattr(exprs, "__iter__"):
        raise ModelError(f"kane: {what}s: expected a list of expressions, got {exprs!r}")
    checked = [scalar(e, f"kane: {what} {i}") for i, e in enumerate(exprs)]
    for i, e in enumerate(checked):
        system.check_symbols(f"kane: {what} {i}", e, own=speeds)
    return checked


def _check_invertible(sub, matrices: dict[str, sp.Matrix], q: list, params: list) -> None:
    """cond(A) at SAMPLES random states (`subexpressions.samples`) for each named square matrix A in q;
    ModelError if it is singular (cond > COND_LIMIT or not finite) at all of them."""
    states = samples(q, params, SAMPLES)
    for what, A in matrices.items():
        if A.rows == 0:
            continue
        conds = []
        for state in states:
            a = np.array(sub.evaluate(list(A), state)).reshape(A.shape)
            finite = np.all(np.isfinite(a)) and not np.iscomplex(a).any()
            conds.append(np.linalg.cond(a.real) if finite else np.inf)
        if min(conds) > COND_LIMIT:
            raise ModelError(f"kane: {what} is not invertible: singular at all {SAMPLES} random states "
                             f"(smallest cond {min(conds):.1e})")


def kane(system: System, speeds=None, kinematic_equations=None, nonholonomic=None, independent=None,
         holonomic=None, dependent_coordinates=None, assume_nonzero=None) -> KaneEquations:
    """Kane's equations of `system` in the generalized `speeds` w, defined by `kinematic_equations`
    (expressions = 0, linear in the joint speeds u = system.u and w; default w = u), with the velocity
    constraints `nonholonomic` (expressions in q and w = 0, linear in w) and the `independent` speeds.
    u is q̇ but for a quaternion ball joint or free flyer (ω, the twist, in child axes) and a planar joint
    (its twist in child axes), whose coordinates follow from q̇ = system.qdot(q, u).

    `holonomic`: configuration constraints f(q) = 0 with as many `dependent_coordinates` (symbols of q);
    their time derivatives ḟ = ∂f/∂q q̇(q, u) join the velocity constraints before the nonholonomic ones.
    The system's rolling disks (`System.add_rolling`) are taken as they are: each disk's height residual
    joins the holonomic constraints after the given ones (name one dependent coordinate more per disk), the
    normal velocity of its contact point (J_n u) their derivatives, its two no-slip rows (J_t u) the
    nonholonomic constraints after the given ones. A disk its tree keeps on the ground (`grounded`: the
    textbook disk, leaning about the contact line) has neither height nor normal row (dropped: listed in
    `KaneEquations.grounded`). So there are len(holonomic) + len(nonholonomic) + 3 × disks − grounded
    dependent speeds. Constraints in the joint speeds u (ḟ, the disks' rows) are written in new
    speeds w through u = −Y⁻¹ (K w + k0) in closed form (pivots of Y proven nonzero; w = u needs none).
    Contacts and loops are refused (write a loop as holonomic constraints). The rhs integrates every q.

    `assume_nonzero`: expressions in q and the parameters (e.g. [sp.cos(x3)]) that the closed forms may
    divide by (a pivot that is a product of them, of their factors and of entries proven nonzero): they
    are then valid where none of them vanishes (kept as `KaneEquations.assume_nonzero`)."""
    if not isinstance(system, System):
        raise ModelError(f"kane: expected an eomgen.System, got {type(system).__name__}")
    if any(isinstance(j, FlexibleLink) for j in system.joints):
        raise ModelError("kane: flexible links are not supported")
    if system.prescribed:
        raise ModelError(f"kane: the prescribed motion of joint '{system.prescribed[0].name}' is not "
                         "supported (its rate is no column of the partial velocities): use eg.derive, by Lagrange")
    if system.contacts or system.loops:
        raise ModelError(f"kane: contacts {[c.name for c in system.contacts]} and loops "
                         f"{[c.name for c in system.loops]} are not taken: write loop closures as holonomic "
                         "constraints and contacts as nonholonomic ones")
    q, u = list(system.q), list(system.u)
    n = len(u)
    speeds = u if speeds is None else _symbols(speeds, "speeds")
    if len(speeds) != n or len(set(speeds)) != n:
        raise ModelError(f"kane: give {n} distinct speeds, got {speeds}")
    kinematic_equations, nonholonomic, holonomic = (
        None if exprs is None else _expressions(system, exprs, what, speeds)
        for exprs, what in ((kinematic_equations, "kinematic equation"),
                            (nonholonomic, "nonholonomic constraint"), (holonomic, "holonomic constraint")))
    kinematic_equations, (Y, K, k0) = _kinematic(kinematic_equations, u, speeds)
    nonholonomic = list(nonholonomic or [])
    holonomic = list(holonomic or [])
    kin = Kinematics(system)
    grounded = kin.grounded_disks()
    dependent_coordinates = _dependent_coordinates(system, holonomic, dependent_coordinates, speeds,
                                                   grounded)
    independent = speeds if independent is None else _symbols(independent, "independent")
    unknown = [s for s in independent if s not in speeds]
    if unknown:
        raise ModelError(f"kane: independent speeds {unknown} are not among the speeds {speeds}")
    dependent = [s for s in speeds if s not in independent]
    disks = len(system.rolling)
    if len(dependent) != len(holonomic) + len(nonholonomic) + 3 * disks - len(grounded):
        raise ModelError(f"kane: {len(holonomic)} holonomic and {len(nonholonomic)} nonholonomic "
                         f"constraints and {disks} rolling disks (3 rows each{_held(grounded, ', 2 for')}) "
                         f"need as many dependent speeds, got {dependent}")
    for i, e in enumerate(nonholonomic):
        stray = sp.sympify(e).free_symbols & (set(u) - set(speeds))
        if stray:
            raise ModelError(f"kane: nonholonomic constraint {i} depends on q̇ (the joint speeds) "
                             f"{sorted(stray, key=str)}: write it in q and the speeds")

    given = [*kinematic_equations, *nonholonomic, *holonomic]
    parameters = (system.parameters | set().union(*(sp.sympify(e).free_symbols for e in given))) - set(
        q + u + speeds)
    assumed = assumptions(system, assume_nonzero, q, parameters)
    sub = kin.sub
    eom = projected_newton_euler.derive(kin)
    f, C, c0, constraint_rates = _constraints(kin, holonomic, nonholonomic, speeds, (Y, K, k0),
                                              Nonzero(assumed))
    F_dep = configuration_jacobian(sub, f, dependent_coordinates)
    Cd = sub.add_matrix(C[:, [speeds.index(s) for s in dependent]])
    Yn = sub.add_matrix(Y)
    _check_invertible(sub, {"∂(holonomic constraints)/∂(dependent coordinates)": F_dep,
                            "the constraints' matrix of the dependent speeds C_dep": Cd,
                            "the speed map (∂ kinematic equations / ∂u) Y": Yn},
                      q, parameters)
    rates = kin.time_derivative(sp.Matrix(kinematic_equations)).col_join(constraint_rates)  # u̇ = ẇ = 0
    gravity = -eom.compact["g"]
    compact = {"M": eom.compact["M"],
               "h": (eom.tau_compact - eom.compact["b"] + gravity).row_join(eom.tau_compact + gravity),
               "Y": Yn.row_join(sub.add_matrix(K)).row_join(sub.add_matrix(k0)),
               "C": sub.add_matrix(C).row_join(sub.add_matrix(c0)), "rates": rates, "qdot": system.qdot,
               "holonomic": f.row_join(F_dep), "tilt": tilts(kin)}
    return KaneEquations(system, kin, speeds, independent, dependent, compact, parameters, eom,
                         dependent_coordinates=dependent_coordinates, grounded=[d.name for d in grounded],
                         assume_nonzero=assumed)


def assumptions(system: System, values, q: list, parameters: set) -> list[sp.Expr]:
    """`assume_nonzero` checked: a list of expressions in q and the parameters, none a number and none
    zero at all random states (`samples`: identically zero, such as cos² + sin² − 1)."""
    if values is None:
        return []
    if isinstance(values, (str, sp.Basic)) or not hasattr(values, "__iter__"):
        raise ModelError(f"kane: assume_nonzero: expected a list of sympy expressions (e.g. [sp.cos(x)]), "
                         f"got {values!r}")
    checked = [scalar(e, f"kane: assume_nonzero {i}") for i, e in enumerate(values)]
    states = samples(q, parameters, SAMPLES)
    for i, e in enumerate(checked):
        what = f"kane: assume_nonzero {i} ({e})"
        if e.is_number:
            raise ModelError(f"{what}: a number states nothing; give expressions in the coordinates {q}")
        system.check_symbols(what, e)
        unknown = e.free_symbols - set(q) - parameters
        if unknown:
            raise ModelError(f"{what}: {sorted(unknown, key=str)} are neither coordinates {q} nor "
                             "parameters of the system or its constraints")
        if all(abs(complex(e.evalf(subs=state))) < 1e-12 for state in states):
            raise ModelError(f"{what}: it is zero at all {SAMPLES} random states (identically zero?), "
                             "so it cannot be assumed nonzero")
    return checked


def _held(grounded: list, prefix: str) -> str:
    """', 2 for [names] (grounded: the tree keeps them on the ground)' or '' (messages)."""
    names = [d.name for d in grounded]
    return f"{prefix} {names}, which the tree keeps on the ground" if names else ""


def _kinematic(equations, u: list, speeds: list) -> tuple[list, tuple]:
    """The kinematic equations (w − u = 0 when none are given and w = u) and (Y, K, k0) of
    Y u + K w + k0 = 0."""
    n = len(u)
    if equations is None:
        if speeds != u:
            raise ModelError("kane: new speeds need kinematic_equations (Y u + K w + k0 = 0, u = system.u)")
        return [w - x for w, x in zip(speeds, u)], (sp.eye(n), -sp.eye(n), sp.zeros(n, 1))
    if len(equations) != n:
        raise ModelError(f"kane: {n} kinematic equations needed, got {len(equations)}")
    if set(speeds) & set(u):
        raise ModelError(f"kane: speeds with kinematic_equations must be new symbols, not the joint "
                         f"speeds {u}")
    YK, k0 = _linear(equations, u + speeds, "kinematic equation")
    return equations, (YK[:, :n], YK[:, n:], k0)


def _constraints(kin: Kinematics, holonomic: list, nonholonomic: list, speeds: list, kinematic: tuple,
                 nonzero: Nonzero):
    """(f, C, c0, rates): the holonomic residuals f(q) (the given ones, then each rolling disk's height,
    but the grounded disks')
    and the velocity constraints C w + c0 = 0 with their rates d/dt at ẇ = 0, stacked: ḟ = ∂f/∂q q̇(q, u)
    (the disks' J_n u), then the nonholonomic ones (the given ones, then the disks' no-slip J_t u)."""
    system, sub, n = kin.system, kin.sub, kin.n
    f = sub.add_matrix(sp.Matrix(len(holonomic), 1, holonomic))
    F_q = configuration_jacobian(sub, f, kin.q)
    in_u = [(F_q * system.qdot.jacobian(kin.u), sp.zeros(f.rows, 1), None)]
    wheels = [rolling_rows(kin, disk) for disk in system.rolling]  # in u: (A, a0, rates of A u)
    touching = [r for r, d in zip(wheels, system.rolling) if d not in kin.grounded_disks()]
    in_u += [(r.J[2:, :], sp.zeros(1, 1), r.Jdot_u[2:, :]) for r in touching]
    slip = [(r.J[:2, :], sp.zeros(2, 1), r.Jdot_u[:2, :]) for r in wheels]
    f = f.col_join(sp.Matrix(len(touching), 1, [r.residual[0] for r in touching]))
    rows = [(sp.zeros(0, n), sp.zeros(0, 1), sp.zeros(0, 1))]
    rows += _in_speeds(kin, in_u, speeds, kinematic, nonzero) if f.rows else []
    if nonholonomic:
        C, c0 = _linear(nonholonomic, speeds, "nonholonomic constraint")
        rows.append((C, c0, kin.time_derivative(sp.Matrix(nonholonomic))))
    rows += _in_speeds(kin, slip, speeds, kinematic, nonzero) if slip else []
    return (f, *(sp.Matrix.vstack(*(r[i] for r in rows)) for i in range(3)))


def _dependent_coordinates(system: System, holonomic: list, coordinates, speeds: list,
                           grounded: list) -> list[sp.Symbol]:
    """The dependent coordinates, one per holonomic constraint and rolling disk but the `grounded` ones,
    checked: symbols of q, distinct; the constraints in q and parameters only."""
    coordinates = [] if coordinates is None else _symbols(coordinates, "dependent_coordinates")
    for i, e in enumerate(holonomic):
        stray = e.free_symbols & (set(system.u) | set(speeds))
        if stray:
            raise ModelError(f"kane: holonomic constraint {i} depends on the speeds "
                             f"{sorted(stray, key=str)}: write it in q (configuration constraints f(q) = 0)")
    q = list(system.q)
    strangers = [x for x in coordinates if x not in q]
    if strangers:
        raise ModelError(f"kane: dependent_coordinates {strangers} are not coordinates of the system {q}")
    disks = [d.name for d in system.rolling if d not in grounded]
    if len(set(coordinates)) != len(coordinates) or len(coordinates) != len(holonomic) + len(disks):
        raise ModelError(f"kane: {len(holonomic)} holonomic constraints and the rolling disks {disks} (one "
                         f"height each{_held(grounded, '; none for')}) need as many distinct "
                         f"dependent_coordinates, got {coordinates}")
    return sorted(coordinates, key=q.index)


def configuration_jacobian(sub, f: sp.Matrix, q: list) -> sp.Matrix:
    """∂f/∂q (k × nq) through the intermediates (directional derivatives along each coordinate)."""
    return sp.Matrix(f.rows, len(q), lambda i, k: sub.add(sub.derivative(f[i], {q[k]: 1}, ("∂", q[k]))))


def _in_speeds(kin: Kinematics, rows: list, speeds: list, kinematic: tuple, nonzero: Nonzero) -> list:
    """Velocity constraints A u + a0 = 0 in the joint speeds (with their rates d/dt at u̇ = 0, or None)
    written in the speeds w: unchanged if w = u, else with u = W w + X0 = −Y⁻¹ (K w + k0) in closed form:
    C = A W, c0 = A X0 + a0, and the rates d/dt (C w + c0) at ẇ = 0. Returns [(C, c0, rates)]."""
    u = list(kin.system.u)
    if speeds == u:
        return [(A, a0, kin.time_derivative(A * sp.Matrix(u) + a0) if rates is None else rates)
                for A, a0, rates in rows]
    Y, K, k0 = kinematic
    X = solve_proven(Y, -K.row_join(k0), "the speed map Y (constraints in the joint speeds, new speeds)",
                     nonzero=nonzero)
    written = []
    for A, a0, _ in rows:
        C, c0 = A * X[:, :-1], A * X[:, -1] + a0
        written.append((C, c0, kin.time_derivative(C * sp.Matrix(speeds) + c0)))
    return written
