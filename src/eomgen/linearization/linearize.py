"""Linearization about an operating point: ẋ ≈ ẋ0 + A (x − x0) + B (r − r0).

The state x = [coordinates, speeds, motor currents]: the coordinates are one tangent direction per
speed (`chart`: q itself where q̇_k = u_j, else δ of q = q0 ⊕ δ), without those the holonomic constraints
fix; the speeds are the independent ones. The inputs r are actuated efforts τ_a and parameters. A and B
are the derivatives of the generated pieces of the equations (`pieces`) carried through the numeric
pipeline by the chain rule (`dual`), or the same at a symbolic point (closed forms)."""

from __future__ import annotations

from collections.abc import Mapping

import numpy as np
import sympy as sp

from ..arguments import flag
from ..eom import EquationsOfMotion
from ..errors import ModelError
from ..methods.kane import KaneEquations
from ..subexpressions import samples
from .dual import Algebra, Dual, solve, vstack
from .equations import EquationsModel
from .kane import KaneModel
from .operating_point import inputs as chosen_inputs, operating_point
from .motors import current_rates
from .pieces import Point, values as parameter_values
from .result import Linearization

SYMBOLIC_STATES = 12  # states beyond which symbolic=True is refused
TOL = 1e-9  # the holonomic constraints' residuals at q0, and the given speeds' differences


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
    symbolic, simplify = flag(symbolic, "linearize: symbolic"), flag(simplify, "linearize: simplify")
    nonzero = equations.nonzero if isinstance(equations, KaneEquations) else None
    algebra, system = Algebra(symbolic, nonzero), model.system
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
    if not symbolic:  # every missing value named at once, not piece by piece
        model.parameters.vector(values, model.pieces.parameters_used())
    point = Point(op.q, values, [*currents, *chosen.parameters], {}, 0, algebra)
    standin, at = _numbers(point, model) if symbolic else (point, {})
    dependent = case.dependent(standin)
    coordinates = [j for j in range(len(model.every)) if j not in dependent]
    sizes = [len(coordinates), len(case.speeds), len(currents), len(chosen.efforts), len(chosen.parameters)]
    if symbolic and sum(sizes[:3]) > SYMBOLIC_STATES:
        raise ModelError(
            f"linearize: {sum(sizes[:3])} states: symbolic=True is for at most {SYMBOLIC_STATES}; "
            "linearize numerically (symbolic=False)"
        )
    d_coordinates, d_speeds, d_currents, d_efforts, d_parameters = _directions(sizes, algebra)
    point.n = d_speeds.shape[0]
    point.tangents = {
        "q": algebra.zeros(point.n, len(model.every)),
        "p": np.concatenate([d_currents, d_parameters], axis=1),
    }
    point.tangents["q"][:, coordinates] = d_coordinates
    if dependent:
        _holonomic(case, point, dependent, at, algebra)
    tau_a = algebra.zeros(point.n, len(op.efforts), 1)
    tau_a[:, chosen.efforts, 0] = d_efforts
    u, w, rates = case.dynamics(
        point,
        Dual(_column(op.speeds, algebra), d_speeds[:, :, None]),
        Dual(_column(op.efforts, algebra), tau_a),
        algebra,
    )
    if op.full is not None:
        _check(w.value[:, 0] - op.full, at, "the speeds differ from those the constraints allow by")
    drift = point.tangents["q"] @ model.chart.drift(u.value[:, 0], algebra).T  # −½ ad(u0) δ
    parts = [(u + Dual(algebra.zeros(*u.value.shape), drift[:, :, None]))[coordinates], rates]
    if currents:
        parts.append(
            current_rates(
                model.pieces, point, u, Dual(_column(op.currents, algebra), d_currents[:, :, None])
            )
        )
    xdot = vstack(parts, point.n, algebra)
    return _result(model, xdot, coordinates, case.speeds, chosen, op, values, symbolic, simplify)


