"""The catalogue of `KaneEquations`: the symbolic pieces of `KaneEquations.compact` (module formulas of
`eomgen.numeric.kane`) as functions of (q, u, w), w in the place of u̇ (none when w is u itself), with the
energies [T, U] and τ_nc of the equations in the joint speeds."""
from __future__ import annotations

import sympy as sp

from ..methods.kane import KaneEquations
from .catalogue import Catalogue, Function
from .expressions import nonconservative
from .parameters import sorted_parameters

WHAT = {"M": "M(q), the mass matrix in the joint speeds", "h": "[τ − b − g | τ − g] in the joint speeds",
        "Y": "[Y | K | k0] of the kinematic equations Y u + K w + k0 = 0",
        "C": "[C | c0] of the constraints C w + c0 = 0", "rates": "[ẏ; ċ] at u̇ = ẇ = 0",
        "qdot": "q̇(q, u)", "holonomic": "[f | ∂f/∂q_dep] of the holonomic constraints",
        "energy": "[T; U]", "tau_nc": "τ of the loads but springs and bending",
        "tilt": "‖e × n‖ of every rolling disk"}


def kane_catalogue(kane: KaneEquations) -> Catalogue:
    """The pieces the numeric Kane's equations need, in the order they are printed."""
    system = kane.system
    exprs = {**kane.compact, "energy": sp.Matrix([kane.eom.compact["T"], kane.eom.compact["U"]]),
             "tau_nc": nonconservative(kane.eom)}
    keys = [k for k in ("M", "h", "Y", "C", "rates", "qdot", "holonomic", "energy", "tau_nc", "tilt")
            if (k != "C" or kane.dependent) and (k != "qdot" or not kane.joint_speeds_are_rates)
            and (k != "holonomic" or kane.dependent_coordinates) and (k != "tilt" or system.rolling)]
    functions = [Function(k, k, WHAT[k], "q, u, ud", exprs[k].shape, lambda k=k: exprs[k],
                          symmetric=k == "M") for k in keys]
    w = [] if kane.speeds_are_qdot else list(kane.speeds)
    inputs = {"q": list(system.q), "u": list(system.u), "ud": w, "p": sorted_parameters(kane.parameters)}
    return Catalogue(kane.subexpressions, inputs, functions, [], {}, keys)
