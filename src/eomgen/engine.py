"""The scalar engine of the hot core (kinematics, the body-frame recursions): sympy, the reference, or
symengine, sympy's C++ counterpart, whose sums and products cost a fraction of sympy's.

Only the hot core computes in the engine. Everything it names enters `Subexpressions` as a sympy
definition (converted once, sympy's canonical order of terms and factors), so the methods, closed
forms, display, worked solutions and printers see sympy objects alone, and the generated sources do
not depend on the engine's hash order. A symengine symbol is a numbered token ("_ε3") tied to its sympy
symbol in both directions: two sympy symbols of one name (a user's "x" and eomgen's "x") stay apart
and keep their assumptions."""
from __future__ import annotations

import gc
from collections.abc import Iterator, Sequence
from contextlib import contextmanager
from functools import cache, cmp_to_key
from operator import itemgetter

import sympy as sp
from sympy.core.mul import _keep_coeff

from .errors import ModelError

try:
    import symengine as se
except ImportError:  # a dependency where it has wheels (not Intel macOS): sympy then
    se = None

ENGINES = ("sympy", "symengine")


def default_engine() -> str:
    """symengine where it is installed, else sympy."""
    return "symengine" if se is not None else "sympy"


def make_engine(name: str | None = None) -> Sympy | Symengine:
    """A fresh engine by name (None: `default_engine`)."""
    name = default_engine() if name is None else name
    if name not in ENGINES:
        raise ModelError(f"engine: {name!r} is not one of {ENGINES}")
    if name == "symengine" and se is None:
        raise ModelError("engine 'symengine' is not installed: pip install 'eomgen[symengine]', "
                         "or engine='sympy'")
    return Sympy() if name == "sympy" else Symengine()


@contextmanager
def collection_paused() -> Iterator[None]:
    """Python's cycle collector paused while a derivation builds its (acyclic) expressions: it would walk
    them again and again as they pile up (a fifth of a big robot's derivation)."""
    enabled = gc.isenabled()
    gc.disable()
    try:
        yield
    finally:
        if enabled:
            gc.enable()


def vector(x: Sequence) -> tuple:
    """The entries of a sequence, or of a `sp.Matrix` row by row (its flat list: indexing one converts
    every entry), as a tuple."""
    return tuple(x.flat() if isinstance(x, sp.MatrixBase) else x)


def total_of(terms: list):
    """Σ terms in the terms' engine (Python integers are neutral: 0 + x is x in either)."""
    for x in terms:
        if isinstance(x, sp.Basic):
            return sp.Add(*terms)
        if se is not None and isinstance(x, se.Basic):
            return se.Add(*terms)
    return sum(terms)


class Sympy:
    """The reference engine: the hot core computes in sympy itself."""
    name = "sympy"

    def owns(self, x) -> bool:
        return False

    def scalar(self, x):
        return x

    def scalars(self, x: Sequence) -> tuple:
        return vector(x)

    def remember(self, x, engine_form) -> None:
        """Nothing to remember: sympy is the engine."""

    def intermediate(self, symbol: sp.Symbol) -> sp.Symbol:
        """A new intermediate's symbol in the engine: itself."""
        return symbol

    def to_sympy(self, x):
        return sp.sympify(x)

    def diff(self, e: sp.Expr, y: sp.Symbol) -> sp.Expr:
        """∂e/∂y (`partial`)."""
        return partial(e, y, sp.Mul, sp.sin, sp.cos)


