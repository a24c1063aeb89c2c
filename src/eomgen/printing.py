"""LaTeX of eomgen's expressions as a textbook prints them.

Speeds and accelerations are the dots of their coordinate (the speed of φ prints φ̇, its
acceleration φ̈, whatever the coordinate is called), joint efforts τ with the joint's name as
subscript, parameters as sympy prints them (m_p → m_{p}, phi → φ), and numbers that came from a
file (floats, rationals such as 44105/9007199254740992) as decimals with `digits` significant digits;
small integers and simple fractions (1/2, 3/4) stay exact."""

from __future__ import annotations

import re
import unicodedata

import sympy as sp
from sympy.printing.latex import LatexPrinter

from .symbols import Generated

CUT = {"a": "a", "alpha": r"\alpha", "F": "F", "T": "T"}  # the free cut's accelerations and reactions
SIMPLE_DENOMINATOR = 1000  # a fraction with a larger denominator is a decimal number from a file
SIMPLE = re.compile(r"^[A-Za-z]+\d*(_\{?[A-Za-z0-9]{1,3}\}?)?$")  # m, l_c1, q_1, phi: sympy prints them well


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
        if not SIMPLE.match(expr.name):  # shoulder_pan_joint, "a b", "φ₁": a name, not a symbol
            return rf"\mathrm{{{escape(expr.name, math=True)}}}"
        return super()._print_Symbol(expr, style)

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


def escape(label: str, math: bool = False) -> str:
    """A name as LaTeX (text mode, or inside \\mathrm when `math`): specials escaped, Greek letters as
    their commands, other non-ASCII letters without their accents (pdflatex has no glyphs for them)."""
    out = []
    for c in label:
        if c in "#$%&_{}":
            out.append("\\" + c)
        elif c in "\\~^":
            out.append(
                {"\\": r"\backslash ", "~": r"\sim ", "^": r"\wedge "}[c]
                if math
                else {"\\": r"\textbackslash{}", "~": r"\textasciitilde{}", "^": r"\textasciicircum{}"}[c]
            )
        elif c == " " and math:
            out.append(r"\ ")
        elif ord(c) < 128:
            out.append(c)
        else:
            out.append(_ascii(c, math))
    return "".join(out)


def _ascii(c: str, math: bool) -> str:
    name = unicodedata.name(c, "")
    if name.startswith("GREEK") and " LETTER " in name:
        letter = name.split(" LETTER ")[1].lower().replace("final ", "").replace("lamda", "lambda")
        command = (
            ("\\" + (letter.capitalize() if "CAPITAL" in name else letter)) if letter.isalpha() else "?"
        )
        return command + " " if math else f"${command}$"
    plain = "".join(x for x in unicodedata.normalize("NFKD", c) if ord(x) < 128)
    return plain or "?"


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
    """A name (body, joint, load) as LaTeX text in math mode."""
    return rf"\text{{{escape(label)}}}"


def name(label: str) -> str:
    """A joint's name as a subscript: as a symbol of that name where it is one (phi → φ, q_1), else text."""
    return Printer().doprint(sp.Symbol(label)) if label.isidentifier() else text(label)