def _directions(sizes: list[int], algebra: Algebra) -> list[np.ndarray]:
    """The directions (rows: one per state, then per input) of the coordinates, speeds, currents, efforts
    and parameters: the columns of the identity, in blocks."""
    E = algebra.eye(sum(sizes))
    ends = np.cumsum([0, *sizes])
    return [E[:, a:b] for a, b in zip(ends[:-1], ends[1:])]


def _holonomic(case, point: Point, dependent: list[int], at: dict, algebra: Algebra) -> None:
    """The dependent directions of dδ from f(q0 ⊕ δ) = 0: dδ_dep = −F_dep⁻¹ (F_ind dδ_ind + ∂f/∂p dp);
    an operating point off the constraints refused."""
    f, F = case.closure(point)
    _check(
        f.value[:, 0],
        at,
        "q0 does not satisfy the holonomic constraints (assemble it: eg.assemble, or "
        "assemble of Kane's generated functions); their residuals are",
    )
    point.tangents["q"][:, dependent] = -solve(algebra, Dual(F[:, dependent]), f, "∂f/∂q_dep").tangent[
        :, :, 0
    ]


def _result(
    model,
    xdot: Dual,
    coordinates: list[int],
    speeds: list,
    chosen,
    op,
    values: dict,
    symbolic: bool,
    simplify: bool,
) -> Linearization:
    """A, B from the derivatives of ẋ (along the states, then the inputs), the names and x0, r0, ẋ0."""
    J = xdot.tangent[:, :, 0].T
    nx = J.shape[0]
    chart, q = model.chart, list(model.system.q)
    x0 = [op.q[q.index(chart.coordinate[j])] if j in chart.coordinate else 0 for j in coordinates]
    r0 = [*op.efforts[chosen.efforts], *(values.get(p, p) for p in chosen.parameters)]
    out = [J[:, :nx], J[:, nx:], [*x0, *op.speeds, *op.currents], r0, xdot.value[:, 0]]
    if symbolic:
        out = [_matrix(np.array(x, dtype=object)) for x in out]
        out = [x.applyfunc(sp.simplify) if simplify else x for x in out]
    else:
        out = [np.asarray(x, dtype=float) for x in out]
    names = [
        *(chart.names[j] for j in coordinates),
        *map(str, speeds),
        *(str(m.current) for m in model.system.motors),
    ]
    return Linearization(out[0], out[1], tuple(names), tuple(chosen.names), *out[2:])


def _model(equations):
    """The linearization's pieces of these equations, generated once and kept with them."""
    if not isinstance(equations, (EquationsOfMotion, KaneEquations)):
        raise ModelError(
            f"linearize: expected EquationsOfMotion or KaneEquations, got {type(equations).__name__} "
            "(derive them first: eg.derive(system) or eg.kane(system, ...))"
        )
    equations.subexpressions  # refused once the system has changed since the derivation
    if "_linearization" not in vars(equations):
        model = KaneModel if isinstance(equations, KaneEquations) else EquationsModel
        vars(equations)["_linearization"] = model(equations)
    return vars(equations)["_linearization"]


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


def _check(x, at: dict, what: str) -> None:
    """Refuse an operating point where x (residuals, at the values `at` of its symbols) exceeds TOL."""
    numbers = np.array([complex(sp.sympify(v).xreplace(at).evalf()) if at else v for v in x], dtype=complex)
    if np.max(np.abs(numbers), initial=0) > TOL:
        raise ModelError(f"linearize: op_point: {what} {np.real_if_close(numbers)}")


def _matrix(x: np.ndarray) -> sp.Matrix:
    """A sympy matrix of a 2-D block (n × m, m = 0 too: no inputs) or a column of a 1-D one."""
    rows, columns = x.shape if x.ndim == 2 else (len(x), 1)
    return sp.Matrix(rows, columns, list(x.flat))
