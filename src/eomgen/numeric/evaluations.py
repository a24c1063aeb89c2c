"""The public functions of an equations' catalogue as methods (NumPy and C alike): one state, or N states
along axis 0; formulas in `eomgen.functions` and the modules it names."""
from __future__ import annotations

import numpy as np

from .constrained import rows
from .facade import Functions, written


class Evaluations(Functions):
    """M, b, g, nle, τ, T, U, q̇, frames, the centre of mass and centroidal momentum, constraint rows, the
    inverse dynamics and its derivatives, the free cut's joint wrenches."""

    def M(self, q, params=None, out=None) -> np.ndarray:
        """Mass matrix M(q), shape (nv, nv) per state; into `out` when given (see `written`), as b, g,
        nle."""
        return self.call("M", q, params=params, out=out)

    def b(self, q, u, params=None, out=None) -> np.ndarray:
        """Coriolis and centrifugal terms b(q, u), shape (nv,) per state."""
        return written(self.call("b", q, u, params=params)[..., 0], out, q=q, u=u)

    def g(self, q, params=None, out=None) -> np.ndarray:
        """Gravity terms g(q) (left-hand side), shape (nv,) per state."""
        return written(self.call("g", q, params=params)[..., 0], out, q=q)

    def nle(self, q, u, params=None, out=None) -> np.ndarray:
        """b + g in one pass (method "recursive"), like Pinocchio's nonLinearEffects."""
        if "nle" not in self.catalogue:
            return written(self.b(q, u, params) + self.g(q, params), out, q=q, u=u)
        return written(self.call("nle", q, u, params=params)[..., 0], out, q=q, u=u)

    def tau(self, q, u, params=None) -> np.ndarray:
        """Generalized forces of all loads."""
        return self.call("tau", q, u, params=params)[..., 0]

    def T(self, q, u, params=None):
        """Kinetic energy T(q, u), a number per state."""
        return self.call("T", q, u, params=params)[..., 0, 0]

    def U(self, q, params=None):
        """Potential energy U(q) (gravity, springs, bending), a number per state."""
        return self.call("U", q, params=params)[..., 0, 0]

    def qdot(self, q, u, params=None) -> np.ndarray:
        """q̇(q, u) (`System.qdot`: u itself but for quaternions, whose rates depend on q)."""
        return self.call("qdot", q, u, params=params)[..., 0]

    def tau_of(self, load: str, q, u, params=None) -> np.ndarray:
        """Generalized force of one load, by name."""
        return self.call(f"tau:{load}", q, u, params=params)[..., 0]

    def jacobian(self, frame: str, q, params=None) -> np.ndarray:
        """6 × n Jacobian [J_P; J_R] of a frame or body origin, world-aligned axes."""
        return self.call(f"J:{frame}", q, params=params)

    def jacobian_dot_u(self, frame: str, q, u, params=None) -> np.ndarray:
        """J̇ u (6-vector, [linear; angular]) of a frame or body origin."""
        return self.call(f"Jdot_u:{frame}", q, u, params=params)[..., 0]

    def placement(self, frame: str, q, params=None) -> tuple[np.ndarray, np.ndarray]:
        """(R, p) of a frame or body in the world (Pinocchio's `oMf` rotation and translation)."""
        X = self.call(f"X:{frame}", q, params=params)
        return X[..., :3], X[..., 3]

    def com(self, q, params=None) -> np.ndarray:
        """Centre of mass c (world), Pinocchio's `centerOfMass`."""
        return self.call("com", q, params=params)[..., 0]

    def com_jacobian(self, q, params=None) -> np.ndarray:
        """J_com (3 × n), Pinocchio's `jacobianCenterOfMass`."""
        return self.call("J_com", q, params=params)

    def centroidal_momentum_matrix(self, q, params=None) -> np.ndarray:
        """A_G (6 × n, [linear; angular about the centre of mass], world axes), Pinocchio's `ccrba`."""
        return self.call("A_G", q, params=params)

    def centroidal_momentum(self, q, u, params=None) -> np.ndarray:
        """h_G = A_G u (6,): linear momentum and angular momentum about the centre of mass."""
        A_G = self.centroidal_momentum_matrix(q, params)
        return np.einsum("...ij,...j->...i", A_G, np.asarray(u, float))

    def contact_jacobian(self, q, params=None) -> np.ndarray:
        """J_c: the stacked rows of every constraint: contacts (3 per point, 6 per frame), loops, rolling
        disks (`constraint_rows` names them)."""
        return self.call("J_c", q, params=params)

    def contact_jacobian_dot_u(self, q, u, params=None) -> np.ndarray:
        """J̇_c u, stacked like J_c's rows."""
        return self.call("Jdot_c_u", q, u, params=params)[..., 0]

    def closure_residual(self, q, params=None) -> np.ndarray:
        """The loops' and rolling disks' position residuals (`closure_rows`), zero when closed."""
        rows(self)  # refused when the system changed, or has no constraints
        return self.call("closure", q, params=params)[..., 0]

    def inverse_dynamics(self, q, u, ud, params=None) -> np.ndarray:
        """τ = M u̇ + b + g in one recursive Newton-Euler pass (Pinocchio's `rnea`), (nv,) per state."""
        return self.call("ID", q, u, ud, params)[..., 0]

    def inverse_dynamics_derivatives(self, q, u, ud, params=None) -> tuple[np.ndarray, np.ndarray]:
        """(∂τ/∂q, ∂τ/∂u), each nv × nv per state, of `inverse_dynamics` (Pinocchio's
        `computeRNEADerivatives`; ∂τ/∂u̇ = M); ∂/∂q in the tangent space."""
        D = self.call("ID_derivatives", q, u, ud, params)
        return D[..., : self._nu], D[..., self._nu :]

    def regressor(self, q, u, ud, params=None) -> np.ndarray:
        """Y (nv × p per state), τ_ID = Y π with π and its names from `eg.regressor(eom)`: 10 per link
        (Pinocchio's `computeJointTorqueRegressor`), then armature and friction per joint speed."""
        return self.call("Y", q, u, ud, params)

    def kinetic_energy_regressor(self, q, u, params=None) -> np.ndarray:
        """The row (1 × p) with T = row π (Pinocchio's `computeKineticEnergyRegressor`, and armature)."""
        return self.call("Y_T", q, u, params=params)

    def potential_energy_regressor(self, q, params=None) -> np.ndarray:
        """The row (1 × p) with U = row π of gravity (Pinocchio's `computePotentialEnergyRegressor`)."""
        return self.call("Y_U", q, params=params)

    def driving_effort(self, joint: str, q, u, ud, params=None) -> np.ndarray:
        """The torque (or force) the prescribed motion θ(t) of `joint` takes at q, u, u̇ and params["t"]:
        Lagrange's equation along θ, d/dt ∂T/∂θ̇ − ∂T/∂θ + ∂U/∂θ − τ_θ of the loads."""
        return self.call(f"drive:{joint}", q, u, ud, params)[..., 0, 0]

    def joint_wrench(self, joint: str, q, u, ud, params=None) -> tuple[np.ndarray, np.ndarray]:
        """(F, T) the parent exerts on the body of `joint` at the joint origin, world axes (free cut)."""
        W = self.call(f"W:{joint}", q, u, ud, params)[..., 0]
        return W[..., :3], W[..., 3:]

    def joint_reaction(self, joint: str, q, u, ud, params=None) -> tuple[np.ndarray, np.ndarray]:
        """(F, T), the reaction of `joint` at its origin (the wrench less its part along the joint's free
        direction), world axes (free cut)."""
        W = self.call(f"R:{joint}", q, u, ud, params)[..., 0]
        return W[..., :3], W[..., 3:]
