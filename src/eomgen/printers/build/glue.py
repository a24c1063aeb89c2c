"""The glue of every extension module, compiled once per cache (`extension.runtime_object`) and linked
into each: the checks of the inputs, the loops over states and the calls of a module's functions, for
any sizes. A module holds its sizes, its vector functions and its hook in an `eomgen_state` (`STATE`),
which it passes to `eomgen_evaluate`, `eomgen_attach` and `eomgen_set_hook`; its own glue is its table
of methods (`extension.module_source`). NumPy's C API is one table per module (`eomgen_numpy`, set by
`eomgen_init` when the module is imported). All of it is hidden in the module (-fvisibility=hidden)."""
from .lanes import HANDOVER

# the state of a module and the glue's entry points, in the glue and in every module
STATE = r"""#define PY_SSIZE_T_CLEAN
#include <Python.h>
#include <numpy/npy_common.h>

typedef void (*eomgen_fn)(const double *, const double *, const double *, const double *,
                          const double *, const double *, double *);

""" + HANDOVER + r"""
/* a module's sizes (coordinates, speeds, parameters, functions), max(nv, 1) zeros, its vector
   functions (nf, NULL until attached) and their loop, the hook of the first batch */
typedef struct {
    int nq, nv, np, nf;
    const double *zeros;
    eomgen_any *lanes;
    eomgen_driver batch_vector;
    PyObject *hook;
} eomgen_state;

int eomgen_init(void);
PyObject *eomgen_evaluate(eomgen_state *st, eomgen_fn f, int i, const int *idx, int nt, npy_intp rows,
                          npy_intp cols, int vector, PyObject *const *args, Py_ssize_t nargs);
PyObject *eomgen_attach(eomgen_state *st, PyObject *capsule);
PyObject *eomgen_set_hook(eomgen_state *st, PyObject *callable);
int eomgen_run_hook(eomgen_state *st);
int eomgen_all_finite(const double *v, npy_intp n);
void eomgen_one_state(const eomgen_state *st, eomgen_fn f, const int *idx, int nt, const double *q,
                      const double *u, const double *ud, const double *p, double *out);
int eomgen_batch(const eomgen_state *st, eomgen_fn f, const int *idx, int nt, npy_intp size, npy_intp n,
                 const double *q, const double *u, npy_intp su, const double *ud, npy_intp sud,
                 const double *p, double *out);
"""

# a module's own state and the methods that hand it to the glue (after its sizes NQ, NV, NP, NF)
MODULE_STATE = r"""static const double zeros[NV > 0 ? NV : 1];
static eomgen_any lanes[NF > 0 ? NF : 1];
static eomgen_state state = {NQ, NV, NP, NF, zeros, lanes, NULL, NULL};
static PyObject *attach(PyObject *self, PyObject *capsule) { return eomgen_attach(&state, capsule); }
static PyObject *set_hook(PyObject *self, PyObject *hook) { return eomgen_set_hook(&state, hook); }
"""

