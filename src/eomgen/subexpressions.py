"""Named intermediate results and the chain rule through them.

Symbolic mechanics gets slow when every entry of M is one huge expression tree. Instead each
intermediate quantity (an entry of a body's rotation, a Jacobian column, ...) is a plain Symbol
x_k (eomgen's own, see `symbols`) with a definition e_k(q, u, parameters, x_<k). Derivatives follow
the chain rule through the definitions,

    d f / d s  =  Σ_y  ∂f/∂y · d y / d s,     d x_k / d s = d e_k / d s   (a new intermediate),

so a derivative is as cheap as the definitions it touches, and code generation can print the
intermediates once each. The partials ∂e_k/∂y are taken once per definition, in the engine
(`engine.partial`), and serve every direction.
"""
from __future__ import annotations

import math
import random
from collections.abc import Iterable, Mapping

import sympy as sp

from .engine import Sympy, Symengine, make_engine, se, total_of
from .symbols import Generated


TRIG = (sp.sin, sp.cos) + ((se.sin, se.cos) if se is not None else ())


def is_trivial(expr: sp.Expr) -> bool:
    """True where naming the expression would not save work: atoms, −atom, sin/cos of an atom."""
    if expr.is_Atom:
        return True
    if expr.is_Mul and len(expr.args) == 2 and expr.args[0].is_Number and expr.args[1].is_Atom:
        return True
    return isinstance(expr, TRIG) and expr.args[0].is_Atom


# d f(a) / da of the one-argument functions, given a and f(a)
_RULES = {sp.sin: lambda a, f: sp.cos(a), sp.cos: lambda a, f: -sp.sin(a), sp.tan: lambda a, f: 1 + f**2,
          sp.exp: lambda a, f: f, sp.log: lambda a, f: 1 / a, sp.asin: lambda a, f: 1 / sp.sqrt(1 - a**2),
          sp.acos: lambda a, f: -1 / sp.sqrt(1 - a**2), sp.atan: lambda a, f: 1 / (1 + a**2),
          sp.sinh: lambda a, f: sp.cosh(a), sp.cosh: lambda a, f: sp.sinh(a), sp.tanh: lambda a, f: 1 - f**2,
          sp.Abs: lambda a, f: sp.sign(a)}


_PLAIN = (sp.Add, sp.Mul, sp.Pow, sp.sin, sp.cos)


def samples(q: Iterable[sp.Symbol], parameters: Iterable[sp.Symbol], count: int) -> list[dict]:
    """`count` random points for `Subexpressions.evaluate` (seeded): q uniform in [−π, π], parameters in
    [0.5, 1.5]."""
    rng = random.Random(0)
    q, parameters = list(q), sorted(parameters, key=str)
    return [{**{s: rng.uniform(-math.pi, math.pi) for s in q},
             **{s: rng.uniform(0.5, 1.5) for s in parameters}} for _ in range(count)]


