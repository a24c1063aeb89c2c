"""A worked solution and its renderings: a LaTeX document (pdflatex), Markdown with math, and the
Jupyter display. Step texts carry their formulas as $...$ math and `code` in backticks."""

from __future__ import annotations

import itertools
import re
from dataclasses import dataclass
from pathlib import Path

import sympy as sp

from ..model import Cylindrical, FreeFlyer, Helical, Prismatic, Revolute, Spherical, Universal
from ..model.loads import Actuator, Damper, Force, Spring, Torque
from ..escaping import PREAMBLE as NAMES_PREAMBLE
from ..escaping import latex_text, markdown_text
from ..methods.free_cut import effort_symbols
from ..model.system import System
from ..printing import latex, text
from .compile import compile_pdf

WIDTH = 60  # printed characters (see `_visible`) per line of a long sum
METHOD_TITLES = {
    "free_cut": "Newton-Euler with a free cut",
    "projected_newton_euler": "Projected Newton-Euler",
    "lagrange": "Lagrange II",
    "recursive": "Recursive Newton-Euler (body frames)",
    "kane": "Kane's method",
    None: "Kinematics",
}
SECTIONS = {"Comparison of the methods": "Comparison", "Equations of motion": "The equations of motion"}
LABELS = {
    "r_S": "r_{{S}}",
    "J_P": "J_{{P}}",
    "J_R": "J_{{R}}",
    "Omega": r"\Omega",
    "tau": r"\tau",
    "Newton": r"\text{{Newton}}",
    "Euler": r"\text{{Euler}}",
    "reaction": r"\text{{reaction}}",
    "v_r": "v_{{r}}",
    "omega_r": r"\omega_{{r}}",
}
NAMES = {
    "dT/du": r"\frac{\partial T}{\partial \dot q}",
    "d/dt dT/du": r"\frac{d}{dt} \frac{\partial T}{\partial \dot q}",
    "dT/dq": r"\frac{\partial T}{\partial q}",
    "dU/dq": r"\frac{\partial U}{\partial q}",
    "F_r": r"\tilde F_{r}",
    "F*_r": r"\tilde F^{*}_{r}",
    "F_r + F*_r": r"\tilde F_{r} + \tilde F^{*}_{r}",
    "M~": r"\tilde M",
    "f~": r"\tilde f",
    "qdot": r"\dot q",
    "N_c": "N_{c}",
    "F_c": "F_{c}",
    "J_c": "J_{c}",
}


@dataclass
class Solution:
    """A worked solution: `steps` (see `Step`), by `methods`, rendered by `latex()` and `markdown()`."""

    title: str
    system: System
    steps: list
    methods: tuple
    form: str  # "textbook" or "shared"
    unsimplified: int = 0  # entries left out of textbook form by the size or time bound

    def __getitem__(self, name: str) -> sp.Basic:
        """The expression `name` of the first step that has it ("M", "T", "J_P[pendulum]", ...)."""
        return self.find(name)

    def find(self, name: str, method: str | None = None) -> sp.Basic:
        """The expression `name`, of `method`'s steps if given."""
        for step in self.steps:
            if name in step.expressions and (method is None or step.method == method):
                return step.expressions[name]
        raise KeyError(f"no step has {name!r}" + (f" for {method}" if method else ""))

    def latex(self, path=None, digits: int = 4) -> str:
        """A complete LaTeX document (pdflatex): title, the system, one section per method, the
        comparison; written to `path` if given."""
        body = [r"\section{The system}", _description(self.system, "latex", digits)]
        numbers = itertools.count(1)
        for section, steps in self._sections():
            body.append(rf"\section{{{section}}}")
            for step in steps:
                body.append(rf"\subsection*{{{step.title}}}")
                body.append(_prose(step.text, "latex"))
                body.extend(_blocks(step, "latex", digits, numbers))
        document = "\n".join(
            [
                PREAMBLE,
                rf"\title{{{latex_text(self.title)}}}",
                r"\date{}",
                r"\begin{document}",
                r"\maketitle",
                *body,
                r"\end{document}",
                "",
            ]
        )
        return _write(path, document)

    def pdf(self, path, digits: int = 4, engine: str = "pdflatex") -> Path:
        """The LaTeX document compiled to a PDF at `path` (needs a LaTeX engine, e.g. TeX Live)."""
        return compile_pdf(self.latex(digits=digits), path, engine)

    def markdown(self, path=None, digits: int = 4) -> str:
        """The same as Markdown with $$ math; written to `path` if given."""
        out = [f"# {markdown_text(self.title)}", "", "## The system", ""]
        out.append(_description(self.system, "markdown", digits))
        numbers = itertools.count(1)
        for section, steps in self._sections():
            out += ["", f"## {section}"]
            for step in steps:
                out += ["", f"### {step.title}", "", _prose(step.text, "markdown"), ""]
                out.extend(_blocks(step, "markdown", digits, numbers))
        return _write(path, "\n".join(out) + "\n")

    def _sections(self):
        sections: list = []
        for step in self.steps:
            name = SECTIONS.get(step.title) or METHOD_TITLES.get(step.method, step.method)
            if not sections or sections[-1][0] != name:
                sections.append((name, []))
            sections[-1][1].append(step)
        return sections

    def _repr_markdown_(self) -> str:
        return self.markdown()

    def __repr__(self) -> str:
        return (
            f"Solution({self.title!r}, methods={list(self.methods)}, {len(self.steps)} steps,"
            f" form={self.form!r})"
        )

    def check(self, **answer):
        """A student's M=, b=, g=, tau= against this system's (see `eomgen.check_answer`)."""
        from ..check_answer import check_answer  # here: the class's one method outside rendering
        return check_answer(self.system, **answer)


