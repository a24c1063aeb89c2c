"""LaTeX of eomgen's expressions as a textbook prints them.

Speeds and accelerations are the dots of their coordinate (the speed of φ prints φ̇, its
acceleration φ̈, whatever the coordinate is called), joint efforts τ with the joint's name as
subscript, parameters as sympy prints them (m_p → m_{p}, phi → φ), and numbers that came from a
file (floats, rationals such as 44105/9007199254740992) as decimals with `digits` significant digits;
small integers and simple fractions (1/2, 3/4) stay exact."""

from __future__ import annotations

import re

import sympy as sp
from sympy.printing.latex import LatexPrinter

from .escaping import latex_math
from .symbols import Generated

CUT = {"a": "a", "alpha": r"\alpha", "F": "F", "T": "T"}  # the free cut's accelerations and reactions
SIMPLE_DENOMINATOR = 1000  # a fraction with a larger denominator is a decimal number from a file
MATRICES = {"Jdot_c qdot": r"\dot{J}_{c} \dot{q}"}  # eomgen's own matrix symbols (the contacts' step)
SIMPLE = re.compile(r"[A-Za-z]+\d*(_[A-Za-z0-9]{1,3}|_\{[A-Za-z0-9]{1,3}\})?")  # m, l_c1, phi: sympy's


class Printer(LatexPrinter):
    """sympy's LaTeX printer with eomgen's symbols and decimal numbers."""

    def __init__(self, digits: int = 4) -> None:
        super().__init__({"mul_symbol": None})
        self.digits = digits

    def _print_Symbol(self, expr, style="plain"):
        tag = getattr(expr, "tag", None) if isinstance(expr, Generated) else None
        if isinstance(tag, tuple) and len(tag) == 2 and tag[0] in ("dot", "ddot"):
            inner = self._print(tag[1])
            if inner.startswith(r"\mathrm{"):  # a long name: q̇ with the name as subscript, readable
                return rf"\{tag[0]}{{q}}_{{{inner}}}"
            base, sub = _split_subscript(inner)
            return rf"\{tag[0]}{{{base}}}{sub}"
        if isinstance(tag, tuple) and len(tag) == 3 and tag[0] in CUT:  # free cut: a, α, F, T of a body
            return rf"{CUT[tag[0]]}_{{{text(tag[1])},{tag[2]}}}"
        if isinstance(tag, tuple) and len(tag) == 2 and tag[0] == "tau":
            return rf"\tau_{{{name(tag[1])}}}"
        if not SIMPLE.fullmatch(expr.name):  # shoulder_pan_joint, "a b", "φ₁": a name, not a symbol
            return text(expr.name)
        return super()._print_Symbol(expr, style)

    def _print_MatrixSymbol(self, expr):
        return MATRICES.get(expr.name) or super()._print_MatrixSymbol(expr)

    def _print_Float(self, expr):
        return super()._print_Float(sp.Float(expr, self.digits))

    def _print_Rational(self, expr):
        if expr.q > SIMPLE_DENOMINATOR:
            return self._print_Float(sp.Float(expr, self.digits + 2))
        return super()._print_Rational(expr)


def _split_subscript(symbol: str) -> tuple[str, str]:
    """'x_{1}' → ('x', '_{1}'): the dot goes on the letter, not on its subscript."""
    if "_" in symbol and "{" not in symbol.split("_", 1)[0]:
        base, sub = symbol.split("_", 1)
        return base, "_" + sub
    return symbol, ""


def latex(expr, digits: int = 4) -> str:
    """LaTeX of a sympy expression or matrix (see the module)."""

    def decimals(e):
        e = sp.sympify(e)
        return e.xreplace(
            {r: sp.Float(r, digits + 2) for r in e.atoms(sp.Rational) if r.q > SIMPLE_DENOMINATOR}
        )

    expr = expr.applyfunc(decimals) if isinstance(expr, sp.MatrixBase) else decimals(expr)
    return Printer(digits).doprint(expr)


def text(label: str) -> str:
    """A name (body, joint, load, a symbol's that is no symbol) as upright text in math mode."""
    return rf"\mathrm{{{latex_math(label)}}}"


def name(label: str) -> str:
    """A joint's name as a subscript: as a symbol of that name where it is one (phi → φ, q_1), else text."""
    return Printer().doprint(sp.Symbol(label)) if label.isidentifier() else text(label)
