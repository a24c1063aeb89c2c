"""The derivations. Each is independent of the others; their agreement is a test."""
from __future__ import annotations

import sympy as sp

from ..engine import collection_paused
from ..eom import EquationsOfMotion
from ..errors import ModelError
from ..kinematics import Kinematics
from ..model import FlexibleLink
from ..model.system import System
from ..symbols import t
from . import free_cut, lagrange, projected_newton_euler, recursive
from .flexible import flexible_mass

QUANTITIES = ("M", "b", "g")
METHODS = {
    "free_cut": free_cut.derive,
    "projected_newton_euler": projected_newton_euler.derive,
    "lagrange": lagrange.derive,
    "recursive": recursive.derive,
}


def derive(system: System, method: str | None = None, quantities=None,
           frames=None, engine: str | None = None) -> EquationsOfMotion:
    """Equations of motion M u̇ + b + g = τ + Sᵀ τ_a of `system` by `method`: "recursive" (the
    body-frame composite-rigid-body and recursive Newton-Euler algorithms, which give the cheapest
    code), or the lecture's "projected_newton_euler", "lagrange", "free_cut". The default (None) is the
    method with the cheapest code that applies: "recursive", or "lagrange" with flexible links or a
    joint of prescribed motion (`Revolute(..., motion=θ(eg.t))`: the time t is then a parameter "t").

    Model only what a scene requires: `quantities`, a subset of ("M", "b", "g") (default all), derives
    only those, e.g. ("g",) for gravity compensation (() for none); `frames`, frame or body names whose
    Jacobian J and J̇ u are derived with the equations (and generated with them), e.g. the contact
    frames of a scene. The other frames' Jacobians are still derived when first asked for.

    `engine` does the arithmetic of the kinematics and the recursions: "symengine" (the default where it
    is installed, several times faster) or "sympy" (the reference); the equations are sympy either way,
    and the generated code is printed from sympy's canonical form."""
    if not isinstance(system, System):
        raise TypeError(f"derive expects an eomgen.System, got {type(system).__name__}")
    flexible = any(isinstance(j, FlexibleLink) for j in system.joints)
    moving = [j.name for j in system.prescribed]
    if method is None:
        method = "lagrange" if flexible or moving else "recursive"
    if method not in METHODS:
        raise ModelError(f"unknown method {method!r}; choose one of {sorted(METHODS)}")
    if not system.bodies:
        raise ModelError("the system has no bodies")
    if system.nq == 0:
        raise ModelError("the system has no moving joint (every body is fixed)")
    if method != "lagrange" and flexible:
        raise ModelError(f"method {method!r} does not handle flexible links; use 'lagrange'")
    if method != "lagrange" and moving:
        raise ModelError(f"method {method!r} does not handle the prescribed motion of joint '{moving[0]}' "
                         "(its rate is no column of the Jacobians): use 'lagrange', which differentiates in time")
    timed = [where for where, values in system.fields() if not where.endswith(": motion")
             and any(t in sp.sympify(v).free_symbols for v in values)] if moving else []
    if timed:
        raise ModelError(f"{timed[0]} depends on the time eg.t, which only a joint's motion may (Lagrange's "
                         "d/dt has no ∂/∂t of other values); with prescribed motion a parameter named 't' is "
                         "the time")
    if moving and system.constraint_rows():
        raise ModelError(f"joint '{moving[0]}': prescribed motion in a system with contacts, loops or "
                         "rolling disks is not supported (their rows J_c u = 0 would miss the motion's own rate)")
    total = sum((b.mass for b in system.bodies), 0) + flexible_mass(system)
    if total == 0:
        raise ModelError("the total mass of the system is zero: M would be singular")
    quantities = QUANTITIES if quantities is None else (quantities,) if isinstance(quantities, str) else tuple(quantities)
    wrong = sorted(set(quantities) - set(QUANTITIES))
    if wrong:
        raise ModelError(f"quantities: a subset of {QUANTITIES}; unknown {wrong}")
    frames = [frames] if isinstance(frames, str) else list(frames or [])
    with collection_paused():
        kin = Kinematics(system, engine)
        for frame in frames:
            kin.jacobian(frame)  # an unknown name is an error here, before any derivation
        eom = METHODS[method](kin, tuple(k for k in QUANTITIES if k in quantities))
        for frame in frames:
            eom.compact[f"J:{frame}"] = kin.jacobian(frame)
            if not moving:  # J̇ u is the bias of J u, which a prescribed motion's own rate is not part of
                eom.compact[f"Jdot_u:{frame}"] = kin.jacobian_dot_u(frame)
    return eom
