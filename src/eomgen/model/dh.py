"""Denavit-Hartenberg tables: a serial chain of revolute and prismatic joints given link by link.

Standard DH (Spong, Corke): T_{i-1,i} = Rz(θ_i) Tz(d_i) Tx(a_i) Rx(α_i); the joint moves in the middle.
Modified DH (Craig): T_{i-1,i} = Rx(α_{i-1}) Tx(a_{i-1}) Rz(θ_i) Tz(d_i); row i holds α_{i-1}, a_{i-1}.

Body i ("link{i}") has the frame F_{i-1} Rz(θ_i) Tz(d_i) (standard) or F_i (modified): its origin on
the joint axis, so that the joint is a `Revolute` or `Prismatic` about its z axis. In standard DH
this is DH frame i moved back by the tail Tx(a_i) Rx(α_i), through which com and inertia pass."""
from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass, fields

import mpmath
import sympy as sp

from ..errors import ModelError
from .joints import Placement, Prismatic, Revolute
from .system import System
from .values import matrix3, scalar, vector3

CONVENTIONS = ("standard", "modified")
KINDS = {"revolute": ("theta", "d"), "prismatic": ("d", "theta")}  # kind: (its variable, its constant)
Value = float | sp.Expr  # a number or a sympy expression
SNAP = 1e-12  # a float angle this close to a multiple of π/2 gives exact 0, ±1 entries


@dataclass(kw_only=True)
class DHLink:
    """One row of a DH table and the link it moves. The variable (θ of a revolute, d of a prismatic)
    is q + offset and must not be given. com and inertia (about the com) are in DH frame i; the
    joint's armature is armature + gear_ratio² · motor_inertia (the rotor reflected through the gear)."""

    d: Value | None = None
    a: Value | None = None
    alpha: Value | None = None
    theta: Value | None = None
    kind: str = "revolute"
    offset: Value = 0
    mass: Value = 0
    com: Sequence[Value] | sp.Matrix = (0, 0, 0)
    inertia: Sequence[Sequence[Value]] | sp.Matrix | None = None
    armature: Value = 0
    gear_ratio: Value = 1
    motor_inertia: Value = 0
    name: str | sp.Symbol | None = None


def from_dh(links, convention: str = "standard", base: Placement | None = None,
            tool: Placement | None = None, gravity=(0, 0, -9.81), *, strict: bool = True) -> System:
    """A `System` from a DH table (a sequence of `DHLink`), T_{i-1,i} = Rz(θ_i) Tz(d_i) Tx(a_i) Rx(α_i)
    (standard) or Rx(α_{i-1}) Tx(a_{i-1}) Rz(θ_i) Tz(d_i) (modified): body "link{i}" on joint q{i}
    (or the link's name), frame "dh{i}" at DH frame i (i = 1 … n), frame "tool" at `tool` in DH
    frame n; `base` places DH frame 0 in the world. `strict=False`: impossible inertias only warn."""
    if convention not in CONVENTIONS:
        raise ModelError(f"from_dh: convention must be 'standard' or 'modified', got {convention!r}")
    links = list(links) if isinstance(links, (list, tuple)) else links
    if not isinstance(links, list) or not links:
        raise ModelError(f"from_dh: links must be a non-empty list of DHLink, got {links!r}")
    for what, value in (("base", base), ("tool", tool)):
        if value is not None and not isinstance(value, Placement):
            raise ModelError(f"from_dh: {what} must be an eomgen.Placement, got {type(value).__name__}")
    system = System(gravity=gravity, strict=strict)
    tail, parent = base or Placement(), None  # tail: where the next joint frame sits on the parent
    for i, link in enumerate(links, start=1):
        row = _row(link, i)
        head = _head(row, convention)
        end = _tail(row, convention)
        joint = (Revolute if row["kind"] == "revolute" else Prismatic)(row["name"], armature=row["armature"])
        try:
            parent = system.add_body(
                f"link{i}", parent=parent, joint=joint, mass=row["mass"],
                com=end.translation + end.rotation * row["com"],
                inertia=end.rotation * row["inertia"] * end.rotation.T, placement=_compose(tail, head))
        except ModelError as error:
            raise ModelError(f"{row['label']}: {error}") from None
        system.add_frame(f"dh{i}", parent, end)
        tail = end
    if tool is not None:
        system.add_frame("tool", parent, _compose(tail, tool))
    return system


