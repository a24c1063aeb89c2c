"""The linearization of M u̇ + b + g = τ + Sᵀ τ_a (+ J_cᵀ F_c): the forward dynamics, and with contacts,
loops and rolling disks the dynamics in the independent speeds u_i (`reduction`):

    u = R u_i,  R = [1; −J_d⁻¹ J_i],  s = [0; −J_d⁻¹ J̇_c u],  (Rᵀ M R) u̇_i = Rᵀ (τ + Sᵀ τ_a − b − g − M s),

written once for the values (`dual.Dual`) so that its derivatives follow by the chain rule; the
coordinates q0 ⊕ δ of the directions that the closures r(q) = 0 fix are solved from them,
δ_dep = −(∂r/∂δ_dep)⁻¹ (∂r/∂δ_ind δ_ind + ∂r/∂p dp)."""

from __future__ import annotations

from dataclasses import replace

import numpy as np

from ..functions import forward_dynamics
from ..numeric import codegen
from ..numeric.parameters import Parameters
from ..eom import EquationsOfMotion
from ..errors import ModelError
from ..numeric.reduction import Reduced
from .chart import Chart
from .motors import motor_pieces
from .dual import Algebra, Dual, placed, solve
from .pieces import Pieces, Point


class EquationsModel:
    """The pieces M, b + g, τ (and J_c, J̇_c u, r) of an `EquationsOfMotion` and its pipeline."""

    def __init__(self, eom: EquationsOfMotion) -> None:
        if not forward_dynamics(eom):
            raise ModelError(
                f"linearize: the equations have only {list(eom.quantities)}: derive M, b and g"
            )
        system = self.system = eom.system
        exprs = {"M": (eom.compact["M"], ()), "nle": (eom.nle_compact, {"u"}), "tau": (eom.tau_compact, {"u"})}
        self.f = codegen(eom)  # the forward dynamics' derivatives; which rows carry forces (`Reduced`)
        if system.constraint_rows():
            J, Jdot_u = eom.kinematics.constraint_jacobian()
            exprs.update(J_c=(J, ()), Jdot_c_u=(Jdot_u, {"u"}))
            if system.closure_rows():
                exprs["closure"] = (eom.kinematics.closure_residual(), ())
        self.parameters = Parameters(system.parameters)
        self.pieces = Pieces(
            eom.subexpressions, system, {**exprs, **motor_pieces(system)}, self.parameters, []
        )
        self.chart = Chart(system)
        self.every = list(system.u)
        self._reduced: dict[tuple, Reduced] = {}

    def case(self, independent) -> EquationsCase:
        """The pipeline for these independent speeds: every speed, or (contacts, loops, rolling disks) those
        named."""
        if not self.f.constraint_rows:
            if independent is not None:
                raise ModelError(
                    "linearize: independent: the system has no contacts, loops or rolling disks; "
                    "every speed is independent (leave it out)"
                )
            return EquationsCase(self, None)
        if independent is None:
            raise ModelError(
                "linearize: independent: name the independent speeds (or coordinates) of the "
                f"constrained system, one per speed the constraints {self.f.constraint_rows} leave "
                "free (as for eg.reduce)"
            )
        key = tuple(map(str, [independent] if isinstance(independent, str) else independent))
        if key not in self._reduced:
            self._reduced[key] = Reduced(self.f, independent)
        return EquationsCase(self, self._reduced[key])