class Subexpressions:
    """An ordered set of definitions x_k = e_k, with directional derivatives through them."""

    def __init__(self, prefix: str = "_ξ", engine: str | None = "sympy") -> None:
        self.prefix = prefix
        self.engine: Sympy | Symengine = make_engine(engine)  # the hot core's scalars (`engine`)
        self._named_engine: dict = {}
        self.definitions: dict[sp.Symbol, sp.Expr] = {}
        self._index: dict[sp.Symbol, int] = {}
        self._named: dict[sp.Expr, sp.Symbol] = {}
        self._uses: dict[sp.Symbol, tuple] = {}  # the intermediates each definition reads
        self._reads: dict[sp.Symbol, frozenset] = {}  # the other symbols each definition reads
        self._symbols: list[sp.Symbol] = []  # by index
        self._derivatives: dict = {}  # {direction: {index of an intermediate: its derivative}}
        self._needs: dict[sp.Expr, list[int]] = {}  # the indices of `dependencies`, by expression
        self._inlined: dict[sp.Symbol, sp.Expr] = {}
        self._gradients: dict[sp.Expr, list | None] = {}

    def __len__(self) -> int:
        return len(self.definitions)

    def __getstate__(self) -> dict:
        """Pickled without the caches that are rebuilt on demand (partials, dependency lists)."""
        return {**self.__dict__, "_gradients": {}, "_needs": {}}

    def add(self, expr: sp.Expr) -> sp.Expr:
        """Name `expr` as a new intermediate (unless trivial) and return the name; an engine scalar
        is named by its sympy form and answered in the engine (an integer as the engine's)."""
        if isinstance(expr, int):
            return self.engine.scalar(sp.Integer(expr))
        if not self.engine.owns(expr):
            return self._name(sp.sympify(expr))
        if is_trivial(expr):
            return expr
        named = self._named_engine.get(expr)
        if named is None:
            definition, symbols = self.engine.definition(expr)
            if symbols is None or is_trivial(definition):  # collected: its terms may have cancelled
                named = self.engine.scalar(self._name(definition))
            else:  # the engine's own terms, known to the engine from here on
                self.engine.remember(definition, expr)
                name = self._named.get(definition)
                named = self.engine.scalar(name) if name is not None else \
                    self.engine.intermediate(self._new(definition, symbols))
            self._named_engine[expr] = named
        return named

    def _name(self, expr: sp.Expr) -> sp.Expr:
        """The name of a sympy expression (`add`)."""
        if is_trivial(expr):
            return expr
        if expr in self._named:  # the same expression twice: one name
            return self._named[expr]
        return self._new(expr, expr.free_symbols)

    def _new(self, expr: sp.Expr, symbols) -> Generated:
        """A new intermediate named `expr` (not trivial, not named yet) with its `symbols`."""
        k = len(self._symbols)
        symbol = Generated(f"{self.prefix}{k}", (self.prefix, k))  # same model, same order
        self._record(symbol, expr, symbols)
        self._named[expr] = symbol
        return symbol

    def add_matrix(self, matrix):
        """Name every entry of `matrix`: an `sp.Matrix`, or a tuple of entries (`linalg`)."""
        if isinstance(matrix, sp.MatrixBase):
            return matrix.applyfunc(self.add)
        return tuple(map(self.add, matrix))

    def scalar(self, x):
        """A sympy scalar as the engine's."""
        return self.engine.scalar(x)

    def vector(self, x) -> tuple:
        """The entries of a sympy vector or matrix (row by row) as the engine's scalars."""
        return self.engine.scalars(x)

    def matrix(self, x, cols: int = 1) -> sp.Matrix:
        """The `sp.Matrix` of `cols` columns with the engine scalars `x` row by row, in sympy."""
        return sp.Matrix(len(x) // cols if cols else 0, cols, [self.engine.to_sympy(e) for e in x])

    def reads(self, symbol: sp.Symbol) -> frozenset:
        """The symbols other than intermediates that the definition of `symbol` holds (inputs,
        parameters), known since it was defined."""
        return self._reads[symbol]

    def dependencies(self, exprs: Iterable[sp.Expr]) -> list[sp.Symbol]:
        """The intermediates that `exprs` need, in definition order."""
        stack = [s for e in exprs for s in sp.sympify(e).free_symbols if s in self.definitions]
        needed: set[sp.Symbol] = set()
        while stack:
            s = stack.pop()
            if s not in needed:
                needed.add(s)
                stack.extend(self._uses[s])
        return sorted(needed, key=self._index.__getitem__)

    def derivative(self, expr: sp.Expr, seeds: Mapping[sp.Symbol, sp.Expr], key) -> sp.Expr:
        """Directional derivative Σ_y ∂expr/∂y · ẏ, where ẏ = seeds[y] for the independent symbols
        and the chain rule for the intermediates, but for an intermediate that `seeds` holds (its
        derivative is then its seed: a prescribed motion's variable, whose rate is named). `key` names
        the direction (memoization)."""
        expr, known = sp.sympify(expr), self._derivatives.setdefault(key, {})
        if expr not in self._needs:
            self._needs[expr] = [self._index[s] for s in self.dependencies([expr])]
        for k in self._needs[expr]:
            if k not in known:
                s = self._symbols[k]
                known[k] = seeds[s] if s in seeds else \
                    self.add(self._chain(self.definitions[s], seeds, known))
        return self.engine.to_sympy(self._chain(expr, seeds, known))

    def _chain(self, expr: sp.Expr, seeds: Mapping[sp.Symbol, sp.Expr], known: dict):
        """The derivative of one definition (or expression) in the engine, Σ_y ∂expr/∂y · ẏ (`gradient`),
        or by `_direct` where `gradient` gives none."""
        partials = self.gradient(expr)
        if partials is None:
            return self._direct(expr, seeds, known)
        terms = []
        for y, k, partial in partials:
            dy = known[k] if k >= 0 else seeds.get(y, 0)
            if dy != 0:
                terms.append(partial * self.engine.scalar(dy))
        return total_of(terms)

    def gradient(self, expr: sp.Expr) -> list[tuple] | None:
        """[(y, its index (-1: not an intermediate), ∂expr/∂y in the engine)] over expr's symbols y in a
        fixed order (intermediates by index, then by name), once per expression; None where expr holds
        more than sums, products, numbers' powers, sin and cos of atoms (`_direct` differentiates it:
        symengine would write sin(a − b) as −sin(b − a))."""
        if expr not in self._gradients:
            stack, plain = [expr], True
            while stack and plain:
                e = stack.pop()
                if not e.is_Atom:
                    plain = type(e) in _PLAIN and not (e.is_Pow and not e.exp.is_Number) \
                        and not (isinstance(e, TRIG) and not e.args[0].is_Atom)
                    stack.extend(e.args)
            e = self.engine.scalar(expr) if plain else None
            self._gradients[expr] = None if not plain else [
                (y, k, self.engine.diff(e, self.engine.scalar(y)))
                for k, y in sorted(((self._index.get(y, -1), y) for y in expr.free_symbols),
                                   key=lambda ky: (ky[0], ky[1].name))]
        return self._gradients[expr]

    def define(self, symbol: sp.Symbol, expr: sp.Expr) -> sp.Symbol:
        """Name `expr` by the given `symbol` (one of eomgen's, new here), an intermediate like the others."""
        if symbol in self.definitions:
            raise ValueError(f"{symbol} is defined already")
        expr = sp.sympify(expr)
        self._record(symbol, expr, expr.free_symbols)
        return symbol

    def _record(self, symbol: sp.Symbol, expr: sp.Expr, symbols) -> None:
        """The definition symbol = expr, `symbols` the expression's symbols: the intermediates it uses and
        the other symbols it reads."""
        defined = self.definitions
        self._index[symbol] = len(self._symbols)
        self._symbols.append(symbol)
        uses, reads = [], []
        for s in symbols:
            (uses if s in defined else reads).append(s)
        self._uses[symbol], self._reads[symbol] = tuple(uses), frozenset(reads)
        defined[symbol] = expr

    def _direct(self, expr: sp.Expr, seeds: Mapping[sp.Symbol, sp.Expr], known: dict) -> sp.Expr:
        """Forward-mode derivative of one definition: sum, product, power and the rules of the functions
        the printers cover (real arguments: d|a| = sign(a) da, sign and Heaviside constant, Min / Max
        by their branches), the symbols' derivatives from the seeds and the memo."""
        memo: dict = {}

        def d(e):
            if e in memo:
                return memo[e]
            if e.is_Symbol:
                r = self.engine.to_sympy(known[self._index[e]]) if e in self.definitions else seeds.get(e, 0)
            elif e.is_Number or isinstance(e, (sp.sign, sp.Heaviside)):
                r = 0
            elif e.is_Add:
                r = sp.Add(*[d(a) for a in e.args])
            elif e.is_Mul:
                terms = []
                for i, a in enumerate(e.args):
                    da = d(a)
                    if da != 0:
                        terms.append(sp.Mul(*e.args[:i], da, *e.args[i + 1:]))
                r = sp.Add(*terms)
            elif e.is_Pow:
                base, exp = e.args
                db = d(base)
                if exp.free_symbols and d(exp) != 0:
                    r = sp.diff(e, base) * db + sp.diff(e, exp) * d(exp)
                else:
                    r = 0 if db == 0 else exp * base ** (exp - 1) * db
            elif isinstance(e, sp.Piecewise):
                r = sp.Piecewise(*[(d(value), cond) for value, cond in e.args])
            elif isinstance(e, (sp.Min, sp.Max)):  # the derivative of the argument that is the extremum
                ge = sp.Ge if isinstance(e, sp.Max) else sp.Le
                r = d(sp.Piecewise(*[(a, sp.And(*[ge(a, b) for b in e.args[i + 1:]]))
                                     for i, a in enumerate(e.args)]))
            elif isinstance(e, sp.atan2):
                y, x = e.args
                r = (x * d(y) - y * d(x)) / (x**2 + y**2)
            elif type(e) in _RULES:
                da = d(e.args[0])
                r = 0 if da == 0 else _RULES[type(e)](e.args[0], e) * da
            else:  # any other function: the general rule, symbol by symbol
                r = sp.Add(*[sp.diff(e, y) * d(y) for y in e.free_symbols if d(y) != 0])
            memo[e] = r
            return r

        return d(expr)

    def evaluate(self, exprs, values: Mapping[sp.Symbol, float]) -> list[complex]:
        """The numbers of `exprs` at `values` of the independent symbols, through the intermediates
        (a few sample states: checks, not code)."""
        known = {s: sp.Float(v) for s, v in values.items()}
        for s in self.dependencies(exprs):
            known[s] = self.definitions[s].xreplace(known).evalf()
        return [complex(sp.sympify(e).xreplace(known).evalf()) for e in exprs]

    def substitute(self, expr, mapping: Mapping[sp.Symbol, sp.Expr]):
        """expr with independent symbols replaced (q̇ → q̇(w), say), through the intermediates: every
        intermediate that depends on them gets a new name."""
        if isinstance(expr, sp.MatrixBase):
            return expr.applyfunc(lambda e: self.substitute(e, mapping))
        expr = sp.sympify(expr)
        renamed: dict[sp.Symbol, sp.Expr] = dict(mapping)
        for s in self.dependencies([expr]):
            definition = self.definitions[s]
            if definition.free_symbols & set(renamed):
                renamed[s] = self.add(definition.xreplace(renamed))
        return expr.xreplace(renamed)

    def inline(self, expr):
        """Substitute every intermediate by its definition: the closed form in q, u and parameters."""
        if isinstance(expr, sp.MatrixBase):
            return expr.applyfunc(self.inline)
        expr = sp.sympify(expr)
        for s in self.dependencies([expr]):
            if s not in self._inlined:
                self._inlined[s] = self.definitions[s].xreplace(self._inlined)
        return expr.xreplace(self._inlined)