PREAMBLE = r"""\documentclass[10pt]{article}
\usepackage[margin=2cm]{geometry}
\usepackage{amsmath,amssymb}
\usepackage{booktabs}
\allowdisplaybreaks
\setcounter{MaxMatrixCols}{20}
""" + NAMES_PREAMBLE


def _write(path, document: str) -> str:
    if path is not None:
        with open(path, "w", encoding="utf-8") as f:
            f.write(document)
    return document


def label(name: str) -> str:
    """LaTeX of an expression's name: "J_P[pendulum]" → J_{P}^{(pendulum)}."""
    match = re.fullmatch(r"(.+?)\[(.+)\]", name)
    if name in NAMES:
        return NAMES[name]
    if match and match.group(1) in LABELS:
        return LABELS[match.group(1)].format() + rf"^{{({text(match.group(2))})}}"
    if match and match.group(1) in ("M", "b", "g") and " - " in name:
        return text(name)
    return latex(sp.Symbol(name)) if name.isidentifier() and len(name) <= 3 else text(name)


def _blocks(step, kind: str, digits: int, numbers) -> list[str]:
    """Display math for each expression (and the shared definitions first), then the step's
    equations, numbered from `numbers`, one per line."""
    lines = []
    if step.shared:
        lines.append(_prose("with the shared definitions", kind))
        rows = [rf"{latex(s)} &= {_broken(e, digits)}" for s, e in step.shared]
        if kind == "latex":  # align* breaks across pages (\allowdisplaybreaks): every definition shows
            lines.append(r"\begin{align*}" + " \\\\\n".join(rows) + r"\end{align*}")
        else:
            lines.append(_display(r"\begin{aligned}" + r" \\ ".join(rows) + r"\end{aligned}", kind))
    for name, expr in step.expressions.items():
        lines.append(_display(rf"{label(name)} = {_math(expr, digits)}", kind))
    for group, equations in itertools.groupby(step.equations, key=lambda e: e.group):
        lines.append(_prose(group, kind))
        rows = [(_equation(e.eq, digits), next(numbers)) for e in equations]
        if kind == "latex":  # \tag on a row's last line; align* breaks across pages
            lines.append(r"\begin{align*}" + " \\\\\n".join(rf"&{r} \tag{{{n}}}" for r, n in rows)
                         + r"\end{align*}")
        else:
            lines += [_display(rf"\begin{{aligned}}&{r}\end{{aligned}} \tag{{{n}}}", kind) for r, n in rows]
    return lines


def _equation(eq: sp.Equality, digits: int) -> str:
    """lhs = rhs, broken at the terms of either side into lines of about WIDTH characters."""
    pieces = _pieces(eq.lhs, digits, first=True) + ["="] + _pieces(eq.rhs, digits, first=True)
    return _lines(pieces)


def _math(expr, digits: int) -> str:
    if (
        isinstance(expr, sp.MatrixBase)
        and expr.cols == 1
        and expr.rows > 0
        and _visible(latex(expr, digits)) > WIDTH
    ):
        rows = [_broken(e, digits) for e in expr]
        return (
            r"\begin{bmatrix}"
            + r" \\ ".join(rf"\begin{{aligned}}&{r}\end{{aligned}}" for r in rows)
            + r"\end{bmatrix}"
        )
    if isinstance(expr, sp.MatrixBase) and _visible(latex(expr, digits)) > 4 * WIDTH:
        return (
            r"\left[\begin{aligned}"
            + r" \\ ".join(
                rf"&({i + 1},{j + 1}):\ {_broken(expr[i, j], digits)}"
                for i in range(expr.rows)
                for j in range(expr.cols)
            )
            + r"\end{aligned}\right]"
        )
    if isinstance(expr, sp.MatrixBase) or not isinstance(expr, sp.Add):
        return latex(expr, digits)
    return rf"\begin{{aligned}}&{_broken(expr, digits)}\end{{aligned}}"


