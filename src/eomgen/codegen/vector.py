"""Batches in vector registers: each generated function printed a second time with GCC's vector types
(`vd`, W doubles: 8 with AVX-512, 4 with AVX, else 2), so that one call evaluates W states at once,
structure of arrays (q[k] holds the k-th coordinate of W states). The same `FunctionWriter` prints it,
long functions split in parts as in C. Numbers and parameters broadcast to all lanes (`VD`); the other
functions run lane by lane, sin and cos in libmvec's vector versions where the loop vectorizes.
Functions with branches (Piecewise, sign, Heaviside) are not printed: they keep the scalar batch loop.

The module is built for the machine it runs on (-march=native): its cache key holds `machine()`."""
from __future__ import annotations

import platform
from dataclasses import replace
from functools import cache
from pathlib import Path

import sympy as sp

from ..subexpressions import Subexpressions
from .numpy_backend import C_FUNCTIONS, C_TRIG, FunctionWriter

UNARY = ("sin", "cos", "tan", "exp", "log", "asin", "acos", "atan", "sinh", "cosh", "tanh", "fabs", "sqrt")
BINARY = ("atan2", "pow", "fmin", "fmax")
BRANCHES = (sp.Piecewise, sp.sign, sp.Heaviside)  # printed by the scalar syntax only

_ARGS = "const vd *q, const vd *u, const vd *ud, const vd *p, const vd *sinq, const vd *cosq"
C_VECTOR = replace(C_TRIG, header="static void {name}(" + _ARGS + ", vd *out)\n{{",
                   input="    const vd {var} = {arg}[{k}];", assign="    const vd {var} = VD({expr});",
                   out="    out[{ij}] = VD({expr});", power="v_pow({b}, {e})", sqrt="v_sqrt({x})",
                   functions={k: f"v_{f}" for k, f in C_FUNCTIONS.items()}, type="vd",
                   segment="static EOMGEN_NOINLINE void {name}(" + _ARGS + ", vd *out, vd *X)\n{{")


def lanes(name: str, arity: int) -> str:
    """C of v_<name>: `name` applied lane by lane; numbers broadcast first."""
    args = ", ".join(f"vd x{k}" for k in range(arity))
    each = ", ".join(f"x{k}[l]" for k in range(arity))
    given = ", ".join(f"x{k}" for k in range(arity))
    return (f"static inline vd v_{name}_({args})\n{{ vd r; for (int l = 0; l < W; ++l) r[l] = {name}({each}); "
            f"return r; }}\n#define v_{name}({given}) v_{name}_({', '.join(f'VD(x{k})' for k in range(arity))})")


PRELUDE = r"""/* W states at a time in vector registers (GCC's vector extension), structure of arrays */
#if defined(__AVX512F__)
#define W 8
#elif defined(__AVX__)
#define W 4
#else
#define W 2
#endif
typedef double vd __attribute__((vector_size(W * sizeof(double))));
#define VD(x) _Generic((x), vd: (x), default: (vd){0} + (x))  /* numbers and doubles to all lanes */
""" + "\n".join([lanes(f, 1) for f in UNARY] + [lanes(f, 2) for f in BINARY]) + r"""

typedef void (*eomgen_vfn)(const vd *, const vd *, const vd *, const vd *, const vd *, const vd *, vd *);

/* xv[j][l] = x[l * stride + j], j < n, for the m states from x; the first state in the lanes past m */
static void gather(const double *x, npy_intp stride, int m, int n, vd *xv)
{
    for (int j = 0; j < n; ++j)
        for (int l = 0; l < W; ++l)
            xv[j][l] = x[(l < m ? l : 0) * stride + j];
}

/* N states, W at a time, over the cores for large N: every entry of out (N x size) is written. 0, or -1
   when out of memory */
static int batch_vector(eomgen_vfn f, const int *idx, int nt, npy_intp size, npy_intp n, const double *q,
                        const double *u, npy_intp su, const double *ud, npy_intp sud, const double *p,
                        double *out)
{
    int failed = 0;
    npy_intp blocks = (n + W - 1) / W;
    #pragma omp parallel if (n >= 1024)
    {
        size_t count = 3 * NQ + 2 * NV + NP + size;  /* q, sin q, cos q, u, ud, p, out */
        vd *qv = aligned_alloc(sizeof(vd), count * sizeof(vd));
        vd *sinq = qv + NQ, *cosq = sinq + NQ, *uv = cosq + NQ, *udv = uv + NV, *pv = udv + NV, *ov = pv + NP;
        if (qv != NULL) {
            memset(qv, 0, count * sizeof(vd));  /* the entries f does not write stay 0 */
            for (int j = 0; j < NP; ++j)
                pv[j] = VD(p[j]);
        }
        #pragma omp for schedule(static)
        for (npy_intp b = 0; b < blocks; ++b) {
            npy_intp k0 = b * W;
            int m = n - k0 < W ? (int)(n - k0) : W;
            if (qv == NULL) {
                failed = 1;
                continue;
            }
            gather(q + k0 * NQ, NQ, m, NQ, qv);
            gather(u + k0 * su, su, m, NV, uv);
            gather(ud + k0 * sud, sud, m, NV, udv);
            for (int t = 0; t < nt; ++t) {
                sinq[idx[t]] = v_sin(qv[idx[t]]);
                cosq[idx[t]] = v_cos(qv[idx[t]]);
            }
            f(qv, uv, udv, pv, sinq, cosq, ov);
            for (int l = 0; l < m; ++l) {
                double *o = out + (k0 + l) * size;
                for (npy_intp i = 0; i < size; ++i)
                    o[i] = ov[i][l];
            }
        }
        free(qv);
    }
    return failed ? -1 : 0;
}
"""


def vector_source(writer: FunctionWriter, name: str, expr: sp.Basic, symmetric: bool) -> str | None:
    """C of `name`, `expr` for W states at once by a writer of syntax `C_VECTOR`; None when `expr`
    branches (the scalar batch loop evaluates it)."""
    if branches(writer.sub, expr):
        return None
    return writer.source(name, expr, symmetric)[0]


def branches(sub: Subexpressions, expr: sp.Basic) -> bool:
    """Whether `expr` or an intermediate it reads holds a Piecewise, sign or Heaviside."""
    exprs = list(expr) if isinstance(expr, sp.MatrixBase) else [sp.sympify(expr)]
    return any(e.has(*BRANCHES) for e in (*exprs, *(sub.definitions[s] for s in sub.dependencies(exprs))))


@cache
def machine() -> str:
    """What -march=native compiles for: the CPU's model and flags (Linux), else the platform's name."""
    try:
        info = Path("/proc/cpuinfo").read_text()
    except OSError:
        return platform.machine() + " " + platform.processor()
    keys = ("model name", "flags", "Features", "CPU part")
    return "\n".join(sorted({line for line in info.splitlines() if line.split(":")[0].strip() in keys}))
