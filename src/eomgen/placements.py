"""The world placement of each body (rotation R, origin p, its joint's columns in world axes), formed
when a method first reads it, its parent's first: the body-frame recursions read none, so they name
none of these intermediates.

    R = R_parent R_P R_q,   p = p_parent + R_parent (t_P + R_P t_q),
    columns (u_i, v, ω): the joint's motion subspace through R_joint = R_parent R_P where the joint gives it
    in joint axes, else through R; a flexible link's children sit on its tip (`FlexibleLink.tip`).

`Placements` holds the named intermediates and nothing that holds it: equations that are dropped are
freed at once by reference counting, not left to Python's cycle collector (which walks every object of
every derivation it has not freed yet)."""
from __future__ import annotations

from collections.abc import Iterator, Mapping
from typing import NamedTuple

from .linalg import IDENTITY, ZERO, add, apply, compose
from .model import FlexibleLink
from .model.system import Body
from .subexpressions import Subexpressions


class World(NamedTuple):
    """A body's placement in the world: tuples of the engine's scalars (`linalg`)."""
    R: tuple
    p: tuple
    columns: list  # per speed of the joint: (u index, v of the body origin, ω), world axes
    axes: tuple  # the axes the joint's S and bias are written in
    chain: list  # the bodies with moving joints from the root to the body


class Placements(dict):
    """body → its `World` placement, formed on first reading (`place`) with those of its ancestors not
    placed yet, root first (a loop: a chain of any length); a KeyError for a body not among `bodies` (the
    system's, in its order)."""

    def __init__(self, sub: Subexpressions, bodies: list[Body]) -> None:
        super().__init__()
        self.sub, self.bodies, self._known = sub, list(bodies), frozenset(bodies)

    def __missing__(self, body: Body) -> World:
        if body not in self._known:
            raise KeyError(body)
        path = []
        while body is not None and body not in self:
            path.append(body)
            body = body.parent
        world = None if body is None else self[body]
        for body in reversed(path):
            world = self[body] = place(self.sub, body, world)
        return world


class Field(Mapping):
    """One field of the bodies' placements (R, p, columns, axes or chain), a read-only view by body, in the
    system's order."""

    def __init__(self, placements: Placements, field: str) -> None:
        self._placements, self._index = placements, World._fields.index(field)

    def __getitem__(self, body: Body):
        return self._placements[body][self._index]

    def __iter__(self) -> Iterator:
        return iter(self._placements.bodies)

    def __len__(self) -> int:
        return len(self._placements.bodies)


def place(sub: Subexpressions, body: Body, parent: World | None) -> World:
    """The body's `World` placement from its parent's (None: the world)."""
    joint, name, e = body.joint, sub.add_matrix, sub.vector
    R_parent, p_parent = (IDENTITY, ZERO) if parent is None else (parent.R, parent.p)
    if parent is not None and isinstance(body.parent.joint, FlexibleLink):  # children sit on the tip
        R_tip, t_tip = body.parent.joint.tip()
        p_parent = add(p_parent, apply(R_parent, e(t_tip)))
        R_parent = name(compose(R_parent, e(R_tip)))
    R_joint = name(compose(R_parent, e(body.placement.rotation)))
    p_joint = add(p_parent, apply(R_parent, e(body.placement.translation)))
    R_q, t_q = joint.motion()
    R = name(compose(R_joint, e(R_q)))
    p = name(add(p_joint, apply(R_joint, e(t_q))))
    S = joint.joint_frame_subspace()
    axes = R_joint if S is not None else R
    S = joint.subspace() if S is None else S
    columns = [(i, name(apply(axes, e(v))), name(apply(axes, e(w))))
               for i, (v, w) in zip(body.speed_indices, S)]
    chain = (list(parent.chain) if parent is not None else []) + ([body] if columns else [])
    return World(R, p, columns, axes, chain)


def columns_in_sympy(sub: Subexpressions, columns: list[tuple[int, tuple, tuple]]) -> list[tuple]:
    """A body's columns with v and ω as tuples of sympy scalars."""
    return [(i, tuple(sub.matrix(v)), tuple(sub.matrix(w))) for i, v, w in columns]
