"""The numeric facade over a printed catalogue: its functions by key, printed on first request, with the
parameters by name (or bound once), one state or N states along axis 0, and `out=`.

    f.call(key, q, u, ud, params, out)     the catalogue function `key` at (q, u, u̇)
    f.generated(key)                        its printed form (source, shape, operations, callable)
    f.reference(key, ...)                   the same expressions in mpmath, the high-precision reference
"""
from __future__ import annotations

from collections.abc import Callable, Mapping
from contextlib import nullcontext

import numpy as np

from ..errors import ModelError
from ..functions import Catalogue
from ..printers.python import compile_function
from ..printers.runtime import mpmath_functions, runtime_namespace
from ..printers.walker import Generated, writer
from .lines import check_ends
from .parameters import Parameters, bind

_call = runtime_namespace()["_call"]


def written(result: np.ndarray, out: np.ndarray | None, **inputs) -> np.ndarray:
    """`result`, copied into `out` when given: a writeable C-contiguous float64 array of its shape (a
    batch reuses its buffers; the C backend writes there directly) that shares no memory with the
    `inputs` {name: q, u or ud} (the C backend would write over states it has not read yet), else a
    ModelError naming out."""
    if out is None:
        return result
    for name, x in inputs.items():
        if isinstance(out, np.ndarray) and isinstance(x, np.ndarray) and np.shares_memory(out, x):
            raise ModelError(f"out: shares memory with the input {name}; give an output array apart from "
                             "the inputs")
    if not isinstance(out, np.ndarray):
        got = type(out).__name__
    elif out.dtype != np.float64 or out.shape != result.shape or not out.flags.c_contiguous \
            or not out.flags.writeable:
        flags = out.flags
        kind = " non-contiguous" if not flags.c_contiguous else " read-only" if not flags.writeable else ""
        got = f"a{kind} {out.dtype} array of shape {out.shape}"
    else:
        out[...] = result
        return out
    raise ModelError(f"out: expected a writeable C-contiguous float64 array of shape {result.shape}, "
                     f"got {got}")


class Functions:
    """The functions of a catalogue, printed as Python on first request (`generated`) and evaluated by
    key (`call`); `line_loads` are checked where an output is not finite (`lines.check_ends`)."""

    def __init__(self, catalogue: Catalogue, parameters: Parameters, line_loads: list = ()) -> None:
        self.catalogue = catalogue
        self.nq, self._nu = len(catalogue.inputs["q"]), len(catalogue.inputs["u"])
        self.parameters = parameters
        self.params = parameters.symbols  # p[k] of the generated code, sorted by name
        self.line_loads = list(line_loads)
        self._writer = writer(catalogue)
        self.functions: dict[str, Generated] = {}
        self.cache: dict = {}  # what numeric algorithms keep per parameter values (row sizes, ...)
        self._python: dict[str, Callable] = {}  # Python versions for mpmath references
        self._print(catalogue.eager)

    def _print(self, keys: list[str]) -> None:
        """Print and compile the functions `keys` (Python: one function each)."""
        for key in keys:
            source, shape, ops = self._writer.function("f", self.catalogue.printable(key))
            self.functions[key] = Generated(source, shape, ops, compile_function(source, key))

    def generated(self, key: str) -> Generated:
        """The printed function `key` of the catalogue, printed on first request."""
        if key not in self.functions:
            self._print([key])
        return self.functions[key]

    def generate(self, keys: list[str]) -> None:
        """Print the functions `keys` now, those not printed yet together (the C backend: in one
        extension module, one compile instead of one per function asked for later)."""
        self._print([k for k in dict.fromkeys(keys) if k not in self.functions])

    @property
    def sources(self) -> dict[str, str]:
        """The source of each generated function, by key."""
        return {k: f.source for k, f in self.functions.items()}

    @property
    def ops(self) -> dict[str, int]:
        """Floating-point operations of each generated function (after sharing the intermediates)."""
        return {k: f.ops for k, f in self.functions.items()}

    @property
    def multiplications(self) -> dict[str, int]:
        """Multiplications written in each generated function (the '*' of its source, powers excluded)."""
        return {k: f.source.count("*") - 2 * f.source.count("**") for k, f in self.functions.items()}

    def parameter_vector(self, params: Mapping | None, key: str) -> list[float] | np.ndarray:
        """The parameter vector p for function `key` (the bound values, or those it uses from params)."""
        return self.parameters.vector(params, self.generated(key).params_used)

    def bind(self, params: Mapping):
        """The same functions with the parameter values fixed once ({name: value}, every parameter but
        the motor currents, which are state): their calls take no params."""
        return bind(self, params)

    def call(self, key: str, q, u=None, ud=None, params=None, out=None) -> np.ndarray:
        """Evaluate generated function `key` at q, u, u̇ (one state, or N states along axis 0); into
        `out` when given (see `written`)."""
        f = self.generated(key)
        with np.errstate(divide="ignore", invalid="ignore") if self.line_loads else nullcontext():
            p = self.parameter_vector(params, key)
            result = _call(f.function, f.shape, self.nq, self._nu, q, u, ud, p)
        return written(check_ends(self, result, q, params), out, q=q, u=u, ud=ud)

    def reference(self, key: str, q, u=None, ud=None, params=None, digits: int = 50) -> np.ndarray:
        """The same generated expressions evaluated in mpmath with `digits` significant digits (one
        state; the constants are the float64 numbers of the model): the high-precision reference for
        measuring float64 round-off."""
        import mpmath

        shape = self.generated(key).shape
        if key not in self._python:  # the Python text runs with any number type
            self._python[key] = compile_function(self._writer.function("f", self.catalogue[key])[0], key)
        with mpmath.workdps(digits):
            def mp(x, n):
                x = np.zeros(n) if x is None else np.asarray(x, dtype=float)
                return [mpmath.mpf(float(v)) for v in x]
            out, m = np.zeros(shape, dtype=object), mpmath_functions()
            self._python[key](mp(q, self.nq), mp(u, self._nu), mp(ud, self._nu),
                              [mpmath.mpf(v) for v in self.parameter_vector(params, key)], out, m.sin, m.cos,
                              m.sqrt, m)
            return out
