"""The inverse dynamics τ = M u̇ + b + g of an `EquationsOfMotion` in one pass, and the Jacobians of the
dynamics by the chain rule through the intermediates (`eomgen.derivatives`):

    ∂τ/∂q (in the tangent space: column j moves q along speed u_j),  ∂τ/∂u,  ∂τ/∂u̇ = M (no derivative).

The forward dynamics M u̇ = τ + τ_loads − b − g (τ: joint efforts, one per speed) has, at
u̇ = M⁻¹ (τ + τ_loads − b − g),

    ∂u̇/∂q = −M⁻¹ ∂(τ_ID − τ_loads)/∂q,   ∂u̇/∂u = −M⁻¹ ∂(τ_ID − τ_loads)/∂u,   ∂u̇/∂τ = M⁻¹,

τ_ID taken at that u̇ (so ∂M/∂q u̇ is in ∂τ_ID/∂q). The results are kept in `EquationsOfMotion.compact`
under "ID", "ID:loads", "ID:D" and "ID:D_loads" (built once, on first request)."""

from __future__ import annotations

import sympy as sp

from .derivatives import jacobian, speed_seeds, tangent_seeds
from .eom import EquationsOfMotion
from .errors import ModelError
from .linalg import matmul
from .methods import recursive
from .model import FlexibleLink

TANGENT, SPEED = "dq", "u"  # the memo keys of the seed families (`derivatives.jacobian`)


def inverse_dynamics(eom: EquationsOfMotion) -> sp.Matrix:
    """τ = M u̇ + b + g, u̇ = `System.ud`: one recursive Newton-Euler pass on the equations' kinematics,
    whatever the method that derived them (`methods.recursive.inverse_dynamics`); with a flexible link,
    which the recursion does not cover, M u̇ + b + g of the compact forms."""
    _equations(eom, "inverse_dynamics")
    if "ID" not in eom.compact:
        eom.compact["ID"] = _inverse_dynamics(eom)
    return eom.compact["ID"]


def available(eom: EquationsOfMotion) -> bool:
    """Whether the inverse dynamics can be formed: by the recursion, or from M, b and g."""
    return not _from_forms(eom) or all(k in eom.compact for k in ("M", "b", "g"))


def unavailable(eom: EquationsOfMotion) -> str:
    """Why the inverse dynamics cannot be formed (flexible links or prescribed motion without M, b, g)."""
    missing = [k for k in ("M", "b", "g") if k not in eom.compact]
    return (f"inverse dynamics of a system with flexible links or prescribed motion is M u̇ + b + g: derive "
            f"{missing} too (quantities=None)")


def _from_forms(eom: EquationsOfMotion) -> bool:
    """Whether the inverse dynamics is M u̇ + b + g (flexible links, prescribed motions: no recursion)."""
    return bool(eom.system.prescribed) or any(isinstance(j, FlexibleLink) for j in eom.system.joints)


def _inverse_dynamics(eom: EquationsOfMotion) -> sp.Matrix:
    system = eom.system
    if not _from_forms(eom):
        return recursive.inverse_dynamics(eom.kinematics)
    if not available(eom):
        raise ModelError(unavailable(eom))
    return matmul(eom.compact["M"], system.ud) + eom.compact["b"] + eom.compact["g"]


def dynamics_residual(eom: EquationsOfMotion) -> sp.Matrix:
    """τ_ID − τ_loads = M u̇ + b + g − τ_loads: the recursion with the loads as external forces (their
    derivatives then follow the body frames, not the world Jacobians of every load point), or with a
    flexible link the inverse dynamics less the compact τ_loads."""
    if "ID:loads" not in eom.compact:
        eom.compact["ID:loads"] = (
            inverse_dynamics(eom) - eom.tau_compact
            if _from_forms(eom)
            else recursive.inverse_dynamics(eom.kinematics, loads=True)
        )
    return eom.compact["ID:loads"]


def dynamics_jacobian(eom: EquationsOfMotion, loads: bool = False) -> sp.Matrix:
    """[∂r/∂q | ∂r/∂u] (n × 2n) of r = τ_ID, or with `loads` r = τ_ID − τ_loads (the forward dynamics'
    Jacobians before M⁻¹); ∂/∂q in the tangent space (`derivatives.tangent_seeds`)."""
    key = "ID:D_loads" if loads else "ID:D"
    if key not in eom.compact:
        r = dynamics_residual(eom) if loads else inverse_dynamics(eom)
        sub, system = eom.subexpressions, eom.system
        eom.compact[key] = jacobian(sub, r, tangent_seeds(system), TANGENT).row_join(
            jacobian(sub, r, speed_seeds(system), SPEED)
        )
    return eom.compact[key]


def _equations(eom, entry: str) -> None:
    if not isinstance(eom, EquationsOfMotion):
        raise ModelError(
            f"{entry}: expected EquationsOfMotion, got {type(eom).__name__} (Kane's equations "
            "are in independent speeds: use eg.derive(system) for the inverse dynamics)"
        )
