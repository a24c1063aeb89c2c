"""Generated C functions as one CPython extension module: compiled with the machine's C compiler,
linked with the glue all modules share (`glue`, compiled once per cache: `runtime_object`), cached by a
hash of the translation units and glue (`compile`; and of the compiler flags, the CPU, Python and NumPy
it was built for), and imported. Each function `e<i>` is exposed twice:
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
not load either. The shared glue's object `glue_<hash>.o` is kept the same way."""
from __future__ import annotations

import hashlib
import importlib.machinery
import importlib.util
import os
import shutil
import stat
import subprocess
import sys
import sysconfig
import tempfile
import warnings
from collections.abc import Callable
from pathlib import Path

import numpy as np

from ...errors import ModelError
from .glue import MODULE_STATE, RUNTIME, STATE
from .lanes import machine, sizes
from .compile import COMPILE, Unit, build_library, optimisation, translation_units

# batches over the cores with vector sin and cos; else one core, scalar sin and cos
ATTEMPTS = (["-fopenmp", "-lmvec", "-lm"], ["-DEOMGEN_NO_MVEC", "-lm"])

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
    and cos(q[k]) it reads), its `state` and the wrappers that hand both to the shared glue
    (`glue.RUNTIME`); `_attach` and `_hook` take the vector functions (`vector`); `extra`: more glue after
    the functions and its entries in the method table."""
    parts = [sizes(nq, nv, n_params, len(functions)), STATE, MODULE_STATE]
    table = ['    {"_attach", attach, METH_O, NULL},', '    {"_hook", set_hook, METH_O, NULL},']
    for i, (source, (rows, cols), trig) in enumerate(functions):
        parts.append(source)  # static functions (`numpy_backend.C_TRIG`)
        parts.append(f"static const int t{i}[] = {{{', '.join(map(str, trig or [0]))}}};\n")
        for kind, column in (("m", 0), ("v", 1)):
            parts.append(f"static PyObject *{kind}{i}(PyObject *self, PyObject *const *args, Py_ssize_t n)\n"
                         f"{{ return eomgen_evaluate(&state, e{i}, {i}, t{i}, {len(trig)}, {rows}, {cols}, "
                         f"{column}, args, n); }}\n")
            table.append(f'    {{"{kind}{i}", (PyCFunction)(void (*)(void)){kind}{i}, METH_FASTCALL, NULL}},')
    parts.append(extra[0])
    table.extend(extra[1])
    parts.append("static PyMethodDef methods[] = {\n" + "\n".join(table) + "\n    {NULL, NULL, 0, NULL}\n};\n"
                 f'static struct PyModuleDef module = {{PyModuleDef_HEAD_INIT, "{name}", NULL, -1, methods}};\n'
                 f"PyMODINIT_FUNC PyInit_{name}(void)\n"
                 "{\n    return eomgen_init() < 0 ? NULL : PyModule_Create(&module);\n}\n")
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


def compile_module(glue: str, units: list[Unit], target: Path, include: tuple[str, ...] = (),
                   runtime: bool = False) -> None:
    """Compile the module (`compile.build_library`; more header folders `include`; with `runtime`, linked
    with the shared glue, `runtime_object`) in a temp folder beside `target`, move it in (an atomic
    rename; a concurrent writer leaves the same bytes), then its checksum."""
    with tempfile.TemporaryDirectory(dir=target.parent) as tmp:  # same file system: the moves are renames
        so_file = Path(tmp) / target.name
        build_library(compiler(), glue, units, headers(include), ATTEMPTS, Path(tmp), so_file,
                      runtime_object if runtime else None)
        move_in(so_file, target)


def headers(include: tuple[str, ...] = ()) -> list[str]:
    """The -I options of Python's and NumPy's headers and of the folders `include`."""
    return [f"-I{folder}" for folder in (python_headers(), np.get_include(), *include)]


def move_in(built: Path, target: Path) -> None:
    """`built` moved to `target` (an atomic rename), then its checksum beside it."""
    digest = built.with_name("sha256")
    digest.write_text(sha256(built) + "\n")
    os.replace(built, target)
    os.replace(digest, checksum_file(target))


def runtime_object(options: list[str]) -> str:
    """The shared glue (`glue.RUNTIME`) compiled with the options of a build attempt, once per cache:
    glue_<hash>.o beside the modules with its checksum, moved in as they are, compiled again where it is
    not intact; a ModelError with the compiler's message."""
    key = repr((RUNTIME, compiler(), COMPILE, options, machine(), sys.version, np.__version__)).encode()
    target = cache_dir() / f"glue_{hashlib.sha256(key).hexdigest()[:24]}.o"
    if not intact(target):
        clear(target)
        with tempfile.TemporaryDirectory(dir=target.parent) as tmp:
            source, built = Path(tmp) / "glue.c", Path(tmp) / target.name
            source.write_text(RUNTIME)
            done = subprocess.run([compiler(), "-O2", *COMPILE, *headers(), *options, "-c", str(source), "-o",
                                   str(built)], capture_output=True, text=True)
            if done.returncode != 0:
                raise ModelError(f"the C compiler failed on the shared glue: {done.stderr[:2000]}")
            move_in(built, target)
    return str(target)


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
    entries = [(header if i == 0 else "", shape, trig) for i, (_, shape, trig) in enumerate(functions)]

    def make(name: str, target: Path) -> None:
        compile_module(module_source(name, entries, nq, nv, n_params, extra), units, target, include, True)

    # all the module is made of: the shared glue, its own glue text (but its name) and its units
    content = (RUNTIME, module_source("", entries, nq, nv, n_params, extra), layout, include)
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