class Symengine:
    """symengine scalars, converted from and to sympy through a table of symbols."""
    name = "symengine"

    def __init__(self) -> None:
        self._token: dict[sp.Symbol, se.Symbol] = {}
        self._symbol: dict[se.Symbol, sp.Symbol] = {}
        self._placeholder: dict[sp.Symbol, sp.Symbol] = {}  # sympy symbols named as their tokens (`scalar`)
        self._by_name: dict[str, sp.Symbol] = {}
        # sympy's 0 is Python's in the engine: the products (`linalg`) skip it at the cost of a hash
        self._in: dict[sp.Basic, se.Basic] = {sp.S.Zero: 0}
        self._out: dict[se.Basic, tuple] = {}  # `definition`

    def owns(self, x) -> bool:
        return isinstance(x, se.Basic)

    def token(self, s: sp.Symbol) -> se.Symbol:
        """The symengine symbol of a sympy symbol."""
        if s not in self._token:
            name = f"_ε{len(self._token)}"
            self._token[s] = token = se.Symbol(name)
            self._symbol[token], self._by_name[name] = s, s
        return self._token[s]

    def scalar(self, x):
        """A sympy scalar (or an integer, or one of the engine's) in the engine."""
        if isinstance(x, int) or isinstance(x, se.Basic):
            return x
        if x not in self._in:
            x = sp.sympify(x)
            if x.is_Symbol:
                self._in[x] = self.token(x)
            else:
                for s in sp.preorder_traversal(x):  # tokens numbered in the order met, not hash order
                    if s.is_Symbol and s not in self._placeholder:
                        self._placeholder[s] = sp.Symbol(self.token(s).name)
                self._in[x] = se.sympify(x.xreplace(self._placeholder))
        return self._in[x]

    def scalars(self, x: Sequence) -> tuple:
        return tuple(map(self.scalar, vector(x)))

    def intermediate(self, symbol: sp.Symbol) -> se.Symbol:
        """A new intermediate's symbol in the engine (`scalar` of a symbol it has not met)."""
        self._in[symbol] = token = self.token(symbol)
        return token

    def remember(self, x: sp.Expr, engine_form) -> None:
        """x (sympy, converted from `engine_form` without collecting terms) is `engine_form` in the
        engine: `scalar` answers it without converting."""
        self._in.setdefault(x, engine_form)

    def __getstate__(self) -> dict:
        """Pickled without the conversions to sympy (`_out`), which are rebuilt on demand."""
        return {**self.__dict__, "_out": {}}

    def diff(self, e, y):
        """∂e/∂y in the engine (`partial`; its products as sympy forms them, `product`)."""
        return partial(e, y, product, se.sin, se.cos)

    def to_sympy(self, x):
        """The sympy expression of an engine scalar (`definition`, without its symbols)."""
        return self._converted(x)[0] if isinstance(x, se.Basic) else sp.sympify(x)

    def definition(self, x) -> tuple[sp.Expr, list[sp.Symbol] | None]:
        """(the sympy expression of an engine scalar, its symbols): symbols from the table, powers, sin and
        cos rebuilt here, sums and products in sympy's order without collecting them again (`_ordered`),
        a rational times a sum distributed as sympy distributes it (`_distributed`), a sum that holds a
        distributed one collected by sympy (its terms may cancel: the symbols are None then, not
        symengine's), anything else through symengine's own conversion, the tokens renamed. Each engine
        node is converted once per engine (`_out`: its sympy form, its `sort_key`, whether a sum was
        collected in it)."""
        expr, _, collected = self._converted(x)
        return expr, None if collected else list(map(self._symbol.__getitem__, x.free_symbols))

    def _converted(self, x) -> tuple:
        """(sympy form, `sort_key`, collected) of an engine scalar, from the memo or `_convert`."""
        return self._out.get(x) or _convert(x, self._out, self)


def _convert(e, memo: dict, engine: Symengine) -> tuple:
    """(sympy form, `sort_key`, collected) of an engine node (`Symengine.definition`), memoized."""
    kind = type(e)
    if kind is se.Add or kind is se.Mul:
        args = [memo.get(a) or _convert(a, memo, engine) for a in e.args]
        collected = False
        for a in args:
            if a[2]:
                collected = True
                break
        if kind is se.Mul:
            if len(args) == 2 and (args[0][0].is_Number or args[1][0].is_Number) \
                    and (args[0][0].is_Add or args[1][0].is_Add):  # 2 (a + b) → 2 a + 2 b
                done = None if collected or not args[1][0].is_Add else _distributed(*args)
                if done is None:
                    r = sp.Mul(args[0][0], args[1][0])
                    done = (r, sort_key(r), collected)
            else:
                done = (*_ordered(sp.Mul, args), collected)
        elif any(a[0].is_Add for a in args):
            r = sp.Add(*(a[0] for a in args))
            done = (r, sort_key(r), True)
        else:
            done = (*_ordered(sp.Add, args), collected)
    elif kind is se.Symbol:
        r = engine._symbol[e]
        done = (r, sort_key(r), False)
    elif kind in _BUILD:
        args = [memo.get(a) or _convert(a, memo, engine) for a in e.args]
        r = _BUILD[kind](*(a[0] for a in args))
        done = (r, (_class_key(type(r)), len(args), *(a[1] for a in args)), any(a[2] for a in args))
    elif e.is_Number:
        r = sp.Integer(int(e)) if e.is_Integer else e._sympy_()
        done = (r, sort_key(r), False)
    else:  # symengine's conversion, which may collect a sum inside (Abs(2 (a/2 + b) − 2 b))
        r = e._sympy_()
        r = r.xreplace({s: engine._by_name[s.name] for s in r.free_symbols})
        done = (r, sort_key(r), len(r.free_symbols) != len(e.free_symbols))
    memo[e] = done
    return done


