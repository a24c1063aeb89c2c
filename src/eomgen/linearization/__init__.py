"""Linearization about an operating point: ẋ ≈ ẋ0 + A (x − x0) + B (r − r0).

The state x = [coordinates, speeds, motor currents]: the coordinates are one tangent direction per
speed (`chart`: q itself where q̇_k = u_j, else δ of q = q0 ⊕ δ), without those the holonomic constraints
fix; the speeds are the independent ones. The inputs r are actuated efforts τ_a and parameters. A and B
are the derivatives of the generated pieces of the equations (`pieces`) carried through the numeric
pipeline by the chain rule (`dual`), or the same at a symbolic point (closed forms)."""

from __future__ import annotations

import weakref
from collections.abc import Mapping
from dataclasses import dataclass

import numpy as np
import sympy as sp

from ..eom import EquationsOfMotion
from ..errors import ModelError
from ..methods.kane import KaneEquations
from ..subexpressions import samples
from .dual import Algebra, Dual, solve, vstack
from .equations import EquationsModel
from .kane import KaneModel
from .operating_point import inputs as chosen_inputs, operating_point
from .pieces import Point, values as parameter_values

SYMBOLIC_STATES = 12  # states beyond which symbolic=True is refused
TOL = 1e-9  # the holonomic constraints at q0, and the given dependent speeds, relative to max(1, |x|)
_models: weakref.WeakKeyDictionary = weakref.WeakKeyDictionary()


@dataclass(frozen=True)
class Linearization:
    """ẋ ≈ xdot0 + A (x − x0) + B (r − r0) about an operating point: `states` name the entries of x (the
    independent coordinates, `delta_<speed>` for a tangent coordinate of a quaternion or planar joint,
    then the independent speeds, then the motor currents), `inputs` those of r. NumPy arrays, or sympy
    matrices when symbolic. xdot0 = 0 at an equilibrium; a steady motion (u0 ≠ 0) has the coordinates'
    rates in it."""

    A: np.ndarray | sp.Matrix
    B: np.ndarray | sp.Matrix
    states: tuple[str, ...]
    inputs: tuple[str, ...]
    x0: np.ndarray | sp.Matrix
    r0: np.ndarray | sp.Matrix
    xdot0: np.ndarray | sp.Matrix

    def index(self, names) -> list[int]:
        """The positions of states in x, by name."""
        names = [names] if isinstance(names, str) else list(names)
        unknown = [x for x in names if x not in self.states]
        if unknown:
            raise ModelError(f"Linearization: unknown states {unknown}; the states are {list(self.states)}")
        return [self.states.index(x) for x in names]

    def select(self, states, inputs=None) -> Linearization:
        """The rows and columns of some states (and of some inputs; default all): the linearization of a
        subsystem, exact when the other states do not drive these (A block triangular)."""
        i = self.index(states)
        inputs = self.inputs if inputs is None else [inputs] if isinstance(inputs, str) else list(inputs)
        unknown = [x for x in inputs if x not in self.inputs]
        if unknown:
            raise ModelError(f"Linearization: unknown inputs {unknown}; the inputs are {list(self.inputs)}")
        k = [self.inputs.index(x) for x in inputs]
        if isinstance(self.A, sp.MatrixBase):
            part = lambda X, r, c=(0,): X.extract(r, list(c))  # noqa: E731
        else:
            part = lambda X, r, c=None: X[np.ix_(r, c)] if c is not None else X[r]  # noqa: E731
        return Linearization(
            part(self.A, i, i),
            part(self.B, i, k),
            tuple(self.states[j] for j in i),
            tuple(inputs),
            part(self.x0, i),
            part(self.r0, k),
            part(self.xdot0, i),
        )

    def eigenvalues(self) -> np.ndarray:
        """The eigenvalues of A, sorted (numpy.sort_complex); numbers only."""
        try:
            A = np.array(self.A.tolist() if isinstance(self.A, sp.MatrixBase) else self.A, dtype=float)
        except TypeError:
            raise ModelError(
                "Linearization: A has symbols: substitute numbers for its eigenvalues"
            ) from None
        return np.sort_complex(np.linalg.eigvals(A))


