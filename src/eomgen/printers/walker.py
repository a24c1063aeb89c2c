"""The expression walker every printer shares (`Printer`, `FunctionWriter`): a catalogue function as
source text.

A generated function `f(q, u, ud, p, out, sin, cos, sqrt, m)` evaluates, in order, the intermediates its
outputs need and writes the outputs into `out` (shape (rows, cols) + batch), each output as soon as the
intermediates it reads are known (short lives: faster to compile and to run). A long C function is
written as parts of about `SEGMENT` operations, called in turn (see `FunctionWriter._parts`). It runs with
math's sin, cos, sqrt and the runtime's `_Scalar` as `m` (one state, Python floats: fast per call), with numpy's and
the numpy module (states along the last axis: batched) or with mpmath's (the reference); `m` holds the
other functions under numpy's names (m.tan, m.arctan2, m.where, ...). Every branch of a Piecewise is
evaluated: where math raises (a pole, off the domain), the runtime evaluates the state again in numpy.

Generated names are ours (_q0, _u0, _ud0, _p0, _x0, ...): no text of the model (body, joint or
symbol names) is ever printed into the source, so running it can do nothing but arithmetic."""
from __future__ import annotations

import itertools
import re
from collections.abc import Callable
from dataclasses import dataclass, field
from functools import reduce

import sympy as sp

