"""The XLA FFI glue of an extension module (`c_extension`, ffi=True): each function e<i> also as an XLA
FFI handler x<i> (XLA's C API, `jax.ffi.include_dir()`), which evaluates the states of XLA's input
buffers straight into XLA's output buffer (no copy, no Python):

    q (B..., nq), u, ud (B..., nv), p (B..., np)  →  out (B..., rows, cols)

with JAX's vmap "expand_dims" convention: every input has the output's batch axes B, each of size B_d or
1 (broadcast); one state when B is empty. Inputs broadcast are gathered; u, ud or a p shared by all
states are passed once, a p per state evaluates one state at a time. float64 or float32 buffers (the
latter computed in float64, rounded). A NaN or infinite input is an INVALID_ARGUMENT error naming q,
u, ud or p. A large output gets transparent huge pages (as NumPy's arrays). `_ffi()` attaches the
vector functions (`vector`) and returns the handlers' capsules, in the functions' order."""
from __future__ import annotations

FFI = r"""
#include "xla/ffi/api/c_api.h"
#if defined(__linux__)
#include <sys/mman.h>
#endif

/* The call frame's extension: XLA_FFI_Extension_Base up to the C API 0.3 (JAX 0.10), renamed
   XLA_FFI_InternalExtension from 0.4 (JAX 0.11); the same fields (struct_size, type, next). */
#if XLA_FFI_API_MAJOR == 0 && XLA_FFI_API_MINOR < 4
typedef XLA_FFI_Extension_Base eomgen_extension;
#else
typedef XLA_FFI_InternalExtension eomgen_extension;
#endif

/* Transparent huge pages for a large output not touched yet, as NumPy asks for its arrays (4 MB and
   more): a fresh buffer then costs one page fault per 2 MB instead of per 4 kB (XLA's 268 MB output of
   talos's M: 0.15 s of faults without) */
static void huge_pages(void *data, size_t bytes)
{
#if defined(__linux__) && defined(MADV_HUGEPAGE)
    uintptr_t start = ((uintptr_t)data + 4095) & ~(uintptr_t)4095;
    if (bytes >= (4u << 20) && start < (uintptr_t)data + bytes)
        madvise((void *)start, (uintptr_t)data + bytes - start, MADV_HUGEPAGE);
#endif
}

static XLA_FFI_Error *ffi_error(XLA_FFI_CallFrame *frame, const char *message)
{
    XLA_FFI_Error_Create_Args args = {XLA_FFI_Error_Create_Args_STRUCT_SIZE, NULL, message,
                                      XLA_FFI_Error_Code_INVALID_ARGUMENT};
    return frame->api->XLA_FFI_Error_Create(&args);
}

/* x's rows as a C-contiguous (n, width) array: x itself when its batch axes are the output's, else
   gathered into *copy (malloc'd) along the output's batch axes `lead` (L of them; an axis of size 1
   broadcast). NULL when out of memory. */
static const double *rows_of(const XLA_FFI_Buffer *x, int L, const int64_t *lead, int64_t n, int64_t width,
                             double **copy)
{
    int full = 1;
    for (int d = 0; d < L; ++d)
        full &= x->dims[d] == lead[d];
    if (full)
        return x->data;
    *copy = malloc(sizeof(double) * (size_t)(n * width));
    if (*copy == NULL)
        return NULL;
    for (int64_t k = 0; k < n; ++k) {
        int64_t rest = k, at = 0, stride = 1;
        for (int d = L - 1; d >= 0; --d) {
            int64_t i = rest % lead[d];
            rest /= lead[d];
            at += (x->dims[d] == 1 ? 0 : i) * stride;
            stride *= x->dims[d];
        }
        memcpy(*copy + k * width, (const double *)x->data + at * width, sizeof(double) * (size_t)width);
    }
    return *copy;
}

/* e<i> at the float64 inputs x (q, u, ud, p: `count` states each, broadcast along the output's batch
   axes `lead`, L of them) into out: n states of `size` values. 0, or -1 when out of memory. */
static int run(eomgen_fn f, int i, const int *idx, int nt, int64_t size, XLA_FFI_Buffer *const *x,
               const int64_t *count, int L, const int64_t *lead, int64_t n, double *out)
{
    double *copies[4] = {NULL, NULL, NULL, NULL};
    const int64_t widths[4] = {NQ, NV, NV, NP};
    const double *in[4];
    for (int k = 0; k < 4; ++k)  /* u, ud or p shared by all states: passed once */
        in[k] = count[k] == 1 && k > 0 ? x[k]->data : rows_of(x[k], L, lead, n, widths[k], &copies[k]);
    int failed = in[0] == NULL || in[1] == NULL || in[2] == NULL || in[3] == NULL;
    int64_t su = count[1] == 1 ? 0 : NV, sud = count[2] == 1 ? 0 : NV;
    /* W states at a time, every entry written */
    eomgen_any v = count[3] == 1 && n > 1 ? state.lanes[i] : NULL;
    if (!failed && !v)
        memset(out, 0, sizeof(double) * (size_t)(n * size));
    if (failed)
        ;
    else if (v)
        failed = state.batch_vector(v, idx, nt, size, n, in[0], in[1], su, in[2], sud, in[3], out);
    else if (count[3] == 1 && n > 1)
        failed = eomgen_batch(&state, f, idx, nt, size, n, in[0], in[1], su, in[2], sud, in[3], out);
    else  /* one state, or a p per state */
        for (int64_t k = 0; k < n; ++k)
            eomgen_one_state(&state, f, idx, nt, in[0] + k * NQ, in[1] + k * su, in[2] + k * sud,
                             in[3] + (count[3] > 1) * k * NP, out + k * size);
    for (int k = 0; k < 4; ++k)
        free(copies[k]);
    return failed ? -1 : 0;
}

/* float32 buffers: x as float64 (malloc'd into *data, the buffer `as` pointing to it). 0, or -1. */
static int widen(const XLA_FFI_Buffer *x, int64_t size, XLA_FFI_Buffer *as, double **data)
{
    *as = *x;
    *data = malloc(sizeof(double) * (size_t)(size ? size : 1));
    if (*data == NULL)
        return -1;
    for (int64_t k = 0; k < size; ++k)
        (*data)[k] = ((const float *)x->data)[k];
    as->data = *data;
    return 0;
}

static XLA_FFI_Error *ffi_evaluate(XLA_FFI_CallFrame *frame, eomgen_fn f, int i, const int *idx, int nt,
                                   int64_t size)
{
    eomgen_extension *extension = frame->extension_start;
    if (extension != NULL && extension->type == XLA_FFI_Extension_Metadata) {  /* XLA asks the version */
        XLA_FFI_Metadata *metadata = ((XLA_FFI_Metadata_Extension *)extension)->metadata;
        metadata->api_version = (XLA_FFI_Api_Version){XLA_FFI_Api_Version_STRUCT_SIZE, NULL,
                                                      XLA_FFI_API_MAJOR, XLA_FFI_API_MINOR};
        metadata->traits = 0;
        metadata->state_type_id = (XLA_FFI_TypeId){0};
        return NULL;
    }
    if (frame->stage != XLA_FFI_ExecutionStage_EXECUTE)
        return NULL;
    static const char *messages[4] = {
        "q: contains NaN or infinite values", "u: contains NaN or infinite values",
        "ud: contains NaN or infinite values", "p: contains NaN or infinite values"};
    const int64_t widths[4] = {NQ, NV, NV, NP};
    XLA_FFI_Buffer *out = frame->rets.rets[0], **given = (XLA_FFI_Buffer **)frame->args.args;
    XLA_FFI_Buffer wide[4], *x[4];
    XLA_FFI_DataType type = out->dtype;
    int L = (int)out->rank - 2, failed = 0;
    int64_t n = 1, count[4];
    double *data[5] = {NULL, NULL, NULL, NULL, NULL};
    if (type != XLA_FFI_DataType_F64 && type != XLA_FFI_DataType_F32)
        return ffi_error(frame, "expected float64 or float32 buffers");
    for (int d = 0; d < L; ++d)
        n *= out->dims[d];
    for (int k = 0; k < 4; ++k) {
        count[k] = 1;
        for (int d = 0; d < L; ++d)
            count[k] *= given[k]->dims[d];
        if (given[k]->dtype != type)
            return ffi_error(frame, "expected float64 or float32 buffers");
        x[k] = given[k];
        if (type == XLA_FFI_DataType_F32 && !failed) {
            failed = widen(given[k], count[k] * widths[k], &wide[k], &data[k]);
            x[k] = &wide[k];
        }
        if (!failed && !eomgen_all_finite(x[k]->data, count[k] * widths[k])) {
            for (int j = 0; j <= k; ++j)
                free(data[j]);
            return ffi_error(frame, messages[k]);
        }
    }
    double *o = out->data;
    huge_pages(out->data, (size_t)(n * size) * (type == XLA_FFI_DataType_F32 ? 4 : 8));
    if (type == XLA_FFI_DataType_F32 && !failed) {
        o = data[4] = malloc(sizeof(double) * (size_t)(n * size));
        failed = o == NULL;
    }
    if (!failed)
        failed = run(f, i, idx, nt, size, x, count, L, out->dims, n, o);
    if (type == XLA_FFI_DataType_F32 && !failed)  /* computed in float64, rounded */
        for (int64_t k = 0; k < n * size; ++k)
            ((float *)out->data)[k] = (float)o[k];
    for (int k = 0; k < 5; ++k)
        free(data[k]);
    return failed ? ffi_error(frame, "out of memory") : NULL;
}
"""


