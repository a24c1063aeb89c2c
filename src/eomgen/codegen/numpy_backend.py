"""Python/NumPy source for the equations of motion.

A generated function `f(q, u, ud, p, out, sin, cos, sqrt)` evaluates, in order, the intermediates its
outputs need and writes the outputs into `out` (shape (rows, cols) + batch). The same function runs
with math's sin, cos, sqrt (one state, Python floats: fast per call) and numpy's (states along the
last axis: batched).

Generated names are ours (_q0, _u0, _ud0, _p0, _x0, ...): no text of the model (body, joint or
symbol names) is ever printed into the source, so running it can do nothing but arithmetic."""
from __future__ import annotations

from dataclasses import dataclass, replace

import sympy as sp

from ..subexpressions import Subexpressions

@dataclass(frozen=True)
class Syntax:
    """How one language writes a generated function."""

    header: str
    input: str
    assign: str
    out: str
    mirror: str
    footer: str
    power: str
    trig_q: str = "{f}({x})"  # sin / cos of q[k]; the extension reads them from arrays (sinq, cosq)


PYTHON = Syntax(header="def {name}(q, u, ud, p, out, sin, cos, sqrt):", input="    {var} = {arg}[{k}]",
                assign="    {var} = {expr}", out="    out[{i}, {j}] = {expr}",
                mirror="    out[{j}, {i}] = out[{i}, {j}]", footer="    return out", power="({b}**{e})")
C = Syntax(header="void {name}(const double *q, const double *u, const double *ud, const double *p, double *out)\n{{",
           input="    const double {var} = {arg}[{k}];", assign="    const double {var} = {expr};",
           out="    out[{ij}] = {expr};", mirror="    out[{ji}] = out[{ij}];", footer="}}", power="pow({b}, {e})")
C_TRIG = replace(C, header="void {name}(const double *q, const double *u, const double *ud, const double *p, "
                           "const double *sinq, const double *cosq, double *out)\n{{", trig_q="{f}q[{k}]")


class Printer:
    """A small printer for the expressions eomgen builds (sums, products, powers, sin, cos, sqrt),
    counting the floating-point operations it writes."""

    def __init__(self, names: dict[sp.Symbol, str], syntax: Syntax = PYTHON) -> None:
        self.names = names
        self.syntax = syntax
        self.ops = 0

    def __call__(self, e: sp.Expr) -> str:
        if e in self.names:  # symbols, and sin / cos of the inputs computed once up front
            return self.names[e]
        if e.is_Symbol:
            raise ValueError(f"symbol without a value: {e}")
        if e.is_Integer:
            return f"{int(e)}.0" if abs(int(e)) < 2**53 else repr(float(e))
        if e.is_Number:
            return repr(float(e))
        if e.is_Add:
            self.ops += len(e.args) - 1
            return "(" + " + ".join(self(a) for a in e.args) + ")"
        if e.is_Mul:
            args = list(e.args)
            sign = ""
            if args[0] == -1:
                sign, args = "-", args[1:]
            self.ops += len(args) - 1 + (sign == "-")
            return "(" + sign + "*".join(self(a) for a in args) + ")"
        if e.is_Pow:
            base, exp = e.args
            if exp == sp.Rational(1, 2):
                self.ops += 1
                return f"sqrt({self(base)})"
            if exp == -sp.Rational(1, 2):
                self.ops += 2
                return f"(1.0/sqrt({self(base)}))"
            if exp.is_Integer and 0 < int(exp) <= 4:
                self.ops += int(exp) - 1
                b = self(base)
                return "(" + "*".join([b] * int(exp)) + ")"
            if exp == -1:
                self.ops += 1
                return f"(1.0/{self(base)})"
            self.ops += 1
            return self.syntax.power.format(b=self(base), e=self(exp))
        if isinstance(e, (sp.sin, sp.cos)):
            self.ops += 1
            return f"{type(e).__name__}({self(e.args[0])})"
        raise ValueError(f"cannot generate code for {type(e).__name__}: {e}")


