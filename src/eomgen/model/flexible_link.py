"""A flexible link: an Euler-Bernoulli beam on a revolute joint, in finite elements (Lagrange II); planar, or
bending in two planes and twisting (3D)."""

from __future__ import annotations

import numpy as np
import sympy as sp

from ..errors import ModelError
from ..symbols import Generated
from .beam import integrals, quadratic
from .beam_modes import clamped_modes
from .joints import Joint, complement, drive, rotation_about, scalar, wrench_basis, zero


DOFS = {"y": 2, "z": 2, "x": 1}  # nodal values per node: deflection and slope, or twist
NODAL = {"y": lambda n: [(kind, k) for k in range(2, n + 2) for kind in ("w", "s")],
         "z": lambda n: [(kind, k) for k in range(2, n + 2) for kind in ("wz", "sz")],
         "x": lambda n: [("phi", k) for k in range(2, n + 2)]}
MODAL = {"y": "eta", "z": "etaz", "x": "etax"}  # the amplitudes' names with modes


def section_turn(y_slope, z_slope, twist) -> sp.Matrix:
    """D = R_z(y') R_y(−z') R_x(φ): how a cross-section (and the tip) is turned from the link frame."""
    return rotation_about(sp.Matrix([0, 0, 1]), y_slope) * rotation_about(sp.Matrix([0, 1, 0]), -z_slope) \
        * rotation_about(sp.Matrix([1, 0, 0]), twist)


