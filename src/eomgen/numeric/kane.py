"""Numeric Kane's equations: the symbolic pieces of `KaneEquations.compact` as generated functions of
(q, u, w), u the joint speeds, and every linear solve in NumPy with pivoting (np.linalg.solve, batched
over states):

    w_dep = −C_dep⁻¹ (C_ind w_ind + c0),  T = [I; −C_dep⁻¹ C_ind],  u = −Y⁻¹ (K w + k0),  P = −Y⁻¹ K T,
    ẇ_dep,0 = −C_dep⁻¹ ċ,  u̇₀ = −Y⁻¹ (K ẇ₀ + ẏ),  M̃ = Pᵀ M P,  f̃ = Pᵀ (h − M u̇₀),  F̃_r = Pᵀ Q,
    q̇ = q̇(q, u),  M̃ ẇ_ind = f̃ + Pᵀ Sᵀ τ_a (`rhs`, τ_a the actuated joints' efforts)

(ċ, ẏ: the "rates", d/dt of the constraints and kinematic equations at ẇ = 0, u̇ = 0). The algorithms are
written once for an array module `xp` (numpy here; jax.numpy in `numeric.jax_kane`): no array is written
into, w and T are stacked from their independent and dependent parts."""
from __future__ import annotations

import numpy as np

from ..arguments import count, finite_array, positive
from ..errors import ModelError
from ..functions import kane_catalogue
from ..state import unit_quaternions
from .compiled import Compiled
from .contacts import refuse_flat
from .facade import Functions
from .parameters import Parameters, actuated
from .state_equations import efforts, split, work_rate