def _row(link, i: int) -> dict:
    """The link's fields checked, as sympy values; errors name the link (1-based) and the field."""
    if not isinstance(link, DHLink):
        raise ModelError(f"DH link {i}: expected an eomgen.DHLink, got {type(link).__name__}")
    label = f"DH link {i}" + ("" if link.name is None else f" ({str(link.name)!r})")
    if link.name is not None and not (isinstance(link.name, sp.Symbol)
                                      or isinstance(link.name, str) and link.name.strip()):
        raise ModelError(f"{label}: field 'name' must be a non-empty string or a sympy Symbol (the joint's "
                         f"coordinate), got {link.name!r}")
    if not isinstance(link.kind, str) or link.kind not in KINDS:
        raise ModelError(f"{label}: field 'kind' must be 'revolute' or 'prismatic', got {link.kind!r}")
    variable, constant = KINDS[link.kind]
    if getattr(link, variable) is not None:
        raise ModelError(f"{label}: field '{variable}' is the joint variable of a {link.kind} link "
                         "(q + offset); leave it out and give a constant offset instead")
    for name in (constant, "a", "alpha"):
        if getattr(link, name) is None:
            raise ModelError(f"{label}: field '{name}' is missing (a {link.kind} link needs "
                             f"{constant}, a and alpha)")
    row = {"kind": link.kind, "name": f"q{i}" if link.name is None else link.name, "label": label,
           "inertia": sp.zeros(3)}
    for f in fields(DHLink):
        value, what = getattr(link, f.name), f"{label}: field '{f.name}'"
        if f.name in ("kind", "name") or value is None:
            continue
        check = {"com": vector3, "inertia": matrix3}.get(f.name, scalar)
        row[f.name] = check(value, what)
    row[variable] = row["offset"]
    row["armature"] = row["armature"] + row["gear_ratio"] ** 2 * row["motor_inertia"]
    return row


def _head(row: dict, convention: str) -> Placement:
    """The constant transform between DH frame i−1 and the joint's motion: Rz(θ) Tz(d) (standard),
    Rx(α) Tx(a) Rz(θ) Tz(d) (modified); the variable holds only its offset here."""
    c, s = cos_sin(row["theta"])
    Rz = sp.Matrix([[c, -s, 0], [s, c, 0], [0, 0, 1]])
    motion_side = Placement(rotation=Rz, translation=(0, 0, row["d"]))
    return motion_side if convention == "standard" else _compose(_x_screw(row), motion_side)


def _tail(row: dict, convention: str) -> Placement:
    """DH frame i in the body frame: Tx(a) Rx(α) (standard), the identity (modified)."""
    return _x_screw(row) if convention == "standard" else Placement()


def _x_screw(row: dict) -> Placement:
    """Tx(a) Rx(α) = Rx(α) Tx(a)."""
    c, s = cos_sin(row["alpha"])
    return Placement(rotation=sp.Matrix([[1, 0, 0], [0, c, -s], [0, s, c]]), translation=(row["a"], 0, 0))


def _compose(A: Placement, B: Placement) -> Placement:
    """A · B: (R_A R_B, p_A + R_A p_B)."""
    return Placement(rotation=A.rotation * B.rotation,
                     translation=A.translation + A.rotation * B.translation)


def cos_sin(angle: sp.Expr) -> tuple[sp.Expr, sp.Expr]:
    """(cos, sin) of an angle; a float within SNAP of k π/2 gives the exact 0, ±1 (math.pi / 2 would
    leave 6e-17 where the table means 0)."""
    if angle.is_number and angle.has(sp.Float) and (k := _quarter_turns(angle)) is not None:
        return sp.cos(k * sp.pi / 2), sp.sin(k * sp.pi / 2)
    return sp.cos(angle), sp.sin(angle)


def _quarter_turns(angle: sp.Expr) -> int | None:
    """k where |angle − k π/2| < SNAP, else None, the difference taken with the angle's binary exponent
    and 64 bits more: in float64, every angle above 2^52 (whose spacing is 1 or more) is 'within' any
    tolerance of a multiple of π/2, and alpha = 1e17 (cos −0.886) became the identity."""
    bits = 64 + max(0, math.frexp(float(angle))[1])
    with mpmath.workprec(bits):
        x = mpmath.mpf(angle.evalf(math.ceil(bits * math.log10(2)) + 1))
        k = int(mpmath.nint(2 * x / mpmath.pi))
        return k if abs(x - k * mpmath.pi / 2) < SNAP else None
