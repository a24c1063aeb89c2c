"""A dependency-free Python module (numpy only) with the equations of motion of one model.

Byte-identical for the same model: no dates, no paths, intermediates in derivation order. Names from
the model (frames, parameters, joints) appear only as string literals written by `repr`, never as code."""
from __future__ import annotations

import re
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path

from .. import __version__, centroidal
from ..eom import EquationsOfMotion
from ..errors import ModelError
from . import QUANTITIES, NumericEoM, equations, quantities
from .derivative_functions import forward_dynamics, module_api
from .derivative_functions import outputs as derivatives
from .kinematic_functions import placement
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

_PLACEMENT_API = '''
def placement(frame, q, params=None):
    """(R, p): the rotation and position of a frame in the world."""
    f, used = _PLACEMENTS[_frame(frame)]
    X = _call(f, (3, 4), NQ, NV, q, p=_p(params, used))
    return X[..., :3], X[..., 3]
'''

_CENTROIDAL_MOMENTUM = '''
def centroidal_momentum(q, u, params=None):
    """h_G = A_G u: linear momentum and angular momentum about the centre of mass."""
    return numpy.einsum("...ij,...j->...i", centroidal_momentum_matrix(q, params), numpy.asarray(u, float))
'''

_FORWARD = '''
def forward_dynamics(q, u, tau_a=None, params=None):
    """u̇ = M⁻¹ (τ(q, u) + Sᵀ τ_a − b − g); tau_a: one value per ACTUATED joint, or None."""
    h = _actuated(tau(q, u, params) - {nle}, tau_a, S)
    return numpy.linalg.solve(M(q, params), h[..., None])[..., 0]
'''


ARGS = {"M": "q", "g": "q", "U": "q"}  # the rest: q, u
MATRICES = ("M", "J_c", "J_com", "A_G", "ID_derivatives", "FD_jacobian")  # the rest: vectors (T, U numbers)


@dataclass(frozen=True)
class Output:
    """A generated output beyond the equations: its key, public name, what it is, its expression (built on
    request), its rows' names (constraints) and arguments."""

    key: str
    name: str
    what: str
    build: Callable
    rows: list = field(default_factory=list)
    args: str = "q"


def _api(key: str, shape: tuple, used: frozenset, name: str | None = None, doc: str | None = None,
         args: str | None = None) -> str:
    """The public function `name` (default: `key`) of quantity `key` (M(q, params), b(q, u, params), ...),
    or of an `Output` (J_c(q, ...), Jdot_c_u(q, u, ...), com(q, ...), ...)."""
    args = args or ARGS.get(key, "q, u")
    last = "" if key in MATRICES else "[..., 0, 0]" if key in ("T", "U") else "[..., 0]"
    return (f"def {name or key}({args}, params=None):\n    \"\"\"{doc or QUANTITIES[key]}.\"\"\"\n"
            f"    return _call(_{key}, {shape}, NQ, NV, {args}, p=_p(params, {tuple(sorted(used))}))"
            f"{last}\n")


ROWS = {"J_c": "CONSTRAINT_ROWS", "Jdot_c_u": "CONSTRAINT_ROWS", "closure": "CLOSURE_ROWS"}  # rows' names


