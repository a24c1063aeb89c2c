"""A dependency-free Python module (numpy only) with the equations of motion of one model.

Byte-identical for the same model: no dates, no paths, intermediates in derivation order. Names from
the model (frames, parameters, joints) appear only as string literals written by `repr`, never as code."""
from __future__ import annotations

import re
from collections.abc import Callable
from pathlib import Path

from .. import __version__
from ..eom import EquationsOfMotion
from . import QUANTITIES, NumericEoM, equations, quantities
from .parameters import RUNTIME as PARAMETER_RUNTIME
from .runtime import RUNTIME

_HELPERS = '''
_INDEX = {name: k for k, name in enumerate(PARAMETERS)}
_RULES = {_INDEX[name]: rules for name, rules in ASSUMPTIONS.items()}
_Error = ValueError


def _p(params, used):
    """The parameter vector from params, a mapping {name: value}; only the parameters in `used` must
    be given, each a finite real number meeting its ASSUMPTIONS."""
    return _parameter_vector(PARAMETERS, _INDEX, used, params, _RULES)


def _frame(frame):
    if frame not in FRAMES:
        raise ValueError("unknown frame %r; the frames are %s" % (frame, list(FRAMES)))
    return FRAMES.index(frame)
'''

_JACOBIAN_API = '''
def jacobian(frame, q, params=None):
    """6 × NV Jacobian [J_P; J_R] of a frame's origin, world-aligned axes."""
    f, used = _JACOBIANS[_frame(frame)]
    return _call(f, (6, NV), NQ, NV, q, p=_p(params, used))


def jacobian_dot_u(frame, q, u, params=None):
    """J̇ u of a frame ([linear; angular])."""
    f, used = _JACOBIANS_DOT_U[_frame(frame)]
    return _call(f, (6, 1), NQ, NV, q, u, p=_p(params, used))[..., 0]
'''

_FORWARD = '''
def forward_dynamics(q, u, tau_a=None, params=None):
    """u̇ = M⁻¹ (τ(q, u) + Sᵀ τ_a − b − g); tau_a: one value per ACTUATED joint, or None."""
    h = _actuated(tau(q, u, params) - {nle}, tau_a, S)
    return numpy.linalg.solve(M(q, params), h[..., None])[..., 0]
'''


def _api(key: str, shape: tuple, used: frozenset, name: str | None = None, doc: str | None = None) -> str:
    """The public function `name` (default: `key`) of quantity `key` (M(q, params), b(q, u, params), ...;
    J_c(q, ...), Jdot_c_u(q, u, ...), closure(q, ...))."""
    args = "q" if key in ("M", "g", "U", "J_c", "closure") else "q, u"
    last = "" if key in ("M", "J_c") else "[..., 0, 0]" if key in ("T", "U") else "[..., 0]"
    return (f"def {name or key}({args}, params=None):\n    \"\"\"{doc or QUANTITIES[key]}.\"\"\"\n"
            f"    return _call(_{key}, {shape}, NQ, NV, {args}, p=_p(params, {tuple(sorted(used))}))"
            f"{last}\n")


ROWS = {"J_c": "CONSTRAINT_ROWS", "Jdot_c_u": "CONSTRAINT_ROWS", "closure": "CLOSURE_ROWS"}  # rows' names


def constraint_outputs(eom: EquationsOfMotion) -> list[tuple[str, str, str, Callable, list[str]]]:
    """(key, public name, what, expression, row names) of J_c, J̇_c u (when the system has contacts, loops
    or rolling disks) and the closure residual (when it has loops or rolling disks)."""
    system, kin = eom.system, eom.kinematics
    rows, closure = system.constraint_rows(), system.closure_rows()
    outputs = [("J_c", "contact_jacobian", "J_c: the stacked rows of every contact, loop and rolling disk, "
                "world-aligned axes", lambda: kin.constraint_jacobian()[0], rows),
               ("Jdot_c_u", "contact_jacobian_dot_u", "J̇_c u, stacked like J_c's rows",
                lambda: kin.constraint_jacobian()[1], rows),
               ("closure", "closure_residual", "the loops' and rolling disks' position residuals, zero when "
                "closed", kin.closure_residual, closure)]
    return [out for out in outputs if out[4]]


