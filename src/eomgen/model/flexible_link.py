"""A flexible link: an Euler-Bernoulli beam on a revolute joint, in finite elements (Lagrange II)."""

from __future__ import annotations

import sympy as sp

from ..errors import ModelError
from ..symbols import Generated
from .joints import Joint, complement, rotation_about, scalar, wrench_basis, zero


class FlexibleLink(Joint):
    """A planar flexible link on a revolute joint about its z axis: an Euler-Bernoulli beam of length L
    along the body's x axis, mass per length m and bending stiffness E I, deflecting along y, split
    into n elements with Hermite cubic shape functions. Coordinates: the joint angle θ, then the
    deflection and slope of nodes 2 … n+1 (node 1 is clamped to the joint). Children attach to the
    tip frame: translated by (L, w_tip) and turned by the tip slope. Lagrange II only."""

    def __init__(
        self, name, length, mass_per_length, EI, elements: int = 1, *, actuated: bool = True
    ) -> None:
        super().__init__(name, axis=(0, 0, 1), actuated=actuated)
        if not isinstance(elements, int) or isinstance(elements, bool) or elements < 1:
            raise ModelError(f"joint '{self.name}': elements must be a positive integer, got {elements!r}")
        values = {"length": length, "mass_per_length": mass_per_length, "EI": EI}
        for label, value in values.items():
            values[label] = scalar(value, f"joint '{self.name}': {label}")
            if values[label].is_nonpositive:
                raise ModelError(f"joint '{self.name}': {label} must be positive, got {values[label]}")
        self.length, self.mass_per_length, self.EI = values.values()
        self.elements = elements
        self.nodal = [
            Generated(f"{kind}{k}_{self.name}", (self.name, kind, k))
            for k in range(2, elements + 2)
            for kind in ("w", "s")
        ]

    def constants(self) -> dict[str, sp.Expr]:
        return {
            **super().constants(),
            "length": self.length,
            "mass_per_length": self.mass_per_length,
            "EI": self.EI,
        }

    @property
    def coordinates(self):
        return [self.q, *self.nodal]

    def motion(self):
        return rotation_about(self.axis, self.q), sp.zeros(3, 1)

    def tip(self) -> tuple[sp.Matrix, sp.Matrix]:
        """(R, t) of the tip frame in the link frame: turned by the tip slope, at (L, w_tip)."""
        w, s = self.nodal[-2:]
        return rotation_about(self.axis, s), sp.Matrix([self.length, w, 0])

    @property
    def efforts(self) -> int:
        """Only the joint angle is driven; the beam's nodes move by its elasticity."""
        return 1

    def subspace(self):
        """The joint angle turns the link frame; the nodal coordinates deform the beam only."""
        return [(zero(), self.axis)] + [(zero(), zero()) for _ in self.nodal]

    def joint_frame_subspace(self):
        return self.subspace()

    def reaction_basis(self):
        return wrench_basis(sp.eye(3), complement([self.axis]))
