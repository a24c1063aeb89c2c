"""C backend: the same functions printed as C, compiled with the machine's C compiler into shared
libraries (cached by a hash of the source, reused across runs) and called through ctypes, one state
per call or N states in one call. `write_c` writes plain C source and a header for a controller."""
from __future__ import annotations

import ctypes
import hashlib
import math
import os
import re
import shutil
import subprocess
import tempfile
from pathlib import Path

import numpy as np

from ..eom import EquationsOfMotion
from ..errors import ModelError
from . import Generated, NumericEoM, _inputs
from .numpy_backend import C, FunctionWriter

_P = ctypes.c_void_p


def compiler() -> str:
    cc = os.environ.get("CC", "cc")
    path = shutil.which(cc)
    if path is None:
        raise ModelError(f"no C compiler found (looked for {cc!r}; set CC); the NumPy backend works without one")
    return path


def cache_dir() -> Path:
    folder = Path(os.environ.get("EOMGEN_CACHE", Path.home() / ".cache" / "eomgen"))
    folder.mkdir(parents=True, exist_ok=True)
    return folder


def library_source(function: str, shape: tuple, nq: int, nv: int) -> str:
    """One generated function `f` and its batched loop `f_batch`."""
    size = shape[0] * shape[1]
    return (f"#include <math.h>\n\n{function}\n"
            "void f_batch(long n, const double *q, const double *u, const double *ud, const double *p, double *out)\n"
            f"{{\n    for (long k = 0; k < n; ++k)\n        f(q + k * {nq}, u + k * {nv}, ud + k * {nv}, p, out + k * {size});\n}}\n")


def compile_library(source: str):
    """The shared library of `source`, compiled once per distinct source."""
    digest = hashlib.sha256(source.encode()).hexdigest()[:24]
    target = cache_dir() / f"eomgen_{digest}.so"
    if not target.exists():
        with tempfile.TemporaryDirectory() as tmp:
            c_file, so_file = Path(tmp) / "f.c", Path(tmp) / "f.so"
            c_file.write_text(source)
            result = subprocess.run([compiler(), "-O2", "-fPIC", "-shared", str(c_file), "-o", str(so_file), "-lm"],
                                    capture_output=True, text=True)
            if result.returncode != 0:
                raise ModelError(f"the C compiler failed: {result.stderr[:2000]}")
            shutil.move(str(so_file), target)  # atomic enough for a cache: same bytes from any writer
    lib = ctypes.CDLL(str(target))
    lib.f.argtypes = [_P, _P, _P, _P, _P]
    lib.f.restype = None
    lib.f_batch.argtypes = [ctypes.c_long, _P, _P, _P, _P, _P]
    lib.f_batch.restype = None
    return lib


class CompiledEoM(NumericEoM):
    """`NumericEoM` with every function compiled from C (per call and batched)."""

    def __init__(self, eom: EquationsOfMotion) -> None:
        compiler()  # a clear error before any work
        self._buffers: dict = {}
        self._c = FunctionWriter(eom.subexpressions, {"q": list(eom.q), "u": list(eom.u),
                                                       "ud": list(eom.system.ud),
                                                       "p": sorted(eom.system.parameters, key=str)}, C)
        super().__init__(eom)

    def _function(self, key, build, symmetric=False) -> Generated:
        if key not in self.functions:
            source, shape, ops = self._c.source("f", build(), symmetric)
            lib = compile_library(library_source(source, shape, self.nq, self.nv))
            self.functions[key] = Generated(source, shape, ops, lib)
        return self.functions[key]

    def call(self, key, q, u=None, ud=None, params=None) -> np.ndarray:
        if key not in self.functions:
            self._on_demand(key)
        f = self.functions[key]
        if params is None and np.ndim(q) == 1:  # one state: persistent buffers, one ctypes call
            return self._single(key, f, q, u, ud)
        (q, u, ud), batch = _inputs(self.nq, self.nv, q, u, ud)
        q, u, ud = (np.ascontiguousarray(x) for x in (q, u, ud))
        p = np.array(self._p(params, key), dtype=float)
        out = np.zeros(batch + f.shape)
        pointers = [x.ctypes.data for x in (q, u, ud, p, out)]
        if batch:
            f.function.f_batch(batch[0], *pointers)
        else:
            f.function.f(*pointers)
        return out

    def _single(self, key, f, q, u, ud) -> np.ndarray:
        buffers = self._buffers.get(key)
        if buffers is None:
            arrays = [np.zeros(self.nq), np.zeros(self.nv), np.zeros(self.nv),
                      np.array(self._p(None, key), dtype=float), np.zeros(f.shape)]
            buffers = self._buffers[key] = (arrays, [a.ctypes.data for a in arrays])
        (qb, ub, udb, _, out), pointers = buffers
        try:
            qb[:] = q
            ub[:] = 0.0 if u is None else u
            udb[:] = 0.0 if ud is None else ud
        except (ValueError, TypeError):
            _inputs(self.nq, self.nv, q, u, ud)  # raises the error that names the argument
            raise
        if not math.isfinite(qb.dot(qb) + ub.dot(ub) + udb.dot(udb)):
            _inputs(self.nq, self.nv, q, u, ud)
        f.function.f(*pointers)  # writes only the nonzero entries; the others stay 0
        return out.copy()


def write_c(eom: EquationsOfMotion, directory, name: str = "eom", frames: list[str] | None = None) -> tuple[Path, Path]:
    """Plain C (no Python) for a controller: <name>.c and <name>.h with <name>_M, <name>_b, <name>_g and
    per frame <name>_J_<k>, <name>_Jdot_u_<k>, each (q, u, ud, p, out) with out row-major and zeroed by the caller."""
    if not re.fullmatch(r"[A-Za-z_][A-Za-z0-9_]{0,63}", name):
        raise ModelError(f"write_c: name must be a C identifier, got {name!r}")
    directory = Path(directory)
    directory.mkdir(parents=True, exist_ok=True)
    writer = FunctionWriter(eom.subexpressions, {"q": list(eom.q), "u": list(eom.u), "ud": list(eom.system.ud),
                                                  "p": sorted(eom.system.parameters, key=str)}, C)
    frames = list(eom.system.frames) if frames is None else list(frames)
    parts = [("M", eom.compact["M"], True), ("b", eom.compact["b"], False), ("g", eom.compact["g"], False)]
    for k, frame in enumerate(frames):
        parts += [(f"J_{k}", eom.kinematics.jacobian(frame), False), (f"Jdot_u_{k}", eom.kinematics.jacobian_dot_u(frame), False)]
    body, decls = ["#include <math.h>", f'#include "{name}.h"', ""], []
    for key, expr, symmetric in parts:
        source, shape, _ = writer.source(f"{name}_{key}", expr, symmetric)
        body.append(source)
        decls.append(f"/* out: {shape[0]} x {shape[1]} */\n" + source.split("\n")[0] + ";")
    frame_list = "".join(f"/*   {k}: frame {repr(f)[1:-1].replace('*/', '* /')} */\n" for k, f in enumerate(frames))
    guard = f"EOMGEN_{name.upper()}_H"
    header = (f"#ifndef {guard}\n#define {guard}\n/* generated by eomgen: NQ = {len(eom.q)}, NV = {len(eom.u)} */\n"
              f"{frame_list}\n" + "\n".join(decls) + "\n#endif\n")
    c_path, h_path = directory / f"{name}.c", directory / f"{name}.h"
    c_path.write_text("\n".join(body))
    h_path.write_text(header)
    return c_path, h_path
