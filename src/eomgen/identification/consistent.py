"""Physically consistent identification (Wensing, Kim, Slotine 2017): the full parameters π, each
body's pseudo-inertia J_k(π) ⪰ 0 (`pseudo_inertia`: a realisable mass distribution) and the named
parameters (armature, viscous and Coulomb friction) ≥ 0, as a semidefinite program:

    min ‖A π − c‖² + λ (‖A‖²_F / p) ‖π − π₀‖²    subject to    J_k(π) ⪰ 0,   π_i ≥ 0 (i named),

A = W Y and c = W τ the weighted stacks over all p parameters (W: `weighting`, by default Gautier's
weights of the base least-squares fit), π₀ a prior (default 0) and λ = `regularisation` small: it
only picks one π among those with the same base parameters. Each J_k is the solver's variable, and
π_k = (J₄₄, J₁₄, J₂₄, J₃₄, Σ₂₂+Σ₃₃, −Σ₁₂, Σ₁₁+Σ₃₃, −Σ₁₃, −Σ₂₃, Σ₁₁+Σ₂₂) with Σ its upper 3 × 3
block (I = tr(Σ) 1 − Σ). Solved by cvxpy with Clarabel (the optional extra `identification`)."""
from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from ..errors import ModelError, unknown
from . import weighting
from .base import BaseParameters, base_parameters
from .data import rows, stack, states
from .model import ModelRegressor, resolve
from .pseudo_inertia import PER_BODY, smallest_eigenvalues


@dataclass(frozen=True)
class ConsistentIdentification:
    """π̂ realisable, and its base parameters."""

    pi: np.ndarray  # (p,) the full parameters
    beta: np.ndarray  # (b,) base.map · π̂
    base: BaseParameters
    eigenvalues: np.ndarray  # (bodies,) each body's smallest eigenvalue of J (≥ 0 up to the solver)
    weights: np.ndarray  # (nv,)
    rms: np.ndarray  # (nv,) the unweighted residual's RMS per joint
    status: str  # the solver's


def identify_consistent(regressor, q, u, ud, tau, *, names: Sequence[str] | None = None,
                        bodies: int | None = None, nonnegative: Sequence[str] | None = None, weights=None,
                        prior=None, regularisation: float = 1e-6,
                        base: BaseParameters | None = None) -> ConsistentIdentification:
    """π̂ of the module's program; the first `bodies` × 10 parameters are the bodies' (Pinocchio's order),
    `nonnegative` names the parameters kept ≥ 0. For a model (System, EquationsOfMotion,
    `eg.regressor(...)`): its links and its armatures, viscous and Coulomb coefficients by default."""
    import cvxpy as cp

    regressor, names = resolve(regressor, names)
    model = isinstance(regressor, ModelRegressor)
    bodies = regressor.bodies if bodies is None and model else bodies
    nonnegative = (regressor.nonnegative if model else ()) if nonnegative is None else nonnegative
    q, u, ud = states(q, u, ud)
    tau = rows(tau, "tau", u.shape[1])
    p = len(names)
    if not isinstance(bodies, int) or not 0 <= PER_BODY * bodies <= p:
        raise ModelError(f"argument 'bodies' must be a count of bodies with {PER_BODY} parameters each "
                         f"among the {p} names, got {bodies!r}")
    for name in nonnegative:
        if name not in names:
            raise unknown("parameter", name, names)
    signs = [names.index(n) for n in nonnegative]
    prior = np.zeros((1, p)) if prior is None else rows(prior, "prior", p)
    if len(prior) != 1:
        raise ModelError(f"argument 'prior' must be one vector of {p} parameters, got {len(prior)} rows")
    if not regularisation >= 0:
        raise ModelError(f"argument 'regularisation' must be ≥ 0, got {regularisation!r}")
    Y = stack(regressor, names, q, u, ud)
    if len(tau) != len(Y):
        raise ModelError(f"argument 'tau' must have one row per state ({len(Y)}), got {len(tau)}")
    base = base or base_parameters(regressor, q, u, ud, names=names)
    w = weighting.gautier(base.regressor(Y), tau) if weights is None else weighting.given(weights, Y.shape[1])
    A, c = weighting.weighted(Y, tau, w)
    Q, R = np.linalg.qr(A)  # ‖Aπ − c‖² = ‖Rπ − Qᵀc‖² + a constant
    J = [cp.Variable((4, 4), symmetric=True) for _ in range(bodies)]
    rest = cp.Variable(p - PER_BODY * bodies)
    pi = cp.hstack([_parameters(Jk) for Jk in J] + [rest])
    scale = max(c @ c, np.finfo(float).tiny)
    objective = (cp.sum_squares(R @ pi - Q.T @ c)
                 + regularisation * np.sum(A**2) / p * cp.sum_squares(pi - prior[0])) / scale
    constraints = [Jk >> 0 for Jk in J] + [pi[i] >= 0 for i in signs]
    problem = cp.Problem(cp.Minimize(objective), constraints)
    problem.solve(solver=cp.CLARABEL)
    if problem.status not in ("optimal", "optimal_inaccurate"):
        raise ModelError(f"identify_consistent: the solver ended with status {problem.status!r}")
    value = np.asarray(pi.value, dtype=float)
    return ConsistentIdentification(
        pi=value, beta=base.of(value), base=base, eigenvalues=smallest_eigenvalues(value, bodies),
        weights=w, rms=np.sqrt(((tau - Y @ value) ** 2).mean(axis=0)), status=problem.status)


def _parameters(J):
    """π_k from J_k (see the module's text)."""
    import cvxpy as cp

    S = J[:3, :3]
    return cp.hstack([J[3, 3], J[0, 3], J[1, 3], J[2, 3], S[1, 1] + S[2, 2], -S[0, 1], S[0, 0] + S[2, 2],
                      -S[0, 2], -S[1, 2], S[0, 0] + S[1, 1]])