def linearize(
    equations,
    op_point,
    inputs=None,
    *,
    params: Mapping | None = None,
    independent=None,
    symbolic: bool = False,
    simplify: bool = False,
) -> Linearization:
    """A, B of ẋ = A x + B r about `op_point` for an `EquationsOfMotion` (with contacts, loops or rolling
    disks: in the `independent` speeds, named as for `eg.reduce`, and the coordinates the closures leave
    free) or `KaneEquations` (x = [q_ind, w_ind], as sympy's Linearizer).

    op_point: (q0, speeds[, tau_a0[, currents]]) arrays (the speeds: all, or the independent ones) or a
    mapping {name: value} (every coordinate; independent speeds, efforts 'tau_<joint>' and motor currents,
    0 when left out); q0 must satisfy the holonomic constraints (`eg.assemble`). inputs: names of actuated
    efforts 'tau_<joint>' and of parameters (loads, motor voltages); default: the actuated efforts.
    params: the parameters' values {name: value}. symbolic: sympy matrices (the operating point and params
    may hold symbols; small systems only), `simplify` applies sympy's simplify to each entry."""
    model = _model(equations)
    algebra, system = Algebra(symbolic), model.system
    case = model.case(independent)
    currents = [m.current for m in system.motors]
    chosen = chosen_inputs(system, model.parameters.symbols, currents, inputs)
    op = operating_point(system, case.speeds, model.every, currents, op_point, algebra)
    given = parameter_values(model.parameters, params, symbolic)
    if any(i in given for i in currents):
        raise ModelError(
            f"params: {[str(i) for i in currents if i in given]} are motor currents, part of the "
            "state: give them in op_point"
        )
    values = {**given, **dict(zip(currents, op.currents))}
    point = Point(op.q, values, [*currents, *chosen.parameters], {}, 0, algebra)
    standin, at = _numbers(point, model) if symbolic else (point, {})
    dependent = case.dependent(standin)
    coordinates = [j for j in range(len(model.every)) if j not in dependent]
    sizes = np.cumsum(
        [0, len(coordinates), len(case.speeds), len(currents), len(chosen.efforts), len(chosen.parameters)]
    )
    n = point.n = int(sizes[-1])
    if symbolic and sizes[3] > SYMBOLIC_STATES:
        raise ModelError(
            f"linearize: {sizes[3]} states: symbolic=True is for at most {SYMBOLIC_STATES}; "
            "linearize numerically (symbolic=False)"
        )
    E = algebra.eye(n)
    dq = algebra.zeros(n, len(model.every))
    dq[:, coordinates] = E[:, : sizes[1]]
    point.tangents = {"q": dq, "p": np.concatenate([E[:, sizes[2] : sizes[3]], E[:, sizes[4] :]], axis=1)}
    if dependent:
        f, F = case.closure(point)
        _check(
            f.value[:, 0],
            0,
            at,
            "q0 does not satisfy the holonomic constraints (assemble it: eg.assemble, "
            "or assemble of Kane's generated functions); their residuals are",
        )
        dq[:, dependent] = -solve(algebra, Dual(F[:, dependent]), f, "∂f/∂q_dep").tangent[:, :, 0]
    speeds = Dual(_column(op.speeds, algebra), E[:, sizes[1] : sizes[2], None])
    d_efforts = algebra.zeros(n, len(op.efforts), 1)
    for k, i in enumerate(chosen.efforts):
        d_efforts[sizes[3] + k, i, 0] = E[0, 0]
    u, w, rates = case.dynamics(point, speeds, Dual(_column(op.efforts, algebra), d_efforts), algebra)
    if op.full is not None:
        _check(w.value[:, 0] - op.full, 0, at, "the speeds differ from those the constraints allow by")
    qdot = u + Dual(
        algebra.zeros(*u.value.shape), (dq @ model.chart.drift(u.value[:, 0], algebra).T)[:, :, None]
    )
    parts = [qdot[coordinates], rates]
    if currents:
        c = model.pieces.dual("motor", point, u)
        parts.append(
            c[:, 0:1] - c[:, 1:2] * Dual(_column(op.currents, algebra), E[:, sizes[2] : sizes[3], None])
        )
    xdot = vstack(parts, n, algebra)
    J = xdot.tangent[:, :, 0].T
    chart, q = model.chart, list(system.q)
    x0 = [op.q[q.index(chart.coordinate[j])] if j in chart.coordinate else 0 for j in coordinates]
    r0 = [*op.efforts[chosen.efforts], *(values.get(p, p) for p in chosen.parameters)]
    out = [J[:, : sizes[3]], J[:, sizes[3] :], [*x0, *op.speeds, *op.currents], r0, xdot.value[:, 0]]
    if symbolic:
        out = [sp.Matrix(np.reshape(np.array(x, dtype=object), (len(x), -1)).tolist()) for x in out]
        out = [x.applyfunc(sp.simplify) if simplify else x for x in out]
    else:
        out = [np.asarray(x, dtype=float) for x in out]
    names = [*(chart.names[j] for j in coordinates), *map(str, case.speeds), *map(str, currents)]
    return Linearization(out[0], out[1], tuple(names), tuple(chosen.names), *out[2:])


def _model(equations):
    """The linearization's pieces of these equations (generated once, kept while the equations live)."""
    if not isinstance(equations, (EquationsOfMotion, KaneEquations)):
        raise ModelError(
            f"linearize: expected EquationsOfMotion or KaneEquations, got {type(equations).__name__} "
            "(derive them first: eg.derive(system) or eg.kane(system, ...))"
        )
    if equations not in _models:
        _models[equations] = (KaneModel if isinstance(equations, KaneEquations) else EquationsModel)(
            equations
        )
    return _models[equations]


def _column(x, algebra: Algebra) -> np.ndarray:
    return algebra.array(list(x)).reshape(-1, 1)


def _numbers(point: Point, model) -> tuple[Point, dict]:
    """A numeric stand-in of a symbolic point (for the choices and checks that need numbers): every symbol
    of it and every parameter without a value at a random value in [0.5, 1.5]; and those values."""
    exprs = [*point.q, *point.values.values()]
    free = set().union(*(sp.sympify(x).free_symbols for x in exprs)) | set(model.parameters.symbols)
    at = samples([], free, 1)[0]
    number = lambda x: float(sp.sympify(x).xreplace(at))  # noqa: E731
    values = {p: number(point.values.get(p, p)) for p in model.parameters.symbols}
    return Point(np.array([number(x) for x in point.q]), values, point.chosen, {}, 0, Algebra(False)), at


def _check(x, expected, at: dict, what: str) -> None:
    """Refuse an operating point where x differs from `expected` by more than TOL max(1, |expected|)."""
    numbers = np.array([complex(sp.sympify(v).xreplace(at).evalf()) if at else v for v in x], dtype=complex)
    scale = max(1.0, float(np.max(np.abs(expected), initial=0)))
    if np.max(np.abs(numbers - expected), initial=0) > TOL * scale:
        raise ModelError(f"linearize: op_point: {what} {np.real_if_close(numbers)}")
