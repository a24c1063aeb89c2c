"""`solution(system)`: the worked solution of a system's equations of motion, method by method."""

from __future__ import annotations

import numpy as np
import sympy as sp

from ..eom import EquationsOfMotion
from ..errors import ModelError
from ..methods import METHODS, derive
from ..methods.kane import KaneEquations
from ..model import FreeFlyer
from ..model.system import System
from ..printing import SIMPLE_DENOMINATOR
from ..state import random_states
from ..subexpressions import samples
from . import kane_steps, steps
from .document import Solution
from ..textbook import MAX_OPS, SECONDS, Simplifier, is_zero

LECTURE = ("free_cut", "projected_newton_euler", "lagrange")
TEXTBOOK_DOF = 4  # form "auto": textbook closed forms up to this many speeds, shared forms beyond
STEPS = {
    "free_cut": steps.free_cut,
    "projected_newton_euler": steps.projected_newton_euler,
    "lagrange": steps.lagrange,
    "recursive": steps.recursive,
}


def solution(
    equations,
    methods=LECTURE,
    form: str = "auto",
    title: str | None = None,
    max_ops: int = MAX_OPS,
    seconds: float = SECONDS,
) -> Solution:
    """The worked solution of a `System` by each of `methods` (the lecture's three by default), or of
    `KaneEquations` (from `eg.kane`): steps with the intermediate results, M, b, g by each method and
    their comparison (exact for closed forms, at random states for shared ones).

    form: "textbook" (closed forms, each entry simplified when it has at most `max_ops` operations and
    the `seconds` budget is not spent), "shared" (the derivation's shared intermediates, renamed χ_k),
    or "auto" (textbook up to 4 speeds)."""
    if isinstance(equations, KaneEquations):
        return kane_steps.solution(equations, _simplifier(equations.system, max_ops, seconds), title)
    if isinstance(equations, EquationsOfMotion):
        raise ModelError(
            "solution: give the System (each method derives its own equations) or KaneEquations"
        )
    if not isinstance(equations, System):
        raise ModelError(
            f"solution: expected an eomgen.System or KaneEquations, got {type(equations).__name__}"
        )
    system = equations
    if system.prescribed:
        raise ModelError(f"solution: joint '{system.prescribed[0].name}' has a prescribed motion, which the "
                         "worked steps (velocities J u, d/dt along q and u) leave out; use eg.derive")
    methods = tuple(dict.fromkeys((methods,) if isinstance(methods, str) else methods))  # each once
    unknown = [m for m in methods if m not in METHODS]
    if unknown or not methods:
        raise ModelError(f"solution: unknown methods {unknown}; choose from {sorted(METHODS)}")
    if form not in ("auto", "textbook", "shared"):
        raise ModelError(f"solution: form is 'auto', 'textbook' or 'shared', not {form!r}")
    if form == "auto":
        form = "textbook" if len(system.u) <= TEXTBOOK_DOF else "shared"
    simplifier = _simplifier(system, max_ops, seconds)
    derived = {m: derive(system, method=m) for m in methods}
    forms = {m: steps.Forms(eom, simplifier, form) for m, eom in derived.items()}
    first = forms[methods[0]]
    common = [steps.kinematics(first)]
    if system.constraint_rows() or any(isinstance(j, FreeFlyer) for j in system.joints):
        common.append(steps.contacts(first))
    per_method = {m: STEPS[m](forms[m]) for m in methods}
    results = {m: forms[m].results for m in methods}
    all_steps = common + [s for m in methods for s in per_method[m]]
    if len(methods) > 1:
        all_steps.append(_comparison(derived, results, form))
    all_steps.append(steps.assembled(first))
    return Solution(title or "Equations of motion", system, all_steps, methods, form, simplifier.left)


def _simplifier(system: System, max_ops: int, seconds: float) -> Simplifier:
    return Simplifier([b.mass for b in system.bodies], max_ops, seconds)


def _from_a_file(expr: sp.Expr) -> bool:
    """Decimals, or rationals such as 44105/9007199254740992 (a file's numbers, with their round-off:
    a rotation from rpy angles is orthogonal to round-off only)."""
    return bool(expr.atoms(sp.Float)) or any(r.q > SIMPLE_DENOMINATOR for r in expr.atoms(sp.Rational))


def _comparison(derived: dict[str, EquationsOfMotion], results: dict, form: str) -> steps.Step:
    """Each method's M, b, g against the first's: exactly (the difference's trigonometric normal form
    is 0) in textbook form without decimal numbers or quaternions; else at random states through the
    intermediates (a file's numbers carry round-off, which no exact comparison survives, and a
    quaternion's unit norm is not part of the normal form)."""
    quaternion = any(j.group in ("SO3", "SE3") for j in next(iter(derived.values())).system.joints)
    exact = form == "textbook" and not quaternion and not any(
        _from_a_file(e) for r in results.values() for k in ("M", "b", "g") for e in sp.Matrix(r[k]))
    names = list(derived)
    first = names[0]
    expressions = {}
    for other in names[1:]:
        for key in ("M", "b", "g"):
            label = f"{key}[{other}] - {key}[{first}]"
            if exact:
                difference = sp.Matrix(results[other][key]) - sp.Matrix(results[first][key])
                if not is_zero(difference):
                    raise ModelError(f"solution: {label} is not zero (please report this model)")
                expressions[label] = sp.zeros(*difference.shape)
            else:
                expressions[label] = sp.Float(_largest_difference(derived[other], derived[first], key), 3)
    how = (
        "exactly: each difference, brought to a polynomial in the sines and cosines of the coordinates, "
        "is zero"
        if exact
        else (
            "at 5 random states, through each derivation's shared intermediates: the largest absolute "
            "difference of any entry is given"
        )
    )
    return steps.Step(
        "Comparison of the methods", f"M, b and g of {', '.join(names)} agree {how}.", expressions
    )


def _largest_difference(a: EquationsOfMotion, b: EquationsOfMotion, key: str) -> float:
    """max |a − b| over the entries at 5 valid random states (unit quaternions), parameters in
    [0.5, 1.5]; an error when it exceeds round-off relative to the entries' size."""
    system = a.system
    q, u, _ = random_states(system, 5, np.random.default_rng(0))
    parameters = samples([], system.parameters, 5)
    worst, scale = 0.0, 1.0
    for qk, uk, point in zip(q, u, parameters):
        point.update(zip(list(system.q) + list(system.u), [float(v) for v in (*qk, *uk)]))
        x = a.subexpressions.evaluate(list(a.compact[key]), point)
        y = b.subexpressions.evaluate(list(b.compact[key]), point)
        worst = max([worst] + [abs(p - r) for p, r in zip(x, y)])
        scale = max([scale] + [abs(p) for p in x])
    if worst > 1e-8 * scale:
        raise ModelError(
            f"solution: {key} of {a.method} and {b.method} differ by {worst:.3g} at random states "
            "(please report this model)"
        )
    return worst
