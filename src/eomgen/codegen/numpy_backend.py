"""Python/NumPy source for the equations of motion.

A generated function `f(q, u, ud, p, out, sin, cos, sqrt, m)` evaluates, in order, the intermediates its
outputs need and writes the outputs into `out` (shape (rows, cols) + batch). It runs with math's sin,
cos, sqrt and the runtime's `_Scalar` as `m` (one state, Python floats: fast per call), with numpy's and
the numpy module (states along the last axis: batched) or with mpmath's (the reference); `m` holds the
other functions under numpy's names (m.tan, m.arctan2, m.where, ...). Every branch of a Piecewise is
evaluated: where math raises (a pole, off the domain), the runtime evaluates the state again in numpy.

Generated names are ours (_q0, _u0, _ud0, _p0, _x0, ...): no text of the model (body, joint or
symbol names) is ever printed into the source, so running it can do nothing but arithmetic."""
from __future__ import annotations

from dataclasses import dataclass, replace
from functools import reduce

import sympy as sp

from ..errors import ModelError
from ..subexpressions import Subexpressions

# sympy's functions printed as calls of one name (Min and Max: nested, two arguments a call)
C_FUNCTIONS = {**{k: k for k in ("sin", "cos", "tan", "exp", "log", "asin", "acos", "atan", "atan2", "sinh",
                                  "cosh", "tanh")}, "Abs": "fabs", "Min": "fmin", "Max": "fmax"}
NUMPY_FUNCTIONS = {**{k: f"m.{f}" for k, f in C_FUNCTIONS.items()}, "sin": "sin", "cos": "cos",
                   "asin": "m.arcsin", "acos": "m.arccos", "atan": "m.arctan", "atan2": "m.arctan2"}
SUPPORTED = sorted({*C_FUNCTIONS, "sqrt", "Pow", "sign", "Heaviside", "Piecewise"})


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
    select: str  # Piecewise: value {a} where {c}, else {b}
    sign: str
    heaviside: str  # of {x}, {h} at 0
    logic: tuple[str, str, str]  # and, or (infix), not ({c})
    nan: str  # a Piecewise's value where no condition holds
    functions: dict[str, str]  # sympy's function name: the name printed
    trig_q: str = "{f}({x})"  # sin / cos of q[k]; the extension reads them from arrays (sinq, cosq)


PYTHON = Syntax(header="def {name}(q, u, ud, p, out, sin, cos, sqrt, m):", input="    {var} = {arg}[{k}]",
                assign="    {var} = {expr}", out="    out[{i}, {j}] = {expr}",
                mirror="    out[{j}, {i}] = out[{i}, {j}]", footer="    return out",
                power="m.power({b}, {e})",
                select="m.where({c}, {a}, {b})", sign="m.sign({x})", heaviside="m.heaviside({x}, {h})",
                logic=("&", "|", "m.logical_not({c})"), nan="m.nan", functions=NUMPY_FUNCTIONS)
C = Syntax(header="void {name}(const double *q, const double *u, const double *ud, const double *p, double *out)\n{{",
           input="    const double {var} = {arg}[{k}];", assign="    const double {var} = {expr};",
           out="    out[{ij}] = {expr};", mirror="    out[{ji}] = out[{ij}];", footer="}}",
           power="pow({b}, {e})",
           select="({c} ? {a} : {b})", sign="(({x} > 0) ? 1.0 : ({x} < 0) ? -1.0 : 0.0 * {x})",
           heaviside="(({x} > 0) ? 1.0 : ({x} < 0) ? 0.0 : {h} + 0.0 * {x})", logic=("&&", "||", "(!{c})"),
           nan="NAN", functions=C_FUNCTIONS)
C_TRIG = replace(C, header="void {name}(const double *q, const double *u, const double *ud, const double *p, "
                           "const double *sinq, const double *cosq, double *out)\n{{", trig_q="{f}q[{k}]")


class Printer:
    """A small printer for the expressions eomgen builds (sums, products, powers, the elementary
    functions, Min, Max, sign, Heaviside, Piecewise), counting the floating-point operations it writes
    (a function call or a comparison is one)."""

    def __init__(self, names: dict[sp.Symbol, str], syntax: Syntax = PYTHON) -> None:
        self.names = names
        self.syntax = syntax
        self.ops = 0

    def __call__(self, e: sp.Basic) -> str:
        if e in self.names:  # symbols, and sin / cos of the inputs computed once up front
            return self.names[e]
        if e.is_Symbol:
            raise ModelError(f"cannot generate code for the symbol {e}: it is no coordinate, speed, "
                             "acceleration or parameter")
        if e.is_Number and e.is_finite and e.is_extended_real:
            if e.is_Integer:
                return f"{int(e)}.0" if abs(int(e)) < 2**53 else repr(float(e))
            return repr(float(e))
        if e.is_NumberSymbol:  # pi, E (exp(1)), GoldenRatio, ...: their float value
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
            return self._power(*e.args)
        name = type(e).__name__
        syntax = self.syntax
        if name in syntax.functions:
            f, args = syntax.functions[name], [self(a) for a in e.args]
            if isinstance(e, (sp.Min, sp.Max)):  # fmin(fmin(a, b), c)
                self.ops += len(args) - 1
                return reduce(lambda x, y: f"{f}({x}, {y})", args)
            self.ops += 1
            return f"{f}({', '.join(args)})"
        if isinstance(e, sp.sign):
            self.ops += 1
            return syntax.sign.format(x=self(e.args[0]))
        if isinstance(e, sp.Heaviside):
            self.ops += 1
            return syntax.heaviside.format(x=self(e.args[0]), h=self(e.args[1]))
        if isinstance(e, sp.Piecewise):
            return self._piecewise(e)
        raise ModelError(f"cannot generate code for {name}: {e} (the printers cover {', '.join(SUPPORTED)})")

    def _power(self, base: sp.Expr, exp: sp.Expr) -> str:
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

    def _piecewise(self, e: sp.Piecewise) -> str:
        """Nested selections, the last condition innermost; nan where no condition holds."""
        *rest, (value, cond) = e.args
        if cond is sp.true:
            text = self(value)
        else:
            rest.append((value, cond))
            text = self.syntax.nan
        for value, cond in reversed(rest):
            self.ops += 1
            text = self.syntax.select.format(c=self._condition(cond), a=self(value), b=text)
        return text

    def _condition(self, c: sp.Basic) -> str:
        """A relation (<, <=, >, >=, ==, !=) or And / Or / Not of them."""
        if isinstance(c, sp.core.relational.Relational):
            self.ops += 1
            return f"({self(c.lhs)} {c.rel_op} {self(c.rhs)})"
        if isinstance(c, (sp.And, sp.Or)):
            self.ops += len(c.args) - 1
            op = self.syntax.logic[isinstance(c, sp.Or)]
            return "(" + f" {op} ".join(self._condition(a) for a in c.args) + ")"
        if isinstance(c, sp.Not):
            self.ops += 1
            return self.syntax.logic[2].format(c=self._condition(c.args[0]))
        raise ModelError(f"cannot generate code for the condition {type(c).__name__}: {c} (relations and "
                         "And, Or, Not of them are covered)")


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
        """(source of function `name`(q, u, ud, p, out[, sin, cos, sqrt, m]), output shape, operation count).
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
    exec(compile(source, f"<eomgen {ascii(label)}>", "exec"), namespace)
    return namespace[name]
