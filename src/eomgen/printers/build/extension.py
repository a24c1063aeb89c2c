"""Generated C functions as one CPython extension module: compiled with the machine's C compiler,
cached by a hash of the translation units and glue (`compile`; and of the compiler flags, the CPU,
Python and NumPy it was built for), and imported. Each function `e<i>` is exposed twice:
`m<i>(q, u=None, ud=None, p=None, out=None)` returns the output matrix (rows, cols), `v<i>` the column
as a vector (rows,), written into `out` when given; q of shape (nq,) is one state, (N, nq) is N states
evaluated in one C loop with the GIL released, over all cores for large N (OpenMP; OMP_NUM_THREADS=1
for one), W states at a time in vector registers by its vector function `w<i>` where there is one
(`vector`: a second module, built by the hook `_hook` on the first batch and handed over by `_attach`).
Inputs are checked in C with the messages of the NumPy backend (the argument named, shapes, NaN and
infinities).

The cache, $EOMGEN_CACHE or ~/.cache/eomgen, is created private to the user (mode 0o700). Its modules
are loaded as code, so a folder that other users could write into is refused (world-writable, or owned
by someone else) and a group-writable one is warned about; a folder that cannot be created or written
is a ModelError naming EOMGEN_CACHE. Each module `<name><EXT_SUFFIX>` is moved in by an atomic rename,
then its checksum `<file>.sha256` (sha256 of the module's bytes) beside it; a module with no checksum,
another checksum or that does not load is rebuilt once (a truncated or corrupt file, an interrupted
build; a folder in the place of either file is removed first), and a ModelError if the rebuilt one does
not load either."""
from __future__ import annotations

import hashlib
import importlib.machinery
import importlib.util
import os
import shutil
import stat
import sys
import sysconfig
import tempfile
import warnings
from collections.abc import Callable
from pathlib import Path

import numpy as np

from ...errors import ModelError
from .lanes import HANDOVER, machine, sizes
from .compile import COMPILE, Unit, build_library, optimisation, translation_units

# batches over the cores with vector sin and cos; else one core, scalar sin and cos
ATTEMPTS = (["-fopenmp", "-lmvec", "-lm"], ["-DEOMGEN_NO_MVEC", "-lm"])

PRELUDE = r"""#define PY_SSIZE_T_CLEAN
#include <Python.h>
#define NPY_NO_DEPRECATED_API NPY_1_7_API_VERSION
#include <numpy/arrayobject.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

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
static int all_finite(const double *v, npy_intp n)
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
    int ok = nd < 0 ? ((PyArray_NDIM(a) == 1 || PyArray_NDIM(a) == 2) && PyArray_DIM(a, PyArray_NDIM(a) - 1) == n)
                    : (PyArray_NDIM(a) == nd && PyArray_DIM(a, nd - 1) == n && (nd == 1 || PyArray_DIM(a, 0) == batch));
    if (!ok) {
        shape_text(got, sizeof got, (PyObject *)a);
        if (nd < 0)
            PyErr_Format(PyExc_ValueError, "%s: expected shape (%ld,) or (N, %ld), got %s", name, (long)n, (long)n, got);
        else {
            if (nd == 1) snprintf(want, sizeof want, "(%ld,)", (long)n);
            else snprintf(want, sizeof want, "(%ld, %ld)", (long)batch, (long)n);
            PyErr_Format(PyExc_ValueError, "%s: expected shape %s, got %s", name, want, got);
        }
        Py_DECREF(a);
        return NULL;
    }
    if (!all_finite((const double *)PyArray_DATA(a), PyArray_SIZE(a))) {
        PyErr_Format(PyExc_ValueError, "%s: contains NaN or infinite values", name);
        Py_DECREF(a);
        return NULL;
    }
    return a;
}

static const double ZEROS[NV > 0 ? NV : 1];

typedef void (*eomgen_fn)(const double *, const double *, const double *, const double *,
                          const double *, const double *, double *);

#define BLOCK 64
#if defined(__x86_64__) && defined(__GLIBC__) && !defined(EOMGEN_NO_MVEC)
/* glibc's vector sin and cos (libmvec, within 4 ulp) for the angles of a state and of a block of states */
__attribute__((simd("notinbranch"))) extern double sin(double);
__attribute__((simd("notinbranch"))) extern double cos(double);
__attribute__((target_clones("avx2", "default")))
#endif
static void trig_block(const double *q, int m, const int *idx, int nt, double *sinq, double *cosq)
{
    /* sin and cos of q[k][idx[t]] for m <= BLOCK states, written at [k * NQ + idx[t]] */
    double x[BLOCK], s[BLOCK], c[BLOCK];
    for (int t = 0; t < nt; ++t) {
        int j = idx[t];
        for (int k = 0; k < m; ++k) x[k] = q[k * NQ + j];
        for (int k = 0; k < m; ++k) s[k] = sin(x[k]);
        for (int k = 0; k < m; ++k) c[k] = cos(x[k]);
        for (int k = 0; k < m; ++k) { sinq[k * NQ + j] = s[k]; cosq[k * NQ + j] = c[k]; }
    }
}

static void one_state(eomgen_fn f, const int *idx, int nt, const double *q, const double *u,
                      const double *ud, const double *p, double *out)
{
    /* the angles gathered, their sin and cos in two loops of a fixed length (vector calls), scattered */
    enum { LANES = (NQ + 7) / 8 * 8 };
    double sinq[NQ], cosq[NQ], x[LANES] = {0.0}, s[LANES], c[LANES];
    for (int t = 0; t < nt; ++t) x[t] = q[idx[t]];
    for (int t = 0; t < LANES; ++t) s[t] = sin(x[t]);
    for (int t = 0; t < LANES; ++t) c[t] = cos(x[t]);
    for (int t = 0; t < nt; ++t) {
        sinq[idx[t]] = s[t];
        cosq[idx[t]] = c[t];
    }
    f(q, u, ud, p, sinq, cosq, out);
}

/* N states one at a time (out zeroed), in blocks of BLOCK over the cores for large N. 0, or -1 when out of
   memory */
static int batch(eomgen_fn f, const int *idx, int nt, npy_intp size, npy_intp n, const double *q,
                 const double *u, npy_intp su, const double *ud, npy_intp sud, const double *p, double *out)
{
    int failed = 0;
    npy_intp blocks = (n + BLOCK - 1) / BLOCK;
    /* blocks of states over the cores (OpenMP, OMP_NUM_THREADS) when the batch is large */
    #pragma omp parallel if (blocks >= 16)
    {
        double *sinq = malloc(2 * sizeof(double) * BLOCK * NQ), *cosq = sinq + BLOCK * NQ;
        #pragma omp for schedule(static)
        for (npy_intp b = 0; b < blocks; ++b) {
            npy_intp k0 = b * BLOCK;
            int m = n - k0 < BLOCK ? (int)(n - k0) : BLOCK;
            if (sinq == NULL) {
                failed = 1;
                continue;
            }
            trig_block(q + k0 * NQ, m, idx, nt, sinq, cosq);
            for (npy_intp k = k0; k < k0 + m; ++k)
                f(q + k * NQ, u + k * su, ud + k * sud, p, sinq + (k - k0) * NQ, cosq + (k - k0) * NQ,
                  out + k * size);
        }
        free(sinq);
    }
    return failed ? -1 : 0;
}
"""

