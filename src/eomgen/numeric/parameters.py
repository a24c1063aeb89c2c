"""Parameters by name, the same way in every output.

A model's parameters are its free symbols other than q, u and u̇ (masses, lengths, g, ...). Each is
named by `str(symbol)` and given by that name (or by the symbol itself) in a mapping
{name: value}: `f.M(q, params={"m_c": 1.0, "l": 0.7})` for the NumPy and C backends, and for a
written module; never by position (a sequence is refused). Positions appear only where generated
code reads the parameter vector p: it holds them sorted by name (p[k] is the value of `names[k]`),
which a written module lists as `PARAMETERS` and a C header as one comment per index. A function
asks only for the parameters it uses; an unknown name, a missing value, a value that is not a finite
real number (strings and bools included) or one that contradicts the symbol's assumptions (positive,
negative, nonnegative, nonpositive, nonzero, integer) is an error naming the parameters. `bind`
fixes the values once: the bound functions then take no params, but for the state parameters (the
motor currents, which `rhs` takes from its state x, and the time "t" of a prescribed motion, which
`rhs` takes from its t).

The vector and the actuator term are computed by one text (`printers.runtime.PARAMETERS`), run by
eomgen and written verbatim into generated modules, which need only numpy."""
from __future__ import annotations

import copy
from collections.abc import Iterable, Mapping

import numpy as np
import sympy as sp

from ..errors import ModelError
from ..functions import assumptions, sorted_parameters
from ..printers.runtime import runtime_namespace

_runtime = runtime_namespace()
parameter_vector, actuated = _runtime["_parameter_vector"], _runtime["_actuated"]


class Parameters:
    """The parameters of a model sorted by name: `names[k]` is p[k] of the generated code. The `state`
    ones (motor currents) are part of the state: `bind` leaves them to each call."""

    values: np.ndarray | None = None  # p, once every parameter is bound

    def __init__(self, symbols: Iterable[sp.Symbol], state: Iterable[sp.Symbol] = ()) -> None:
        self.symbols = sorted_parameters(symbols)
        #: the parameter names, sorted: p[k] is the value of names[k]
        self.names = tuple(str(s) for s in self.symbols)
        self.index = {**{n: k for k, n in enumerate(self.names)},
                      **{s: k for k, s in enumerate(self.symbols)}}  # by name or by symbol
        self.assumptions = {str(s): a for s in self.symbols if (a := assumptions(s))}
        self.rules = {self.index[n]: a for n, a in self.assumptions.items()}  # by position, for each call
        self.state = frozenset(self.index[s] for s in state if s in self.index)

    def vector(self, values: Mapping | None, used: Iterable[int]) -> list[float]:
        """p from {name or symbol: value}; only the k in `used` must be given (the others are 0.0)."""
        return parameter_vector(self.names, self.index, used, values, self.rules)

    def _named(self, values: Mapping | None, state: bool) -> list[str]:
        """The names of the state (or, with state False, the other) parameters `values` gives."""
        found = (self.index.get(key, self.index.get(str(key))) for key in values or {})
        return sorted(self.names[k] for k in found if k is not None and (k in self.state) == state)

    def with_state(self, values: Mapping | None, state: Mapping[sp.Symbol, float]) -> dict:
        """`values` and the values of the state parameters `state` gives (motor currents from x, the time t
        of a prescribed motion from the integrator), which `values` may not give."""
        if values is not None and not isinstance(values, Mapping):
            self.vector(values, ())  # refused as in every call
        given = {str(s) for s in state}
        if named := [n for n in self._named(values, state=True) if n in given]:
            what = ("the time of a prescribed motion, taken from the integrator's t" if named == ["t"]
                    else "motor currents, taken from the state x")
            raise ModelError(f"params: {named} are {what}: leave them out")
        return {**(values or {}), **{s: v for s, v in state.items() if s in self.index}}

    def bind(self, values: Mapping) -> BoundParameters:
        """The same parameters with every value but the state ones fixed."""
        if isinstance(values, Mapping) and (named := self._named(values, state=True)):
            raise ModelError(f"bind: {named} are motor currents or the time, part of the state: give them "
                             "per call (rhs takes them from x and t), not to bind")
        return BoundParameters(self, self.vector(values, set(range(len(self.names))) - self.state))


class BoundParameters(Parameters):
    """Parameters whose values are fixed: `vector` returns them, with the state parameters (motor
    currents) given in each call; it refuses the others."""

    def __init__(self, parameters: Parameters, p: list[float]) -> None:
        vars(self).update(vars(parameters))  # names, index, rules, state
        self.unbound = parameters
        self.bound = np.array(p, dtype=float)
        self.bound.flags.writeable = False
        self.values = None if self.state else self.bound  # the C backend passes `values` as they are
        self._from_call = np.isin(np.arange(len(self.names)), list(self.state))

    def vector(self, values: Mapping | None, used: Iterable[int]) -> np.ndarray:
        if values is not None and (not isinstance(values, Mapping) or self._named(values, state=False)):
            raise ModelError("params: these functions have their parameter values bound (bind or "
                             "codegen(params=...)); call them without params (but for motor currents), "
                             "or bind new values")
        needed = self.state.intersection(used)
        if values is None and not needed:
            return self.bound
        return np.where(self._from_call, self.unbound.vector(values, needed), self.bound)

    def bind(self, values: Mapping) -> BoundParameters:
        return self.unbound.bind(values)


def bind(functions, values: Mapping):
    """A copy of numeric `functions` whose calls take no params: the values are fixed once (every
    parameter but the motor currents, by name; see the module doc). The copy shares the generated
    functions."""
    bound = copy.copy(functions)
    bound.parameters = functions.parameters.bind(values)
    return bound
