"""How each language writes a generated function (`Syntax`): Python/NumPy (`PYTHON`), C (`C`; `C_TRIG`
reads sin and cos of the coordinates from arrays, as the extension passes them) and the functions each
prints sympy's under."""
from __future__ import annotations

import re
from dataclasses import dataclass, replace

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
    logic: tuple[str, str, str]  # and, or (infix, or calls of {a}, {b}), not ({c})
    nan: str  # a Piecewise's value where no condition holds
    functions: dict[str, str]  # sympy's function name: the name printed
    trig_q: str = "{f}({x})"  # sin / cos of q[k]; the extension reads them from arrays (sinq, cosq)
    segment: str = ""  # C: the header of a part of a long function (`FunctionWriter.source`), {name}
    call: str = ""  # the call of a part, {name}
    vector_trig: bool = False  # sin and cos of the coordinates in vector loops (`VECTOR_TRIG`)
    sqrt: str = "sqrt({x})"
    type: str = "double"  # C: the type of a variable (the values passed between parts)


# a long C function is split in parts the compiler does not merge back: its time grows faster than the length
NOINLINE = """#ifndef EOMGEN_NOINLINE
#if defined(__GNUC__)
#define EOMGEN_NOINLINE __attribute__((noinline))
#else
#define EOMGEN_NOINLINE
#endif
#endif"""
SEGMENT = 1000  # operations per part
# plain C: sin and cos of the coordinates in two loops that the compiler turns into glibc's vector sin and
# cos (libmvec, within 4 ulp; part of -lm on x86-64 Linux), as wide as the machine it compiles for
VECTOR_TRIG = """#if defined(__GNUC__) && !defined(__clang__) && defined(__x86_64__) && defined(__GLIBC__) \\
    && !defined(EOMGEN_NO_MVEC)
__attribute__((simd("notinbranch"))) extern double sin(double);
__attribute__((simd("notinbranch"))) extern double cos(double);
#endif"""
LANES = 8  # the trig loops run over a multiple of this: no remainder loop
NAMES = re.compile(r"\b_[A-Za-z_]+[0-9]+\b")  # the variables of generated code: _x3, _q0, _sin_q1, ...


PYTHON = Syntax(header="def {name}(q, u, ud, p, out, sin, cos, sqrt, m):", input="    {var} = {arg}[{k}]",
                assign="    {var} = {expr}", out="    out[{i}, {j}] = {expr}",
                mirror="    out[{j}, {i}] = out[{i}, {j}]", footer="    return out",
                power="m.power({b}, {e})",
                select="m.where({c}, {a}, {b})", sign="m.sign({x})", heaviside="m.heaviside({x}, {h})",
                logic=("&", "|", "m.logical_not({c})"), nan="m.nan", functions=NUMPY_FUNCTIONS)
C = Syntax(header="void {name}(const double *q, const double *u, const double *ud, const double *p, "
                  "double *out)\n{{",
           input="    const double {var} = {arg}[{k}];", assign="    const double {var} = {expr};",
           out="    out[{ij}] = {expr};", mirror="    out[{ji}] = out[{ij}];", footer="}}",
           power="pow({b}, {e})",
           select="({c} ? {a} : {b})", sign="(({x} > 0) ? 1.0 : ({x} < 0) ? -1.0 : 0.0 * {x})",
           heaviside="(({x} > 0) ? 1.0 : ({x} < 0) ? 0.0 : {h} + 0.0 * {x})", logic=("&&", "||", "(!{c})"),
           nan="NAN", functions=C_FUNCTIONS,
           segment="static EOMGEN_NOINLINE void {name}(const double *q, const double *u, const double *ud, "
                   "const double *p, double *out, double *X)\n{{", call="    {name}(q, u, ud, p, out, X);",
           vector_trig=True)
_TRIG_ARGS = ("const double *q, const double *u, const double *ud, const double *p, const double *sinq, "
              "const double *cosq")
C_TRIG = replace(C, header="static void {name}(" + _TRIG_ARGS + ", double *out)\n{{", trig_q="{f}q[{k}]",
                 vector_trig=False,
                 segment="static EOMGEN_NOINLINE void {name}(" + _TRIG_ARGS
                         + ", double *out, double *X)\n{{",
                 call="    {name}(q, u, ud, p, sinq, cosq, out, X);")