EVALUATE = r"""
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

static eomgen_any lanes[NF];  /* the vector functions, once their module is attached */
static eomgen_driver batch_vector;  /* and their batched loop */
static PyObject *hook;  /* called on the first batch: builds and attaches them */

/* lanes[] and batch_vector from the capsule of the module of vector functions (`vector.lanes_source`) */
static PyObject *attach(PyObject *self, PyObject *capsule)
{
    eomgen_lanes *handed = PyCapsule_GetPointer(capsule, "eomgen.lanes");
    if (handed == NULL)
        return NULL;
    memcpy(lanes, handed->table, sizeof lanes);
    batch_vector = handed->driver;
    Py_RETURN_NONE;
}

static PyObject *set_hook(PyObject *self, PyObject *callable)
{
    Py_XSETREF(hook, Py_NewRef(callable));
    Py_RETURN_NONE;
}

/* the hook called once (then cleared): 0, or -1 with its exception */
static int run_hook(void)
{
    if (hook == NULL)
        return 0;
    PyObject *h = hook, *done;
    hook = NULL;
    done = PyObject_CallNoArgs(h);
    Py_DECREF(h);
    Py_XDECREF(done);
    return done == NULL ? -1 : 0;
}

static PyObject *evaluate(eomgen_fn f, int i, const int *idx, int nt, npy_intp rows, npy_intp cols,
                          int vector, PyObject *const *args, Py_ssize_t nargs)
{
    if (nargs < 1 || nargs > 5)
        return PyErr_Format(PyExc_TypeError, "expected (q, u=None, ud=None, p=None, out=None), got %zd "
                            "arguments", nargs);
    PyArrayObject *a[4] = {NULL, NULL, NULL, NULL}, *result = NULL;
    static const char *names[4] = {"q", "u", "ud", "p"};
    a[0] = input(args[0], "q", NQ, -1, 0);
    if (a[0] == NULL)
        return NULL;
    int nd = PyArray_NDIM(a[0]);
    npy_intp n = nd == 2 ? PyArray_DIM(a[0], 0) : 1;
    for (int k = 1; k < 4; ++k)
        if (k < nargs && args[k] != Py_None) {
            a[k] = k == 3 ? input(args[k], "p", NP, 1, 0) : input(args[k], names[k], NV, nd, n);
            if (a[k] == NULL)
                goto done;
        }
    if (NP > 0 && a[3] == NULL) {
        PyErr_SetString(PyExc_TypeError, "p: the parameter values are required");
        goto done;
    }
    if (nd == 2 && run_hook() < 0)  /* the first batch */
        goto done;
    eomgen_any v = nd == 2 ? lanes[i] : NULL;  /* W states at a time, every entry written */
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
        const double *u = a[1] ? PyArray_DATA(a[1]) : ZEROS, *ud = a[2] ? PyArray_DATA(a[2]) : ZEROS;
        const double *p = a[3] ? PyArray_DATA(a[3]) : ZEROS;
        npy_intp su = a[1] ? NV : 0, sud = a[2] ? NV : 0;
        double *out = PyArray_DATA(result);
        int failed = 0;
        if (nd == 1)
            one_state(f, idx, nt, q, u, ud, p, out);
        else {
            Py_BEGIN_ALLOW_THREADS
            failed = v ? batch_vector(v, idx, nt, rows * cols, n, q, u, su, ud, sud, p, out)
                       : batch(f, idx, nt, rows * cols, n, q, u, su, ud, sud, p, out);
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


def compiler() -> str:
    cc = os.environ.get("CC", "cc")
    path = shutil.which(cc)
    if path is None:
        raise ModelError(f"no C compiler found (looked for {cc!r}; set CC); the NumPy backend works without one")
    return path


def python_headers() -> str:
    """The folder holding Python.h, which an extension module is compiled against."""
    include = sysconfig.get_paths()["include"]
    if not (Path(include) / "Python.h").exists():
        raise ModelError(f"the C backend needs the Python headers (no Python.h in {include}; on Debian: "
                         "apt install python3-dev); the NumPy backend works without them")
    return include


def cache_dir() -> Path:
    """The cache folder ($EOMGEN_CACHE or ~/.cache/eomgen), created with mode 0o700; a ModelError naming
    EOMGEN_CACHE when it cannot be created or written, or other users could write into it."""
    env = os.environ.get("EOMGEN_CACHE")
    folder = Path(env) if env else Path.home() / ".cache" / "eomgen"
    where = f"EOMGEN_CACHE={folder}" if env else f"the default {folder} (EOMGEN_CACHE is not set)"

    def unusable(reason: str) -> ModelError:
        return ModelError(f"the C extension cache, {where}, {reason}; set EOMGEN_CACHE to a folder of yours")

    existed = folder.is_dir()
    if folder.exists() and not existed:
        raise unusable("is a file, not a folder")
    try:
        folder.mkdir(mode=0o700, parents=True, exist_ok=True)
        if not existed:
            folder.chmod(0o700)  # whatever the umask
    except OSError as error:
        raise unusable(f"cannot be created: {error.strerror or error}") from None
    if not os.access(folder, os.W_OK | os.X_OK):
        raise unusable("is not writable")
    if os.name == "posix":
        info = folder.stat()
        if info.st_uid != os.geteuid():
            raise unusable(f"belongs to another user (uid {info.st_uid}), who could replace the compiled "
                           "code")
        if info.st_mode & stat.S_IWOTH:
            raise unusable(f"is writable by all users (mode {stat.S_IMODE(info.st_mode):o}), who could "
                           "replace the compiled code")
        if info.st_mode & stat.S_IWGRP:
            warnings.warn(f"the C extension cache, {where}, is writable by its group (mode "
                          f"{stat.S_IMODE(info.st_mode):o}), whose members could replace the compiled code",
                          stacklevel=2)
    return folder


def module_source(name: str, functions: list[tuple[str, tuple, list[int]]], nq: int, nv: int, n_params: int,
                  extra: tuple[str, list[str]] = ("", [])) -> str:
    """The extension module `name`: the functions (C text of `e<i>`, output shape, the k of the sin(q[k])
    and cos(q[k]) it reads) and their wrappers; `_attach` and `_hook` take the vector functions
    (`vector`); `extra`: more glue after the functions and its entries in the method table."""
    parts = [sizes(nq, nv, n_params, len(functions)), PRELUDE, HANDOVER, EVALUATE]
    table = ['    {"_attach", attach, METH_O, NULL},', '    {"_hook", set_hook, METH_O, NULL},']
    for i, (source, (rows, cols), trig) in enumerate(functions):
        parts.append(source)  # static functions (`numpy_backend.C_TRIG`)
        parts.append(f"static const int t{i}[] = {{{', '.join(map(str, trig or [0]))}}};\n")
        for kind, column in (("m", 0), ("v", 1)):
            parts.append(f"static PyObject *{kind}{i}(PyObject *self, PyObject *const *args, Py_ssize_t nargs)\n"
                         f"{{ return evaluate(e{i}, {i}, t{i}, {len(trig)}, {rows}, {cols}, {column}, args, "
                         "nargs); }\n")
            table.append(f'    {{"{kind}{i}", (PyCFunction)(void (*)(void)){kind}{i}, METH_FASTCALL, NULL}},')
    parts.append(extra[0])
    table.extend(extra[1])
    parts.append("static PyMethodDef methods[] = {\n" + "\n".join(table) + "\n    {NULL, NULL, 0, NULL}\n};\n"
                 f'static struct PyModuleDef module = {{PyModuleDef_HEAD_INIT, "{name}", NULL, -1, methods}};\n'
                 f"PyMODINIT_FUNC PyInit_{name}(void)\n{{\n    import_array();\n    return PyModule_Create(&module);\n}}\n")
    return "\n".join(parts)


def sha256(path: Path) -> str:
    return hashlib.sha256(path.read_bytes()).hexdigest()


def checksum_file(target: Path) -> Path:
    return target.with_name(target.name + ".sha256")


def intact(target: Path) -> bool:
    """The module and its checksum exist, and sha256(module) equals the checksum."""
    try:
        return checksum_file(target).read_text().strip() == sha256(target)
    except OSError:
        return False


def compile_module(glue: str, units: list[Unit], target: Path, include: tuple[str, ...] = ()) -> None:
    """Compile the module (`compile.build_library`; more header folders `include`) in a temp folder beside
    `target`, move it in (an atomic rename; a concurrent writer leaves the same bytes), then its checksum."""
    with tempfile.TemporaryDirectory(dir=target.parent) as tmp:  # same file system: the moves are renames
        so_file = Path(tmp) / target.name
        headers = [f"-I{folder}" for folder in (python_headers(), np.get_include(), *include)]
        build_library(compiler(), glue, units, headers, ATTEMPTS, Path(tmp), so_file)
        digest = Path(tmp) / "sha256"
        digest.write_text(sha256(so_file) + "\n")
        os.replace(so_file, target)
        os.replace(digest, checksum_file(target))


def clear(target: Path) -> None:
    """Remove a folder standing where the module or its checksum goes (no rename can replace it): the
    cache is eomgen's own; a ModelError naming the path if it cannot be removed."""
    for path in (target, checksum_file(target)):
        if path.is_dir() and not path.is_symlink():
            try:
                shutil.rmtree(path)
            except OSError as error:
                raise ModelError(f"the C extension cache holds a folder at {path}, where a compiled module "
                                 f"or its checksum goes, and it cannot be removed: {error}") from None


