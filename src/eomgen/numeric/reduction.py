"""The dynamics of a constrained system in its independent speeds u_i.

With the rows of J_c u = 0 that some motion can violate split into the dependent and independent
speeds' columns, J_c = [J_d J_i] (J_d square), every motion is u = R u_i and u̇ = R u̇_i + s:

    R = [1; −J_d⁻¹ J_i],  s = [0; −J_d⁻¹ J̇_c u]  (rows ordered back into u),
    M_r u̇_i + b_r + g_r = τ_r,  M_r = Rᵀ M R,  b_r = Rᵀ (b + M s),  g_r = Rᵀ g,  τ_r = Rᵀ (τ + Sᵀ τ_a),

Kane's equations with the constraint forces eliminated (Rᵀ J_cᵀ = 0). Numerically (`Reduced`, one state
at a time, J_d by LU), or symbolically for small mechanisms (`Reduced.symbolic`: J_d⁻¹ by the adjugate,
closed forms in all q)."""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import sympy as sp

import warnings

from ..errors import ModelError
from ..state import random_states
from .assembly import numeric, speed_indices
from .constrained import held, row_sizes
from .contacts import RANK_RTOL, redundant_rows
from .parameters import actuated

SYMBOLIC_LIMIT = 3  # dependent speeds up to which J_d⁻¹ is written by its adjugate


@dataclass
class ReducedForms:
    """Closed forms of the reduced equations M u̇_i + b + g = Rᵀ (τ + Sᵀ τ_a) in q and u_i."""

    M: sp.Matrix
    b: sp.Matrix
    g: sp.Matrix
    R: sp.Matrix
    u_independent: list[sp.Symbol]


