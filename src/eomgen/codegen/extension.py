"""Generated C functions as one CPython extension module: compiled with the machine's C compiler,
cached by a hash of the source (and of the compiler flags, Python and NumPy it was built for), and
imported. Each function `e<i>` is exposed twice: `m<i>(q, u=None, ud=None, p=None)` returns the
output matrix (rows, cols), `v<i>` the column as a vector (rows,); q of shape (nq,) is one state,
(N, nq) is N states evaluated in one C loop with the GIL released, over all cores for large N (OpenMP;
OMP_NUM_THREADS=1 for one). Inputs are checked in C with the
messages of the NumPy backend (the argument named, shapes, NaN and infinities).

The cache, $EOMGEN_CACHE or ~/.cache/eomgen, is created private to the user (mode 0o700). Its modules
are loaded as code, so a folder that other users could write into is refused (world-writable, or owned
by someone else) and a group-writable one is warned about; a folder that cannot be created or written
is a ModelError naming EOMGEN_CACHE. Each module `<name><EXT_SUFFIX>` is moved in by an atomic rename,
then its checksum `<file>.sha256` (sha256 of the module's bytes) beside it; a module with no checksum,
another checksum or that does not load is rebuilt once (a truncated or corrupt file, an interrupted
build), and a ModelError if the rebuilt one does not load either."""
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
from pathlib import Path

import numpy as np

from ..errors import ModelError
from .compile import COMPILE, Unit, build_library, optimisation, translation_units

# batches over the cores with vector sin and cos; else one core, scalar sin and cos
ATTEMPTS = (["-fopenmp", "-lmvec", "-lm"], ["-DEOMGEN_NO_MVEC", "-lm"])