def load(name: str, target: Path):
    loader = importlib.machinery.ExtensionFileLoader(name, str(target))
    spec = importlib.util.spec_from_file_location(name, str(target), loader=loader)
    module = importlib.util.module_from_spec(spec)
    loader.exec_module(module)
    sys.modules[name] = module
    return module


def build(functions: list[tuple[str, tuple, list[int]]], nq: int, nv: int, n_params: int,
          extra: tuple[str, list[str]] = ("", []), include: tuple[str, ...] = ()):
    """The extension module of `functions` (see `module_source`; `extra` glue, compiled with the header
    folders `include`): their definitions compiled as translation units in parallel (`compile`) and linked
    with the module's glue, once (`compiled`)."""
    header, units = translation_units([source for source, _, _ in functions])
    layout = [(optimisation(unit), unit.text) for unit in units]
    shapes = [(shape, trig) for _, shape, trig in functions]

    def make(name: str, target: Path) -> None:
        entries = [(header if i == 0 else "", shape, trig) for i, (shape, trig) in enumerate(shapes)]
        compile_module(module_source(name, entries, nq, nv, n_params, extra), units, target, include)

    content = (PRELUDE, HANDOVER, EVALUATE, header, layout, shapes, nq, nv, n_params)
    content += (extra, include) if include else ()
    return compiled(content, make)


def compiled(content, make: Callable[[str, Path], None]):
    """The module `make(name, target)` compiles for `content` (all it is made of), compiled once per distinct
    content, compiler, flags, machine, Python and NumPy, and imported; a cached module that is not intact or
    does not load is rebuilt once."""
    built_for = (compiler(), COMPILE, ATTEMPTS, machine(), sys.version, np.__version__)
    key = repr((content, *built_for)).encode()
    name = "eomgen_" + hashlib.sha256(key).hexdigest()[:24]
    target = cache_dir() / (name + sysconfig.get_config_var("EXT_SUFFIX"))
    if name in sys.modules:
        return sys.modules[name]
    fresh = not intact(target)
    if fresh:
        clear(target)
        make(name, target)
    while True:
        try:
            return load(name, target)
        except ImportError as error:
            if fresh:
                raise ModelError(f"the compiled module {target} does not load: {error}") from None
        clear(target)
        make(name, target)
        fresh = True
