"""The written module target: a dependency-free Python module (numpy only) with the catalogue of one
model's equations: each function printed in Python (`walker`, the NumPy syntax) with a public function
that calls it, a family (one function per frame, load or joint) as a table and one public function taking
the item's name, and the runtime (`runtime`) for calls, parameters and the forward dynamics' derivatives.

Byte-identical for the same model: no dates, no paths, intermediates in derivation order. Names from
the model (frames, parameters, joints) appear only as string literals written by `repr`, never as code."""
from __future__ import annotations

import re
from pathlib import Path

from ..version import __version__
from ..eom import EquationsOfMotion
from ..functions import QUANTITIES, Catalogue, Family, Function, assumptions, catalogue, expect_equations
from ..functions import forward_dynamics
from .runtime import DERIVATIVES, PARAMETERS, RUNTIME
from .syntax import PYTHON
from .walker import FunctionWriter, reads, writer

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


_ITEM = '''
def _item(items, kind, name):
    if name not in items:
        raise ValueError("unknown %s %r; the %ss are %s" % (kind, name, kind, list(items)))
    return items.index(name)
'''

# the functions of form "columns": the matrix's private name, and the public function that splits it
_COLUMNS = {"ID_derivatives": ("_inverse_dynamics_jacobian", '''
def inverse_dynamics_derivatives(q, u, ud, params=None):
    """(∂τ/∂q, ∂τ/∂u) of inverse_dynamics, ∂/∂q in the tangent space (one column per speed)."""
    D = _inverse_dynamics_jacobian(q, u, ud, params)
    return D[..., :NV], D[..., NV:]
''')}

_FORWARD_DERIVATIVES = '''
def forward_dynamics_derivatives(q, u, tau=None, params=None):
    """(∂u̇/∂q, ∂u̇/∂u, ∂u̇/∂τ) of u̇ = M⁻¹ (τ + τ(q, u) − b − g), tau one effort per speed (Sᵀ τ_a for
    forward_dynamics' tau_a), or None; ∂/∂q in the tangent space."""
    return _forward_dynamics_derivatives(q, u, tau, params)


def _forward_dynamics_derivatives(q, u, efforts, params):
    h = tau(q, u, params) - {nle} + _efforts(efforts, NV, numpy.shape(q)[:-1])
    return _forward_derivatives(M(q, params), h, lambda ud: {jacobian}(q, u, ud, params), NV)
'''

_TABLES = {"J": "_JACOBIANS", "Jdot_u": "_JACOBIANS_DOT_U", "X": "_PLACEMENTS"}
ROWS = {"J_c": "CONSTRAINT_ROWS", "Jdot_c_u": "CONSTRAINT_ROWS", "closure": "CLOSURE_ROWS"}  # rows' names
_RETURNS = {"matrix": "", "vector": "[..., 0]", "number": "[..., 0, 0]", "columns": ""}


def printed(cat: Catalogue, fn: Function) -> bool:
    """Whether the module prints `fn`: every public function, and D, the part of the forward dynamics'
    derivatives its runtime calls (it forms [M | h] from M, tau and nle)."""
    runtime = {cat["FD_derivatives"].parts[1]} if "FD_derivatives" in cat else set()
    return (fn.public or fn.key in runtime) and not fn.composite


def _api(fn: Function, used: frozenset) -> str:
    """The public function of `fn`: M(q, params), b(q, u, params), ..., the private matrix of a split
    output."""
    name = _COLUMNS[fn.key][0] if fn.form == "columns" else fn.name
    doc = f"{fn.what} ({ROWS[fn.key]})" if fn.rows else fn.what
    used = tuple(sorted(used))
    return (f"def {name}({fn.inputs}, params=None):\n    \"\"\"{doc}.\"\"\"\n"
            f"    return _call(_{fn.key}, {fn.shape}, NQ, NV, {fn.inputs}, p=_p(params, {used}))"
            f"{_RETURNS[fn.form]}\n")


def _family_api(family: Family, table: str, items: str) -> str:
    """The public function of a family but the frames': {name}(item, inputs, params)."""
    returns = {"vector": "X[..., 0]", "number": "X[..., 0, 0]",
               "wrench": "X[..., :3, 0], X[..., 3:, 0]"}.get(family.form, "X")
    return (f"def {family.name}({family.kind}, {family.inputs}, params=None):\n"
            f"    \"\"\"{family.what.format(item=family.kind)}, a name of {items}.\"\"\"\n"
            f"    f, used = {table}[_item({items}, {family.kind!r}, {family.kind})]\n"
            f"    X = _call(f, {family.shape}, NQ, NV, {family.inputs}, p=_p(params, used))\n"
            f"    return {returns}\n")


class _Printed:
    """The sources of a module's functions, printed in the order their expressions are built (which names
    the intermediates a function adds)."""

    def __init__(self, cat: Catalogue) -> None:
        self.writer: FunctionWriter = writer(cat, PYTHON)
        self.sources: dict[str, str] = {}
        self.used: dict[str, frozenset] = {}

    def add(self, name: str, fn: Function) -> None:
        self.sources[name] = self.writer.function(f"_{name}", fn)[0]
        self.used[name] = frozenset(reads(self.sources[name])["p"])


