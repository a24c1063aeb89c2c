"""C backend: the same functions printed as C, compiled into a CPython extension module (see
`extension`) and called directly, one state per call or N states in one call. `write_c` writes plain C
source and a header for a controller."""
from __future__ import annotations

import re
import warnings
from collections.abc import Callable
from pathlib import Path

import numpy as np

from .. import __version__
from ..eom import EquationsOfMotion
from ..errors import ModelError
from ..progress import progress
from . import (QUANTITIES, Generated, NumericEoM, equations, expression, listed, quantities, reads, writer,
               written)
from .c_derivatives import CompiledDerivatives, plain_function, plain_parts
from .extension import build, compile_module, compiled, compiler, python_headers
from .kinematic_functions import placement
from .lines import check_ends
from .module import outputs
from .numpy_backend import C, C_TRIG, VECTOR_TRIG
from .parameters import Parameters
from .vector import C_VECTOR, TYPES, lanes_source, vector_sources


class CompiledEoM(CompiledDerivatives, NumericEoM):
    """`NumericEoM` with every function compiled from C (per call and batched). M, b, g, nle and the
    frames derived with them are built in one extension module up front; the others in a module each
    on first use."""

    def __init__(self, eom: EquationsOfMotion) -> None:
        compiler(), python_headers()  # a clear error before any work
        self._c, self._lanes = writer(eom, C_TRIG), writer(eom, C_VECTOR)
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
        written, exprs = [], []
        for i, key in enumerate(progress(keys, "printing C", unit="function")):
            build, symmetric = self._pending.pop(key)
            exprs.append((build(), symmetric))
            source, shape, ops = self._c.source(f"e{i}", *exprs[-1])
            written.append((key, source, shape, ops, self._c.trig_indices))

        def lanes() -> list[str | None]:  # on the first batch
            printing = progress(exprs, "printing vector C", unit="function")
            return vector_sources(self._lanes, printing, len(exprs))
        self.functions.update(extension_functions(written, self.nq, self.nv, len(self.params), lanes))

    def _pvec(self, params, key) -> list[float] | np.ndarray | None:
        """p as the extension reads it: the bound values, else those `key` uses (the others 0.0)."""
        if params is None and self.parameters.values is not None:
            return self.parameters.values
        return self._p(params, key) if self.params else None

    def _get(self, key: str) -> Generated:
        if key not in self.functions:
            self._on_demand(key)
        return self.functions[key]

    def call(self, key, q, u=None, ud=None, params=None, out=None) -> np.ndarray:
        return check_ends(self, self._get(key).function(q, u, ud, self._pvec(params, key), out), q, params)

    # the common entry points call the compiled function directly (vector outputs as vectors)
    def M(self, q, params=None, out=None) -> np.ndarray:
        return self._get("M").function(q, None, None, self._pvec(params, "M"), out)

    def b(self, q, u, params=None, out=None) -> np.ndarray:
        return self._get("b").vector(q, u, None, self._pvec(params, "b"), out)

    def g(self, q, params=None, out=None) -> np.ndarray:
        return self._get("g").vector(q, None, None, self._pvec(params, "g"), out)

    def nle(self, q, u, params=None, out=None) -> np.ndarray:
        if "nle" not in self.functions:
            return written(self.b(q, u, params) + self.g(q, params), out, q=q, u=u)
        return self.functions["nle"].vector(q, u, None, self._pvec(params, "nle"), out)


def extension_functions(written: list, nq: int, nv: int, n_params: int,
                        lanes: Callable[[], list[str | None]] | None = None) -> dict[str, Generated]:
    """The written functions [(key, C source of e<i>, shape, operations, trig indices)], compiled into
    one extension module; with `lanes`, the C of their vector functions w<i> (`vector.vector_sources`),
    compiled into a second module on the first batch."""
    module = build([(source, shape, trig) for _, source, shape, _, trig in written], nq, nv, n_params)

    def attach() -> None:  # on the first batch
        try:
            module._attach(lanes_module(lanes(), nq, nv, n_params).lanes)
        except ModelError as error:  # the compiler refuses vector types: one state at a time
            warnings.warn(f"batches run one state at a time: {error}", stacklevel=3)

    if lanes is not None:
        module._hook(attach)
    return {key: Generated(source, shape, ops, getattr(module, f"m{i}"), getattr(module, f"v{i}"))
            for i, (key, source, shape, ops, _) in enumerate(written)}


def lanes_module(sources: list[str | None], nq: int, nv: int, n_params: int):
    """The module of the vector functions `sources` (`vector.lanes_source`)."""
    return compiled((TYPES, sources, nq, nv, n_params),
                    lambda name, target: compile_module(lanes_source(name, sources), [], target))


def comment(text: str) -> str:
    """`text` safe inside a C comment: no comment delimiters, no line breaks or other unprintables."""
    text = "".join(c if c.isprintable() else "?" for c in str(text))
    return text.replace("*/", "*?").replace("/*", "/?")


