"""Batches in vector registers: each generated function printed a second time with GCC's vector types
(`vd`, W doubles: 8 with AVX-512, 4 with AVX, else 2), so that one call evaluates W states at once,
structure of arrays (q[k] holds the k-th coordinate of W states). The same `FunctionWriter` prints it,
long functions split in parts as in C. Numbers and parameters broadcast to all lanes (`VD`); sin and
cos of q in the lanes (`v_sincos`), the other functions lane by lane (sin, cos in libmvec's vector
versions where that loop vectorizes). Functions with branches (Piecewise, sign, Heaviside) are not
printed: they keep the scalar batch loop. `DRIVER` transposes the states in W x W tiles (`gather`), the
outputs back through an aligned stage (`scatter`, `put`; non-temporal stores past 16 MB).

The vector functions are a module of their own (`lanes_source`), printed and compiled on the first batch
(twice the C of the per-state functions to compile: a build that never batches does not pay for it),
with `DRIVER`, which it hands with the table of its functions to the module of the per-state functions
(`build.lanes.HANDOVER`)."""

from __future__ import annotations

from dataclasses import replace

import sympy as sp

from ..subexpressions import Subexpressions
from .build.lanes import DRIVER, HANDOVER, TYPES, sizes
from .syntax import C_FUNCTIONS, C_TRIG
from .walker import FunctionWriter

BRANCHES = (sp.Piecewise, sp.sign, sp.Heaviside)  # printed by the scalar syntax only

_ARGS = "const vd *q, const vd *u, const vd *ud, const vd *p, const vd *sinq, const vd *cosq"
C_VECTOR = replace(
    C_TRIG,
    header="static void {name}(" + _ARGS + ", vd *out)\n{{",
    input="    const vd {var} = {arg}[{k}];",
    assign="    const vd {var} = VD({expr});",
    out="    out[{ij}] = VD({expr});",
    power="v_pow({b}, {e})",
    sqrt="v_sqrt({x})",
    functions={k: f"v_{f}" for k, f in C_FUNCTIONS.items()},
    type="vd",
    segment="static EOMGEN_NOINLINE void {name}(" + _ARGS + ", vd *out, vd *X)\n{{",
)


def lanes_source(name: str, sources: list[str | None], nq: int, nv: int, n_params: int) -> str:
    """The extension module `name` of the vector functions `w<i>` (None: none for function i), whose
    attribute `lanes` hands them and their batched loop to the module of the per-state functions
    (`extension`)."""
    table = ", ".join(f"(eomgen_any)w{i}" if source else "NULL" for i, source in enumerate(sources))
    return "\n".join(
        [
            "#define PY_SSIZE_T_CLEAN\n#include <Python.h>\n#include <numpy/npy_common.h>\n#include <math.h>",
            "#include <stdint.h>\n#include <stdlib.h>\n#include <string.h>",
            sizes(nq, nv, n_params, len(sources)),
            TYPES,
            HANDOVER,
            DRIVER,
            *(source for source in sources if source),
            f"static const eomgen_any functions[] = {{{table or 'NULL'}}};",
            "static eomgen_lanes table = {driver, functions};",
            f'static struct PyModuleDef module = {{PyModuleDef_HEAD_INIT, "{name}", NULL, -1, NULL}};',
            f"PyMODINIT_FUNC PyInit_{name}(void)\n{{\n    PyObject *m = PyModule_Create(&module);",
            '    PyObject *c = m ? PyCapsule_New(&table, "eomgen.lanes", NULL) : NULL;',
            '    if (m != NULL && (c == NULL || PyModule_AddObject(m, "lanes", c) < 0)) {',
            "        Py_XDECREF(c);\n        Py_CLEAR(m);\n    }\n    return m;\n}\n",
        ]
    )


def vector_sources(writer: FunctionWriter, exprs, count: int) -> list[str | None]:
    """C of w<i> for W states at once, from the (expr, symmetric) in turn (None: a composite), by a writer
    of syntax `C_VECTOR`; None for a composite, where an expr branches (the scalar batch loop evaluates it)
    and for the rest of the `count` functions (those with no vector function)."""
    sources = [None if pair is None or branches(writer.sub, pair[0]) else writer.source(f"w{i}", *pair)[0]
               for i, pair in enumerate(exprs)]
    return sources + [None] * (count - len(sources))


def branches(sub: Subexpressions, expr: sp.Basic) -> bool:
    """Whether `expr` or an intermediate it reads holds a Piecewise, sign or Heaviside."""
    exprs = list(expr) if isinstance(expr, sp.MatrixBase) else [sp.sympify(expr)]
    return any(e.has(*BRANCHES) for e in (*exprs, *(sub.definitions[s] for s in sub.dependencies(exprs))))