class FlexibleLink(Joint):
    """A flexible link on a revolute joint about its z axis: an Euler-Bernoulli beam of length L
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
    (`shapes`: Φ, 2n × k; None without modes).

    3D: EI_y bends the link in its x-z plane too (deflection and slope wz_k, sz_k of each node, after the
    x-y plane's; EI is then E I_z), GJ twists it about its axis (twist phi_k of each node, linear on an
    element), rotary_inertia = (ρI_x, ρI_y, ρI_z) gives its cross-sections rotary inertia per length (the
    twist needs ρI_x > 0). The tip frame then sits at (L + u_x(L), y_L, z_L), turned by
    R_z(y'_L) R_y(−z'_L) R_x(φ_L); with modes each field keeps its own first k (Φ block diagonal)."""

    def __init__(
        self, name, length, mass_per_length, EI, elements: int = 1, *, EI_y=None, GJ=None,
        rotary_inertia=None, actuated: bool = True, stiffening: bool = True, modes: int | None = None,
        motion=None,
    ) -> None:
        super().__init__(name, axis=(0, 0, 1), actuated=actuated)
        self._arguments = dict(name=name, length=length, mass_per_length=mass_per_length, EI=EI,
                               elements=elements, EI_y=EI_y, GJ=GJ, rotary_inertia=rotary_inertia,
                               actuated=actuated, stiffening=stiffening, modes=modes, motion=motion)
        if motion is not None:  # the angle a given function of time: no coordinate, no actuator
            drive(self, motion)
        if not isinstance(stiffening, bool):
            raise ModelError(f"joint '{self.name}': stiffening must be True or False, got {stiffening!r}")
        self.stiffening = stiffening
        if not isinstance(elements, int) or isinstance(elements, bool) or elements < 1:
            raise ModelError(f"joint '{self.name}': elements must be a positive integer, got {elements!r}")
        self.length, self.mass_per_length, self.EI = (
            self._positive(label, value) for label, value in
            (("length", length), ("mass_per_length", mass_per_length), ("EI", EI)))
        self.EI_y, self.GJ = (None if value is None else self._positive(label, value)
                              for label, value in (("EI_y", EI_y), ("GJ", GJ)))
        self.rotary_inertia = None if rotary_inertia is None else self._section(rotary_inertia)
        if self.GJ is not None and (self.rotary_inertia is None or self.rotary_inertia[0] == 0):
            raise ModelError(f"joint '{self.name}': torsion (GJ) needs rotary_inertia with a positive "
                             "ρI_x, the cross-sections' inertia about the link's axis")
        self.fields = ["y"] + ["z"] * (self.EI_y is not None) + ["x"] * (self.GJ is not None)
        self.stiffness = {"y": self.EI, "z": self.EI_y, "x": self.GJ}
        self.elements = elements
        self.shapes = None if modes is None else self._modes(modes)
        labels = [label for field in self.fields for label in (
            NODAL[field](elements) if modes is None else [(MODAL[field], k) for k in range(1, modes + 1)])]
        self.nodal = [Generated(f"{kind}{k}_{self.name}", (self.name, kind, k)) for kind, k in labels]

    def changed(self, **choices) -> "FlexibleLink":
        """The same link with other choices (`stiffening`, `modes`, `elements`, ...): the trade-off's
        variants."""
        return FlexibleLink(**{**self._arguments, **choices})

    def _positive(self, label: str, value) -> sp.Expr:
        value = scalar(value, f"joint '{self.name}': {label}")
        if value.is_nonpositive:
            raise ModelError(f"joint '{self.name}': {label} must be positive, got {value}")
        return value

    def _section(self, values) -> tuple[sp.Expr, sp.Expr, sp.Expr]:
        """(ρI_x, ρI_y, ρI_z), each a scalar ≥ 0."""
        not_a_sequence = isinstance(values, (str, bytes, set, frozenset, dict))  # (a set has no order)
        if not_a_sequence or not hasattr(values, "__len__") or len(values) != 3:
            raise ModelError(f"joint '{self.name}': rotary_inertia must be three values (ρI_x, ρI_y, ρI_z), "
                             f"got {values!r}")
        section = tuple(scalar(v, f"joint '{self.name}': rotary_inertia") for v in values)
        if any(v.is_negative for v in section):
            raise ModelError(f"joint '{self.name}': rotary_inertia must not be negative, got {section}")
        return section

    def _modes(self, k) -> np.ndarray:
        """Φ of the first k modes of each field (block diagonal), refusing a k out of 1 … 2n (n for
        torsion) or a symbolic m, E I, L, GJ, ρI_x."""
        top = self.most_modes
        if not isinstance(k, int) or isinstance(k, bool) or not 1 <= k <= top:
            raise ModelError(f"joint '{self.name}': modes must be an integer from 1 to {top} (the nodal "
                             f"coordinates of {'the twist' if top == self.elements else 'a bending plane'}), "
                             f"got {k!r}")
        values = {"length": self.length, "mass_per_length": self.mass_per_length, **{
            label: self.stiffness[field] for label, field in (("EI", "y"), ("EI_y", "z"), ("GJ", "x"))
            if field in self.fields}}
        section = (0, 0, 0) if self.rotary_inertia is None else self.rotary_inertia
        values.update({f"rotary_inertia {a}": v for a, v in zip("xyz", section) if v != 0})
        for label, value in values.items():
            if not sp.sympify(value).is_number:
                raise ModelError(f"joint '{self.name}': modes needs a numeric {label}, got {value}")
        # per field: its inertia, the sections' rotary inertia about the bending axis (at rest: M_nn)
        inertia = {"y": (self.mass_per_length, section[2]), "z": (self.mass_per_length, section[1]),
                   "x": (section[0], 0)}
        import scipy.linalg

        return scipy.linalg.block_diag(*[clamped_modes(self.length, inertia[f][0], self.stiffness[f],
                                                       self.elements, k, DOFS[f], inertia[f][1])[0]
                                         for f in self.fields])

    @property
    def most_modes(self) -> int:
        """The largest `modes`: the nodal coordinates of a field, 2n (bending) or n (with the twist)."""
        return self.elements * (1 if "x" in self.fields else 2)

    def constants(self) -> dict[str, sp.Expr]:
        extra = {label: value for label, value in (("EI_y", self.EI_y), ("GJ", self.GJ)) if value is not None}
        if self.rotary_inertia is not None:
            extra.update({f"rotary_inertia {a}": v for a, v in zip("xyz", self.rotary_inertia)})
        return {**super().constants(), "length": self.length, "mass_per_length": self.mass_per_length,
                "EI": self.EI, **extra}

    @property
    def coordinates(self):
        return [*super().coordinates, *self.nodal]

    def motion(self):
        angle = self.q if self.prescribed is None else self.driven[0]
        return rotation_about(self.axis, angle), sp.zeros(3, 1)

    def deflections(self, amplitudes=None) -> dict[str, list[sp.Expr]]:
        """Per field, its nodal values from the joint to the tip, node 1's (clamped) zero: "y" and "z" the
        deflection and slope of each node in that bending plane, "x" the twist of each node. From the nodal
        coordinates, or with modes Φ η; `amplitudes`: others in the coordinates' place (their speeds: the
        nodal rates)."""
        a = sp.Matrix(self.nodal if amplitudes is None else amplitudes)
        d = list(a if self.shapes is None else sp.Matrix(self.shapes) * a)
        values, start = {}, 0
        for field in self.fields:
            size = DOFS[field] * self.elements
            values[field] = [sp.Integer(0)] * DOFS[field] + d[start:start + size]
            start += size
        return values

    def shortening(self, e: int) -> sp.Expr:
        """−½ ∫ (y'² + z'²) dx over element e = −½ Σ d_eᵀ G d_e over the bending planes: how much closer to
        the joint it brings the points beyond it (0 without stiffening)."""
        if not self.stiffening:
            return sp.Integer(0)
        G = integrals(self.length / self.elements)["G"]
        planes = [d[2 * e:2 * e + 4] for field, d in self.deflections().items() if field != "x"]
        return -sp.Add(*[quadratic(G, d, d) for d in planes]) / 2

    def foreshortening(self) -> sp.Expr:
        """u_x(L), the tip's axial displacement: the elements' `shortening` summed."""
        return sp.Add(*[self.shortening(e) for e in range(self.elements)])

    def tip(self) -> tuple[sp.Matrix, sp.Matrix]:
        """(R, t) of the tip frame in the link frame: at (L + u_x(L), y_tip, z_tip), turned by
        R_z(y'_tip) R_y(−z'_tip) R_x(φ_tip) (the slopes and the twist; the fields absent: 0)."""
        tip = {field: d[-DOFS[field]:] for field, d in self.deflections().items()}
        (y, y_slope), (z, z_slope), (twist,) = tip["y"], tip.get("z", (0, 0)), tip.get("x", (0,))
        return section_turn(y_slope, z_slope, twist), sp.Matrix([self.length + self.foreshortening(), y, z])

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
