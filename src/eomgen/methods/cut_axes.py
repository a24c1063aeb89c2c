"""The free cut's reaction unknowns and their axes.

A joint's reaction basis B (`Joint.reaction_basis`, child axes) spans the wrenches it transmits
without work. As unknowns the cut takes, like the lecture, world axes: the world's x, y, z where the
joint blocks every force (every torque), a blocked direction as it is where it keeps its world
direction (R B constant); only the other directions stay in the child body's axes (primed: x')."""

from __future__ import annotations

from dataclasses import dataclass

import sympy as sp

from ..kinematics import Kinematics
from ..symbols import Generated

WORLD = "world"


@dataclass(frozen=True)
class Reaction:
    """One reaction unknown: its symbol, its force and torque direction (world axes), its axes."""

    symbol: Generated
    force: sp.Matrix
    torque: sp.Matrix
    axes: str  # WORLD, or the name of the child body whose axes it is in


def reactions(kin: Kinematics, body) -> list[Reaction]:
    """The unknowns of `body`'s joint reaction (see the module)."""
    B, zero = body.joint.reaction_basis(), sp.zeros(3, 1)
    R = kin.sub.inline(kin.R[body])
    q = set(kin.system.q)
    out = []
    for kind, rows in (("F", slice(0, 3)), ("T", slice(3, 6))):
        other = slice(3, 6) if kind == "F" else slice(0, 3)
        columns = [B[rows, k] for k in range(B.cols) if B[other, k].is_zero_matrix]
        if len(columns) == 3:  # every direction blocked: the world's axes
            columns, R_k = [sp.eye(3)[:, i] for i in range(3)], sp.eye(3)
        else:
            R_k = R
        for k, c in enumerate(columns):
            d = R_k * c
            world = not (sp.Matrix(d).free_symbols & q)
            name = _axis_name(d if world else c, k) + ("" if world else "'")
            symbol = Generated(f"{kind}_{body.name}_{name}", (kind, body.name, name))
            force, torque = (d, zero) if kind == "F" else (zero, d)
            out.append(Reaction(symbol, force, torque, WORLD if world else body.name))
    for k in range(B.cols):  # a screw (force and torque together): the child's axes
        if not B[:3, k].is_zero_matrix and not B[3:, k].is_zero_matrix:
            symbol = Generated(f"W_{body.name}_{k + 1}", ("W", body.name, str(k + 1)))
            out.append(Reaction(symbol, R * B[:3, k], R * B[3:, k], body.name))
    return out


def _axis_name(d: sp.Matrix, k: int) -> str:
    """x, y or z for a unit axis, else the direction's number k + 1."""
    axes = [list(sp.eye(3)[:, i]) for i in range(3)]
    return "xyz"[axes.index(list(d))] if list(d) in axes else str(k + 1)