def _distributed(a: tuple, b: tuple) -> tuple | None:
    """c (t_1 + ... + t_n) of converted arguments (a number c, then a sum, as symengine orders them) as
    sympy's `Mul` forms it where c is rational: c t_1 + ... + c t_n, each c t_k formed by sympy
    (`_keep_coeff`), in sympy's order. Each term keeps its factors (only its coefficient changes), so the
    terms stay distinct and the sum collects nothing. None (sympy's `Mul` then) for a float c, which sympy
    distributes otherwise, and for a term with one factor that sympy may rewrite when it multiplies it
    (not `_plain`: 2 √8 = 4 √2, where symengine keeps √8, which may then collect with a term in √2)."""
    c = a[0]
    if not c.is_Rational:
        return None
    scaled = []
    for t, k in zip(b[0].args, b[1][2:]):
        factors = t.args[t.args[0].is_Number:] if t.is_Mul else () if t.is_Number else (t,)
        if len(factors) == 1 and not _plain(factors[0]):
            return None
        r = _keep_coeff(c, t)
        known = dict(zip(t.args, k[2:])) if t.is_Mul else {t: k}
        if r in known:
            scaled.append((r, known[r]))
        elif r.is_Mul:
            keys = (known[x] if x in known else sort_key(x) for x in r.args)
            scaled.append((r, (_MUL, len(r.args), *keys)))
        else:
            scaled.append((r, sort_key(r)))
    return (*_ordered(sp.Add, scaled), False)


def _plain(factor: sp.Expr) -> bool:
    """True for a symbol, a function's value and their powers with a number exponent: sympy multiplies them by
    a number as they stand."""
    if factor.is_Pow:
        factor = factor.base if factor.exp.is_Number else None
    return factor is not None and (factor.is_Symbol or isinstance(factor, sp.Function))


@cache
def _class_key(kind: type) -> tuple:
    """The place of a class in sympy's canonical order (`Basic.compare`): its index in
    `ordering_of_classes`, else after them all by name."""
    order = sp.core.basic.ordering_of_classes
    name = kind.__name__
    return (order.index(name), "") if name in order else (len(order) + 1, name)


def sort_key(e: sp.Basic) -> tuple:
    """A key that orders sympy objects as `Basic.compare` does: the class, the length of the hashable
    content, then its items one by one (sympy objects by their keys)."""
    content = e._hashable_content()
    return (_class_key(type(e)), len(content),
            *(sort_key(c) if isinstance(c, sp.Basic) else sort_key(sp.Basic(*c)) if isinstance(c, frozenset)
              else c for c in content))


def product(*factors):
    """Π factors in symengine, as sympy forms a product: a number times a sum distributed (symengine
    keeps that pair), so that what is built from it next has sympy's form."""
    p = se.Mul(*factors)
    if type(p) is se.Mul and len(p.args) == 2:
        number, rest = p.args if p.args[0].is_Number else p.args[::-1]
        if number.is_Number and type(rest) is se.Add:
            return se.Add(*[number * term for term in rest.args])
    return p


def partial(e, y, mul, sin, cos):
    """∂e/∂y of a sum, product, power (a number's), sin, cos or atom, by the rules, in either engine
    (its Mul, sin, cos): Σ_k a_1 ⋯ ∂a_k ⋯ a_n for a product, each formed in one `mul`, n b^(n−1) ∂b,
    cos a ∂a, −sin a ∂a. Each step forms what sympy would form, so both engines give one expression for
    the same input (sin and cos of atoms: symengine writes sin(a − b) as −sin(b − a))."""
    if e == y:
        return 1
    if e.is_Atom:
        return 0
    if e.is_Add:
        return total_of([partial(a, y, mul, sin, cos) for a in e.args])
    if e.is_Mul:
        return total_of([mul(*e.args[:k], da, *e.args[k + 1:])
                         for k, a in enumerate(e.args) if (da := partial(a, y, mul, sin, cos)) != 0])
    a = e.args[0]
    da = partial(a, y, mul, sin, cos)
    if da == 0:
        return 0
    if e.is_Pow:
        return mul(e.args[1], a ** (e.args[1] - 1), da)
    return mul(cos(a), da) if type(e) is sin else mul(-1, sin(a), da)


_ORDER = cmp_to_key(sp.Basic.compare)
_MUL = _class_key(sp.Mul)
_HEAD = {sp.Add: _class_key(sp.Add), sp.Mul: _MUL}


def _ordered(head, args: list[tuple]) -> tuple:
    """(head(*args), its `sort_key`) of converted arguments (sympy form, sort key, ...) that are already
    collected (symengine's sums and products are): sympy's canonical order (by `Basic.compare`, as its
    `flatten` sorts; the number, whose class comes first, leads) without collecting them again."""
    try:
        if len(args) == 2:
            if args[0][1] > args[1][1]:
                args.reverse()
        else:
            args.sort(key=itemgetter(1))
    except TypeError:  # items that Python cannot order (symbols of one name, told apart by a tag)
        args.sort(key=lambda a: _ORDER(a[0]))
    expr = head._from_args([a[0] for a in args], is_commutative=True)  # the model refuses others (`values`)
    return expr, (_HEAD[head], len(args), *[a[1] for a in args])


_BUILD = {} if se is None else {se.Pow: lambda b, e: sp.Pow(b, e, evaluate=False),
                                se.sin: lambda a: sp.sin(a, evaluate=False),
                                se.cos: lambda a: sp.cos(a, evaluate=False)}
