"""The forward dynamics of numeric functions `f` (NumPy or C; one state or N along axis 0) and its
derivatives (formulas in `eomgen.inverse_dynamics`; ∂/∂q in the tangent space, one column per speed):

    h = τ_loads + Sᵀ τ_a − b − g,   u̇ = M⁻¹ h (no constraints),
    forward_dynamics_derivatives(q, u, tau) = (∂u̇/∂q, ∂u̇/∂u, ∂u̇/∂τ) = (−M⁻¹ D_q, −M⁻¹ D_u, M⁻¹),

D = ∂(τ_ID − τ_loads)/∂(q, u) at u̇ = M⁻¹ (τ + τ_loads − b − g), tau one effort per speed (as Pinocchio's
computeABADerivatives; Sᵀ τ_a for the τ_a of `forward_dynamics`, and ∂u̇/∂τ_a = M⁻¹ Sᵀ). M⁻¹ comes from
one Cholesky factorisation (`printers.runtime.DERIVATIVES`, the text a written module runs too)."""
from __future__ import annotations

import warnings

import numpy as np

from ..functions import forward_key
from ..printers.runtime import runtime_namespace
from .parameters import actuated
from .singular import singular_mass_matrix

_runtime = runtime_namespace()
joint_efforts, forward_derivatives = _runtime["_efforts"], _runtime["_forward_derivatives"]


def h(f, q, u, tau_a, params) -> np.ndarray:
    """h = τ_loads + Sᵀ τ_a − b − g."""
    return actuated(f.tau(q, u, params) - f.nle(q, u, params), tau_a, f.S)


def euler_singularity(f, q, tol: float = 1e-3, params=None) -> float | None:
    """For ZYX Euler angles (an Euler base, a ZYX ball joint): warn when a pitch is within `tol` of ±90°
    (where the angle rates are undefined and M is singular) and return cond(M); None when the state is
    regular."""
    for b in f.system.bodies:
        if b.joint.pitch_index is not None:
            pitch = float(np.asarray(q, float)[b.q_index + b.joint.pitch_index])
            if abs(np.cos(pitch)) < tol:
                cond = float(np.linalg.cond(f.M(q, params)))
                warnings.warn(f"joint '{b.joint.name}': pitch {pitch:.6f} rad is {abs(np.cos(pitch)):.1e} "
                              f"from ±90°, where ZYX Euler angles are singular; cond(M) = {cond:.1e}",
                              stacklevel=4)
                return cond
    return None


def forward_dynamics(f, q, u, tau_a=None, params=None) -> np.ndarray:
    """u̇ = M⁻¹ h, solved numerically (no contacts); warns near an Euler-angle singularity."""
    if np.ndim(q) == 1:
        euler_singularity(f, q, params=params)
    M = f.M(q, params)
    try:
        return np.linalg.solve(M, h(f, q, u, tau_a, params)[..., None])[..., 0]
    except np.linalg.LinAlgError:
        raise singular_mass_matrix(f.system, M, "forward_dynamics") from None


def euler(system) -> bool:
    """Whether a joint has ZYX Euler angles (`euler_singularity`)."""
    return any(b.joint.pitch_index is not None for b in system.bodies)


def forward_checks(f, q, params) -> None:
    """Refuse equations without M, b, g and systems with constraints (their u̇ is the constrained
    dynamics': the catalogue says why it has no forward derivatives); warn near an Euler-angle
    singularity (one state)."""
    f.catalogue["FD_derivatives"]
    if euler(f.system) and np.ndim(q) == 1:
        euler_singularity(f, q, params=params)


def forward_dynamics_derivatives(f, q, u, tau=None, params=None) -> tuple[np.ndarray, ...]:
    """(∂u̇/∂q, ∂u̇/∂u, ∂u̇/∂τ) of u̇ = M⁻¹ (τ + τ_loads − b − g) (module formulas)."""
    forward_checks(f, q, params)
    h_tau = h(f, q, u, None, params) + joint_efforts(tau, f.nv, np.shape(q)[:-1])
    key = forward_key(f.eom)
    return forward_derivatives(f.M(q, params), h_tau, lambda ud: f.call(key, q, u, ud, params), f.nv)