RUNTIME = STATE + r"""
#define PY_ARRAY_UNIQUE_SYMBOL eomgen_numpy
#define NPY_NO_DEPRECATED_API NPY_1_7_API_VERSION
#include <numpy/arrayobject.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

int eomgen_init(void)
{
    import_array1(-1);
    return 0;
}

static void dims_text(char *buf, size_t size, int nd, const npy_intp *dims)
{
    /* "(6,)", "(10, 6)", as Python prints a shape */
    size_t used = (size_t)snprintf(buf, size, "(");
    for (int d = 0; d < nd && used < size; ++d)
        used += (size_t)snprintf(buf + used, size - used, d ? ", %ld" : "%ld", (long)dims[d]);
    if (used < size)
        snprintf(buf + used, size - used, nd == 1 ? ",)" : ")");
}

static void shape_text(char *buf, size_t size, PyObject *obj)
{
    if (PyArray_Check(obj))
        dims_text(buf, size, PyArray_NDIM((PyArrayObject *)obj), PyArray_DIMS((PyArrayObject *)obj));
    else
        dims_text(buf, size, 0, NULL);
}

/* Whether the n values of v are finite: x - x is NaN for NaN and infinities (8 sums at once, vectorized) */
int eomgen_all_finite(const double *v, npy_intp n)
{
    double nan[8] = {0};
    npy_intp k = 0;
    for (; k + 8 <= n; k += 8)
        for (int j = 0; j < 8; ++j)
            nan[j] += v[k + j] - v[k + j];
    for (; k < n; ++k)
        nan[0] += v[k] - v[k];
    for (int j = 0; j < 8; ++j)
        if (nan[j] != 0.0)  /* NaN */
            return 0;
    return 1;
}

/* x as a C-contiguous float64 array of shape batch + (n,), or NULL with a ValueError naming it. */
static PyArrayObject *input(PyObject *x, const char *name, npy_intp n, int nd, npy_intp batch)
{
    char got[128], want[64];
    PyArrayObject *a = (PyArrayObject *)PyArray_FROM_OTF(x, NPY_DOUBLE, NPY_ARRAY_IN_ARRAY);
    if (a == NULL)
        return NULL;
    int last = PyArray_NDIM(a) - 1;
    int ok = nd < 0 ? ((last == 0 || last == 1) && PyArray_DIM(a, last) == n)
                    : (last == nd - 1 && PyArray_DIM(a, last) == n
                       && (nd == 1 || PyArray_DIM(a, 0) == batch));
    if (!ok) {
        shape_text(got, sizeof got, (PyObject *)a);
        if (nd < 0)
            PyErr_Format(PyExc_ValueError, "%s: expected shape (%ld,) or (N, %ld), got %s", name, (long)n,
                         (long)n, got);
        else {
            if (nd == 1) snprintf(want, sizeof want, "(%ld,)", (long)n);
            else snprintf(want, sizeof want, "(%ld, %ld)", (long)batch, (long)n);
            PyErr_Format(PyExc_ValueError, "%s: expected shape %s, got %s", name, want, got);
        }
        Py_DECREF(a);
        return NULL;
    }
    if (!eomgen_all_finite((const double *)PyArray_DATA(a), PyArray_SIZE(a))) {
        PyErr_Format(PyExc_ValueError, "%s: contains NaN or infinite values", name);
        Py_DECREF(a);
        return NULL;
    }
    return a;
}

#define BLOCK 64
#if defined(__x86_64__) && defined(__GLIBC__) && !defined(EOMGEN_NO_MVEC)
/* glibc's vector sin and cos (libmvec, within 4 ulp) for the angles of a state and of a block of states */
__attribute__((simd("notinbranch"))) extern double sin(double);
__attribute__((simd("notinbranch"))) extern double cos(double);
__attribute__((target_clones("avx2", "default")))
#endif
static void trig_block(const double *q, int nq, int m, const int *idx, int nt, double *sinq, double *cosq)
{
    /* sin and cos of q[k][idx[t]] for m <= BLOCK states, written at [k * nq + idx[t]] */
    double x[BLOCK], s[BLOCK], c[BLOCK];
    for (int t = 0; t < nt; ++t) {
        int j = idx[t];
        for (int k = 0; k < m; ++k) x[k] = q[k * nq + j];
        for (int k = 0; k < m; ++k) s[k] = sin(x[k]);
        for (int k = 0; k < m; ++k) c[k] = cos(x[k]);
        for (int k = 0; k < m; ++k) { sinq[k * nq + j] = s[k]; cosq[k * nq + j] = c[k]; }
    }
}

void eomgen_one_state(const eomgen_state *st, eomgen_fn f, const int *idx, int nt, const double *q,
                      const double *u, const double *ud, const double *p, double *out)
{
    /* the angles gathered, their sin and cos in two loops over whole vectors (vector calls), scattered */
    int nq = st->nq ? st->nq : 1, lanes = (nq + 7) / 8 * 8;
    double sinq[nq], cosq[nq], x[lanes], s[lanes], c[lanes];
    memset(x, 0, sizeof x);
    for (int t = 0; t < nt; ++t) x[t] = q[idx[t]];
    for (int t = 0; t < lanes; ++t) s[t] = sin(x[t]);
    for (int t = 0; t < lanes; ++t) c[t] = cos(x[t]);
    for (int t = 0; t < nt; ++t) {
        sinq[idx[t]] = s[t];
        cosq[idx[t]] = c[t];
    }
    f(q, u, ud, p, sinq, cosq, out);
}

/* N states one at a time (out zeroed), in blocks of BLOCK over the cores for large N. 0, or -1 when out of
   memory */
int eomgen_batch(const eomgen_state *st, eomgen_fn f, const int *idx, int nt, npy_intp size, npy_intp n,
                 const double *q, const double *u, npy_intp su, const double *ud, npy_intp sud,
                 const double *p, double *out)
{
    int failed = 0, nq = st->nq;
    npy_intp blocks = (n + BLOCK - 1) / BLOCK;
    /* blocks of states over the cores (OpenMP, OMP_NUM_THREADS) when the batch is large */
    #pragma omp parallel if (blocks >= 16)
    {
        double *sinq = malloc(2 * sizeof(double) * BLOCK * (nq ? nq : 1)), *cosq = sinq + BLOCK * nq;
        #pragma omp for schedule(static)
        for (npy_intp b = 0; b < blocks; ++b) {
            npy_intp k0 = b * BLOCK;
            int m = n - k0 < BLOCK ? (int)(n - k0) : BLOCK;
            if (sinq == NULL) {
                failed = 1;
                continue;
            }
            trig_block(q + k0 * nq, nq, m, idx, nt, sinq, cosq);
            for (npy_intp k = k0; k < k0 + m; ++k)
                f(q + k * nq, u + k * su, ud + k * sud, p, sinq + (k - k0) * nq, cosq + (k - k0) * nq,
                  out + k * size);
        }
        free(sinq);
    }
    return failed ? -1 : 0;
}

/* out, when given: a writeable C-contiguous float64 array of shape `shape` (a new reference), else NULL
   with a ValueError naming it */
static PyArrayObject *output(PyObject *out, int nd, const npy_intp *shape)
{
    char want[128], got[128];
    PyArrayObject *a = (PyArrayObject *)out;
    int ok = PyArray_Check(out) && PyArray_TYPE(a) == NPY_DOUBLE && PyArray_IS_C_CONTIGUOUS(a)
             && PyArray_ISWRITEABLE(a) && PyArray_NDIM(a) == nd;
    for (int d = 0; ok && d < nd; ++d)
        ok = PyArray_DIM(a, d) == shape[d];
    if (ok) {
        Py_INCREF(out);
        return a;
    }
    dims_text(want, sizeof want, nd, shape);
    if (!PyArray_Check(out)) {
        PyErr_Format(PyExc_ValueError, "out: expected a writeable C-contiguous float64 array of shape %s, "
                     "got %s", want, Py_TYPE(out)->tp_name);
        return NULL;
    }
    shape_text(got, sizeof got, out);
    const char *kind = !PyArray_IS_C_CONTIGUOUS(a) ? " non-contiguous"
                       : !PyArray_ISWRITEABLE(a) ? " read-only" : "";
    PyErr_Format(PyExc_ValueError, "out: expected a writeable C-contiguous float64 array of shape %s, "
                 "got a%s %s array of shape %s", want, kind, PyArray_DESCR(a)->typeobj->tp_name, got);
    return NULL;
}

/* Whether two C-contiguous arrays share memory (their byte ranges meet) */
static int overlap(PyArrayObject *x, PyArrayObject *y)
{
    const char *a = PyArray_DATA(x), *b = PyArray_DATA(y);
    return a < b + PyArray_NBYTES(y) && b < a + PyArray_NBYTES(x);
}

/* the vector functions and their loop from the capsule of their module (`vector.lanes_source`) */
PyObject *eomgen_attach(eomgen_state *st, PyObject *capsule)
{
    eomgen_lanes *handed = PyCapsule_GetPointer(capsule, "eomgen.lanes");
    if (handed == NULL)
        return NULL;
    memcpy(st->lanes, handed->table, sizeof(eomgen_any) * (size_t)st->nf);
    st->batch_vector = handed->driver;
    Py_RETURN_NONE;
}

PyObject *eomgen_set_hook(eomgen_state *st, PyObject *callable)
{
    Py_XSETREF(st->hook, Py_NewRef(callable));
    Py_RETURN_NONE;
}

/* the hook called once (then cleared): 0, or -1 with its exception */
int eomgen_run_hook(eomgen_state *st)
{
    if (st->hook == NULL)
        return 0;
    PyObject *h = st->hook, *done;
    st->hook = NULL;
    done = PyObject_CallNoArgs(h);
    Py_DECREF(h);
    Py_XDECREF(done);
    return done == NULL ? -1 : 0;
}

PyObject *eomgen_evaluate(eomgen_state *st, eomgen_fn f, int i, const int *idx, int nt, npy_intp rows,
                          npy_intp cols, int vector, PyObject *const *args, Py_ssize_t nargs)
{
    if (nargs < 1 || nargs > 5)
        return PyErr_Format(PyExc_TypeError, "expected (q, u=None, ud=None, p=None, out=None), got %zd "
                            "arguments", nargs);
    PyArrayObject *a[4] = {NULL, NULL, NULL, NULL}, *result = NULL;
    static const char *names[4] = {"q", "u", "ud", "p"};
    a[0] = input(args[0], "q", st->nq, -1, 0);
    if (a[0] == NULL)
        return NULL;
    int nd = PyArray_NDIM(a[0]);
    npy_intp n = nd == 2 ? PyArray_DIM(a[0], 0) : 1;
    for (int k = 1; k < 4; ++k)
        if (k < nargs && args[k] != Py_None) {
            a[k] = k == 3 ? input(args[k], "p", st->np, 1, 0) : input(args[k], names[k], st->nv, nd, n);
            if (a[k] == NULL)
                goto done;
        }
    if (st->np > 0 && a[3] == NULL) {
        PyErr_SetString(PyExc_TypeError, "p: the parameter values are required");
        goto done;
    }
    if (nd == 2 && eomgen_run_hook(st) < 0)  /* the first batch */
        goto done;
    eomgen_any v = nd == 2 ? st->lanes[i] : NULL;  /* W states at a time, every entry written */
    npy_intp dims[3] = {n, rows, cols}, *shape = nd == 2 ? dims : dims + 1;
    if (nargs == 5 && args[4] != Py_None) {
        result = output(args[4], nd + 1 - vector, shape);
        for (int k = 0; k < 3 && result != NULL; ++k)  /* a batch would write over states not read yet */
            if (a[k] != NULL && overlap(result, a[k])) {
                PyErr_Format(PyExc_ValueError, "out: shares memory with the input %s; give an output "
                             "array apart from the inputs", names[k]);
                Py_CLEAR(result);
            }
        if (result != NULL && !v)
            memset(PyArray_DATA(result), 0, PyArray_NBYTES(result));
    } else
        result = (PyArrayObject *)(v ? PyArray_EMPTY(nd + 1 - vector, shape, NPY_DOUBLE, 0)
                                     : PyArray_ZEROS(nd + 1 - vector, shape, NPY_DOUBLE, 0));
    if (result == NULL)
        goto done;
    {
        const double *q = PyArray_DATA(a[0]);
        const double *u = a[1] ? PyArray_DATA(a[1]) : st->zeros, *ud = a[2] ? PyArray_DATA(a[2]) : st->zeros;
        const double *p = a[3] ? PyArray_DATA(a[3]) : st->zeros;
        npy_intp su = a[1] ? st->nv : 0, sud = a[2] ? st->nv : 0;
        double *out = PyArray_DATA(result);
        int failed = 0;
        if (nd == 1)
            eomgen_one_state(st, f, idx, nt, q, u, ud, p, out);
        else {
            Py_BEGIN_ALLOW_THREADS
            failed = v ? st->batch_vector(v, idx, nt, rows * cols, n, q, u, su, ud, sud, p, out)
                       : eomgen_batch(st, f, idx, nt, rows * cols, n, q, u, su, ud, sud, p, out);
            Py_END_ALLOW_THREADS
        }
        if (failed) {
            Py_CLEAR(result);
            PyErr_NoMemory();
        }
    }
done:
    for (int k = 0; k < 4; ++k)
        Py_XDECREF(a[k]);
    return (PyObject *)result;
}
"""
