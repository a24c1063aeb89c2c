"""The C every vector batch needs, in the module of vector functions: the vector type `vd` of W doubles
(8 with AVX-512, 4 with AVX, else 2) and the functions lane by lane (`TYPES`), and the batched loop
(`DRIVER`) that transposes the states in W x W tiles (`gather`), calls a vector function and writes the
outputs back through an aligned stage (`scatter`, `put`; non-temporal stores past 16 MB). That module
hands its loop and functions to the extension's glue (`HANDOVER`), which so compiles none of it up front
(the intrinsics' headers alone were half the glue's compile time). Both are built for the machine they
run on (-march=native): the cache key holds `machine()`."""
from __future__ import annotations

import platform
from functools import cache
from pathlib import Path

UNARY = ("sin", "cos", "tan", "exp", "log", "asin", "acos", "atan", "sinh", "cosh", "tanh", "fabs", "sqrt")
BINARY = ("atan2", "pow", "fmin", "fmax")


def lanes(name: str, arity: int) -> str:
    """C of v_<name>: `name` applied lane by lane; numbers broadcast first."""
    args = ", ".join(f"vd x{k}" for k in range(arity))
    each = ", ".join(f"x{k}[l]" for k in range(arity))
    given = ", ".join(f"x{k}" for k in range(arity))
    return (
        f"static inline vd v_{name}_({args})\n{{ vd r; for (int l = 0; l < W; ++l) r[l] = {name}({each}); "
        f"return r; }}\n#define v_{name}({given}) v_{name}_({', '.join(f'VD(x{k})' for k in range(arity))})"
    )


def transpose() -> str:
    """C of transpose(r): the W x W matrix of rows r[0..W-1] transposed in registers, for each W, by
    swapping the off-diagonal blocks of size h = W/2, ..., 1 (two shuffles per pair of rows)."""
    lines = [
        "#ifdef __clang__",
        "#define SHUFFLE(a, b, ...) __builtin_shufflevector(a, b, __VA_ARGS__)",
        "#else",
        "#define SHUFFLE(a, b, ...) __builtin_shuffle(a, b, (vl){__VA_ARGS__})",
        "#endif",
        "static inline void transpose(vd *r)",
        "{",
    ]
    for w in (8, 4, 2):
        lines.append(f"#{'if' if w == 8 else 'elif'} W == {w}")
        h = w // 2
        while h:
            for i in (i for i in range(w) if not i & h):
                low = [k if not k & h else w + k - h for k in range(w)]
                high = [k + h if not k & h else w + k for k in range(w)]
                lines.append(
                    f"    {{ vd a = r[{i}], b = r[{i + h}]; r[{i}] = SHUFFLE(a, b,"
                    f" {', '.join(map(str, low))}); r[{i + h}] = SHUFFLE(a, b,"
                    f" {', '.join(map(str, high))}); }}"
                )
            h //= 2
    return "\n".join(lines + ["#endif", "}"])


TYPES = (
    r"""/* W states at a time in vector registers (GCC's vector extension), structure of arrays */
#if defined(__AVX512F__)
#define W 8
#elif defined(__AVX__)
#define W 4
#else
#define W 2
#endif
typedef double vd __attribute__((vector_size(W * sizeof(double))));
typedef long long vl __attribute__((vector_size(W * sizeof(double))));
typedef unsigned long long vu __attribute__((vector_size(W * sizeof(double))));
#define VD(x) _Generic((x), vd: (x), default: (vd){0} + (x))  /* numbers and doubles to all lanes */
"""
    + "\n".join([lanes(f, 1) for f in UNARY] + [lanes(f, 2) for f in BINARY])
    + r"""

typedef void (*eomgen_vfn)(const vd *, const vd *, const vd *, const vd *, const vd *, const vd *, vd *);
"""
)

# what the module of vector functions hands to the glue (`_attach`): its batched loop and its functions
HANDOVER = r"""/* the vector functions w<i> (NULL: none) and their batched loop, opaque to the glue */
typedef void (*eomgen_any)(void);
typedef int (*eomgen_driver)(eomgen_any, const int *, int, npy_intp, npy_intp, const double *,
                             const double *, npy_intp, const double *, npy_intp, const double *, double *);
typedef struct { eomgen_driver driver; const eomgen_any *table; } eomgen_lanes;
"""

