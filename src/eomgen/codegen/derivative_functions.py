"""The inverse dynamics and the derivatives of the dynamics as generated functions (formulas in
`eomgen.inverse_dynamics`; ∂/∂q in the tangent space, one column per speed):

    inverse_dynamics(q, u, ud) = τ = M u̇ + b + g,
    inverse_dynamics_derivatives(q, u, ud) = (∂τ/∂q, ∂τ/∂u),
    forward_dynamics_derivatives(q, u, tau) = (∂u̇/∂q, ∂u̇/∂u, ∂u̇/∂τ) = (−M⁻¹ D_q, −M⁻¹ D_u, M⁻¹),

D = ∂(τ_ID − τ_loads)/∂(q, u) at u̇ = M⁻¹ (τ + τ_loads − b − g), tau one effort per speed (as Pinocchio's
computeABADerivatives; Sᵀ τ_a for the τ_a of `forward_dynamics`, and ∂u̇/∂τ_a = M⁻¹ Sᵀ). M⁻¹ comes from
one Cholesky factorisation. The NumPy arithmetic is one text (`RUNTIME`), run by eomgen and written
verbatim into generated modules; the compiled functions do it in C (`c_derivatives`)."""

from __future__ import annotations

import functools
import math

import numpy as np
import sympy as sp

from ..errors import ModelError
from ..inverse_dynamics import available, dynamics_jacobian, inverse_dynamics

RUNTIME = '''
def _efforts(tau, nv, batch):
    """tau (one effort per speed, for all states or one per state) as floats of shape batch + (nv,)."""
    if tau is None:
        return numpy.zeros(batch + (nv,))
    try:
        t = numpy.asarray(tau, dtype=float)
    except (TypeError, ValueError):
        raise _Error("tau: expected %d real numbers (one per speed), got %s"
                     % (nv, type(tau).__name__)) from None
    if t.shape not in ((nv,), batch + (nv,)) or not numpy.all(numpy.isfinite(t)):
        raise _Error("tau: expected %d finite values (one per speed), shape (%d,) or %s, got shape %s"
                     % (nv, nv, batch + (nv,), t.shape))
    return numpy.broadcast_to(t, batch + (nv,))


def _forward_derivatives(M, h, jacobian, nv):
    """(−M⁻¹ D_q, −M⁻¹ D_u, M⁻¹) with D = jacobian(u̇) at u̇ = M⁻¹ h; M⁻¹ = L⁻ᵀ L⁻¹, M = L Lᵀ."""
    try:
        L_inv = numpy.linalg.inv(numpy.linalg.cholesky(M))
    except numpy.linalg.LinAlgError:
        raise _Error("forward_dynamics_derivatives: M is not positive definite at this state") from None
    M_inv = numpy.swapaxes(L_inv, -1, -2) @ L_inv
    D = -M_inv @ jacobian(numpy.einsum("...ij,...j->...i", M_inv, h))
    return D[..., :nv], D[..., nv:], M_inv
'''

# the functions in a written module: their outputs are generated as "_<key>" (see `outputs`)
MODULE_API = '''
def inverse_dynamics_derivatives(q, u, ud, params=None):
    """(∂τ/∂q, ∂τ/∂u) of inverse_dynamics, ∂/∂q in the tangent space (one column per speed)."""
    D = _inverse_dynamics_jacobian(q, u, ud, params)
    return D[..., :NV], D[..., NV:]
'''

MODULE_FORWARD = '''
def forward_dynamics_derivatives(q, u, tau=None, params=None):
    """(∂u̇/∂q, ∂u̇/∂u, ∂u̇/∂τ) of u̇ = M⁻¹ (τ + τ(q, u) − b − g), tau one effort per speed (Sᵀ τ_a for
    forward_dynamics' tau_a), or None; ∂/∂q in the tangent space."""
    return _forward_dynamics_derivatives(q, u, tau, params)


def _forward_dynamics_derivatives(q, u, efforts, params):
    h = tau(q, u, params) - {nle} + _efforts(efforts, NV, numpy.shape(q)[:-1])
    return _forward_derivatives(M(q, params), h, lambda ud: {jacobian}(q, u, ud, params), NV)
'''


def _namespace() -> dict:
    namespace = {"math": math, "numpy": np, "_Error": ModelError}
    exec(RUNTIME, namespace)  # eomgen's own fixed text
    return namespace


_runtime = _namespace()
efforts, forward_derivatives = _runtime["_efforts"], _runtime["_forward_derivatives"]


def forward_key(eom) -> str:
    """The key of D = ∂(τ_ID − τ_loads)/∂(q, u): the inverse dynamics' own Jacobian without loads."""
    return "FD_jacobian" if eom.load_names else "ID_derivatives"


def jacobians(eom) -> dict:
    """Key: build of the Jacobians the functions use (`inverse_dynamics.dynamics_jacobian`)."""
    return {
        "ID_derivatives": lambda: dynamics_jacobian(eom),
        "FD_jacobian": lambda: dynamics_jacobian(eom, True),
    }


def forward_parts(eom) -> sp.Matrix:
    """[M | τ_loads − b − g] (n × (n + 1)), M's lower triangle only (what the C factorisation reads)."""
    n = len(eom.u)
    M = eom.compact["M"]
    h = eom.tau_compact - eom.nle_compact
    return sp.Matrix(n, n, lambda i, j: M[i, j] if j <= i else 0).row_join(h)


