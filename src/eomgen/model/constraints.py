"""Constraints that close the tree: loop closures between two frames and disks rolling on a plane.

They hold rows of J_c u = 0 like the contacts (see `Contact`), and have a position residual that is
zero when they are closed (`Kinematics.closure_residual`)."""
from __future__ import annotations

from dataclasses import dataclass

import sympy as sp

from ..errors import ModelError
from .joints import Placement
from .values import vector3

LOOP_KINDS = {"point": ("x", "y", "z"), "spherical": ("x", "y", "z"),
              "frame": ("x", "y", "z", "rx", "ry", "rz"), "revolute": ("x", "y", "z", "r1", "r2")}


@dataclass(frozen=True)
class Contact:
    """A rigid contact at a frame: "point" (3 rows, J_P of its origin) or "frame" (6 rows)."""

    frame: str
    kind: str

    @property
    def name(self) -> str:
        return self.frame

    @property
    def rows(self) -> int:
        """The contact's rows in J_c: 3 for a point, 6 for a frame."""
        return 3 if self.kind == "point" else 6

    @property
    def row_names(self) -> list[str]:
        return [f"{self.frame}.{a}" for a in ("x", "y", "z", "rx", "ry", "rz")[:self.rows]]


@dataclass(frozen=True, eq=False)
class Loop:
    """frame_a and frame_b held together: origins coincide ("point", "spherical"), poses coincide
    ("frame"), or origins coincide and the relative rotation is about `axis` (frame_a's axes; "revolute").
    Its force F (rows like `row_names`: force along world x, y, z; torque along world x, y, z, or for a
    revolute loop along t_i = R_a n_i ⟂ axis) acts on frame_a's body at its origin, −F on frame_b's."""

    name: str
    frame_a: str
    frame_b: str
    kind: str
    axis: sp.Matrix  # unit, frame_a's axes (revolute)
    normals: tuple  # revolute: two unit vectors ⟂ axis (frame_a's axes), else ()

    @property
    def row_names(self) -> list[str]:
        return [f"{self.name}.{a}" for a in LOOP_KINDS[self.kind]]

    @property
    def closure_names(self) -> list[str]:
        return self.row_names


@dataclass(frozen=True, eq=False)
class Rolling:
    """A thin disk of `radius`, centre at the body origin, axle `axis` (unit, body axes), rolling without
    slip on the plane z = 0 of `ground` (its z axis the normal toward the disk, its x, y axes the rows t1, t2
    of the no-slip conditions)."""

    name: str
    body: object
    radius: sp.Expr
    axis: sp.Matrix
    ground: Placement

    @property
    def row_names(self) -> list[str]:
        return [f"{self.name}.{a}" for a in ("t1", "t2", "n")]

    @property
    def closure_names(self) -> list[str]:
        return [f"{self.name}.height"]


def unit(v: sp.Matrix, what: str) -> sp.Matrix:
    """v / |v|, refused when zero."""
    norm = sp.sqrt(sum(x ** 2 for x in v))
    if norm.is_zero:
        raise ModelError(f"{what} must not be zero")
    return v if norm == 1 else v / norm


def normals(axis: sp.Matrix, what: str) -> tuple[sp.Matrix, sp.Matrix]:
    """Two unit vectors n1, n2 with (n1, n2, axis) right-handed and orthonormal (numeric axis)."""
    if not all(x.is_number for x in axis):
        raise ModelError(f"{what} must be numeric (the constrained directions are built from it)")
    k = min(range(3), key=lambda i: abs(float(axis[i])))
    e = sp.eye(3)[:, k]
    n1 = unit(e - axis * axis.dot(e), what)
    return n1, axis.cross(n1)


def default_ground(gravity: sp.Matrix, name: str) -> Placement:
    """The plane through the origin facing against gravity: normal −g/|g| (+z without gravity); refused
    when the direction cannot be decided (a symbolic gravity off the z axis, or of unknown sign)."""
    g_z = gravity[2]
    if gravity[0] == 0 and gravity[1] == 0:
        if g_z.is_positive:
            return Placement(rotation=sp.diag(1, -1, -1))
        if g_z.is_nonpositive:
            return Placement()
    elif all(x.is_number for x in gravity):
        n = unit(-gravity, f"rolling disk '{name}': gravity")
        t1, t2 = normals(n, f"rolling disk '{name}': gravity")
        return Placement(rotation=sp.Matrix.hstack(t1, t2, n))
    raise ModelError(f"rolling disk '{name}': the direction of gravity {list(gravity)} is not known, so the "
                     "side of the ground is not either: declare its symbol positive (sympy.Symbol(..., "
                     "positive=True)) or give ground=eg.Placement(...)")


def loop(name: str, frame_a: str, frame_b: str, kind: str, axis) -> Loop:
    """A checked `Loop` (the system checks the frames); `axis` only for a revolute loop (default z)."""
    if kind not in LOOP_KINDS:
        raise ModelError(f"loop '{name}': kind must be one of {list(LOOP_KINDS)}, got {kind!r}")
    if axis is not None and kind != "revolute":
        raise ModelError(f"loop '{name}': an axis is given for a revolute loop only, not for kind {kind!r}")
    axis = (0, 0, 1) if axis is None else axis
    axis = unit(vector3(axis, f"loop '{name}': axis"), f"loop '{name}': axis")
    n = normals(axis, f"loop '{name}': axis") if kind == "revolute" else ()
    return Loop(name, frame_a, frame_b, kind, axis, n)
