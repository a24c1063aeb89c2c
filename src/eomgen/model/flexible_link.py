"""A flexible link: an Euler-Bernoulli beam on a revolute joint, in finite elements (Lagrange II)."""

from __future__ import annotations

import numpy as np
import sympy as sp

from ..errors import ModelError
from ..symbols import Generated
from .beam import integrals, quadratic
from .beam_modes import clamped_modes
from .joints import Joint, complement, drive, rotation_about, scalar, wrench_basis, zero


class FlexibleLink(Joint):
    """A planar flexible link on a revolute joint about its z axis: an Euler-Bernoulli beam of length L
    along the body's x axis, mass per length m and bending stiffness E I, deflecting along y, split
    into n elements with Hermite cubic shape functions. Coordinates: the joint angle θ, then the
    deflection and slope of nodes 2 … n+1 (node 1 is clamped to the joint). Children attach to the
    tip frame: translated by (L + u_x(L), w_tip) and turned by the tip slope. Lagrange II only. With
    `motion` (an expression of eg.t) the angle is prescribed, as for `Revolute(..., motion=...)`.

    stiffening (the default): a point at x also moves along the link by the foreshortening of the bent
    beam, u_x(x) = −½ ∫₀ˣ y'² ds, kept whole in the energies (`methods.flexible`), so that axial loads —
    centrifugal, gravity along the link, a tip mass's — stiffen or soften bending.
    stiffening=False: the paper's model, transverse deflection only (u_x = 0); it loses the centrifugal
    stiffening of a spinning link (its in-plane frequency falls as ω² = ω₀² − Ω² and the link buckles
    at Ω = ω₀), so it is right only for slow rotation.

    modes=k (numeric m, E I, L): modal reduction, the coordinates after θ the amplitudes η_1 … η_k of the
    first k clamped-free modes of the link's own elements (`model.beam_modes`), the nodes d = Φ η
    (`shapes`: Φ, 2n × k; None without modes)."""

    def __init__(
        self, name, length, mass_per_length, EI, elements: int = 1, *, actuated: bool = True,
        stiffening: bool = True, modes: int | None = None, motion=None,
    ) -> None:
        super().__init__(name, axis=(0, 0, 1), actuated=actuated)
        if motion is not None:  # the angle a given function of time: no coordinate, no actuator
            drive(self, motion)
        if not isinstance(stiffening, bool):
            raise ModelError(f"joint '{self.name}': stiffening must be True or False, got {stiffening!r}")
        self.stiffening = stiffening
        if not isinstance(elements, int) or isinstance(elements, bool) or elements < 1:
            raise ModelError(f"joint '{self.name}': elements must be a positive integer, got {elements!r}")
        values = {"length": length, "mass_per_length": mass_per_length, "EI": EI}
        for label, value in values.items():
            values[label] = scalar(value, f"joint '{self.name}': {label}")
            if values[label].is_nonpositive:
                raise ModelError(f"joint '{self.name}': {label} must be positive, got {values[label]}")
        self.length, self.mass_per_length, self.EI = values.values()
        self.elements = elements
        self.shapes = None if modes is None else self._modes(modes)
        labels = [(kind, k) for k in range(2, elements + 2) for kind in ("w", "s")] if modes is None \
            else [("eta", k) for k in range(1, modes + 1)]
        self.nodal = [Generated(f"{kind}{k}_{self.name}", (self.name, kind, k)) for kind, k in labels]

    def _modes(self, k) -> np.ndarray:
        """Φ (2n × k) of the first k modes, refusing a k out of 1 … 2n or a symbolic m, E I, L."""
        if not isinstance(k, int) or isinstance(k, bool) or not 1 <= k <= 2 * self.elements:
            raise ModelError(f"joint '{self.name}': modes must be an integer from 1 to 2 × elements = "
                             f"{2 * self.elements}, got {k!r}")
        for label in ("length", "mass_per_length", "EI"):
            if not (value := getattr(self, label)).is_number:
                raise ModelError(f"joint '{self.name}': modes needs a numeric {label}, got {value}")
        return clamped_modes(self.length, self.mass_per_length, self.EI, self.elements, k)[0]

    def constants(self) -> dict[str, sp.Expr]:
        return {
            **super().constants(),
            "length": self.length,
            "mass_per_length": self.mass_per_length,
            "EI": self.EI,
        }

    @property
    def coordinates(self):
        return [*super().coordinates, *self.nodal]

    def motion(self):
        angle = self.q if self.prescribed is None else self.driven[0]
        return rotation_about(self.axis, angle), sp.zeros(3, 1)

    def nodes(self, amplitudes=None) -> list[sp.Expr]:
        """The nodal deflections and slopes from the joint to the tip, node 1's (clamped) zero: the nodal
        coordinates, or with modes Φ η. `amplitudes`: others in the coordinates' place (their speeds:
        the nodal rates)."""
        a = sp.Matrix(self.nodal if amplitudes is None else amplitudes)
        d = a if self.shapes is None else sp.Matrix(self.shapes) * a
        return [sp.Integer(0), sp.Integer(0), *d]

    def shortening(self, e: int) -> sp.Expr:
        """−½ ∫ y'² dx over element e = −½ d_eᵀ G d_e: how much closer to the joint it brings the points
        beyond it (0 without stiffening)."""
        if not self.stiffening:
            return sp.Integer(0)
        d = self.nodes()[2 * e:2 * e + 4]
        return -quadratic(integrals(self.length / self.elements)["G"], d, d) / 2

    def foreshortening(self) -> sp.Expr:
        """u_x(L), the tip's axial displacement: the elements' `shortening` summed."""
        return sp.Add(*[self.shortening(e) for e in range(self.elements)])

    def tip(self) -> tuple[sp.Matrix, sp.Matrix]:
        """(R, t) of the tip frame in the link frame: turned by the tip slope, at (L + u_x(L), w_tip)."""
        w, s = self.nodes()[-2:]
        return rotation_about(self.axis, s), sp.Matrix([self.length + self.foreshortening(), w, 0])

    @property
    def efforts(self) -> int:
        """Only the joint angle is driven (unless prescribed); the beam's nodes move by its elasticity."""
        return int(self.prescribed is None)

    def subspace(self):
        """The joint angle turns the link frame (unless prescribed); the nodal coordinates deform the beam
        only."""
        return [(zero(), self.axis)] * self.efforts + [(zero(), zero()) for _ in self.nodal]

    def joint_frame_subspace(self):
        return self.subspace()

    def reaction_basis(self):
        return wrench_basis(sp.eye(3), complement([self.axis]))