class FunctionWriter:
    """Writes functions of one set of sub-results; each definition is printed once for all of them."""

    def __init__(self, sub: Subexpressions, inputs: dict[str, list[sp.Symbol]], syntax: Syntax = PYTHON) -> None:
        self.sub, self.inputs, self.syntax = sub, inputs, syntax
        names = {s: f"_{arg}{k}" for arg, symbols in inputs.items() for k, s in enumerate(symbols)}
        self.trig = {f(s): f"_{f.__name__}_{arg}{k}" for arg, symbols in inputs.items()
                     for k, s in enumerate(symbols) for f in (sp.sin, sp.cos)}
        self.printer = Printer({**names, **self.trig}, syntax)
        self._lines: dict[sp.Symbol, tuple[str, int]] = {}
        self._q_index = {s: k for k, s in enumerate(inputs.get("q", []))}
        self.trig_indices: list[int] = []  # of the last function: the k with sin(q[k]) or cos(q[k]) used

    def _line(self, s: sp.Symbol) -> tuple[str, int]:
        if s not in self._lines:
            before = self.printer.ops
            text = self.syntax.assign.format(var=self.printer.names[s], expr=self.printer(self.sub.definitions[s]))
            self._lines[s] = (text, self.printer.ops - before)
        return self._lines[s]

    def source(self, name: str, outputs: sp.Basic, symmetric: bool = False) -> tuple[str, tuple, int]:
        """(source of function `name`(q, u, ud, p, out[, sin, cos, sqrt]), output shape, operation count).
        With `symmetric` only the upper triangle is computed and mirrored."""
        for k, s in enumerate(self.sub.definitions):  # intermediates added since the last call
            self.printer.names.setdefault(s, f"_x{k}")
        matrix = outputs if isinstance(outputs, sp.MatrixBase) else sp.Matrix([[outputs]])
        rows, cols = matrix.shape
        cells = [(i, j) for i in range(rows) for j in range(cols) if not symmetric or j >= i]
        exprs = [sp.sympify(matrix[i, j]) for i, j in cells]
        needed = self.sub.dependencies(exprs)
        used = set().union(*(self.sub.definitions[s].free_symbols for s in needed),
                           *(e.free_symbols for e in exprs))
        trig = set().union(*(self.sub.definitions[s].atoms(sp.sin, sp.cos) for s in needed),
                           *(e.atoms(sp.sin, sp.cos) for e in exprs)) & set(self.trig)
        syntax = self.syntax
        lines = [syntax.header.format(name=name)]
        for arg, symbols in self.inputs.items():
            lines += [syntax.input.format(var=f"_{arg}{k}", arg=arg, k=k) for k, s in enumerate(symbols) if s in used]
        ops = len(trig)
        for t in sorted(trig, key=lambda t: self.trig[t]):
            f, x = type(t).__name__, t.args[0]
            trig_q = syntax.trig_q if x in self._q_index else "{f}({x})"
            lines.append(syntax.assign.format(var=self.trig[t], expr=trig_q.format(f=f, x=self.printer.names[x],
                                                                                  k=self._q_index.get(x))))
        self.trig_indices = sorted({self._q_index[t.args[0]] for t in trig if t.args[0] in self._q_index})
        for s in needed:
            text, n = self._line(s)
            lines.append(text)
            ops += n
        for (i, j), e in zip(cells, exprs):
            if e != 0:
                before = self.printer.ops
                lines.append(syntax.out.format(i=i, j=j, ij=i * cols + j, expr=self.printer(e)))
                ops += self.printer.ops - before
                if symmetric and i != j:
                    lines.append(syntax.mirror.format(i=i, j=j, ij=i * cols + j, ji=j * cols + i))
        lines.append(syntax.footer.format())
        return "\n".join(lines) + "\n", (rows, cols), ops


def compile_function(source: str, label: str, name: str = "f"):
    """The function `name` defined by `source` (our own generated arithmetic, nothing else)."""
    namespace: dict = {}
    exec(compile(source, f"<eomgen {label}>", "exec"), namespace)
    return namespace[name]