def _broken(expr, digits: int) -> str:
    """A long expression broken into lines of about WIDTH characters (inside aligned): at the terms
    of a sum, and inside a long term's one parenthesised sum, m (a + b + ...) → m \\Big( a + b ... \\Big).
    """
    return _lines(_pieces(sp.sympify(expr), digits, first=True))


def _lines(pieces: list[str]) -> str:
    """Pieces of LaTeX joined into lines of about WIDTH characters (inside aligned, after &)."""
    lines, current = [], ""
    for piece in pieces:
        if current and _visible(current) + _visible(piece) > WIDTH:
            lines.append(current)
            current = piece
        else:
            current = f"{current} {piece}".strip()
    lines.append(current)
    return r" \\ &\quad ".join(lines)


def _visible(math: str) -> int:
    """About how many characters wide LaTeX math prints: a command one, \\left, \\right, braces,
    sub- and superscript marks none."""
    math = re.sub(r"\\(left|right|mathrm|operatorname|Big)\b", "", math)
    return len(re.sub(r"[{}^_ ]", "", re.sub(r"\\[A-Za-z]+", "x", math)))


def _pieces(expr, digits: int, first: bool) -> list[str]:
    """LaTeX pieces that may stand on lines of their own, each sum term with its sign."""
    text = latex(expr, digits)
    if _visible(text) <= (
        WIDTH if isinstance(expr, sp.Add) else 1.4 * WIDTH
    ):  # a term: split only if far too long
        return [text if first or text.startswith("-") else "+ " + text]
    if isinstance(expr, sp.Add):
        return [
            p for k, t in enumerate(sp.Add.make_args(expr)) for p in _pieces(t, digits, first and k == 0)
        ]
    if isinstance(expr, sp.Mul):
        sums = [f for f in expr.args if isinstance(f, sp.Add)]
        if len(sums) == 1:
            rest = sp.Mul(*[f for f in expr.args if f is not sums[0]])
            head = "" if rest == 1 else "-" if rest == -1 else latex(rest, digits)
            sign = "" if first or head.startswith("-") else "+ "
            return [rf"{sign}{head} \Big("] + _pieces(sums[0], digits, True) + [r"\Big)"]
    return [text if first or text.startswith("-") else "+ " + text]


def _display(math: str, kind: str) -> str:
    """Display math; in Markdown a block of its own (after a blank line: a `$$` that continues a
    paragraph is text to MyST and to Jupyter's renderer)."""
    return rf"\[ {math} \]" if kind == "latex" else f"\n$$ {math} $$\n"


PROSE = re.compile(r"(\\.|\$[^$]+\$|`[^`]+`)", re.S)  # a \-escaped character, $math$, `code`


def _prose(s: str, kind: str) -> str:
    """A step's text (see `Step`): $math$ kept, `code` as typewriter, the rest (and a \\-escaped
    character) as text of `kind`."""
    out = []
    for part in PROSE.split(s):
        if part.startswith("$"):
            out.append(part)
        elif part.startswith("`"):
            out.append(rf"\texttt{{{latex_text(part[1:-1])}}}" if kind == "latex" else part)
        else:
            plain = part[1:] if part.startswith("\\") else part
            out.append(latex_text(plain) if kind == "latex" else markdown_text(plain))
    return "".join(out)


class Cells:
    """Table cells of one kind of document: names as text, formulas as inline math."""

    def __init__(self, kind: str) -> None:
        self.kind = kind

    def name(self, s: str) -> str:
        return latex_text(s) if self.kind == "latex" else markdown_text(s)

    def math(self, m: str) -> str:  # a | of Markdown's math would end the table's cell
        return f"${m}$" if self.kind == "latex" else "$" + m.replace("|", r"\|") + "$"

    def body(self, body) -> str:
        return "the world" if body is None else self.name(body.name)


