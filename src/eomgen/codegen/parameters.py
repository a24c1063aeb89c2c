"""Parameters by name, the same way in every output.

A model's parameters are its free symbols other than q, u and u̇ (masses, lengths, g, ...). Each is
named by `str(symbol)` and given by that name (or by the symbol itself) in a mapping
{name: value}: `f.M(q, params={"m_c": 1.0, "l": 0.7})` for the NumPy and C backends, and for a
written module. Positions are used only where the order is written out: the parameter vector p of
generated code holds them sorted by name (p[k] is the value of `names[k]`), which a written module
lists as `PARAMETERS` (there a sequence of that length is also accepted) and a C header as one
comment per index. A function asks only for the parameters it uses; an unknown name, a missing
value or a value that is not a finite number is an error naming the parameters. `bind` fixes the
values once: the bound functions then take no params.

The vector and the actuator term are computed by one text (`RUNTIME`), run by eomgen and written
verbatim into generated modules, which need only numpy."""
from __future__ import annotations

import copy
import math
from collections.abc import Iterable, Mapping

import numpy as np
import sympy as sp

from ..errors import ModelError

RUNTIME = '''
def _parameter_vector(names, index, used, values, positional=False):
    """p (p[k]: the value of names[k]; index maps a name or symbol to k) from a mapping {name: value},
    or, with `positional`, a sequence in the order of names; the k outside `used` may be left out (0.0)."""
    if values is None:
        values = {}
    if not isinstance(values, Mapping):
        if not positional or isinstance(values, (str, bytes)) or not hasattr(values, "__len__"):
            raise _Error("params: expected a mapping {name: value}, got %s" % type(values).__name__)
        if len(values) != len(names):
            raise _Error("params: expected %d values in the order of PARAMETERS %s, got %d"
                         % (len(names), list(names), len(values)))
        values = dict(zip(names, values))
    p = [0.0] * len(names)
    given, unknown, bad = set(), [], []
    for key, value in values.items():
        k = index.get(key)
        if k is None:
            k = index.get(str(key))
            if k is None:
                unknown.append(str(key))
                continue
        try:
            p[k] = float(value)
        except (TypeError, ValueError):
            p[k] = math.nan
        if not math.isfinite(p[k]):
            bad.append(names[k])
        given.add(k)
    if unknown:
        raise _Error("params: unknown parameters %s; the parameters are %s" % (unknown, list(names)))
    if not given.issuperset(used):
        missing = [names[k] for k in sorted(set(used) - given)]
        raise _Error("params: values missing for the parameters %s" % missing)
    if bad:
        raise _Error("params: the values of %s are not finite numbers" % bad)
    return p


def _actuated(h, tau_a, S):
    """h + Sᵀ τ_a, τ_a with one value per actuated joint (per state, or one for all states)."""
    if tau_a is None:
        return h
    tau_a = numpy.asarray(tau_a, dtype=float)
    if tau_a.shape[-1:] != (S.shape[0],) or not numpy.all(numpy.isfinite(tau_a)):
        raise _Error("tau_a: expected %d finite values (one per actuated joint), got shape %s"
                     % (S.shape[0], tau_a.shape))
    return h + tau_a @ S
'''


def _namespace() -> dict:
    namespace = {"math": math, "numpy": np, "Mapping": Mapping, "_Error": ModelError}
    exec(RUNTIME, namespace)  # eomgen's own fixed text
    return namespace


_runtime = _namespace()
parameter_vector, actuated = _runtime["_parameter_vector"], _runtime["_actuated"]


class Parameters:
    """The parameters of a model sorted by name: `names[k]` is p[k] of the generated code."""

    values: np.ndarray | None = None  # p, once bound

    def __init__(self, symbols: Iterable[sp.Symbol]) -> None:
        self.symbols = sorted(symbols, key=str)
        self.names = tuple(str(s) for s in self.symbols)
        twice = sorted({n for n in self.names if self.names.count(n) > 1})
        if twice:
            raise ModelError(f"parameters {twice} each name two different symbols (other assumptions): "
                             "parameters are given by name, so their names must differ")
        self.index = {**{n: k for k, n in enumerate(self.names)},
                      **{s: k for k, s in enumerate(self.symbols)}}  # by name or by symbol

    def vector(self, values: Mapping | None, used: Iterable[int]) -> list[float]:
        """p from {name or symbol: value}; only the k in `used` must be given (the others are 0.0)."""
        return parameter_vector(self.names, self.index, used, values)

    def bind(self, values: Mapping) -> BoundParameters:
        """The same parameters with every value fixed."""
        return BoundParameters(self, self.vector(values, range(len(self.names))))


class BoundParameters(Parameters):
    """Parameters whose values are fixed: `vector` returns them and refuses new ones."""

    def __init__(self, parameters: Parameters, p: list[float]) -> None:
        self.symbols, self.names, self.index = parameters.symbols, parameters.names, parameters.index
        self.values = np.array(p, dtype=float)
        self.values.flags.writeable = False

    def vector(self, values: Mapping | None, used: Iterable[int]) -> np.ndarray:
        if values is not None:
            raise ModelError("params: these functions have their parameter values bound (bind or "
                             "codegen(params=...)); call them without params, or bind new values")
        return self.values

    def bind(self, values: Mapping) -> BoundParameters:
        return Parameters(self.symbols).bind(values)


def bind(functions, values: Mapping):
    """A copy of numeric `functions` whose calls take no params: the values are fixed once (every
    parameter, by name; see the module doc). The copy shares the generated functions."""
    bound = copy.copy(functions)
    bound.parameters = functions.parameters.bind(values)
    return bound