# the batched loop of the module of vector functions (`driver`: for a function handed over)
DRIVER = transpose() + r"""

/* sin and cos of x: x - n π/2 (π/2 in three parts, each product exact for |n| < 2^20) into [-π/4, π/4],
   fdlibm's polynomials there, n mod 4 choosing and signing them (for |x| up to BIG) */
#define BIG 1e5
static inline void v_sincos(vd x, vd *s, vd *c)
{
    const double shift = 0x1.8p52;  /* t's low bits: n mod 2^51 */
    vd t = x * 6.36619772367581382433e-01 + shift, n = t - shift;
    vu k = (vu)t, odd = -(k & 1);
    vd r = x - n * 1.57079632673412561417e+00;
    r = r - n * 6.07710050630396597660e-11;
    r = r - n * 2.02226624871116645580e-21;
    vd z = r * r;
    vd sr = r + r * z * (-1.66666666666666324348e-01 + z * (8.33333333332248946124e-03 + z * (
        -1.98412698298579493134e-04 + z * (2.75573137070700676789e-06 + z * (-2.50507602534068634195e-08
        + z * 1.58969099521155010221e-10)))));
    vd cr = 1.0 - 0.5 * z + z * z * (4.16666666666666019037e-02 + z * (-1.38888888888741095749e-03 + z * (
        2.48015872894767294178e-05 + z * (-2.75573143513906633035e-07 + z * (2.08757232129817482790e-09
        + z * -1.13596475577881948265e-11)))));
    *s = (vd)((((vu)sr & ~odd) | ((vu)cr & odd)) ^ ((k & 2) << 62));
    *c = (vd)((((vu)cr & ~odd) | ((vu)sr & odd)) ^ (((k + 1) & 2) << 62));
}

/* sinq[j], cosq[j] for the nt indices j = idx[t] of the angles qv; libm's in the lanes past BIG */
static void trig_lanes(const vd *qv, const int *idx, int nt, vd *sinq, vd *cosq)
{
    vl big = {0};
    for (int t = 0; t < nt; ++t) {
        v_sincos(qv[idx[t]], sinq + idx[t], cosq + idx[t]);
        big |= (vd)((vu)qv[idx[t]] & 0x7fffffffffffffffULL) > BIG;
    }
    long long any = 0;
    for (int l = 0; l < W; ++l)
        any |= big[l];
    for (int t = 0; any && t < nt; ++t)
        for (int l = 0; l < W; ++l)
            if (fabs(qv[idx[t]][l]) > BIG) {
                sinq[idx[t]][l] = sin(qv[idx[t]][l]);
                cosq[idx[t]][l] = cos(qv[idx[t]][l]);
            }
}

/* v stored past the caches (non-temporal: the line is not read first); p aligned to a vector */
#if W == 8 && defined(__AVX512F__)
#include <immintrin.h>
#define STREAM(p, v) _mm512_stream_pd(p, (__m512d)(v))
#elif W == 4 && defined(__AVX__)
#include <immintrin.h>
#define STREAM(p, v) _mm256_stream_pd(p, (__m256d)(v))
#elif W == 2 && defined(__SSE2__)
#include <immintrin.h>
#define STREAM(p, v) _mm_stream_pd(p, (__m128d)(v))
#else
#define STREAM(p, v) memcpy(p, &(v), sizeof(vd))
#endif
#if defined(__SSE2__)
#define FENCE() _mm_sfence()
#else
#define FENCE() __sync_synchronize()
#endif

/* out[i] = stage[i], i < count: the whole vectors of out by aligned stores (streamed: by STREAM) */
static void put(const double *stage, npy_intp count, double *out, int streamed)
{
    npy_intp i = 0;
    for (; i < count && (uintptr_t)(out + i) % sizeof(vd); ++i)
        out[i] = stage[i];
    for (; i + W <= count; i += W) {
        vd v;
        memcpy(&v, stage + i, sizeof v);
        if (streamed)
            STREAM(out + i, v);
        else
            *(vd *)(out + i) = v;
    }
    for (; i < count; ++i)
        out[i] = stage[i];
}


/* xv[j][l] = x[l * stride + j], j < n, for the m states from x (`size` doubles there); the first state in
   the lanes past m. A full block in W x W tiles (the last one overlapping the one before it, or past n when
   n < W); a row that would run past x's end is copied to n */
static void gather(const double *x, npy_intp stride, npy_intp size, int m, int n, vd *xv)
{
    if (m < W) {
        for (int j = 0; j < n; ++j)
            for (int l = 0; l < W; ++l)
                xv[j][l] = x[(l < m ? l : 0) * stride + j];
        return;
    }
    for (int j = 0; j < n; j += W) {
        int j0 = n >= W && j + W > n ? n - W : j, count = n - j0 < W ? n - j0 : W;
        vd r[W] = {0};
        for (int l = 0; l < W; ++l)
            if (l * stride + j0 + W <= size)
                memcpy(&r[l], x + l * stride + j0, sizeof(vd));
            else
                for (int k = 0; k < count; ++k)
                    r[l][k] = x[l * stride + j0 + k];
        transpose(r);
        for (int k = 0; k < count; ++k)
            xv[j0 + k] = r[k];
    }
}

/* out[l * size + i] = ov[i][l], i < size, for the m states of a block; a full one in W x W tiles as
   `gather` (ov holds at least W entries: a row past size lands in the next state's entries, written
   after) */
static void scatter(const vd *ov, npy_intp size, int m, double *out)
{
    if (m < W) {
        for (int l = 0; l < m; ++l)
            for (npy_intp i = 0; i < size; ++i)
                out[l * size + i] = ov[i][l];
        return;
    }
    for (npy_intp i = 0; i < size; i += W) {
        npy_intp i0 = size >= W && i + W > size ? size - W : i, count = size - i0 < W ? size - i0 : W;
        vd r[W];
        memcpy(r, ov + i0, sizeof r);
        transpose(r);
        for (int l = 0; l < W; ++l)
            if (l * size + i0 + W <= W * size)
                memcpy(out + l * size + i0, &r[l], sizeof(vd));
            else
                for (npy_intp k = 0; k < count; ++k)
                    out[l * size + i0 + k] = r[l][k];
    }
}

#define STREAMED (16 << 20)  /* bytes of output past which it is streamed (too large for the caches) */

/* N states, W at a time, over the cores for large N: every entry of out (N x size) is written. 0, or -1
   when out of memory */
static int batch_vector(eomgen_vfn f, const int *idx, int nt, npy_intp size, npy_intp n, const double *q,
                        const double *u, npy_intp su, const double *ud, npy_intp sud, const double *p,
                        double *out)
{
    int failed = 0, streamed = n * size * sizeof(double) > STREAMED;
    npy_intp blocks = (n + W - 1) / W;
    #pragma omp parallel if (n >= 1024)
    {
        /* q, sin q, cos q, u, ud, p, out (at least W entries), the output's stage */
        size_t count = 3 * NQ + 2 * NV + NP + (size > W ? size : W) + size;
        vd *qv = aligned_alloc(sizeof(vd), count * sizeof(vd));  /* u, ud absent: zeros throughout */
        vd *sinq = qv + NQ, *cosq = sinq + NQ, *uv = cosq + NQ, *udv = uv + NV, *pv = udv + NV;
        vd *ov = pv + NP;
        double *stage = (double *)(ov + (size > W ? size : W));
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
            gather(q + k0 * NQ, NQ, (n - k0) * NQ, m, NQ, qv);
            if (su)
                gather(u + k0 * su, su, (n - k0) * su, m, NV, uv);
            if (sud)
                gather(ud + k0 * sud, sud, (n - k0) * sud, m, NV, udv);
            trig_lanes(qv, idx, nt, sinq, cosq);
            f(qv, uv, udv, pv, sinq, cosq, ov);
            scatter(ov, size, m, stage);  /* aligned, then out (aligned or not) by aligned stores */
            put(stage, m * size, out + k0 * size, streamed);
        }
        free(qv);
        FENCE();
    }
    return failed ? -1 : 0;
}

static int driver(eomgen_any f, const int *idx, int nt, npy_intp size, npy_intp n, const double *q,
                  const double *u, npy_intp su, const double *ud, npy_intp sud, const double *p, double *out)
{
    return batch_vector((eomgen_vfn)f, idx, nt, size, n, q, u, su, ud, sud, p, out);
}
"""


def sizes(nq: int, nv: int, n_params: int, count: int) -> str:
    """The C macros of a module's sizes: coordinates NQ, speeds NV, parameters NP, functions NF."""
    return f"#define NQ {nq}\n#define NV {nv}\n#define NP {n_params}\n#define NF {count}\n"


@cache
def machine() -> str:
    """What -march=native compiles for: the CPU's model and flags (Linux), else the platform's name."""
    try:
        info = Path("/proc/cpuinfo").read_text()
    except OSError:
        return platform.machine() + " " + platform.processor()
    keys = ("model name", "flags", "Features", "CPU part")
    return "\n".join(sorted({line for line in info.splitlines() if line.split(":")[0].strip() in keys}))
