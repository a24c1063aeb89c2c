"""The XLA FFI glue of an extension module (`c_extension`, ffi=True): each function e<i> also as an XLA
FFI handler x<i> (XLA's C API, `jax.ffi.include_dir()`), which evaluates the states of XLA's input
buffers straight into XLA's output buffer (no copy, no Python):

    q (B..., nq), u, ud (B..., nv), p (B..., np)  →  out (B..., rows, cols)

with JAX's vmap "expand_dims" convention: every input has the output's batch axes B, each of size B_d or
1 (broadcast); one state when B is empty. q, u and ud broadcast are gathered; a p shared by all states is
passed once, a p per state evaluates one state at a time. A NaN or infinite input is an
INVALID_ARGUMENT error naming q, u, ud or p. `_ffi()` attaches the vector functions (`vector`) and
returns the handlers' capsules, in the functions' order."""
from __future__ import annotations

FFI = r"""
#include "xla/ffi/api/c_api.h"

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

static XLA_FFI_Error *ffi_evaluate(XLA_FFI_CallFrame *frame, eomgen_fn f, int i, const int *idx, int nt,
                                   int64_t size)
{
    XLA_FFI_Extension_Base *extension = frame->extension_start;
    if (extension != NULL && extension->type == XLA_FFI_Extension_Metadata) {  /* XLA asks the version */
        XLA_FFI_Metadata *metadata = ((XLA_FFI_Metadata_Extension *)extension)->metadata;
        metadata->api_version.major_version = XLA_FFI_API_MAJOR;
        metadata->api_version.minor_version = XLA_FFI_API_MINOR;
        metadata->traits = 0;
        return NULL;
    }
    if (frame->stage != XLA_FFI_ExecutionStage_EXECUTE)
        return NULL;
    static const char *messages[4] = {
        "q: contains NaN or infinite values", "u: contains NaN or infinite values",
        "ud: contains NaN or infinite values", "p: contains NaN or infinite values"};
    const int64_t widths[4] = {NQ, NV, NV, NP};
    XLA_FFI_Buffer *out = frame->rets.rets[0], **x = (XLA_FFI_Buffer **)frame->args.args;
    int L = (int)out->rank - 2;
    int64_t n = 1, count[4];
    for (int d = 0; d < L; ++d)
        n *= out->dims[d];
    for (int k = 0; k < 4; ++k) {
        count[k] = 1;
        for (int d = 0; d < L; ++d)
            count[k] *= x[k]->dims[d];
        if (!all_finite(x[k]->data, count[k] * widths[k]))
            return ffi_error(frame, messages[k]);
    }
    double *copies[3] = {NULL, NULL, NULL}, *o = out->data;
    const double *in[3];
    for (int k = 0; k < 3; ++k)  /* a state shared by all: stride 0 */
        in[k] = count[k] == 1 && k > 0 ? x[k]->data : rows_of(x[k], L, out->dims, n, widths[k], &copies[k]);
    int failed = in[0] == NULL || in[1] == NULL || in[2] == NULL;
    int64_t su = count[1] == 1 ? 0 : NV, sud = count[2] == 1 ? 0 : NV;
    eomgen_vfn v = lanes[i];
    if (failed)
        ;
    else if (count[3] == 1 && n == 1) {
        memset(o, 0, sizeof(double) * (size_t)size);
        one_state(f, idx, nt, in[0], in[1], in[2], x[3]->data, o);
    } else if (count[3] == 1) {
        if (!v)
            memset(o, 0, sizeof(double) * (size_t)(n * size));
        failed = v ? batch_vector(v, idx, nt, size, n, in[0], in[1], su, in[2], sud, x[3]->data, o)
                   : batch(f, idx, nt, size, n, in[0], in[1], su, in[2], sud, x[3]->data, o);
    } else {  /* a p per state */
        double *p = NULL;
        const double *ps = rows_of(x[3], L, out->dims, n, NP, &p);
        failed = ps == NULL;
        memset(o, 0, sizeof(double) * (size_t)(n * size));
        for (int64_t k = 0; k < n && !failed; ++k)
            one_state(f, idx, nt, in[0] + k * NQ, in[1] + k * su, in[2] + k * sud, ps + k * NP, o + k * size);
        free(p);
    }
    for (int k = 0; k < 3; ++k)
        free(copies[k]);
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
                "    if (run_hook() < 0)\n        return NULL;\n"
                f"    return Py_BuildValue(\"({'N' * len(shapes)})\", {capsules});\n}}\n")
    return "\n".join(text), ['    {"_ffi", ffi, METH_NOARGS, NULL},']
