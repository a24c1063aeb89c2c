"""The constrained dynamics of numeric functions `f` (one state at a time): every contact, loop and
rolling disk held (the linear algebra in `contacts`),

    F_c = −(J M⁻¹ Jᵀ)⁻¹ (J M⁻¹ h + c),   M u̇ = h + Jᵀ F_c,   N_c = 1 − M⁻¹ Jᵀ (J M⁻¹ Jᵀ)⁻¹ J,

J the rows of J_c some motion can violate at q (`held`), c = J̇ u (with Baumgarte's gains
c = J̇ u + 2 α J u + β² r, r the closure residual on its rows)."""
from __future__ import annotations

import warnings

import numpy as np

from ..errors import ModelError
from ..state import random_states
from .contacts import contact_dynamics, refuse_flat, support_projector as projector
from .forward import h


def rows(f) -> list[str]:
    """The names of J_c's rows; refused when the system changed since the functions were generated, or
    has no constraints."""
    if f.eom.kinematics.version != f.system.version:
        raise ModelError("the system changed after these functions were generated (a body, frame, "
                         "contact, loop or rolling disk was added): derive and generate them again")
    if not f.constraint_rows:
        raise ModelError("the system has no contacts, loops or rolling disks: add them with "
                         "System.add_contact, add_loop or add_rolling")
    return f.constraint_rows


def closure_index(system) -> list[int]:
    """For each row of the closure residual, its row of J_c (d r / dt = J_c u there): a loop's rows are
    its own, a rolling disk's height goes with its normal row n."""
    names = system.constraint_rows()
    return [names.index(r) for r in [*(r for x in system.loops for r in x.row_names),
                                      *(x.row_names[2] for x in system.rolling)]]


def row_sizes(f, params) -> np.ndarray:
    """The size of each row of J_c (with J̇_c u) at three random states (`random_states`: unit
    quaternions), per parameter values; rows of size 0 (the z row of a loop in a plane mechanism;
    round-off below 1e-12 of the largest row or of 1; the normal row of a disk its tree keeps on the
    ground, `grounded`) no motion can violate."""
    key = ("row sizes", tuple(np.ravel(f.parameter_vector(params, "J_c"))))
    if key not in f.cache:
        q, u, _ = random_states(f.system, 3, np.random.default_rng(0))
        sizes = [np.abs(f.contact_jacobian(q[k], params)).max(axis=1)
                 + np.abs(f.contact_jacobian_dot_u(q[k], u[k], params)) for k in range(3)]
        grounded = {d.row_names[2] for d in f.eom.kinematics.grounded_disks()}
        size = np.where([r in grounded for r in f.constraint_rows], 0.0, np.max(sizes, axis=0))
        f.cache[key] = np.where(size > 1e-12 * max(1.0, size.max()), size, 0.0)  # round-off: 0
    return f.cache[key]


def held(f, q, params) -> tuple[np.ndarray, np.ndarray, list[str]]:
    """(mask, J, names) of the rows of J_c some motion can violate at q: they carry the forces; the others
    carry none. A row that vanishes only at q (below 1e-12 of its size, a singular configuration of the
    constraint) is warned of; a rolling disk lying (nearly) flat (`refuse_flat`) and a row that is not
    finite refused."""
    names, size, J = rows(f), row_sizes(f, params), f.contact_jacobian(q, params)
    if f.system.rolling:
        refuse_flat(f.system.rolling, f.call("tilt", q, params=params))
    broken = [n for n, row in zip(names, J) if not np.all(np.isfinite(row))]
    if broken:
        raise ModelError(f"constraint rows {broken} are not finite at this state (a rolling disk whose "
                         "axle is normal to the ground, lying flat, has no contact point)")
    kept = (size > 0) & (np.abs(J).max(axis=1) > 1e-12 * size)
    lost = [n for n, s, k in zip(names, size, kept) if s > 0 and not k]
    if lost:
        warnings.warn(f"constraint rows {lost} cannot be violated by any motion at this state (a singular "
                      "configuration): no force along them", stacklevel=4)
    return kept, J[kept], [n for n, k in zip(names, kept) if k]


def constrained_dynamics(f, q, u, tau_a=None, params=None,
                         baumgarte: tuple[float, float] | None = None) -> tuple[np.ndarray, np.ndarray]:
    """(u̇, F_c) with every contact, loop and rolling disk held (module formulas), F_c stacked like J_c's
    rows (0 on rows no motion can violate). With baumgarte = (α, β), J u̇ + J̇ u = −2 α J u − β² r (r on
    its rows, `closure_index`; 0 on the rows of contacts and no-slip), which drives a drift of r and J u
    back to zero (critically damped at α = β)."""
    active, J, names = held(f, q, params)
    F = np.zeros(len(active))
    if not active.any():
        return f.forward_dynamics(q, u, tau_a, params), F
    bias = f.contact_jacobian_dot_u(q, u, params)
    if baumgarte is not None:
        alpha, beta = baumgarte
        bias[active] += 2 * alpha * (J @ np.asarray(u, float))  # the rows that carry forces
        if f.closure_rows:
            bias[closure_index(f.system)] += beta ** 2 * f.closure_residual(q, params)
    u_dot, F_active = contact_dynamics(f.M(q, params), h(f, q, u, tau_a, params), J, bias[active], names)
    F[active] = F_active
    return u_dot, F


def constraint_forces(f, q, u, tau_a=None, params=None) -> dict[str, np.ndarray]:
    """F_c by constraint name (a contact's frame, a loop's or a rolling disk's name)."""
    F, system, out = constrained_dynamics(f, q, u, tau_a, params)[1], f.system, {}
    for c in (*system.contacts, *system.loops, *system.rolling):
        out[c.name], F = F[:len(c.row_names)], F[len(c.row_names):]
    return out


def support_projector(f, q, params=None) -> np.ndarray:
    """N_c = 1 − M⁻¹ J_cᵀ (J_c M⁻¹ J_cᵀ)⁻¹ J_c of the held rows (J_c N_c = 0, N_c² = N_c)."""
    active, J, names = held(f, q, params)
    return projector(f.M(q, params), J, names) if active.any() else np.eye(f.nv)


def support_consistent_residual(f, q, u, ud, tau_a=None, params=None) -> np.ndarray:
    """N_cᵀ (M u̇ + b + g − Sᵀ τ − τ_loads): zero along any motion the contacts allow."""
    N = support_projector(f, q, params)
    return N.T @ (f.M(q, params) @ np.asarray(ud, float) - h(f, q, u, tau_a, params))