class EquationsCase:
    """One linearization's pipeline: the independent speeds, and (constrained) the rows that carry forces
    and the closures among them."""

    def __init__(self, model: EquationsModel, reduced: Reduced | None) -> None:
        self.model, self.pieces, self.reduced = model, model.pieces, reduced
        self.speeds = model.every if reduced is None else reduced.u_independent

    def dependent(self, point: Point) -> list[int]:
        """The directions the closures fix: of the dependent speeds, those that resolve ∂r/∂δ best (all of
        them for a holonomic system; QR with column pivoting when some rows are velocity constraints).
        `point`: numbers (a stand-in for a symbolic point)."""
        if self.reduced is None:
            return []
        f = self.model.f
        self.active = self.reduced._rows(point.values)
        self.reduced._J_d(point.q, point.values)  # refused where singular, naming the rows and speeds
        self.closures = [k for k, i in enumerate(f.closure_index) if self.active[i]]
        candidates, k = self.reduced.dependent, len(self.closures)
        if k == len(candidates) or not k:
            return candidates[:k]
        F = self.pieces.evaluate("closure", "q", point)[self.closures]
        import scipy.linalg

        _, R, pivots = scipy.linalg.qr(F[:, candidates], pivoting=True)
        if k and abs(R[k - 1, k - 1]) <= 1e-10 * max(1.0, abs(R[0, 0])):
            raise ModelError(
                "linearize: the closures do not determine the dependent coordinates at this "
                "state (∂r/∂q of the dependent speeds' coordinates is singular)"
            )
        return sorted(candidates[i] for i in pivots[:k])

    def closure(self, point: Point) -> tuple[Dual, np.ndarray]:
        """The closure residuals that carry forces (f(q) = 0 of the holonomic constraints) and ∂f/∂δ."""
        F = self.pieces.evaluate("closure", "q", point)[self.closures]
        return self.pieces.dual("closure", point)[self.closures], F

    def dynamics(
        self, point: Point, speeds: Dual, efforts: Dual, algebra: Algebra
    ) -> tuple[Dual, Dual, Dual]:
        """(u, u, u̇_i): the speeds (twice: they are the equations' speeds), the independent ones' rates."""
        pieces, nv = self.pieces, len(self.model.every)
        S = Dual(algebra.array(self.model.system.S.T.tolist()).reshape(nv, -1))
        if self.reduced is None and not algebra.symbolic:
            return speeds, speeds, self._forward(point, speeds, efforts, S)
        M = pieces.dual("M", point)
        tau_a = S @ efforts
        if self.reduced is None:
            h = pieces.dual("tau", point, speeds) - pieces.dual("nle", point, speeds) + tau_a
            return speeds, speeds, solve(algebra, M, h, "the mass matrix M")
        ind, dep, n = self.reduced.independent, self.reduced.dependent, point.n
        J = pieces.dual("J_c", point)[self.active]
        J_d, J_i = J[:, dep], J[:, ind]
        what = "J_d (the constraint rows' columns of the dependent speeds)"
        u = placed([(ind, speeds), (dep, -solve(algebra, J_d, J_i @ speeds, what))], n, algebra)
        c = pieces.dual("Jdot_c_u", point, u)[self.active]
        R = placed([(ind, Dual(algebra.eye(len(ind)))), (dep, -solve(algebra, J_d, J_i, what))], n, algebra)
        s = placed(
            [(ind, Dual(algebra.zeros(len(ind), 1))), (dep, -solve(algebra, J_d, c, what))], n, algebra
        )
        h = pieces.dual("tau", point, u) - pieces.dual("nle", point, u) + tau_a
        return u, u, solve(algebra, R.T @ M @ R, R.T @ (h - M @ s), "the reduced mass matrix Rᵀ M R")

    def _forward(self, point: Point, speeds: Dual, efforts: Dual, S: Dual) -> Dual:
        """u̇ = M⁻¹ (τ + Sᵀ τ_a − b − g) with its derivatives along q, u and τ_a from the generated forward
        dynamics derivatives (`forward_dynamics_derivatives`), along the parameters from the pieces."""
        tau = (S @ efforts).value[:, 0]
        Fq, Fu, Ftau = self.model.f.forward_dynamics_derivatives(
            point.q, speeds.value[:, 0], tau, point.values
        )
        along = replace(point, tangents={"q": None, "p": point.tangents["p"]})
        u, algebra = Dual(speeds.value), point.algebra
        h = self.pieces.dual("tau", along, u) - self.pieces.dual("nle", along, u) + S @ Dual(efforts.value)
        ud = solve(algebra, self.pieces.dual("M", along), h, "the mass matrix M")
        d = point.tangents["q"] @ Fq.T + speeds.tangent[:, :, 0] @ Fu.T
        d += efforts.tangent[:, :, 0] @ (Ftau @ S.value).T
        return Dual(ud.value, d[:, :, None] if ud.tangent is None else ud.tangent + d[:, :, None])
