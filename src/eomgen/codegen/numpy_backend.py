"""NumPy backend: each requested quantity becomes a Python function that evaluates the needed
intermediates in order and fills the output array.

Generated names are ours (_q0, _u0, _p0, _x0, ...): no text of the model (body, joint or symbol
names) is ever printed into the source, so exec'ing it can run nothing but arithmetic."""
from __future__ import annotations

import numpy as np
import sympy as sp
from sympy.printing.numpy import NumPyPrinter

from ..subexpressions import Subexpressions


class _Printer(NumPyPrinter):
    def _print_Float(self, expr):
        return repr(float(expr))


class FunctionWriter:
    """Prints functions of one set of sub-results; each definition is printed once for all of them."""

    def __init__(self, sub: Subexpressions, inputs: dict[str, list[sp.Symbol]]) -> None:
        self.sub, self.inputs = sub, inputs
        self.rename = {s: sp.Symbol(f"_{arg}{k}") for arg, symbols in inputs.items()
                       for k, s in enumerate(symbols)}
        self.printer = _Printer()
        self._lines: dict[sp.Symbol, str] = {}

    def _line(self, s: sp.Symbol) -> str:
        if s not in self._lines:
            self._lines[s] = f"    {self.rename[s]} = {self.printer.doprint(self.sub.definitions[s].xreplace(self.rename))}"
        return self._lines[s]

    def source(self, name: str, outputs: sp.Basic) -> str:
        """Source of `def name(q, u, p)` returning `outputs` (a matrix, or a scalar expression)."""
        for k, s in enumerate(self.sub.definitions):  # intermediates added since the last call
            self.rename.setdefault(s, sp.Symbol(f"_x{k}"))
        return function_source(self, name, outputs)


def function_source(writer: FunctionWriter, name: str, outputs: sp.Basic) -> str:
    matrix = isinstance(outputs, sp.MatrixBase)
    exprs = list(outputs) if matrix else [outputs]
    rename, printer = writer.rename, writer.printer
    needed = writer.sub.dependencies(exprs)
    used = set().union(*(writer.sub.definitions[s].free_symbols for s in needed),
                       *(sp.sympify(e).free_symbols for e in exprs))
    lines = [f"def {name}({', '.join(writer.inputs)}):"]
    for arg, symbols in writer.inputs.items():
        lines += [f"    _{arg}{k} = {arg}[{k}]" for k, s in enumerate(symbols) if s in used]
    lines += [writer._line(s) for s in needed]
    values = [printer.doprint(sp.sympify(e).xreplace(rename)) for e in exprs]
    unknown = set().union(*(sp.sympify(e).free_symbols for e in exprs)) - set(rename)
    if unknown:
        raise ValueError(f"{name}: symbols without a value: {sorted(map(str, unknown))}")
    if matrix:
        rows, cols = outputs.shape
        lines.append(f"    out = numpy.zeros(({rows}, {cols}))")
        for k, v in enumerate(values):
            if v != "0":
                lines.append(f"    out[{k // cols}, {k % cols}] = {v}")
        lines.append("    return out")
    else:
        lines.append(f"    return {values[0]}")
    return "\n".join(lines) + "\n"


def compile_function(source: str, name: str):
    namespace = {"numpy": np}
    exec(compile(source, f"<eomgen {name}>", "exec"), namespace)  # our own generated arithmetic only
    return namespace[name]