def outputs(eom) -> list[tuple[str, str, str, object, str]]:
    """(key, name, what, build, args) of the inverse dynamics and its Jacobian (where it can be formed), and
    with M, b, g the Jacobian of the forward dynamics (when it differs, with loads), for the written outputs.
    """
    if not available(eom):
        return []
    build = jacobians(eom)
    found = [
        (
            "ID",
            "inverse_dynamics",
            "τ = M u̇ + b + g, one recursive Newton-Euler pass",
            lambda: inverse_dynamics(eom),
            "q, u, ud",
        ),
        (
            "ID_derivatives",
            "_inverse_dynamics_jacobian",
            "[∂τ/∂q | ∂τ/∂u] (NV x 2 NV) of the inverse dynamics, ∂/∂q in the tangent space",
            build["ID_derivatives"],
            "q, u, ud",
        ),
    ]
    if forward_dynamics(eom) and eom.load_names:
        found.append(
            (
                "FD_jacobian",
                "_forward_dynamics_jacobian",
                "[∂/∂q | ∂/∂u] (NV x 2 NV) of τ_ID − τ_loads, ∂/∂q in the tangent space",
                build["FD_jacobian"],
                "q, u, ud",
            )
        )
    return found


def forward_dynamics(eom) -> bool:
    """Whether the forward dynamics (and its derivatives) are there: M, b and g derived."""
    return {"M", "b", "g"} <= set(eom.compact)


def module_api(eom, nle: str) -> list[str]:
    """The texts of inverse_dynamics_derivatives and (with M, b, g) forward_dynamics_derivatives, with the
    runtime; `nle`: the module's text for b + g."""
    if not available(eom):
        return []
    if not forward_dynamics(eom):
        return [MODULE_API]
    jacobian = "_forward_dynamics_jacobian" if eom.load_names else "_inverse_dynamics_jacobian"
    return [MODULE_API, RUNTIME, MODULE_FORWARD.format(nle=nle, jacobian=jacobian)]


class DerivativeFunctions:
    """Mixed into `NumericEoM`: one state or N states along axis 0."""

    def inverse_dynamics(self, q, u, ud, params=None) -> np.ndarray:
        """τ = M u̇ + b + g in one recursive Newton-Euler pass (Pinocchio's `rnea`), (nv,) per state."""
        self._function("ID", lambda: inverse_dynamics(self.eom))
        return self.call("ID", q, u, ud, params)[..., 0]

    def _dynamics_jacobian(self, key: str, q, u, ud, params) -> np.ndarray:
        self._function(key, jacobians(self.eom)[key])
        return self.call(key, q, u, ud, params)

    def inverse_dynamics_derivatives(self, q, u, ud, params=None) -> tuple[np.ndarray, np.ndarray]:
        """(∂τ/∂q, ∂τ/∂u), each nv × nv per state, of `inverse_dynamics` (Pinocchio's
        `computeRNEADerivatives`; ∂τ/∂u̇ = M); ∂/∂q in the tangent space."""
        D = self._dynamics_jacobian("ID_derivatives", q, u, ud, params)
        return D[..., : self.nv], D[..., self.nv :]

    def forward_dynamics_derivatives(self, q, u, tau=None, params=None) -> tuple[np.ndarray, ...]:
        """(∂u̇/∂q, ∂u̇/∂u, ∂u̇/∂τ), each nv × nv per state, of u̇ = M⁻¹ (τ + τ_loads − b − g) (Pinocchio's
        `computeABADerivatives`): tau one effort per speed (Sᵀ τ_a for `forward_dynamics`' τ_a), or None;
        ∂/∂q in the tangent space; M⁻¹ from one Cholesky factorisation."""
        self._forward_checks(q, params)
        h = self._h(q, u, None, params) + efforts(tau, self.nv, np.shape(q)[:-1])
        key = forward_key(self.eom)
        return forward_derivatives(
            self.M(q, params), h, lambda ud: self._dynamics_jacobian(key, q, u, ud, params), self.nv
        )

    def _forward_checks(self, q, params) -> None:
        """Refuse equations without M, b, g and systems with constraints (their u̇ is the constrained
        dynamics'); warn near an Euler-angle singularity (one state)."""
        rows = self.eom.system.constraint_rows()
        if rows:
            raise ModelError(f"forward_dynamics_derivatives: the system has constraint rows {rows[:6]}, "
                             "whose forces these derivatives of M⁻¹ (τ − b − g) leave out; linearize the "
                             "constrained dynamics with eg.linearize(eom, op_point, independent=[...])")
        if not forward_dynamics(self.eom):
            raise ModelError(
                f"forward_dynamics_derivatives needs M, b and g; derived: {list(self.eom.quantities)} "
                "(derive with quantities=None)"
            )
        if self._euler and np.ndim(q) == 1:
            self.euler_singularity(q, params=params)

    @functools.cached_property
    def _euler(self) -> bool:
        """Whether a joint has ZYX Euler angles (`euler_singularity`)."""
        return any(b.joint.pitch_index is not None for b in self.eom.system.bodies)


class KaneRefusals:
    """Mixed into `NumericKane`: Kane's equations are in the independent speeds, the inverse dynamics and the
    derivatives are those of `eg.derive`'s equations."""

    def _refuse(self, *args, **kwargs):
        raise ModelError(
            "inverse_dynamics, inverse_dynamics_derivatives and forward_dynamics_derivatives are "
            "generated for EquationsOfMotion (eg.derive(system)), not for Kane's equations"
        )

    inverse_dynamics = inverse_dynamics_derivatives = forward_dynamics_derivatives = _refuse