def outputs(eom: EquationsOfMotion) -> list[Output]:
    """The centre of mass, its Jacobian and A_G (when the system has moving mass and no flexible link) and,
    with contacts, loops or rolling disks, J_c and J̇_c u, with loops or disks the closure residual."""
    system, kin = eom.system, eom.kinematics
    rows, closure = system.constraint_rows(), system.closure_rows()
    found = []
    try:
        centroidal.total_mass(kin)
        found += [Output("com", "com", "centre of mass c (world)", lambda: centroidal.com(kin)),
                  Output("J_com", "com_jacobian", "J_com (3 x NV), the Jacobian of the centre of mass",
                         lambda: centroidal.com_jacobian(kin)),
                  Output("A_G", "centroidal_momentum_matrix", "A_G (6 x NV): [linear momentum; angular "
                         "momentum about c] per unit speed, world axes",
                         lambda: centroidal.centroidal_momentum_matrix(kin))]
    except ModelError:  # no moving mass, or a flexible link: no centre of mass to write
        pass
    if rows:
        found += [Output("J_c", "contact_jacobian", "J_c: the stacked rows of every contact, loop and "
                         "rolling disk, world-aligned axes", lambda: kin.constraint_jacobian()[0], rows),
                  Output("Jdot_c_u", "contact_jacobian_dot_u", "J̇_c u, stacked like J_c's rows",
                         lambda: kin.constraint_jacobian()[1], rows, "q, u")]
    if closure:
        found.append(Output("closure", "closure_residual", "the loops' and rolling disks' position "
                            "residuals, zero when closed", kin.closure_residual, closure))
    return found + [Output(key, name, what, build, args=args)
                    for key, name, what, build, args in derivatives(eom)]


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
    kin = eom.kinematics
    for k, frame in enumerate(frames):
        f._function(f"J:{k}", lambda frame=frame: kin.jacobian(frame))
        f._function(f"Jdot_u:{k}", lambda frame=frame: kin.jacobian_dot_u(frame))
        f._function(f"X:{k}", lambda frame=frame: placement(kin, frame))
    extra = outputs(eom)
    for out in extra:
        f._function(out.key, out.build)
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
             *(f"{ROWS[out.key]} = {out.rows!r}  # the rows of {out.name}" for out in extra
               if out.key in ("J_c", "closure")),
             _HELPERS, RUNTIME, PARAMETER_RUNTIME]
    written = keys + [out.key for out in extra]
    parts += [f.functions[key].source.replace("def f(", f"def _{key}(", 1) for key in written]
    per_frame = (("_JACOBIANS", "J"), ("_JACOBIANS_DOT_U", "Jdot_u"), ("_PLACEMENTS", "X"))
    for k in range(len(frames)):
        parts += [f.functions[f"{prefix}:{k}"].source.replace("def f(", f"def _{prefix}{k}(", 1)
                  for _, prefix in per_frame]
    for name, prefix in per_frame:
        pairs = [f"(_{prefix}{k}, {tuple(sorted(f.functions[f'{prefix}:{k}'].params_used))})"
                 for k in range(len(frames))]
        parts.append(f"{name} = [{', '.join(pairs)}]")
    parts += [_api(key, f.functions[key].shape, f.functions[key].params_used) for key in keys]
    parts += [_api(out.key, f.functions[out.key].shape, f.functions[out.key].params_used, out.name,
                   f"{out.what} ({ROWS[out.key]})" if out.rows else out.what, out.args) for out in extra]
    nle = "nle(q, u, params)" if "nle" in keys else "(b(q, u, params) + g(q, params))"
    parts += [_JACOBIAN_API, _PLACEMENT_API, *module_api(eom, nle)]
    if any(out.key == "A_G" for out in extra):
        parts.append(_CENTROIDAL_MOMENTUM)
    if forward_dynamics(eom):
        parts.append(_FORWARD.format(nle=nle))
    return "\n\n".join(p.strip("\n") for p in parts) + "\n"


def write_module(eom: EquationsOfMotion, path, frames: list[str] | None = None,
                 title: str | None = None) -> Path:
    """Write an importable `.py` module that needs only numpy: M, b, g, nle, T, U (those derived), tau
    (the loads), forward_dynamics, jacobian, jacobian_dot_u and placement (for the given frames; default:
    every moving body and named frame), com, com_jacobian, centroidal_momentum_matrix and
    centroidal_momentum (when the system has moving mass and no flexible link) of `eom`, with PARAMETERS,
    their ASSUMPTIONS, ACTUATED and the selection matrix S; with contacts, loops or rolling disks also
    contact_jacobian (J_c), contact_jacobian_dot_u (J̇_c u) and closure_residual (loops, disks), their rows
    named in CONSTRAINT_ROWS and CLOSURE_ROWS."""
    equations(eom, "write_module")
    path = Path(path)
    title = title or getattr(eom.system, "name", None) or path.stem
    path.write_text(module_source(eom, frames, title))
    return path
