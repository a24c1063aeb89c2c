"""eomgen's own symbols: speeds, accelerations, intermediates, free-flyer components, joint efforts,
reaction unknowns, motor currents.

They live in a namespace that no name of a user or of a file can reach: `Generated` is a sympy Symbol
of its own class, which sympy never takes for equal to a Symbol, and its identity is a `tag` (what it
stands for: ("dot", q) for the speed of coordinate q, ("ξ", k) for intermediate k, ...), not its
text. Joints named `a` and `adot`, `a` and `ad` (whose speed and the other's acceleration are both
labelled `addot`), `q_1` and `qdot_1`, `_ξ0` or `root_joint_vx` thus derive the same equations as
joints named `x1, x2`: names are labels for people, never identities and never code (generated code
prints indices, not names)."""
from __future__ import annotations

import sympy as sp


class Generated(sp.Symbol):
    """A symbol made by eomgen, labelled `name` (`phidot` renders as φ̇) and identified by `tag`."""

    __slots__ = ("tag",)

    def __new__(cls, name: str, tag, **assumptions) -> "Generated":
        cls._sanitize(assumptions, cls)
        obj = sp.Symbol.__xnew__(cls, name, **assumptions)
        obj.tag = tag
        return obj

    def __getnewargs_ex__(self):
        return (self.name, self.tag), self._assumptions_orig

    def _hashable_content(self):
        return sp.Symbol._hashable_content(self) + (self.tag,)


def user_symbols(expr) -> set[sp.Symbol]:
    """The symbols of an expression (or a matrix) that a user or a file wrote, not eomgen's own."""
    return {s for s in sp.sympify(expr).free_symbols if not isinstance(s, Generated)}


t = sp.Symbol("t")  # time: a prescribed joint's motion is an expression in it (`Revolute(..., motion=...)`)
