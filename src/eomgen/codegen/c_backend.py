"""C backend: the same functions printed as C, compiled into a CPython extension module (see
`extension`) and called directly, one state per call or N states in one call. `write_c` writes plain C
source and a header for a controller."""
from __future__ import annotations

import re
from pathlib import Path

import numpy as np

from ..eom import EquationsOfMotion
from ..errors import ModelError
from . import Generated, NumericEoM, NumericKane, writer
from .extension import build, compiler, python_headers
from .numpy_backend import C, C_TRIG


class CompiledEoM(NumericEoM):
    """`NumericEoM` with every function compiled from C (per call and batched). M, b, g, nle and the
    frames derived with them are built in one extension module up front; the others in a module each
    on first use."""

    def __init__(self, eom: EquationsOfMotion) -> None:
        compiler(), python_headers()  # a clear error before any work
        self._c = writer(eom, C_TRIG)
        self._pending: dict = {}
        self._deferring = True
        super().__init__(eom)  # registers the eager functions, then builds them together
        self._deferring = False
        self._build(list(self._pending))

    def _function(self, key, build, symmetric=False) -> Generated:
        self._built.setdefault(key, (build, symmetric))
        if key not in self.functions:
            self._pending[key] = (build, symmetric)
            if not self._deferring:
                self._build([key])
        return self.functions.get(key)

    def _build(self, keys: list[str]) -> None:
        written = []
        for i, key in enumerate(keys):
            expr, symmetric = self._pending.pop(key)
            source, shape, ops = self._c.source(f"e{i}", expr(), symmetric)
            written.append((key, source, shape, ops, self._c.trig_indices))
        self.functions.update(extension_functions(written, self.nq, self.nv, len(self.params)))

    def _pvec(self, params, key):
        return np.array(self._p(params, key), dtype=float) if self.params else None

    def _get(self, key: str) -> Generated:
        if key not in self.functions:
            self._on_demand(key)
        return self.functions[key]

    def call(self, key, q, u=None, ud=None, params=None) -> np.ndarray:
        return self._get(key).function(q, u, ud, self._pvec(params, key))

    # the common entry points call the compiled function directly (vector outputs as vectors)
    def M(self, q, params=None) -> np.ndarray:
        return self._get("M").function(q, None, None, self._pvec(params, "M"))

    def b(self, q, u, params=None) -> np.ndarray:
        return self._get("b").vector(q, u, None, self._pvec(params, "b"))

    def g(self, q, params=None) -> np.ndarray:
        return self._get("g").vector(q, None, None, self._pvec(params, "g"))

    def nle(self, q, u, params=None) -> np.ndarray:
        if "nle" not in self.functions:
            return self.b(q, u, params) + self.g(q, params)
        return self.functions["nle"].vector(q, u, None, self._pvec(params, "nle"))


def extension_functions(written: list, nq: int, nv: int, n_params: int) -> dict[str, Generated]:
    """The written functions [(key, C source of e<i>, shape, operations, trig indices)], compiled into
    one extension module."""
    module = build([(source, shape, trig) for _, source, shape, _, trig in written], nq, nv, n_params)
    return {key: Generated(source, shape, ops, getattr(module, f"m{i}"), getattr(module, f"v{i}"))
            for i, (key, source, shape, ops, _) in enumerate(written)}


class CompiledKane(NumericKane):
    """`NumericKane` compiled from C: the same functions, per call and batched."""

    syntax = C_TRIG

    def __init__(self, kane) -> None:
        compiler(), python_headers()
        super().__init__(kane)

    def _compile(self, written: list) -> dict[str, Generated]:
        return extension_functions(written, self.nq, self.nv, len(self.params))

    _pvec = CompiledEoM._pvec

    def _call(self, key, q, w, params):
        return self.functions[key].function(q, w, None, self._pvec(params, key))


def write_c(eom: EquationsOfMotion, directory, name: str = "eom", frames: list[str] | None = None) -> tuple[Path, Path]:
    """Plain C (no Python) for a controller: <name>.c and <name>.h with <name>_M, <name>_b, <name>_g (those
    derived) and per frame <name>_J_<k>, <name>_Jdot_u_<k> (default: the frames of derive(frames=...),
    else all), each (q, u, ud, p, out) with out row-major and zeroed by the caller."""
    if not re.fullmatch(r"[A-Za-z_][A-Za-z0-9_]{0,63}", name):
        raise ModelError(f"write_c: name must be a C identifier, got {name!r}")
    directory = Path(directory)
    directory.mkdir(parents=True, exist_ok=True)
    c = writer(eom, C)
    frames = list(eom.frames or eom.system.frames) if frames is None else list(frames)
    parts = [(k, eom.compact[k], k == "M") for k in eom.quantities]
    for k, frame in enumerate(frames):
        parts += [(f"J_{k}", eom.kinematics.jacobian(frame), False), (f"Jdot_u_{k}", eom.kinematics.jacobian_dot_u(frame), False)]
    body, decls = ["#include <math.h>", f'#include "{name}.h"', ""], []
    for key, expr, symmetric in parts:
        source, shape, _ = c.source(f"{name}_{key}", expr, symmetric)
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
