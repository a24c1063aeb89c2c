"""The arguments of `eg.linearize` read and checked where they enter: the inputs r (actuated efforts and
parameters by name) and the operating point (q0, speeds, efforts τ_a0, motor currents i0)."""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass, replace

import numpy as np
import sympy as sp

from ..errors import ModelError
from ..model.system import System
from ..state import unit_quaternions
from .dual import Algebra


def effort_names(system: System) -> list[str]:
    """The names of the actuated efforts τ_a, one per row of S: 'tau_<joint>' ('tau_<speed>' for a joint
    with several)."""
    names = []
    for b in system.bodies:
        if b.index is not None and b.joint.actuated:
            k = b.joint.efforts
            names += (
                [f"tau_{b.joint.name}"] if k == 1 else [f"tau_{u}" for u in system.u[b.index : b.index + k]]
            )
    return names


@dataclass
class Inputs:
    """The chosen inputs: `efforts` (indices into τ_a) and `parameters` (symbols), with their names."""

    efforts: list[int]
    parameters: list[sp.Symbol]
    names: list[str]


def inputs(system: System, parameters: list[sp.Symbol], currents: list, chosen) -> Inputs:
    """Inputs by name (or symbol): actuated efforts 'tau_<joint>' and parameters; default: the efforts."""
    efforts = effort_names(system)
    if chosen is None:
        return Inputs(list(range(len(efforts))), [], efforts)
    chosen = [chosen] if isinstance(chosen, (str, sp.Symbol)) else chosen
    if not isinstance(chosen, Sequence):
        raise ModelError(f"linearize: inputs: expected a list of names, got {type(chosen).__name__}")
    by_name = {str(p): p for p in parameters}
    out = Inputs([], [], [])
    for x in chosen:
        name = str(x) if isinstance(x, (str, sp.Symbol)) else None
        if name in out.names:
            raise ModelError(f"linearize: inputs: {name!r} is named twice")
        if name in efforts:
            out.efforts.append(efforts.index(name))
        elif name in {str(i) for i in currents}:
            raise ModelError(
                f"linearize: inputs: {name!r} is a motor current, a state; its voltage is an input"
            )
        elif name in by_name:
            out.parameters.append(by_name[name])
        else:
            raise ModelError(
                f"linearize: inputs: unknown input {x!r}; the inputs are the actuated efforts "
                f"{efforts} and the parameters {sorted(set(by_name) - set(map(str, currents)))}"
            )
        out.names.append(name)
    return out


@dataclass
class OperatingPoint:
    """q0 (nq), the independent speeds, τ_a0 and the currents i0; `full`: all the speeds where they were
    given (to be checked against the constraints)."""

    q: np.ndarray
    speeds: np.ndarray
    efforts: np.ndarray
    currents: np.ndarray
    full: np.ndarray | None = None


def operating_point(
    system: System, speeds: list, every: list, currents: list, op_point, algebra: Algebra
) -> OperatingPoint:
    """(q0, speeds[, τ_a0[, i0]]) arrays, the independent `speeds` or `every` speed, or a mapping
    {name: value} (every coordinate; the independent speeds, efforts and currents default to 0); numbers,
    or sympy values when symbolic. Quaternions made unit."""
    n = [system.nq, len(speeds), system.S.shape[0], len(currents)]
    efforts = effort_names(system)
    if isinstance(op_point, Mapping):
        names = [[str(q) for q in system.q], [str(s) for s in speeds], efforts, [str(i) for i in currents]]
        given = {str(k): v for k, v in op_point.items()}
        unknown = sorted(set(given) - {x for part in names for x in part})
        missing = [x for x in names[0] if x not in given]
        if unknown or missing:
            raise ModelError(
                f"linearize: op_point: {'unknown names ' + str(unknown) if unknown else ''}"
                f"{'; ' if unknown and missing else ''}"
                f"{'coordinates missing: ' + str(missing) if missing else ''}; give the coordinates "
                f"{names[0]}, the speeds {names[1]}, efforts {names[2]}, currents {names[3]}"
            )
        parts = [[given.get(x, 0) for x in part] for part in names]
    elif isinstance(op_point, (tuple, list)) and 2 <= len(op_point) <= 4:
        parts = list(op_point) + [[0] * k for k in n[len(op_point) :]]
        if np.size(parts[1]) == len(every) != len(speeds):
            full = _values(parts[1], len(every), "the speeds", algebra)
            return replace(
                operating_point(
                    system,
                    speeds,
                    every,
                    currents,
                    [parts[0], full[[every.index(s) for s in speeds]], *parts[2:]],
                    algebra,
                ),
                full=full,
            )
    else:
        raise ModelError(
            "linearize: op_point: expected (q0, speeds[, tau_a0[, currents]]) or a mapping "
            f"{{name: value}}, got {type(op_point).__name__}"
        )
    what = [
        "q0 (the coordinates)",
        f"the speeds {[str(s) for s in speeds]} (or all {len(every)})",
        f"tau_a0 (the efforts {efforts})",
        f"the motor currents {[str(i) for i in currents]}",
    ]
    values = [_values(x, k, w, algebra) for x, k, w in zip(parts, n, what)]
    if not algebra.symbolic:
        values[0] = unit_quaternions(system, values[0])
    return OperatingPoint(*values)


def _values(x, n: int, what: str, algebra: Algebra) -> np.ndarray:
    """n numbers (sympy values when symbolic); strings (which numpy and sympy would parse) and booleans
    refused."""
    try:
        if any(isinstance(v, (str, bytes, bool, np.bool_)) for v in np.ravel(np.asarray(x, dtype=object))):
            raise TypeError

        a = algebra.array(x).reshape(-1) if np.ndim(x) else algebra.array([x]).reshape(-1)
    except (TypeError, ValueError, sp.SympifyError):
        raise ModelError(f"linearize: op_point: {what}: expected numbers, got {x!r}") from None
    if a.shape != (n,):
        raise ModelError(f"linearize: op_point: {what}: expected {n} values, got shape {np.shape(x)}")
    if not algebra.symbolic and not np.isfinite(a).all():
        raise ModelError(f"linearize: op_point: {what}: values must be finite")
    return a