from ..engine import collection_paused
from ..errors import ModelError
from ..functions import Catalogue, Function
from ..subexpressions import Subexpressions
from .syntax import LANES, NAMES, NOINLINE, PYTHON, SEGMENT, SUPPORTED, Syntax


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
            return self.syntax.sqrt.format(x=self(base))
        if exp == -sp.Rational(1, 2):
            self.ops += 2
            return f"(1.0/{self.syntax.sqrt.format(x=self(base))})"
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
            op, parts = self.syntax.logic[isinstance(c, sp.Or)], [self._condition(a) for a in c.args]
            if "{a}" in op:  # a call of two arguments, nested
                return reduce(lambda x, y: op.format(a=x, b=y), parts)
            return "(" + f" {op} ".join(parts) + ")"
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
        self._inputs = frozenset(names)
        self._named = 0  # intermediates named _x<k> so far
        self._reads: dict[sp.Symbol, tuple[frozenset, frozenset]] = {}
        self._q_index = {s: k for k, s in enumerate(inputs.get("q", []))}
        self.trig_indices: list[int] = []  # of the last function: the k with sin(q[k]) or cos(q[k]) used

    def _read(self, e: sp.Basic, symbols: frozenset | None = None) -> tuple[frozenset, frozenset]:
        """(the inputs an expression reads, the sin and cos of inputs in it); `symbols`: its free symbols
        where known. Only an expression that reads an input is searched for sin and cos."""
        used = (e.free_symbols if symbols is None else symbols) & self._inputs
        if not used:
            return frozenset(), frozenset()
        trig, stack = set(), [e]
        while stack:
            x = stack.pop()
            if x in self.trig:
                trig.add(x)
            else:
                stack.extend(x.args)
        return frozenset(used), frozenset(trig)

    def _reads_of(self, s: sp.Symbol) -> tuple[frozenset, frozenset]:
        """`_read` of an intermediate's definition, once."""
        if s not in self._reads:
            self._reads[s] = self._read(self.sub.definitions[s], self.sub.reads(s))
        return self._reads[s]

    def _line(self, s: sp.Symbol) -> tuple[str, int]:
        if s not in self._lines:
            before = self.printer.ops
            text = self.syntax.assign.format(var=self.printer.names[s], expr=self.printer(self.sub.definitions[s]))
            self._lines[s] = (text, self.printer.ops - before)
        return self._lines[s]

    def source(self, name: str, outputs: sp.Basic, symmetric: bool = False) -> tuple[str, tuple, int]:
        """(source of function `name`(q, u, ud, p, out[, sin, cos, sqrt, m]), output shape, operation count).
        With `symmetric` only the upper triangle is computed and mirrored."""
        names = self.printer.names
        for k, s in enumerate(itertools.islice(self.sub.definitions, self._named, None), self._named):
            names.setdefault(s, f"_x{k}")  # intermediates added since the last call
        self._named = len(self.sub.definitions)
        matrix = outputs if isinstance(outputs, sp.MatrixBase) else sp.Matrix([[outputs]])
        rows, cols = matrix.shape
        cells = [(i, j) for i in range(rows) for j in range(cols) if not symmetric or j >= i]
        exprs = [sp.sympify(matrix[i, j]) for i, j in cells]
        needed = self.sub.dependencies(exprs)
        reads = [*map(self._reads_of, needed), *map(self._read, exprs)]
        used = set().union(*(symbols for symbols, _ in reads))
        trig = set().union(*(t for _, t in reads))
        syntax = self.syntax
        preamble = {}  # variable: the line that reads it from the inputs
        for arg, symbols in self.inputs.items():
            preamble.update({f"_{arg}{k}": syntax.input.format(var=f"_{arg}{k}", arg=arg, k=k)
                             for k, s in enumerate(symbols) if s in used})
        ops = len(trig)
        self.trig_indices = sorted({self._q_index[t.args[0]] for t in trig if t.args[0] in self._q_index})
        position = {s: k for k, s in enumerate(needed)}
        after: dict[int, list] = {}  # each output once the last intermediate it reads is known (short lives)
        for (i, j), e in zip(cells, exprs):
            if e != 0:
                after.setdefault(max((position[s] for s in e.free_symbols if s in position), default=-1),
                                 []).append((i, j, e))
        statements = []  # (the variable defined or None, the line, its operations)
        for k in range(-1, len(needed)):
            if k >= 0:
                text, n = self._line(needed[k])
                statements.append((self.printer.names[needed[k]], text, n))
                ops += n
            for i, j, e in after.get(k, []):
                before = self.printer.ops
                text = syntax.out.format(i=i, j=j, ij=i * cols + j, expr=self.printer(e))
                statements.append((None, text, self.printer.ops - before))
                ops += self.printer.ops - before
                if symmetric and i != j:
                    statements.append((None, syntax.mirror.format(i=i, j=j, ij=i * cols + j,
                                                                  ji=j * cols + i), 0))
        trig_lines = self._trig(trig, syntax.vector_trig)
        if "_tq" in trig_lines:  # the vector loops come first; parts pass their values on through X
            loops = [(None if v == "_tq" else v, line, 0) for v, line in trig_lines.items()]
            statements = loops + statements
        else:
            preamble.update(trig_lines)
        if syntax.segment and ops > SEGMENT:
            return self._parts(name, preamble, statements), (rows, cols), ops
        lines = [syntax.header.format(name=name), *preamble.values(), *(text for _, text, _ in statements),
                 syntax.footer.format()]
        return "\n".join(lines) + "\n", (rows, cols), ops

    def _trig(self, trig: set, vectors: bool) -> dict[str, str]:
        """The lines that compute sin and cos of the inputs: one call each, or, with `vectors` and two or
        more coordinates, sin and cos of the coordinates in two loops over an array (`VECTOR_TRIG`)."""
        syntax, lines = self.syntax, {}
        trig = sorted(trig, key=lambda t: self.trig[t])
        coordinates = sorted({t.args[0] for t in trig if t.args[0] in self._q_index}, key=self._q_index.get)
        vectors = vectors and len(coordinates) > 1
        if vectors:
            n = -(-len(coordinates) // LANES) * LANES
            values = [self.printer.names[x] for x in coordinates] + ["0.0"] * (n - len(coordinates))
            lines["_tq"] = "\n".join([f"    double _tq[{n}] = {{{', '.join(values)}}}, _ts[{n}], _tc[{n}];",
                                      f"    for (int k = 0; k < {n}; ++k) _ts[k] = sin(_tq[k]);",
                                      f"    for (int k = 0; k < {n}; ++k) _tc[k] = cos(_tq[k]);"])
        for t in trig:
            f, x = type(t).__name__, t.args[0]
            if vectors and x in self._q_index:
                expr = f"_t{f[0]}[{coordinates.index(x)}]"
            else:
                x_name = self.printer.names[x]
                if x in self._q_index:
                    expr = syntax.trig_q.format(f=f, x=x_name, k=self._q_index[x])
                else:  # of a speed or a parameter: the syntax's function
                    expr = f"{syntax.functions.get(f, f)}({x_name})"
            lines[self.trig[t]] = syntax.assign.format(var=self.trig[t], expr=expr)
        return lines

    def _parts(self, name: str, preamble: dict[str, str], statements: list) -> str:
        """A long C function as parts of about `SEGMENT` operations, each its own function, called in turn;
        the values a later part reads pass through the array X."""
        syntax = self.syntax
        chunks, size = [[]], 0
        for v, text, n in statements:
            if size + n > SEGMENT and chunks[-1]:
                chunks.append([])
                size = 0
            chunks[-1].append((v, text))
            size += n
        where = {v: c for c, chunk in enumerate(chunks) for v, _ in chunk if v}
        reads = [set(NAMES.findall(" ".join(text.split("=", 1)[1] for _, text in chunk)))
                 for chunk in chunks]
        slots: dict[str, int] = {}
        for c, names in enumerate(reads):
            for v in sorted(names):
                if where.get(v, c) < c:
                    slots.setdefault(v, len(slots))
        parts, calls = [NOINLINE], []
        for c, (chunk, names) in enumerate(zip(chunks, reads)):
            names |= {x for v in names if v in preamble for x in NAMES.findall(preamble[v].split("=", 1)[1])}
            lines = [syntax.segment.format(name=f"{name}_{c}"),
                     *(line for v, line in preamble.items() if v in names),
                     *(f"    const {syntax.type} {v} = X[{slots[v]}];" for v in sorted(names)
                       if where.get(v, c) < c)]
            for v, text in chunk:
                lines.append(text)
                if v in slots:
                    lines.append(f"    X[{slots[v]}] = {v};")
            parts.append("\n".join(lines + [syntax.footer.format()]))
            calls.append(syntax.call.format(name=f"{name}_{c}"))
        main = [syntax.header.format(name=name), f"    {syntax.type} X[{max(len(slots), 1)}];", *calls,
                syntax.footer.format()]
        return "\n\n".join(parts) + "\n\n" + "\n".join(main) + "\n"

    def function(self, name: str, fn: Function) -> tuple[str, tuple, int]:
        """`source` of a catalogue function, its expression built (derivatives, ...) and printed with the
        cycle collector paused (`collection_paused`: a third of the printing time otherwise)."""
        with collection_paused():
            return self.source(name, fn.expression(), fn.symmetric)


def writer(catalogue: Catalogue, syntax: Syntax = PYTHON) -> FunctionWriter:
    """A function writer over a catalogue's intermediates and inputs q, u, u̇ (or w) and p."""
    return FunctionWriter(catalogue.sub, catalogue.inputs, syntax)


@dataclass
class Generated:
    """One generated function: its source, output shape and operation count."""

    source: str
    shape: tuple
    ops: int
    function: Callable
    vector: Callable | None = None  # compiled: the column output as a vector
    # what its module reads later by weak reference, kept alive with it (compiled: the printing of the
    # module's vector functions, on its first batch)
    kept: object = field(default=None, repr=False, compare=False)

    def __post_init__(self) -> None:
        self.params_used = frozenset(reads(self.source)["p"])


def reads(source: str) -> dict[str, list[int]]:
    """The entries of q, u, ud and p a generated function reads, each once, in order."""
    found: dict[str, set[int]] = {"q": set(), "u": set(), "ud": set(), "p": set()}
    for arg, k in re.findall(r"\b_(q|u|ud|p)(\d+) =", source):
        found[arg].add(int(k))
    return {arg: sorted(ks) for arg, ks in found.items()}


def listed(used: dict[str, list[int]]) -> str:
    """The entries read, as a header lists them: "q[0, 2]; p[1]" (or "nothing")."""
    return "; ".join(f"{arg}[{', '.join(map(str, ks))}]" for arg, ks in used.items() if ks) or "nothing"
