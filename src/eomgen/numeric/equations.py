"""`NumericEoM`: the numeric functions of one `EquationsOfMotion` — its catalogue's functions (`Evaluations`)
and the numeric algorithms on them (forward and constrained dynamics, the state equations, the free cut's
reactions), each in its own module."""
from __future__ import annotations

import numpy as np

from ..eom import EquationsOfMotion
from ..errors import ByName
from ..symbols import t as time
from ..functions import catalogue
from ..functions.expressions import line_loads
from . import constrained, forward, state_equations
from .evaluations import Evaluations
from .parameters import Parameters


class NumericEoM(Evaluations):
    """Numeric M(q), b(q, u), g(q), tau(q, u), T(q, u), U(q), frame Jacobians, forward dynamics, the
    state equations `rhs`, the inverse dynamics and the derivatives of the dynamics, and (free cut) joint
    reactions of one `EquationsOfMotion`.

    q and u are arrays of shape (n,), or (N, n) for N states at once (evaluated without a Python
    loop). Symbolic parameters are given by name in a mapping {name: value} in each call (a function
    asks only for the ones it uses), or fixed once with `bind` (see `eomgen.numeric.parameters`)."""

    def __init__(self, eom: EquationsOfMotion) -> None:
        self.eom = eom
        self.system = eom.system  # the model the functions were generated from
        self.nv = len(eom.u)
        self.S = np.array(eom.S.tolist(), dtype=float).reshape(-1, self.nv)
        parameters = Parameters(eom.system.parameters, state=[m.current for m in eom.system.motors]
                                + ([time] if eom.system.prescribed else []))
        super().__init__(catalogue(eom), parameters, line_loads(eom.system))

    @property
    def constraint_rows(self) -> list[str]:
        """Names of the rows of J_c and of the constraint forces."""
        return self.system.constraint_rows()

    @property
    def closure_rows(self) -> list[str]:
        """Names of the rows of `closure_residual`."""
        return self.system.closure_rows()

    @property
    def closure_index(self) -> list[int]:
        """For each row of `closure_residual`, its row of J_c (`constrained.closure_index`)."""
        return constrained.closure_index(self.system)

    def euler_singularity(self, q, tol: float = 1e-3, params=None) -> float | None:
        """cond(M) with a warning near a ZYX Euler-angle singularity, else None (`forward`)."""
        return forward.euler_singularity(self, q, tol, params)

    def forward_dynamics(self, q, u, tau_a=None, params=None) -> np.ndarray:
        """u̇ = M⁻¹ (τ + Sᵀ τ_a − b − g), solved numerically (no contacts); warns near an Euler-base
        singularity."""
        return forward.forward_dynamics(self, q, u, tau_a, params)

    def forward_dynamics_derivatives(self, q, u, tau=None, params=None) -> tuple[np.ndarray, ...]:
        """(∂u̇/∂q, ∂u̇/∂u, ∂u̇/∂τ), each nv × nv per state, of u̇ = M⁻¹ (τ + τ_loads − b − g) (Pinocchio's
        `computeABADerivatives`): tau one effort per speed (Sᵀ τ_a for `forward_dynamics`' τ_a), or None;
        ∂/∂q in the tangent space; M⁻¹ from one Cholesky factorisation."""
        return forward.forward_dynamics_derivatives(self, q, u, tau, params)

    def reactions(self, q, u, tau_a=None, params=None, ud=None) -> dict[str, tuple[np.ndarray, np.ndarray]]:
        """Reaction force and torque of every joint (world axes, at the joint origin), with u̇ from
        the forward dynamics unless given (free cut)."""
        joints = self.catalogue.family("R").items
        ud = self.forward_dynamics(q, u, tau_a, params) if ud is None else ud
        return ByName("joint", {joint: self.joint_reaction(joint, q, u, ud, params) for joint in joints})

    def constrained_dynamics(self, q, u, tau_a=None, params=None,
                             baumgarte: tuple[float, float] | None = None) -> tuple[np.ndarray, np.ndarray]:
        """(u̇, F_c) with every contact, loop and rolling disk held: F_c = −(J M⁻¹ Jᵀ)⁻¹ (J M⁻¹ h + c),
        the constraint forces on the system, stacked like J_c's rows (0 on rows no motion can violate).
        c = J̇ u holds J u̇ + J̇ u = 0; with baumgarte = (α, β), c = J̇ u + 2 α J u + β² r holds
        J u̇ + J̇ u = −2 α J u − β² r (r: the closure residual on its rows, `closure_index`; 0 on the rows
        of contacts and no-slip), which drives a drift of r and J u back to zero (critically damped at
        α = β)."""
        return constrained.constrained_dynamics(self, q, u, tau_a, params, baumgarte)

    def constraint_forces(self, q, u, tau_a=None, params=None) -> dict[str, np.ndarray]:
        """F_c by constraint name (a contact's frame, a loop's or a rolling disk's name): a loop's force
        acts on frame_a's body, its opposite on frame_b's; a disk's rows are along ground x, y and z."""
        return constrained.constraint_forces(self, q, u, tau_a, params)

    def contact_forces(self, q, u, tau_a=None, params=None) -> np.ndarray:
        """F_c, stacked like J_c's rows (world-aligned axes)."""
        return self.constrained_dynamics(q, u, tau_a, params)[1]

    def support_projector(self, q, params=None) -> np.ndarray:
        """N_c = 1 − M⁻¹ J_cᵀ (J_c M⁻¹ J_cᵀ)⁻¹ J_c (J_c N_c = 0, N_c² = N_c)."""
        return constrained.support_projector(self, q, params)

    def support_consistent_residual(self, q, u, ud, tau_a=None, params=None) -> np.ndarray:
        """N_cᵀ (M u̇ + b + g − Sᵀ τ − τ_loads): zero along any motion the contacts allow."""
        return constrained.support_consistent_residual(self, q, u, ud, tau_a, params)

    @property
    def nx(self) -> int:
        """The size of the state x: nq + nv, and one current per DC motor."""
        return state_equations.size(self)

    def state(self, x, params=None):
        """(q, u, i, params) of x = [q, u, i] (i empty without motors), the currents added to params."""
        return state_equations.state(self, x, params)

    def rhs(self, t, x, tau=None, params=None, baumgarte: tuple[float, float] | None = None) -> np.ndarray:
        """ẋ = [q̇(q, u), u̇ (, di/dt)] (`state_equations`): u̇ of `forward_dynamics`, or of
        `constrained_dynamics` (with its `baumgarte` gains) for a system with contacts, loops or rolling
        disks; τ_a = `tau` (None, values, or a function (t, q, u)). The motor currents are taken from x
        (params, or a bind, leaves them out); voltages may depend on q and u."""
        return state_equations.rhs(self, t, x, tau, params, baumgarte)

    def power(self, t, x, tau=None, params=None) -> np.ndarray:
        """Ẇ = uᵀ (Sᵀ τ_a + τ_nc) (+ Σ i (U − R i − k N q̇) with motors): the power of the actuators, of
        the loads but springs and bending (and of the motors' sources less their resistance)."""
        return state_equations.power(self, t, x, tau, params)

    def energy(self, x, params=None) -> np.ndarray:
        """E = T + U (+ ½ Σ L i² with motors), per state (N states along axis 0)."""
        return state_equations.energy(self, x, params)
