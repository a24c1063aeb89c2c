"""A student's answer read into a system's symbols: sympy expressions, or LaTeX through sympy's parser
(the `check` extra). Symbols are matched by name (m_{p} is m_p, \\varphi is phi): the coordinates q,
the speeds u (also written \\dot q, or Derivative(q(t), t)), the parameters and the joint torques
tau_<joint>; any other symbol is refused, naming it and listing the known ones."""

from __future__ import annotations

import re
from importlib.metadata import PackageNotFoundError, version

import sympy as sp
from sympy.core.function import AppliedUndef

from .errors import ModelError

EXTRA = ("LaTeX answers need sympy's LaTeX parser: pip install 'eomgen[check]' (antlr4-python3-runtime "
         "4.11, the version sympy names); or give sympy expressions")
DOT = re.compile(r"\\dot\s*(?:\{([^{}]*)\}|(\\[A-Za-z]+|[A-Za-z]))(_\{[^{}]*\}|_[A-Za-z0-9])?")
MATRIX = re.compile(r"\\begin\{([pbBvV]?matrix|array)\}(?:\{[^{}]*\})?(.*?)\\end\{\1\}", re.S)
# \sin{\phi} x: sin(φ)·x, not sin(φ x)
BRACED = re.compile(r"\\(sin|cos|tan)(\^\{?\d+\}?)?\s*\{([^{}]*)\}")
VARIANTS = {"varphi": "phi", "vartheta": "theta", "varepsilon": "epsilon"}
MARK = "Upsilon_{%d}"  # a dotted coordinate while the LaTeX is parsed


def plain(name: str) -> str:
    """A symbol's name without LaTeX markup: m_{p} → m_p, l_{c*2} → l_c2, \\varphi → phi."""
    name = re.sub(r"[{}\\*() ]", "", name)
    return VARIANTS.get(name, name)


class Reader:
    """Reads answers for `system`; `extra` symbols (joint torques) are known besides q, u and the
    parameters."""

    def __init__(self, system, extra=()) -> None:
        symbols = [*system.q, *system.u, *sorted(system.parameters, key=str), *extra]
        self.known = {plain(str(s)): s for s in symbols}
        pairs = zip(system.q, system.u) if len(system.q) == len(system.u) else ()  # u = q̇
        self.dotted = {plain(str(qi)): ui for qi, ui in pairs}

    def matrix(self, value, name: str, shape: tuple[int, int]) -> sp.Matrix:
        """`value` (a sympy Matrix, nested lists, a LaTeX matrix) as a matrix of `shape` (a vector
        also as a row or a flat list)."""
        if isinstance(value, str):
            found = MATRIX.search(value)
            if found is None:
                raise ModelError(f"check_answer: {name} is a LaTeX string without a matrix environment "
                                 r"(\begin{bmatrix} ... \end{bmatrix}); or give a list of entries")
            value = [row.split("&") for row in re.split(r"\\\\", found.group(2)) if row.strip()]
        rows = [list(r) if isinstance(r, (list, tuple)) else [r] for r in
                (value.tolist() if isinstance(value, sp.MatrixBase) else value)]
        if shape[1] == 1 and len(rows) == 1:  # a row vector
            rows = [[e] for e in rows[0]]
        got = (len(rows), len({len(r) for r in rows}) == 1 and len(rows[0]) or -1)
        if got != shape:
            raise ModelError(f"check_answer: {name} has {len(rows)} rows of {[len(r) for r in rows]} "
                             f"entries; the system's {name} is {shape[0]}×{shape[1]}")
        label = (lambda i, j: f"{name}[{i},{j}]") if shape[1] > 1 else (lambda i, j: f"{name}[{i}]")
        return sp.Matrix([[self.entry(e, label(i, j)) for j, e in enumerate(r)] for i, r in enumerate(rows)])

    def entry(self, value, label: str) -> sp.Expr:
        """One entry in the system's own symbols."""
        expr = self._latex(value, label) if isinstance(value, str) else sp.sympify(value, strict=True)
        expr = expr.replace(lambda e: isinstance(e, sp.Derivative), lambda d: self._speed(d, label))
        expr = expr.replace(lambda e: isinstance(e, AppliedUndef), lambda f: self._applied(f, label))
        unknown = sorted({str(s) for s in expr.free_symbols if plain(str(s)) not in self.known})
        if unknown:
            raise ModelError(f"check_answer: {label} uses unknown symbols {unknown}; known: "
                             f"{', '.join(map(str, self.known.values()))}")
        return expr.xreplace({s: self.known[plain(str(s))] for s in expr.free_symbols})

    def _latex(self, text: str, label: str) -> sp.Expr:
        try:
            ready = version("antlr4-python3-runtime").startswith("4.11")
        except PackageNotFoundError:
            ready = False
        if not ready:
            raise ModelError(EXTRA)
        from sympy.parsing.latex import LaTeXParsingError, parse_latex

        marked: list[str] = []

        def mark(m: re.Match) -> str:
            marked.append(plain((m.group(1) or m.group(2)) + (m.group(3) or "")))
            return "\\" + MARK % (len(marked) - 1)

        try:
            expr = parse_latex(BRACED.sub(r"\\\1\2\\left(\3\\right)", DOT.sub(mark, text)), strict=True)
        except LaTeXParsingError as e:
            raise ModelError(f"check_answer: {label}: cannot read the LaTeX '{text}': "
                             f"{str(e).splitlines()[0]}") from None
        speeds = {}
        for k, name in enumerate(marked):
            if name not in self.dotted:
                raise ModelError(f"check_answer: {label}: \\dot{{{name}}} is not the speed of a coordinate;"
                                 f" coordinates with u = q̇: {', '.join(self.dotted)}")
            speeds[sp.Symbol(MARK % k)] = self.dotted[name]
        expr = expr.xreplace(speeds)
        for f in expr.atoms(sp.sin, sp.cos, sp.tan):
            if not _linear(f.args[0]):
                raise ModelError(f"check_answer: {label}: '{text}' reads as {f} (an angle times another "
                                 r"symbol); put the angle in brackets, e.g. \sin(\phi)\,\dot\phi^2")
        return expr

    def _speed(self, d: sp.Derivative, label: str) -> sp.Symbol:
        """Derivative(q(t), t) → the speed of q."""
        f = d.expr
        if isinstance(f, AppliedUndef) and d.derivative_count == 1 and plain(f.func.__name__) in self.dotted:
            return self.dotted[plain(f.func.__name__)]
        raise ModelError(f"check_answer: {label}: {d} is not the first time derivative of a coordinate")

    def _applied(self, f, label: str) -> sp.Expr:
        """q(t) → q; m_p(l^2) (how the LaTeX parser reads a product with a bracket) → m_p·l²."""
        name = plain(f.func.__name__)
        if name in self.known and len(f.args) == 1:
            return self.known[name] if str(f.args[0]) == "t" else self.known[name] * f.args[0]
        raise ModelError(f"check_answer: {label}: unknown function {f.func.__name__}")


def _linear(angle: sp.Expr) -> bool:
    """A sum of symbols with numeric coefficients (q₁ + q₂, 2 φ): what an angle in an answer is."""
    return all(len(t.free_symbols) <= 1 and sp.Poly(t, *t.free_symbols).total_degree() <= 1
               if t.free_symbols else True for t in sp.Add.make_args(sp.expand(angle)))