def module_source(eom: EquationsOfMotion, frames: list[str] | None = None, title: str = "model") -> str:
    """The text of the module (see `write_module`)."""
    cat = catalogue(eom)
    if frames is None:
        frames = list(cat.families["J"].items)
    frames = list(frames)
    title = re.sub(r"[^A-Za-z0-9_.-]", "_", title)  # it goes into the docstring
    keys = [fn for fn in cat if fn.key in QUANTITIES]
    others = [fn for fn in cat if printed(cat, fn) and fn not in keys]
    families = [f for prefix, f in cat.families.items() if prefix not in cat.frames() and f.items]
    p = _Printed(cat)
    for fn in keys:
        p.add(fn.key, fn)
    for k, frame in enumerate(frames):
        for prefix in cat.frames():
            p.add(f"{prefix}{k}", cat[f"{prefix}:{frame}"])
    for fn in others:
        p.add(fn.key, fn)
    for family in families:
        for k, item in enumerate(family.items):
            p.add(f"{family.prefix}_{k}", cat[f"{family.prefix}:{item}"])
    parameters = cat.inputs["p"]
    rules = {str(x): a for x in parameters if (a := assumptions(x))}
    S = [[float(x) for x in row] for row in eom.S.tolist()]
    parts = [f'"""Equations of motion M(q) u̇ + b(q, u) + g(q) = τ(q, u) + Sᵀ τ_a of {title!r}, generated '
             f'by eomgen {__version__} ({eom.method}).\n\nNeeds only numpy. q has shape (NQ,) or (N, NQ), '
             "u (NV,) or (N, NV).\nParameters: params={name: value}, by name only (PARAMETERS); a "
             "function asks only for\nthose it uses, and a value must meet the parameter's ASSUMPTIONS."
             "\n\"\"\"",
             "import math\nfrom collections.abc import Mapping\n\nimport numpy\n",
             f"NQ = {len(eom.q)}",
             f"NV = {len(eom.u)}",
             f"COORDINATES = {tuple(str(x) for x in eom.q)!r}",
             f"SPEEDS = {tuple(str(x) for x in eom.u)!r}",
             f"PARAMETERS = {tuple(str(x) for x in parameters)!r}",
             f"ASSUMPTIONS = {rules!r}  # checked in every call (positive: > 0, ...)",
             f"FRAMES = {tuple(frames)!r}",
             f"ACTUATED = {tuple(eom.system.actuated)!r}  # τ_a, a row of S each",
             f"S = numpy.array({S!r}).reshape(len(ACTUATED), NV)  # selection matrix",
             *(f"{ROWS[fn.key]} = {list(fn.rows)!r}  # the rows of {fn.name}" for fn in others
               if fn.key in ("J_c", "closure")),
             *(f"{family.kind.upper()}S = {family.items!r}" for family in families if family.kind != "joint"
               or family.prefix == "W"),
             _HELPERS, RUNTIME, PARAMETERS]
    parts += [p.sources[fn.key] for fn in keys + others]
    for k in range(len(frames)):
        parts += [p.sources[f"{prefix}{k}"] for prefix in cat.frames()]
    for prefix in cat.frames():
        pairs = [f"(_{prefix}{k}, {tuple(sorted(p.used[f'{prefix}{k}']))})" for k in range(len(frames))]
        parts.append(f"{_TABLES[prefix]} = [{', '.join(pairs)}]")
    parts += [_api(fn, p.used[fn.key]) for fn in keys + others]
    nle = "nle(q, u, params)" if "nle" in cat else "(b(q, u, params) + g(q, params))"
    parts += [_JACOBIAN_API, _PLACEMENT_API]
    parts += [_COLUMNS[fn.key][1] for fn in others if fn.form == "columns"]
    if forward_dynamics(eom) and "FD_derivatives" in cat:
        jacobian = "_forward_dynamics_jacobian" if "FD_jacobian" in cat else "_inverse_dynamics_jacobian"
        parts += [DERIVATIVES, _FORWARD_DERIVATIVES.format(nle=nle, jacobian=jacobian)]
    if "A_G" in cat:
        parts.append(_CENTROIDAL_MOMENTUM)
    if forward_dynamics(eom):
        parts.append(_FORWARD.format(nle=nle))
    if families:
        parts.append(_ITEM)
    for family in families:
        table = f"_{family.prefix.upper()}_TABLE"
        parts += [p.sources[f"{family.prefix}_{k}"] for k in range(len(family.items))]
        pairs = [f"(_{family.prefix}_{k}, {tuple(sorted(p.used[f'{family.prefix}_{k}']))})"
                 for k in range(len(family.items))]
        parts += [f"{table} = [{', '.join(pairs)}]", _family_api(family, table, f"{family.kind.upper()}S")]
    return "\n\n".join(part.strip("\n") for part in parts) + "\n"


def write_module(eom: EquationsOfMotion, path, frames: list[str] | None = None,
                 title: str | None = None) -> Path:
    """Write an importable `.py` module that needs only numpy: M, b, g, nle, T, U (those derived), tau
    (the loads), forward_dynamics, jacobian, jacobian_dot_u and placement (for the given frames; default:
    every moving body and named frame), com, com_jacobian, centroidal_momentum_matrix and
    centroidal_momentum (when the system has moving mass and no flexible link) of `eom`, with PARAMETERS,
    their ASSUMPTIONS, ACTUATED and the selection matrix S; with contacts, loops or rolling disks also
    contact_jacobian (J_c), contact_jacobian_dot_u (J̇_c u) and closure_residual (loops, disks), their rows
    named in CONSTRAINT_ROWS and CLOSURE_ROWS; qdot, the inverse dynamics and its derivatives (and without
    constraints the forward dynamics'), tau_of(load, ...) (LOADS) and for the free cut
    joint_wrench(joint, ...) and joint_reaction(joint, ...) (JOINTS): every public function of the
    catalogue (`eomgen.functions`)."""
    expect_equations(eom, "write_module")
    path = Path(path)
    title = title or getattr(eom.system, "name", None) or path.stem
    path.write_text(module_source(eom, frames, title))
    return path