class NumericKane(Functions):
    """Numeric Kane's equations in the independent speeds w (here: w_ind): mass_matrix(q, w), forcing(q, w),
    qdot(q, w) (the coordinate rates, nq of them), joint_speeds(q, w) (u, n of them), dependent_speeds(q, w),
    active_forces(q, w), `rhs(t, x, tau)` for x = [q, w_ind] (solve_ivp), its `energy` and `power`; with
    holonomic constraints holonomic_residual(q) and assemble(q_guess) (a consistent q, the independent
    coordinates held).
    One state (q of shape (nq,)) or N states (N, nq); parameters by name in `params`."""

    xp = np  # the array module of the algorithms
    dtype = "float64"

    def __init__(self, kane) -> None:
        self.kane = kane
        self.system = kane.system  # the model the functions were generated from
        self.n = len(kane.speeds)  # as many as the joint speeds u
        self.nv = len(kane.independent)
        self._dep, self._ind = kane._indices()
        self._order = np.argsort(self._ind + self._dep)  # [independent, dependent] → speeds' order
        self._q_dep = [list(kane.system.q).index(x) for x in kane.dependent_coordinates]
        self.S = np.array(kane.system.S.tolist(), dtype=float).reshape(-1, self.n)
        catalogue = kane_catalogue(kane)
        super().__init__(catalogue, Parameters(catalogue.inputs["p"]))

    def _eval(self, key: str, q, u=None, w=None, params=None) -> np.ndarray:
        """Generated function `key` at (q, u, w): shape batch + (rows, cols)."""
        return self.call(key, q, u, w, params)

    def _refuse(self, *args, **kwargs):
        raise ModelError(
            "inverse_dynamics, inverse_dynamics_derivatives and forward_dynamics_derivatives are "
            "generated for EquationsOfMotion (eg.derive(system)), not for Kane's equations"
        )

    inverse_dynamics = inverse_dynamics_derivatives = forward_dynamics_derivatives = _refuse

    def _w(self, w) -> np.ndarray | None:
        return None if self.kane.speeds_are_qdot else w

    def _rates(self, q, u, params) -> np.ndarray:
        """q̇(q, u), the coordinate rates (u itself where no function "qdot" was needed)."""
        return self._eval("qdot", q, u, params=params)[..., 0] if "qdot" in self.functions else u

    def _array(self, x):
        """x as an array of the module `xp` in `dtype`."""
        return self.xp.asarray(x, dtype=self.dtype)

    def _merged(self, independent, dependent, axis: int):
        """The rows of the independent and (unless None) the dependent speeds along `axis`, in the speeds'
        order."""
        xp = self.xp
        parts = [independent] if dependent is None else [independent, dependent]
        return xp.take(xp.concatenate(parts, axis), self._order, axis=axis)

    def _check_flat(self, q, params) -> None:
        """Refuse a rolling disk lying flat (`contacts.refuse_flat`)."""
        if "tilt" in self.functions:
            refuse_flat(self.kane.system.rolling, self._eval("tilt", q, params=params))

    def _actuated(self, h, tau_a):
        return actuated(h, tau_a, self.S)

    def _speeds(self, q, w_ind, params) -> tuple:
        """(w, u, P = ∂u/∂w_ind, C_dep, Y, K) at q and w_ind."""
        xp = self.xp
        q, w_ind = self._array(q), self._array(w_ind)
        batch, n, p = q.shape[:-1], self.n, self.nv
        if w_ind.shape != batch + (p,):
            raise ModelError(f"w: expected shape {batch + (p,)} (the independent speeds), got {w_ind.shape}")
        self._check_flat(q, params)
        C_dep = w_dep = T_dep = None
        if self._dep:
            Cc = self._eval("C", q, params=params)
            C_dep, C_ind = Cc[..., self._dep], Cc[..., self._ind]
            X = xp.linalg.solve(C_dep, xp.concatenate([C_ind, C_ind @ w_ind[..., None] + Cc[..., n:]], -1))
            T_dep, w_dep = -X[..., :p], -X[..., p]
        w = self._merged(w_ind, w_dep, -1)
        T = self._merged(xp.broadcast_to(xp.eye(p, dtype=q.dtype), batch + (p, p)), T_dep, -2)
        Yk = self._eval("Y", q, params=params)
        Y, K = Yk[..., :n], Yk[..., n:2 * n]
        X = xp.linalg.solve(Y, xp.concatenate([K @ T, K @ w[..., None] + Yk[..., 2 * n:]], -1))
        return w, -X[..., p], -X[..., :p], C_dep, Y, K

    def mass_matrix(self, q, w, params=None) -> np.ndarray:
        """M̃ = Pᵀ M P."""
        P = self._speeds(q, w, params)[2]
        return self.xp.swapaxes(P, -1, -2) @ self._eval("M", q, params=params) @ P

    def forcing(self, q, w, params=None) -> np.ndarray:
        """f̃ = Pᵀ (h − M q̈₀)."""
        return self._dynamics(q, w, params)[2]

    def qdot(self, q, w, params=None) -> np.ndarray:
        """q̇ = q̇(q, u), the coordinate rates (nq)."""
        return self._rates(q, self.joint_speeds(q, w, params), params)

    def joint_speeds(self, q, w, params=None) -> np.ndarray:
        """u = −Y⁻¹ (K w + k0), the joint speeds (n; q̇ but for quaternion ball and planar joints)."""
        return self._speeds(q, w, params)[1]

    def dependent_speeds(self, q, w, params=None) -> np.ndarray:
        """w_dep = −C_dep⁻¹ (C_ind w_ind + c0)."""
        return self._speeds(q, w, params)[0][..., self._dep]

    def active_forces(self, q, w, params=None) -> np.ndarray:
        """F̃_r = Pᵀ Q (Q = τ_loads − g, the generalized active forces in u)."""
        _, u, P, *_ = self._speeds(q, w, params)
        return (self.xp.swapaxes(P, -1, -2) @ self._eval("h", q, u, params=params)[..., 1:])[..., 0]

    def holonomic_residual(self, q, params=None) -> np.ndarray:
        """f(q), the residuals of the holonomic constraints (zero on the constraint)."""
        return self._eval("holonomic", q, params=params)[..., 0]

    def assemble(self, q_guess, params=None, tol: float = 1e-12, iterations: int = 50) -> np.ndarray:
        """q with f(q) = 0 near `q_guess`, the independent coordinates held: Newton on the dependent ones,
        q_dep ← q_dep − (∂f/∂q_dep)⁻¹ f; ModelError if the largest residual stays above `tol`."""
        if not self._q_dep:
            raise ModelError("assemble: these Kane's equations have no holonomic constraints")
        q = np.asarray(q_guess, dtype=object)
        if q.ndim == 0 or q.shape[-1:] != (self.nq,):
            raise ModelError(f"assemble: q_guess: expected {self.nq} coordinates, got shape {q.shape}")
        q = unit_quaternions(self.kane.system, finite_array(q_guess, q.shape, "assemble: q_guess"))
        tol, iterations = positive(tol, "assemble: tol"), count(iterations, "assemble: iterations", least=0)
        for step in range(iterations + 1):
            fF = self._eval("holonomic", q, params=params)
            residual = np.max(np.abs(fF[..., 0]))
            if residual <= tol:
                return q
            if step < iterations:
                q[..., self._q_dep] -= np.linalg.solve(fF[..., 1:], fF[..., :1])[..., 0]
        raise ModelError(f"assemble: the holonomic constraints fail by {residual:.3g} (max |f|) after "
                         f"{iterations} Newton steps from q_guess; no consistent q near it")

    def _dynamics(self, q, w_ind, params, tau_a=None) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """(u, M̃, f̃ + Pᵀ Sᵀ τ_a) at q and w_ind."""
        xp = self.xp
        w, u, P, C_dep, Y, K = self._speeds(q, w_ind, params)
        rates = self._eval("rates", q, u, self._w(w), params)
        wd0_dep = -xp.linalg.solve(C_dep, rates[..., self.n:, :]) if self._dep else None
        wd0 = self._merged(xp.zeros(w.shape[:-1] + (self.nv, 1), w.dtype), wd0_dep, -2)
        ud0 = -xp.linalg.solve(Y, K @ wd0 + rates[..., :self.n, :])
        M = self._eval("M", q, params=params)
        Pt = xp.swapaxes(P, -1, -2)
        h = self._actuated(self._eval("h", q, u, params=params)[..., 0], tau_a)[..., None]
        return u, Pt @ M @ P, (Pt @ (h - M @ ud0))[..., 0]

    @property
    def nx(self) -> int:
        """The size of the state x = [q, w_ind]."""
        return self.nq + self.nv

    def _without_motors(self) -> None:
        """Refuse DC motors: their currents would be constants here, not states driven by the voltages."""
        motors = self.kane.system.motors
        if motors:
            raise ModelError(f"Kane's rhs, energy and power do not integrate the circuits of the DC motors "
                             f"{[str(m.current) for m in motors]}: simulate the equations of motion "
                             "(eg.derive), whose rhs has x = [q, u, i]; eg.linearize takes Kane's with "
                             "motors")

    def _split(self, x) -> list:
        """[q, w_ind] of x (one state or N)."""
        return split(x, [self.nq, self.nv], "q, w_ind", batch=True, xp=self.xp, dtype=self.dtype)

    def rhs(self, t, x, tau=None, params=None) -> np.ndarray:
        """d/dt [q, w_ind] = [q̇(q, u), M̃⁻¹ (f̃ + Pᵀ Sᵀ τ_a)], τ_a = `tau` (None, one value per actuated
        joint, or a function (t, q, w_ind))."""
        self._without_motors()
        xp = self.xp
        q, w = self._split(x)
        u, M, f = self._dynamics(q, w, params, efforts(tau, t, q, w))
        return xp.concatenate([self._rates(q, u, params), xp.linalg.solve(M, f[..., None])[..., 0]], -1)

    def power(self, t, x, tau=None, params=None) -> np.ndarray:
        """Ẇ = uᵀ (Sᵀ τ_a + τ_nc), u the joint speeds: the power of the actuators and of the loads but
        springs (`numeric.state_equations`)."""
        self._without_motors()
        q, w = self._split(x)
        u = self.joint_speeds(q, w, params)
        tau_nc = self._eval("tau_nc", q, u, params=params)[..., 0]
        return work_rate(u, self._actuated(tau_nc, efforts(tau, t, q, w)), self.xp)

    def energy(self, x, params=None) -> np.ndarray:
        """E = T + U at the joint speeds u of (q, w_ind)."""
        self._without_motors()
        q, w = self._split(x)
        return self._eval("energy", q, self.joint_speeds(q, w, params), params=params)[..., 0].sum(-1)


class CompiledKane(Compiled, NumericKane):
    """`NumericKane` with the symbolic pieces compiled from C (per call and batched); solves in NumPy."""

    batches = False