PRELUDE = r"""#define PY_SSIZE_T_CLEAN
#include <Python.h>
#define NPY_NO_DEPRECATED_API NPY_1_7_API_VERSION
#include <numpy/arrayobject.h>
#include <math.h>
#include <stdlib.h>

static void shape_text(char *buf, size_t size, PyObject *obj)
{
    /* "(6,)", "(10, 6)", as Python prints a shape */
    int nd = PyArray_Check(obj) ? PyArray_NDIM((PyArrayObject *)obj) : 0;
    size_t used = (size_t)snprintf(buf, size, "(");
    for (int d = 0; d < nd && used < size; ++d)
        used += (size_t)snprintf(buf + used, size - used, d ? ", %ld" : "%ld",
                                 (long)PyArray_DIM((PyArrayObject *)obj, d));
    if (used < size)
        snprintf(buf + used, size - used, nd == 1 ? ",)" : ")");
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
    const double *v = (const double *)PyArray_DATA(a);
    for (npy_intp k = 0, size = PyArray_SIZE(a); k < size; ++k)
        if (!isfinite(v[k])) {
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
/* glibc's vector sin and cos (libmvec, within 4 ulp) for the batched path; AVX2 where the CPU has it */
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

static PyObject *evaluate(eomgen_fn f, const int *idx, int nt, npy_intp rows, npy_intp cols, int vector,
                          PyObject *const *args, Py_ssize_t nargs)
{
    if (nargs < 1 || nargs > 4)
        return PyErr_Format(PyExc_TypeError, "expected (q, u=None, ud=None, p=None), got %zd arguments", nargs);
    PyArrayObject *a[4] = {NULL, NULL, NULL, NULL};
    PyObject *result = NULL;
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
    npy_intp dims[4] = {n, rows, cols, 0};
    result = PyArray_ZEROS(nd + 1 - vector, nd == 2 ? dims : dims + 1, NPY_DOUBLE, 0);
    if (result == NULL)
        goto done;
    {
        const double *q = PyArray_DATA(a[0]);
        const double *u = a[1] ? PyArray_DATA(a[1]) : ZEROS, *ud = a[2] ? PyArray_DATA(a[2]) : ZEROS;
        const double *p = a[3] ? PyArray_DATA(a[3]) : ZEROS;
        npy_intp su = a[1] ? NV : 0, sud = a[2] ? NV : 0, size = rows * cols;
        double *out = PyArray_DATA((PyArrayObject *)result);
        if (nd == 1) {
            double sinq[NQ], cosq[NQ];
            for (int t = 0; t < nt; ++t) {
                sinq[idx[t]] = sin(q[idx[t]]);
                cosq[idx[t]] = cos(q[idx[t]]);
            }
            f(q, u, ud, p, sinq, cosq, out);
        } else {
            int failed = 0;
            npy_intp blocks = (n + BLOCK - 1) / BLOCK;
            Py_BEGIN_ALLOW_THREADS
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
            Py_END_ALLOW_THREADS
            if (failed) {
                Py_CLEAR(result);
                PyErr_NoMemory();
                goto done;
            }
        }
    }
done:
    for (int k = 0; k < 4; ++k)
        Py_XDECREF(a[k]);
    return result;
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


def module_source(name: str, functions: list[tuple[str, tuple, list[int]]], nq: int, nv: int, n_params: int) -> str:
    """The extension module `name`: the functions (C text of `e<i>`, output shape, the k of the sin(q[k])
    and cos(q[k]) it reads) and their wrappers."""
    parts = [f"#define NQ {nq}\n#define NV {nv}\n#define NP {n_params}\n", PRELUDE]
    table = []
    for i, (source, (rows, cols), trig) in enumerate(functions):
        parts.append(source)  # static functions (`numpy_backend.C_TRIG`)
        parts.append(f"static const int t{i}[] = {{{', '.join(map(str, trig or [0]))}}};\n")
        for kind, vector in (("m", 0), ("v", 1)):
            parts.append(f"static PyObject *{kind}{i}(PyObject *self, PyObject *const *args, Py_ssize_t nargs)\n"
                         f"{{ return evaluate(e{i}, t{i}, {len(trig)}, {rows}, {cols}, {vector}, args, nargs); }}\n")
            table.append(f'    {{"{kind}{i}", (PyCFunction)(void (*)(void)){kind}{i}, METH_FASTCALL, NULL}},')
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


def compile_module(glue: str, units: list[Unit], target: Path) -> None:
    """Compile the module (`compile.build_library`) in a temp folder beside `target`, move it in (an atomic
    rename; a concurrent writer leaves the same bytes), then its checksum."""
    with tempfile.TemporaryDirectory(dir=target.parent) as tmp:  # same file system: the moves are renames
        so_file = Path(tmp) / target.name
        build_library(compiler(), glue, units, [f"-I{python_headers()}", f"-I{np.get_include()}"], ATTEMPTS,
                      Path(tmp), so_file)
        digest = Path(tmp) / "sha256"
        digest.write_text(sha256(so_file) + "\n")
        os.replace(so_file, target)
        os.replace(digest, checksum_file(target))


def load(name: str, target: Path):
    loader = importlib.machinery.ExtensionFileLoader(name, str(target))
    spec = importlib.util.spec_from_file_location(name, str(target), loader=loader)
    module = importlib.util.module_from_spec(spec)
    loader.exec_module(module)
    sys.modules[name] = module
    return module


def build(functions: list[tuple[str, tuple, list[int]]], nq: int, nv: int, n_params: int):
    """Compile (once per distinct translation units, glue, compiler, flags, Python and NumPy) and import the
    extension module; a cached module that is not intact or does not load is rebuilt once."""
    header, units = translation_units([source for source, _, _ in functions])
    layout = [(optimisation(unit), unit.text) for unit in units]
    key = repr((header, layout, [(shape, trig) for _, shape, trig in functions], nq, nv, n_params, PRELUDE,
                compiler(), COMPILE, ATTEMPTS, sys.version, np.__version__)).encode()
    name = "eomgen_" + hashlib.sha256(key).hexdigest()[:24]
    target = cache_dir() / (name + sysconfig.get_config_var("EXT_SUFFIX"))
    if name in sys.modules:
        return sys.modules[name]
    glue = module_source(name, [(header if i == 0 else "", shape, trig)
                                for i, (_, shape, trig) in enumerate(functions)], nq, nv, n_params)
    fresh = not intact(target)
    if fresh:
        compile_module(glue, units, target)
    while True:
        try:
            return load(name, target)
        except ImportError as error:
            if fresh:
                raise ModelError(f"the compiled module {target} does not load: {error}") from None
        compile_module(glue, units, target)
        fresh = True