def write_c(eom: EquationsOfMotion, directory, name: str = "eom",
            frames: list[str] | None = None, derivatives: bool = True) -> tuple[Path, Path]:
    """Plain C (no Python) for a controller: <name>.c and <name>.h with <name>_<quantity> for M, b, g,
    nle, T, U (those derived) and tau, per frame <name>_J_<k>, <name>_Jdot_u_<k>, <name>_X_<k> (default:
    the frames of derive(frames=...), else all), <name>_com, <name>_J_com, <name>_A_G (moving mass, no
    flexible link) and with contacts, loops or rolling disks <name>_J_c,
    <name>_Jdot_c_u and (loops, disks) <name>_closure, the inverse dynamics <name>_ID and its
    derivatives <name>_ID_derivatives, <name>_FD_derivatives (`derivatives=False` leaves those two out:
    the largest functions of a big robot), each f(q, u, ud, p, out). The header documents the inputs
    index by index (p[k]: the parameters sorted by name), and per function its output (row-major,
    zeroed by the caller; the constraint rows by name) and the entries of q, u, ud, p it reads."""
    equations(eom, "write_c")
    if not re.fullmatch(r"[A-Za-z_][A-Za-z0-9_]{0,63}", name):
        raise ModelError(f"write_c: name must be a C identifier, got {name!r}")
    directory = Path(directory)
    directory.mkdir(parents=True, exist_ok=True)
    c = writer(eom, C)
    frames = list(eom.frames or eom.system.frames) if frames is None else list(frames)
    parts = [(k, expression(eom, k), k == "M", QUANTITIES[k], []) for k in quantities(eom)]
    for k, frame in enumerate(frames):
        parts += [(f"J_{k}", eom.kinematics.jacobian(frame), False,
                   f"6 x NV Jacobian [J_P; J_R] of frame {frame}, world-aligned axes", []),
                  (f"Jdot_u_{k}", eom.kinematics.jacobian_dot_u(frame), False,
                   f"J̇ u of frame {frame} ([linear; angular])", []),
                  (f"X_{k}", placement(eom.kinematics, frame), False,
                   f"placement [R | p] (3 x 4) of frame {frame} in the world", [])]
    parts += [(out.key, out.build(), False, out.what, out.rows) for out in outputs(eom)
              if derivatives or out.key not in ("ID_derivatives", "FD_jacobian")]
    parts += plain_parts(eom) if derivatives else []
    body, decls, sources = ["#include <math.h>", VECTOR_TRIG, f'#include "{name}.h"', ""], [], {}
    for key, expr, symmetric, what, names in progress(parts, "writing C", unit="function"):
        source, (rows, cols), _ = sources[key] = c.source(f"{name}_{key}", expr, symmetric)
        body.append(source)
        named = "".join(f"\n *   row {r}: {comment(row)}" for r, row in enumerate(names))
        declaration = C.header.format(name=f"{name}_{key}").split("\n")[0]
        decls.append(f"/* {comment(what)}{named}\n * out: {rows} x {cols}, row-major; reads "
                     f"{listed(reads(source))} */\n{declaration};")
    texts = {key: source for key, (source, _, _) in sources.items()}
    if derivatives and (forward := plain_function(eom, name, texts)):
        body.append(forward[0])
        decls.append(forward[1])
    c_path, h_path = directory / f"{name}.c", directory / f"{name}.h"
    c_path.write_text("\n".join(body))
    h_path.write_text(header(eom, name) + "\n\n".join(decls) + "\n\n#endif\n")
    return c_path, h_path


def speed_labels(system) -> list[str]:
    """The speeds as a header names them: qd_<coordinate> where u_k is a coordinate's rate q̇_i, else their
    own names (the twist of a free flyer or ball joint: base_vx, ..., ball_wz)."""
    u = list(system.u)
    labels = [str(x) for x in u]
    for i, (q, rate) in enumerate(zip(system.q, system.qdot)):
        if rate in u:
            labels[u.index(rate)] = f"qd_{q} = d/dt q[{i}]"
    return labels


def header(eom: EquationsOfMotion, name: str) -> str:
    """The header's guard, sizes and the inputs' documentation, index by index."""
    params = Parameters(eom.system.parameters).symbols
    actuated = eom.system.actuated
    N = name.upper()
    lines = [f"#ifndef EOMGEN_{N}_H", f"#define EOMGEN_{N}_H",
             f"/* Generated by eomgen {__version__} ({eom.method}):",
             " * M(q) u̇ + b(q, u) + g(q) = τ(q, u) + Sᵀ τ_a.",
             " *",
             f" * Every function is {name}_<f>(q, u, ud, p, out), all arrays of double:",
             f" *   q:  {N}_NQ coordinates;  u: {N}_NV speeds;  ud: {N}_NV accelerations (same order as u);",
             f" *   p:  {N}_NP parameters, sorted by name; a function reads only the entries listed with it",
             " *       (the others may hold anything, e.g. 0.0);",
             " *   out: the output, row-major (out[i * cols + j]); only its nonzero entries are written,",
             " *       so out must be zeroed by the caller.",
             " * Entries:"]
    lines += [f" *   q[{k}]: {comment(x)}" for k, x in enumerate(eom.q)]
    lines += [f" *   u[{k}]: {comment(x)}" for k, x in enumerate(speed_labels(eom.system))]
    lines += [f" *   p[{k}]: {comment(x)}" for k, x in enumerate(params)]
    lines += [f" *   tau_a[{r}]: joint {comment(label)}, adds to tau[{list(eom.S.row(r)).index(1)}] "
              "(S^T tau_a)" for r, label in enumerate(actuated)]
    sizes = {"NQ": len(eom.q), "NV": len(eom.u), "NP": len(params), "NA": len(actuated)}
    lines += [" */", *(f"#define {N}_{k} {n}" for k, n in sizes.items()), "", ""]
    return "\n".join(lines)