class Reduced:
    """M_r(q), b_r(q, u), g_r(q), R(q), τ_r and u̇ of the module formulas (u: the full speeds, or the
    independent ones u_i, expanded to R u_i)."""

    def __init__(self, eom, independent) -> None:
        self.f = numeric(eom, "reduce")
        system = self.f.eom.system
        if not system.constraint_rows():
            raise ModelError("reduce: the system has no contacts, loops or rolling disks (nothing to "
                             "reduce)")
        self.independent = speed_indices(system, independent, "reduce: independent")
        self.dependent = [i for i in range(self.f.nv) if i not in self.independent]
        self.u_independent = [system.u[i] for i in self.independent]
        self._forms: dict[bool, ReducedForms] = {}
        self._kept: dict[tuple, np.ndarray] = {}  # `_rows` per parameter values
        if not system.parameters:  # else checked with the first call's params
            self._rows(None)

    def _rows(self, params) -> np.ndarray:
        """The rows of J_c some motion can violate and that repeat none before them (`_repeating`), one per
        dependent speed (refused otherwise)."""
        size = row_sizes(self.f, params)
        key = tuple(np.ravel(self.f.parameter_vector(params, "J_c")))
        if key not in self._kept:
            self._kept[key] = self._repeating(size, params)
        active = self._kept[key]
        if active.sum() != len(self.dependent):
            rows = [n for n, a in zip(self.f.constraint_rows, active) if a]
            raise ModelError(f"reduce: {len(rows)} constraint rows ({rows}) but {len(self.dependent)} "
                             f"dependent speeds ({[str(self.f.eom.u[i]) for i in self.dependent]}): name "
                             f"{self.f.nv - len(rows)} independent speeds")
        return active

    def _repeating(self, size: np.ndarray, params) -> np.ndarray:
        """The mask of the rows of J_c some motion can violate (`size` > 0, `_row_sizes`), less those that
        repeat rows before them (`redundant_rows` of the rows scaled to size 1, at each of three random
        states: a loop stated twice): dropped, with a warning naming them, as the constrained dynamics
        drop them."""
        names, active = self.f.constraint_rows, size > 0
        q, _, _ = random_states(self.f.eom.system, 3, np.random.default_rng(1))
        repeated = set.intersection(*(
            set(redundant_rows(A, RANK_RTOL * max(1.0, np.linalg.norm(A, 2))))
            for A in (self.f.contact_jacobian(x, params)[active] / size[active, None] for x in q)))
        dropped = [int(i) for k, i in enumerate(np.flatnonzero(active)) if k in repeated]
        if dropped:
            warnings.warn(f"reduce: constraint rows {[names[i] for i in dropped]} repeat other constraints "
                          "(at every random state): dropped", stacklevel=4)
            active[dropped] = False
        return active

    def _J_d(self, q, params) -> tuple[np.ndarray, np.ndarray]:
        """(J_d, J_i), J_d refused when singular at q (naming the rows and speeds it cannot resolve)."""
        kept = self._rows(params)
        kept_here, J, rows = held(self.f, q, params)
        J, rows = J[kept[kept_here]], [r for r, k in zip(rows, kept[kept_here]) if k]
        J_d = J[:, self.dependent]
        if J_d.shape[0] < J_d.shape[1]:
            raise ModelError(f"reduce: J_d is singular at this state: only rows {rows} can be violated "
                             "here; choose other independent speeds or another state")
        U, sigma, Vt = np.linalg.svd(J_d)
        if sigma[-1] <= RANK_RTOL * sigma[0]:
            weak_rows = [rows[k] for k in np.flatnonzero(np.abs(U[:, -1]) > 0.1)]
            weak_speeds = [str(self.f.eom.u[self.dependent[k]]) for k in np.flatnonzero(abs(Vt[-1]) > 0.1)]
            raise ModelError(f"reduce: J_d is singular at this state (σ_min / σ_max = "
                             f"{sigma[-1] / sigma[0]:.1e}): "
                             f"rows {weak_rows} do not determine the dependent speeds {weak_speeds}; choose "
                             "other independent speeds")
        return J_d, J[:, self.independent]

    def _R(self, q, params) -> tuple[np.ndarray, np.ndarray]:
        """(R, J_d) at q: R = [1; −J_d⁻¹ J_i] (nv × n_i), J_d kept for s."""
        J_d, J_i = self._J_d(q, params)
        R = np.zeros((self.f.nv, len(self.independent)))
        R[self.independent] = np.eye(len(self.independent))
        R[self.dependent] = -np.linalg.solve(J_d, J_i)
        return R, J_d

    def _state(self, q, u, params) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """(R, the full speeds, s) at q: the speeds u itself (nv values) or R u_i (n_i values);
        s = [0; −J_d⁻¹ J̇_c u]."""
        R, J_d = self._R(q, params)
        u = np.asarray(u, dtype=float)
        u = R @ u if u.shape == (len(self.independent),) else u
        s = np.zeros(self.f.nv)
        Jdot_u = self.f.contact_jacobian_dot_u(q, u, params)[self._rows(params)]
        s[self.dependent] = -np.linalg.solve(J_d, Jdot_u)
        return R, u, s

    def R(self, q, params=None) -> np.ndarray:
        """R = ∂u/∂u_i = [1; −J_d⁻¹ J_i] (nv × n_i)."""
        return self._R(q, params)[0]

    def s(self, q, u, params=None) -> np.ndarray:
        """s = [0; −J_d⁻¹ J̇_c u]: u̇ = R u̇_i + s."""
        return self._state(q, u, params)[2]

    def M(self, q, params=None) -> np.ndarray:
        """M_r = Rᵀ M R."""
        R = self.R(q, params)
        return R.T @ self.f.M(q, params) @ R

    def b(self, q, u, params=None) -> np.ndarray:
        """b_r = Rᵀ (b + M s)."""
        R, u, s = self._state(q, u, params)
        return R.T @ (self.f.b(q, u, params) + self.f.M(q, params) @ s)

    def g(self, q, params=None) -> np.ndarray:
        """g_r = Rᵀ g."""
        return self.R(q, params).T @ self.f.g(q, params)

    def tau(self, q, u, tau_a=None, params=None) -> np.ndarray:
        """τ_r = Rᵀ (τ + Sᵀ τ_a) (τ: the loads)."""
        R, u, _ = self._state(q, u, params)
        return R.T @ actuated(self.f.tau(q, u, params), tau_a, self.f.S)

    def forward_dynamics(self, q, u, tau_a=None, params=None) -> np.ndarray:
        """u̇ = R u̇_i + s with M_r u̇_i = τ_r − b_r − g_r (the full nv speeds' rates)."""
        R, u, s = self._state(q, u, params)
        M = self.f.M(q, params)
        h = actuated(self.f.tau(q, u, params), tau_a, self.f.S) - self.f.nle(q, u, params) - M @ s
        return R @ np.linalg.solve(R.T @ M @ R, R.T @ h) + s

    def symbolic(self, simplify: bool = False, params=None) -> ReducedForms:
        """M_r, b_r(q, u_i), g_r and R in closed form (every q; at most 3 dependent speeds, J_d⁻¹ =
        adj(J_d) / det(J_d)); `simplify` applies sympy's simplify to each entry (slow)."""
        if simplify not in self._forms:
            if len(self.dependent) > SYMBOLIC_LIMIT:
                raise ModelError(f"reduce: the symbolic form inverts J_d by its adjugate, for at most "
                                 f"{SYMBOLIC_LIMIT} dependent speeds; this system has "
                                 f"{len(self.dependent)}: "
                                 "use the numeric functions (M, b, g, R)")
            eom, active = self.f.eom, list(np.flatnonzero(self._rows(params)))
            J, Jdot_u = (eom.subexpressions.inline(x[active, :])
                         for x in eom.kinematics.constraint_jacobian())
            J_d = J[:, self.dependent]
            det, adj = J_d.det(method="berkowitz"), J_d.adjugate()
            R = self._ordered(sp.eye(len(self.independent)), -adj * J[:, self.independent] / det)
            u = dict(zip(eom.u, R * sp.Matrix(self.u_independent)))
            s = self._ordered(sp.zeros(len(self.independent), 1), -adj * Jdot_u.xreplace(u) / det)
            forms = [R.T * eom.M * R, R.T * (eom.b.xreplace(u) + eom.M * s), R.T * eom.g, R]
            if simplify:
                forms = [x.applyfunc(sp.simplify) for x in forms]
            self._forms[simplify] = ReducedForms(*forms, self.u_independent)
        return self._forms[simplify]

    def _ordered(self, independent: sp.Matrix, dependent: sp.Matrix) -> sp.Matrix:
        """The rows of the independent and of the dependent speeds, back in u's order."""
        rows = {**dict(zip(self.independent, independent.tolist())),
                **dict(zip(self.dependent, dependent.tolist()))}
        return sp.Matrix([rows[i] for i in range(self.f.nv)])


def reduce(eom, independent) -> Reduced:
    """The dynamics in the independent speeds (`independent`: their names, or coordinates whose rate
    they are) of an EquationsOfMotion (or its `eg.codegen` functions, or a System: derived with method
    "recursive"): `Reduced`'s M, b, g, R, forward_dynamics numerically, `Reduced.symbolic()` in closed
    form (module formulas)."""
    return Reduced(eom, independent)