def _joint(joint, c: Cells) -> str:
    kind = type(joint).__name__
    if isinstance(joint, (Revolute, Prismatic)) and joint.mimic is not None:
        m = joint.mimic
        return (f"{kind}, axis {c.math(latex(joint.axis.T))}, follows {c.name(m.driver_name)}: "
                f"{c.math(latex(m.multiplier * m.driver.q + m.offset))}")
    if isinstance(joint, (Revolute, Prismatic, Cylindrical)):
        return f"{kind}, axis {c.math(latex(joint.axis.T))}"
    if isinstance(joint, Helical):
        return f"{kind}, axis {c.math(latex(joint.axis.T))}, pitch {c.math(latex(joint.pitch))}"
    if isinstance(joint, Universal):
        return f"{kind}, axes {c.math(latex(joint.axis1.T))}, {c.math(latex(joint.axis2.T))}"
    if isinstance(joint, (FreeFlyer, Spherical)):
        return f"{kind} ({joint.parametrization})"
    return kind


def _actuated(joint, c: Cells) -> str:
    """"actuated (τ_x)" with the joint's efforts, or "passive" (`actuated=False`)."""
    if not joint.dof:
        return "fixed"
    if not joint.actuated:
        return "passive"
    return "actuated " + c.math(", ".join(latex(t) for t in effort_symbols(joint)[: joint.efforts]))


def _load(load, c: Cells) -> tuple[str, str]:
    """The load's kind and what it is, with its points of action (body and coordinates in its frame)."""
    if isinstance(load, Force):
        return "force", f"{c.math(latex(load.force.T))}{_axes(load)} on {_point(load.point, c)}"
    if isinstance(load, Torque):
        return "torque", f"{c.math(latex(load.torque.T))}{_axes(load)} on {c.body(load.body)}"
    if isinstance(load, Actuator):
        what = [] if load.torque is None else [f"torque {c.math(latex(load.torque.T))}{_axes(load)}"]
        what += [] if load.force is None else [f"force {c.math(latex(load.force))} along the line"]
        return "actuator", (f"{' and '.join(what)} on {_point(load.a, c)}, reaction on {_point(load.b, c)}")
    if isinstance(load, Spring):
        stiffness = (c.math(f"k = {latex(load.stiffness)}") + ", "
                     + c.math(f"l_0 = {latex(load.rest_length)}"))
        return "spring", f"{stiffness}, between {_point(load.a, c)} and {_point(load.b, c)}"
    if isinstance(load, Damper):
        damping = c.math(f"c = {latex(load.damping)}")
        return "damper", f"{damping}, between {_point(load.a, c)} and {_point(load.b, c)}"
    return c.name(type(load).__name__), ""


def _axes(load) -> str:
    return " (body axes)" if load.in_body_frame else ""


def _point(point, c: Cells) -> str:
    """A point of action: its body (or the world) at its coordinates in that body's frame."""
    return f"{c.body(point.body)} at {c.math('(' + ', '.join(latex(x) for x in point.offset) + ')')}"


def _description(system: System, kind: str, digits: int) -> str:
    """Tables of the bodies (joint, mass, centre of mass, inertia) and the loads."""
    c = Cells(kind)
    header = ["body", "parent", "joint", "mass", "centre of mass", "inertia"]
    rows = [
        [
            c.name(b.name),
            c.body(b.parent),
            f"{c.name(b.joint.name)}: {_joint(b.joint, c)}, {_actuated(b.joint, c)}",
            c.math(latex(b.mass, digits)),
            c.math(latex(b.com.T, digits)),
            c.math(_inertia(b.inertia, digits)),
        ]
        for b in system.bodies
    ]
    g = f"Gravity ${latex(system.gravity.T, digits)}$; coordinates $q = {latex(system.q.T, digits)}$."
    loads = [[c.name(load.name), *_load(load, c)] for load in system.loads]
    parts = [g, _table(header, rows, kind)]
    if loads:
        parts.append(_table(["load", "kind", "what"], loads, kind))
    return "\n\n".join(parts)


def _inertia(I: sp.Matrix, digits: int) -> str:
    if I.is_zero_matrix:
        return "0"
    if I.is_diagonal():
        return rf"\operatorname{{diag}}({', '.join(latex(I[k, k], digits) for k in range(3))})"
    return latex(I, digits)


def _table(header: list[str], rows: list[list[str]], kind: str) -> str:
    """A table of cells already written for `kind` (see `Cells`)."""
    if kind == "markdown":
        lines = ["| " + " | ".join(header) + " |", "|" + "---|" * len(header)]
        return "\n".join(lines + ["| " + " | ".join(r) + " |" for r in rows])
    spec = "l" * len(header)
    lines = [
        rf"\begin{{center}}\small\begin{{tabular}}{{{spec}}}",
        r"\toprule",
        " & ".join(header) + r" \\",
        r"\midrule",
    ] + [" & ".join(r) + r" \\" for r in rows]
    return "\n".join(lines + [r"\bottomrule", r"\end{tabular}\end{center}"])
