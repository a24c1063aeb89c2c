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


def function_source(name: str, outputs: sp.Basic, sub: Subexpressions,
                    inputs: dict[str, list[sp.Symbol]]) -> str:
    """Source of `def name(q, u, p)` returning `outputs` (a matrix, or a scalar expression)."""
    matrix = isinstance(outputs, sp.MatrixBase)
    exprs = list(outputs) if matrix else [outputs]
    rename: dict[sp.Symbol, sp.Symbol] = {}
    lines = [f"def {name}({', '.join(inputs)}):"]
    for arg, symbols in inputs.items():
        for k, s in enumerate(symbols):
            rename[s] = sp.Symbol(f"_{arg}{k}")
            lines.append(f"    _{arg}{k} = {arg}[{k}]")
    printer = _Printer()
    for k, s in enumerate(sub.dependencies(exprs)):
        rename[s] = sp.Symbol(f"_x{k}")
        lines.append(f"    _x{k} = {printer.doprint(sub.definitions[s].xreplace(rename))}")
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
