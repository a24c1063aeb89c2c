"""The state equations ẋ = f(t, x) of the numeric functions, the energy E and the power Ẇ of what is not
in it, so that E(t) − E(t0) = W(t) along a motion::

    x = [q, u]:      q̇ = q̇(q, u) (`System.qdot`),  M u̇ = τ + Sᵀ τ_a − b − g
    x = [q, u, i]:   and L di/dt = U − R i − k N q̇ per DC motor
    E = T + U (+ ½ Σ L i²),   Ẇ = uᵀ (Sᵀ τ_a + τ_nc) (+ Σ i (U − R i − k N q̇))

With contacts, loops and rolling disks u̇ is that of `constrained_dynamics` (their forces do no work).
τ_nc are the loads' generalized forces but the springs' and the bending's (`conservative`), whose energy
is in U; a motor's torque N k i − N² f q̇ is in τ_nc, so that with the circuit Ẇ is the sources' power
U i less the losses R i² + f (N q̇)². τ_a (`tau`): None, values (one per actuated joint) or a function
(t, q, u) → values."""

from __future__ import annotations

from collections.abc import Mapping

import numpy as np
from ..errors import ModelError
from ..symbols import t as time
from .parameters import actuated


def efforts(tau, t, q, u):
    """τ_a at (t, q, u): None, the values given, or tau(t, q, u) for a function."""
    if isinstance(tau, Mapping):
        raise ModelError(
            "tau: expected the actuator efforts (values, or a function (t, q, u)), got a "
            "mapping; parameters go by name in params="
        )
    return tau(t, q, u) if callable(tau) else tau


def work_rate(u, tau, xp=np) -> np.ndarray:
    """uᵀ τ, per state (arrays of module `xp`)."""
    return xp.einsum("...i,...i->...", u, tau)


def split(x, sizes: list[int], names: str, batch: bool, xp=np, dtype=float) -> list[np.ndarray]:
    """x = [q, u, ...] cut into parts of `sizes` (x of shape (n,), or (N, n) if `batch`; arrays of module
    `xp`)."""
    x, n = xp.asarray(x, dtype=dtype), sum(sizes)
    if x.shape[-1:] != (n,) or x.ndim > 1 + batch:
        raise ModelError(
            f"x: expected [{names}] of shape ({n},){f' or (N, {n})' if batch else ''}, got shape "
            f"{x.shape}{'' if batch else ' (one state per call)'}"
        )
    return xp.split(x, np.cumsum(sizes)[:-1].tolist(), axis=-1)


def size(f) -> int:
    """The size of the state x: nq + nv, and one current per DC motor."""
    return f.nq + f.nv + len(f.system.motors)


def state(f, x, params=None, t=None) -> tuple[np.ndarray, np.ndarray, np.ndarray, Mapping | None]:
    """(q, u, i, params) of x = [q, u, i] (i empty without motors), the currents (and, given `t`, the time
    of a prescribed motion) added to params; N states along axis 0 for a system without contacts, loops,
    rolling disks and motors."""
    system = f.system
    batch = not (system.motors or system.constraint_rows())
    q, u, i = split(x, [f.nq, f.nv, len(system.motors)], "q, u, i" if system.motors else "q, u", batch)
    given = {m.current: c for m, c in zip(system.motors, i)}
    if system.prescribed and t is not None:
        given[time] = t
    if given:
        params = f.parameters.with_state(params, given)
    return q, u, i, params


def rhs(f, t, x, tau=None, params=None, baumgarte: tuple[float, float] | None = None) -> np.ndarray:
    """ẋ = [q̇(q, u), u̇ (, di/dt)] (module formulas): u̇ of `forward_dynamics`, or of `constrained_dynamics`
    (with its `baumgarte` gains) for a system with contacts, loops or rolling disks; τ_a = `tau` (None,
    values, or a function (t, q, u)). The motor currents are taken from x (params, or a bind, leaves them
    out); voltages may depend on q and u."""
    q, u, i, params = state(f, x, params, t)
    tau_a = efforts(tau, t, q, u)
    if f.system.constraint_rows():
        ud = f.constrained_dynamics(q, u, tau_a, params, baumgarte)[0]
    elif baumgarte is not None:
        raise ModelError("baumgarte: the system has no contacts, loops or rolling disks to hold")
    else:
        ud = f.forward_dynamics(q, u, tau_a, params)
    rates = [f.qdot(q, u, params), ud]
    if i.size:
        circuit = f.call("motor", q, u, params=params)
        rates.append((circuit[:, 0] - circuit[:, 1] * i) / circuit[:, 2])
    return np.concatenate(rates, axis=-1)


def power(f, t, x, tau=None, params=None) -> np.ndarray:
    """Ẇ = uᵀ (Sᵀ τ_a + τ_nc) (+ Σ i (U − R i − k N q̇) with motors): the power of the actuators, of the
    loads but springs and bending (and of the motors' sources less their resistance)."""
    q, u, i, params = state(f, x, params, t)
    P = work_rate(u, actuated(f.call("tau_nc", q, u, params=params)[..., 0], efforts(tau, t, q, u), f.S))
    if i.size:
        circuit = f.call("motor", q, u, params=params)
        P = P + i @ (circuit[:, 0] - circuit[:, 1] * i)
    return P


def energy(f, x, params=None) -> np.ndarray:
    """E = T + U (+ ½ Σ L i² with motors), per state (N states along axis 0)."""
    motors = len(f.system.motors)
    q, u, i = split(x, [f.nq, f.nv, motors], "q, u, i" if motors else "q, u", batch=True)
    E = f.T(q, u, params) + f.U(q, params)
    return E + (f.call("motor", q, u, params=params)[..., 2] * i**2).sum(-1) / 2 if motors else E
