"""eomgen's own symbols: speeds, accelerations, intermediates, free-flyer components, joint efforts,
reaction unknowns, motor currents.

They live in a namespace that no name of a user or of a file can reach: `Generated` is a sympy Symbol
of its own class, and sympy never takes two symbols of different classes for equal, whatever their
text. A model with joints named `a` and `adot`, `q_1` and `qdot_1`, `_ξ0` or `root_joint_vx` thus
derives the same equations as one named `x1, x2`: names are labels for people, never identities and
never code (generated code prints indices, not names)."""
from __future__ import annotations

import sympy as sp


class Generated(sp.Symbol):
    """A symbol made by eomgen; prints like a Symbol (`phidot` renders as φ̇), never equals one."""


def generated(name: str, **assumptions) -> Generated:
    """The eomgen symbol labelled `name`."""
    return Generated(name, **assumptions)


def user_symbols(expr) -> set[sp.Symbol]:
    """The symbols of an expression (or a matrix) that a user or a file wrote, not eomgen's own."""
    return {s for s in sp.sympify(expr).free_symbols if not isinstance(s, Generated)}
