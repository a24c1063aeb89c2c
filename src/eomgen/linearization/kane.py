"""The linearization of Kane's equations (`methods.kane`, numerically `codegen.kane`) in the minimal
state x = [q_ind, w_ind], as sympy's Linearizer: the pipeline of `NumericKane` written once for the
values (`dual.Dual`),

    w_dep = −C_dep⁻¹ (C_ind w_ind + c0),  u = −Y⁻¹ (K w + k0),  T = [1; −C_dep⁻¹ C_ind],  P = −Y⁻¹ K T,
    ẇ_dep,0 = −C_dep⁻¹ ċ,  u̇₀ = −Y⁻¹ (K ẇ₀ + ẏ),  (Pᵀ M P) ẇ_ind = Pᵀ (h + Sᵀ τ_a − M u̇₀),

its derivatives by the chain rule; the dependent coordinates from the holonomic constraints f(q) = 0,
δ_dep = −(∂f/∂δ_dep)⁻¹ (∂f/∂δ_ind δ_ind + ∂f/∂p dp)."""

from __future__ import annotations

import numpy as np

from ..numeric.parameters import Parameters
from ..errors import ModelError
from ..methods.kane import KaneEquations
from .chart import Chart
from .dual import Algebra, Dual, placed, solve
from .motors import motor_pieces
from .pieces import Pieces, Point


class KaneModel:
    """The pieces M, h, Y, C, rates, f of `KaneEquations` and its pipeline."""

    def __init__(self, kane: KaneEquations) -> None:
        self.kane, system = kane, kane.system
        self.system = system
        c = kane.compact
        exprs = {
            "M": (c["M"], ()),
            "h": (c["h"][:, 0], {"u"}),
            "Y": (c["Y"], ()),
            "rates": (c["rates"], {"u", "w"}),
        }
        if kane.dependent:
            exprs["C"] = (c["C"], ())
        if kane.dependent_coordinates:
            exprs["f"] = (c["holonomic"][:, 0], ())
        self.parameters = Parameters(kane.parameters)
        w = [] if kane.speeds_are_qdot else list(kane.speeds)
        self.pieces = Pieces(
            kane.subexpressions, system, {**exprs, **motor_pieces(system)}, self.parameters, w
        )
        self.chart = Chart(system)
        self.every, self.speeds = list(kane.speeds), list(kane.independent)
        self._dep, self._ind = kane._indices()
        self.directions = [self.chart.direction(x) for x in kane.dependent_coordinates]
        if None in self.directions:
            odd = [str(x) for x, j in zip(kane.dependent_coordinates, self.directions) if j is None]
            raise ModelError(
                f"linearize: the dependent coordinates {odd} are no joint speed's coordinate (a "
                "quaternion's or a planar joint's position): the tangent coordinates have no "
                "direction of their own; linearize a parametrization in angles (Euler)"
            )

    def case(self, independent) -> KaneModel:
        """The equations themselves: Kane's equations fix their independent speeds."""
        if independent is not None:
            raise ModelError(
                "linearize: independent: Kane's equations fix their independent speeds "
                f"{self.kane.independent} (eg.kane(..., independent=...)); leave it out"
            )
        return self

    def dependent(self, point: Point) -> list[int]:
        """The directions of the dependent coordinates."""
        return sorted(self.directions)

    def closure(self, point: Point) -> tuple[Dual, np.ndarray]:
        """The holonomic constraints' residuals f(q) and ∂f/∂δ."""
        return self.pieces.dual("f", point), self.pieces.evaluate("f", "q", point)

    def dynamics(
        self, point: Point, speeds: Dual, efforts: Dual, algebra: Algebra
    ) -> tuple[Dual, Dual, Dual]:
        """(u, w, ẇ_ind): the joint speeds, Kane's speeds and the rates of the independent ones."""
        n, p, nd = len(self.every), len(self._ind), point.n
        ind, dep, pieces = self._ind, self._dep, self.pieces
        zeros = Dual(algebra.zeros(p, 1))
        w, T, wd0 = speeds, Dual(algebra.eye(p)), zeros
        if dep:
            C = pieces.dual("C", point)
            C_dep, by_C = C[:, dep], "C_dep (the constraints' columns of the dependent speeds)"
            w = placed(
                [(ind, speeds), (dep, -solve(algebra, C_dep, C[:, ind] @ speeds + C[:, n:], by_C))],
                nd,
                algebra,
            )
            T = placed([(ind, T), (dep, -solve(algebra, C_dep, C[:, ind], by_C))], nd, algebra)
        Y = pieces.dual("Y", point)
        Y, K, k0, what = Y[:, :n], Y[:, n : 2 * n], Y[:, 2 * n :], "the speed map Y"
        u = -solve(algebra, Y, K @ w + k0, what)
        rates = pieces.dual("rates", point, u, w)
        if dep:
            wd0 = placed([(ind, zeros), (dep, -solve(algebra, C_dep, rates[n:], by_C))], nd, algebra)
        ud0 = -solve(algebra, Y, K @ wd0 + rates[:n], what)
        P = -solve(algebra, Y, K @ T, what)
        M = pieces.dual("M", point)
        S = Dual(algebra.array(self.system.S.T.tolist()).reshape(n, -1))
        h = pieces.dual("h", point, u) + S @ efforts
        return u, w, solve(algebra, P.T @ M @ P, P.T @ (h - M @ ud0), "Kane's mass matrix Pᵀ M P")