def module_source(eom: EquationsOfMotion, frames: list[str] | None = None, title: str = "model") -> str:
    """The text of the module (see `write_module`)."""
    f = NumericEoM(eom)
    if frames is None:
        frames = [b.name for b in eom.system.bodies if b.index is not None] + list(eom.system.frames)
    frames = list(frames)
    title = re.sub(r"[^A-Za-z0-9_.-]", "_", title)  # it goes into the docstring
    keys = quantities(eom)
    for key in keys:
        if key not in f.functions:  # tau, T, U
            f._on_demand(key)
    for k, frame in enumerate(frames):
        f._function(f"J:{k}", lambda frame=frame: eom.kinematics.jacobian(frame))
        f._function(f"Jdot_u:{k}", lambda frame=frame: eom.kinematics.jacobian_dot_u(frame))
    constraints = constraint_outputs(eom)
    for key, _, _, expr, _ in constraints:
        f._function(key, expr)
    parts = [f'"""Equations of motion M(q) u̇ + b(q, u) + g(q) = τ(q, u) + Sᵀ τ_a of {title!r}, generated '
             f'by eomgen {__version__} ({eom.method}).\n\nNeeds only numpy. q has shape (NQ,) or (N, NQ), '
             "u (NV,) or (N, NV).\nParameters: params={name: value}, by name only (PARAMETERS); a "
             "function asks only for\nthose it uses, and a value must meet the parameter's ASSUMPTIONS."
             "\n\"\"\"",
             "import math\nfrom collections.abc import Mapping\n\nimport numpy\n",
             f"NQ = {f.nq}",
             f"NV = {f.nv}",
             f"COORDINATES = {tuple(str(x) for x in eom.q)!r}",
             f"SPEEDS = {tuple(str(x) for x in eom.u)!r}",
             f"PARAMETERS = {f.parameters.names!r}",
             f"ASSUMPTIONS = {f.parameters.assumptions!r}  # checked in every call (positive: > 0, ...)",
             f"FRAMES = {tuple(frames)!r}",
             f"ACTUATED = {tuple(eom.system.actuated)!r}  # τ_a, a row of S each",
             f"S = numpy.array({f.S.tolist()!r}).reshape(len(ACTUATED), NV)  # selection matrix",
             *(f"{ROWS[key]} = {rows!r}  # the rows of {name}" for key, name, _, _, rows in constraints
               if key != "Jdot_c_u"),
             _HELPERS, RUNTIME, PARAMETER_RUNTIME]
    written = keys + [key for key, *_ in constraints]
    parts += [f.functions[key].source.replace("def f(", f"def _{key}(", 1) for key in written]
    for k in range(len(frames)):
        parts.append(f.functions[f"J:{k}"].source.replace("def f(", f"def _J{k}(", 1))
        parts.append(f.functions[f"Jdot_u:{k}"].source.replace("def f(", f"def _Jdot_u{k}(", 1))
    for name, prefix in (("_JACOBIANS", "J"), ("_JACOBIANS_DOT_U", "Jdot_u")):
        pairs = [f"(_{prefix}{k}, {tuple(sorted(f.functions[f'{prefix}:{k}'].params_used))})"
                 for k in range(len(frames))]
        parts.append(f"{name} = [{', '.join(pairs)}]")
    parts += [_api(key, f.functions[key].shape, f.functions[key].params_used) for key in keys]
    parts += [_api(key, f.functions[key].shape, f.functions[key].params_used, name, f"{what} ({ROWS[key]})")
              for key, name, what, _, _ in constraints]
    parts.append(_JACOBIAN_API)
    if {"M", "b", "g"} <= set(keys):
        nle = "nle(q, u, params)" if "nle" in keys else "(b(q, u, params) + g(q, params))"
        parts.append(_FORWARD.format(nle=nle))
    return "\n\n".join(p.strip("\n") for p in parts) + "\n"


def write_module(eom: EquationsOfMotion, path, frames: list[str] | None = None,
                 title: str | None = None) -> Path:
    """Write an importable `.py` module that needs only numpy: M, b, g, nle, T, U (those derived), tau
    (the loads), forward_dynamics, jacobian and jacobian_dot_u (for the given frames; default: every
    moving body and named frame) of `eom`, with PARAMETERS, their ASSUMPTIONS, ACTUATED and the
    selection matrix S; with contacts, loops or rolling disks also contact_jacobian (J_c),
    contact_jacobian_dot_u (J̇_c u) and closure_residual (loops, disks), their rows named in
    CONSTRAINT_ROWS and CLOSURE_ROWS."""
    equations(eom, "write_module")
    path = Path(path)
    title = title or getattr(eom.system, "name", None) or path.stem
    path.write_text(module_source(eom, frames, title))
    return path
