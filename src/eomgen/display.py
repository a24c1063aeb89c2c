"""How equations show themselves in Jupyter: M(q) q̈ + b + g = τ + Sᵀ τ_a with its parts, sizes and
method; the parts in textbook form for small systems (a few seconds at most), sizes only otherwise."""

from __future__ import annotations

import sympy as sp

from .errors import ModelError
from .escaping import markdown_text
from .printing import latex
from .textbook import Simplifier

SMALL = 4  # speeds up to which the parts are shown
LONG = 6000  # characters of LaTeX beyond which they are not


def _parts(equations, items) -> list[str]:
    """The parts in textbook form, or a note when they are too long to read or have no closed form."""
    simplifier = Simplifier([b.mass for b in equations.system.bodies], max_ops=800, seconds=3.0)
    try:
        parts = [rf"{name} &= {latex(simplifier.matrix(sp.Matrix(value())))}" for name, value in items]
    except ModelError:  # Kane's closed forms need pivots proven nonzero
        return [r"&\text{(no closed form: the generated code, eg.codegen, solves numerically)}"]
    if sum(map(len, parts)) > LONG:
        return [r"&\text{(the parts are long: see eg.solution or the generated code)}"]
    return parts


def equations_math(eom) -> str:
    """The equation, and for small systems M, b, g, τ (LaTeX, aligned)."""
    n = len(eom.u)
    lines = [
        r"M(q)\, \ddot q + b(q, \dot q) + g(q) &= \tau(q, \dot q) + S^{T} \tau_a",
        rf"q &= {latex(eom.q.T)}^{{T}}",
    ]
    derived = [k for k in ("M", "b", "g") if k in eom.compact]
    if n <= SMALL:
        lines += _parts(
            eom,
            [(k, lambda k=k: eom._closed_form(k)) for k in derived]
            + [(r"\tau", lambda: eom.tau), ("S", lambda: eom.S)],
        )
    return r"\begin{aligned}" + r" \\ ".join(lines) + r"\end{aligned}"


def equations_markdown(eom) -> str:
    n = len(eom.u)
    sizes = ", ".join(f"{k}: {n}×{n if k == 'M' else 1}" for k in ("M", "b", "g") if k in eom.compact)
    loads = ", ".join(map(markdown_text, eom.load_names)) or "none"
    return (
        f"**Equations of motion** by `{eom.method}`: {n} speeds ({sizes}); loads: {loads}; "
        f"S: {eom.S.rows}×{n}.\n\n$$ {equations_math(eom)} $$\n"
    )


def kane_math(k) -> str:
    """Kane's equations M̃ ẇ_ind = f̃ and q̇, their parts for small systems."""
    lines = [
        r"\tilde M(q)\, \dot w_{ind} &= \tilde f(q, w_{ind})",
        rf"w_{{ind}} &= {latex(sp.Matrix(k.independent).T)}^{{T}}",
    ]
    if len(k.speeds) <= SMALL:
        lines += _parts(
            k,
            [
                (r"\tilde M", lambda: k.mass_matrix),
                (r"\tilde f", lambda: k.forcing),
                (r"\dot q", lambda: k.qdot),
            ],
        )
    return r"\begin{aligned}" + r" \\ ".join(lines) + r"\end{aligned}"


def kane_markdown(k) -> str:
    n, p, h = len(k.speeds), len(k.independent), len(k.dependent_coordinates)
    dependent = latex(sp.Matrix(k.dependent_coordinates).T)
    holonomic = f" ({h} from holonomic constraints in ${dependent}$)" if h else ""
    return (
        f"**Kane's equations**: {n} speeds, {n - p} velocity constraints{holonomic}, {p} equations.\n\n"
        f"$$ {kane_math(k)} $$\n"
    )