def handlers(shapes: list[tuple[tuple[int, int], int]], jaxlib: str) -> tuple[str, list[str]]:
    """The handlers x<i> of the functions e<i> of `shapes` [((rows, cols), number of trig indices)] and
    `_ffi` (C text, for the headers of `jaxlib`'s version), and the entry of `_ffi` in the module's method
    table."""
    text = [f"/* XLA's FFI of jaxlib {jaxlib} */", FFI]
    for i, ((rows, cols), nt) in enumerate(shapes):
        text.append(f"static XLA_FFI_Error *x{i}(XLA_FFI_CallFrame *frame)\n"
                    f"{{ return ffi_evaluate(frame, e{i}, {i}, t{i}, {nt}, {rows * cols}); }}\n")
    capsules = ", ".join(f"PyCapsule_New((void *)x{i}, NULL, NULL)" for i in range(len(shapes)))
    text.append("static PyObject *ffi(PyObject *self, PyObject *unused)\n{\n"
                "    /* the vector functions attached (the hook of the first batch), then the handlers */\n"
                "    if (eomgen_run_hook(&state) < 0)\n        return NULL;\n"
                f"    return Py_BuildValue(\"({'N' * len(shapes)})\", {capsules});\n}}\n")
    return "\n".join(text), ['    {"_ffi", ffi, METH_NOARGS, NULL},']
