"""A worked solution and its renderings: a LaTeX document (pdflatex), Markdown with math, and the
Jupyter display. Step texts carry their formulas as $...$ math and `code` in backticks."""

from __future__ import annotations

import re
import shutil
import subprocess
import tempfile
from dataclasses import dataclass
from pathlib import Path

import sympy as sp

from ..errors import ModelError
from ..model import Cylindrical, FreeFlyer, Helical, Prismatic, Revolute, Spherical, Universal
from ..model.loads import Actuator, Damper, Force, Spring, Torque
from ..model.system import System
from ..printing import escape, latex, text

WIDTH = 90  # characters of LaTeX per line of a long sum
METHOD_TITLES = {
    "free_cut": "Newton-Euler with a free cut",
    "projected_newton_euler": "Projected Newton-Euler",
    "lagrange": "Lagrange II",
    "recursive": "Recursive Newton-Euler (body frames)",
    "kane": "Kane's method",
    None: "Kinematics",
}
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
        for section, steps in self._sections():
            body.append(rf"\section{{{section}}}")
            for step in steps:
                body.append(rf"\subsection*{{{step.title}}}")
                body.append(_prose(step.text, "latex"))
                body.extend(_blocks(step, "latex", digits))
        document = "\n".join(
            [
                PREAMBLE,
                rf"\title{{{escape(self.title)}}}",
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
        exe = shutil.which(engine)
        if exe is None:
            raise ModelError(
                f"no LaTeX engine {engine!r} on this machine: install one (TeX Live's pdflatex) "
                "or write the .tex with solution.latex(path)"
            )
        path = Path(path)
        with tempfile.TemporaryDirectory() as folder:
            (Path(folder) / "solution.tex").write_text(self.latex(digits=digits), encoding="utf-8")
            run = subprocess.run(
                [exe, "-interaction=nonstopmode", "-halt-on-error", "solution.tex"],
                cwd=folder,
                capture_output=True,
                text=True,
            )
            if run.returncode != 0:
                raise ModelError(f"{engine} failed:\n{run.stdout[-2000:]}")
            shutil.copy(Path(folder) / "solution.pdf", path)
        return path

    def markdown(self, path=None, digits: int = 4) -> str:
        """The same as Markdown with $$ math; written to `path` if given."""
        out = [f"# {self.title}", "", "## The system", "", _description(self.system, "markdown", digits)]
        for section, steps in self._sections():
            out += ["", f"## {section}"]
            for step in steps:
                out += ["", f"### {step.title}", "", _prose(step.text, "markdown"), ""]
                out.extend(_blocks(step, "markdown", digits))
        return _write(path, "\n".join(out) + "\n")

    def _sections(self):
        sections: list = []
        for step in self.steps:
            name = (
                METHOD_TITLES.get(step.method, step.method)
                if step.title != "Comparison of the methods"
                else "Comparison"
            )
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
\setcounter{MaxMatrixCols}{20}"""


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
        return rf"\text{{{escape(name)}}}"
    return latex(sp.Symbol(name)) if name.isidentifier() and len(name) <= 3 else rf"\text{{{escape(name)}}}"


def _blocks(step, kind: str, digits: int) -> list[str]:
    """Display math for each expression (and the shared definitions first)."""
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
    return lines


def _math(expr, digits: int) -> str:
    if (
        isinstance(expr, sp.MatrixBase)
        and expr.cols == 1
        and expr.rows > 0
        and len(latex(expr, digits)) > WIDTH
    ):
        rows = [_broken(e, digits) for e in expr]
        return (
            r"\begin{bmatrix}"
            + r" \\ ".join(rf"\begin{{aligned}}&{r}\end{{aligned}}" for r in rows)
            + r"\end{bmatrix}"
        )
    if isinstance(expr, sp.MatrixBase) and len(latex(expr, digits)) > 4 * WIDTH:
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
    lines, current = [], ""
    for piece in _pieces(sp.sympify(expr), digits, first=True):
        if current and len(current) + len(piece) > WIDTH:
            lines.append(current)
            current = piece
        else:
            current = f"{current} {piece}".strip()
    lines.append(current)
    return r" \\ &\quad ".join(lines)


def _pieces(expr, digits: int, first: bool) -> list[str]:
    """LaTeX pieces that may stand on lines of their own, each sum term with its sign."""
    text = latex(expr, digits)
    if len(text) <= (
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
    return rf"\[ {math} \]" if kind == "latex" else f"$$ {math} $$\n"


def _prose(s: str, kind: str) -> str:
    """A step's text: $math$ kept, `code` as typewriter, the rest escaped (LaTeX)."""
    if kind == "markdown":
        return s
    out = []
    for part in re.split(r"(\$[^$]+\$|`[^`]+`)", s):
        if part.startswith("$"):
            out.append(part)
        elif part.startswith("`"):
            out.append(rf"\texttt{{{escape(part[1:-1])}}}")
        else:
            out.append(escape(part))
    return "".join(out)


def _joint(joint) -> str:
    kind = type(joint).__name__
    if isinstance(joint, (Revolute, Prismatic)) and joint.mimic is not None:
        m = joint.mimic
        return (f"{kind}, axis ${latex(joint.axis.T)}$, follows {escape(m.driver_name)}: "
                f"${latex(m.multiplier * m.driver.q + m.offset)}$")
    if isinstance(joint, (Revolute, Prismatic, Cylindrical)):
        return f"{kind}, axis ${latex(joint.axis.T)}$"
    if isinstance(joint, Helical):
        return f"{kind}, axis ${latex(joint.axis.T)}$, pitch ${latex(joint.pitch)}$"
    if isinstance(joint, Universal):
        return f"{kind}, axes ${latex(joint.axis1.T)}$, ${latex(joint.axis2.T)}$"
    if isinstance(joint, (FreeFlyer, Spherical)):
        return f"{kind} ({joint.parametrization})"
    return kind


def _load(load) -> tuple[str, str]:
    if isinstance(load, Force):
        return "force", f"${latex(load.force.T)}$ on {_body(load.point.body)}"
    if isinstance(load, Torque):
        return "torque", f"${latex(load.torque.T)}$ on {_body(load.body)}"
    if isinstance(load, Actuator):
        return "actuator", f"between {_body(load.a.body)} and {_body(load.b.body)}"
    if isinstance(load, Spring):
        return (
            "spring",
            (
                f"$k = {latex(load.stiffness)}$, $l_0 = {latex(load.rest_length)}$, "
                f"{_body(load.a.body)} to {_body(load.b.body)}"
            ),
        )
    if isinstance(load, Damper):
        return "damper", f"$c = {latex(load.damping)}$"
    return type(load).__name__, ""


def _body(body) -> str:
    return "the world" if body is None else body.name


def _description(system: System, kind: str, digits: int) -> str:
    """Tables of the bodies (joint, mass, centre of mass, inertia) and the loads."""
    header = ["body", "parent", "joint", "mass", "centre of mass", "inertia"]
    rows = [
        [
            b.name,
            _body(b.parent),
            f"{b.joint.name}: {_joint(b.joint)}",
            f"${latex(b.mass, digits)}$",
            f"${latex(b.com.T, digits)}$",
            f"${_inertia(b.inertia, digits)}$",
        ]
        for b in system.bodies
    ]
    g = f"Gravity ${latex(system.gravity.T, digits)}$; coordinates $q = {latex(system.q.T, digits)}$."
    loads = [[load.name, *_load(load)] for load in system.loads]
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
    def cell(c: str) -> str:  # names escaped, math kept
        return (
            c
            if kind == "markdown"
            else "".join(
                part if part.startswith("$") else escape(part) for part in re.split(r"(\$[^$]*\$)", c)
            )
        )

    if kind == "markdown":
        lines = ["| " + " | ".join(header) + " |", "|" + "---|" * len(header)]
        return "\n".join(lines + ["| " + " | ".join(c.replace("|", r"\|") for c in r) + " |" for r in rows])
    spec = "l" * len(header)
    lines = [
        rf"\begin{{center}}\small\begin{{tabular}}{{{spec}}}",
        r"\toprule",
        " & ".join(header) + r" \\",
        r"\midrule",
    ] + [" & ".join(cell(c) for c in r) + r" \\" for r in rows]
    return "\n".join(lines + [r"\bottomrule", r"\end{tabular}\end{center}"])
