"""The catalogue of an `EquationsOfMotion`: which functions it offers, in the order targets print them
(the functions themselves: `outputs`)."""
from __future__ import annotations

from ..eom import EquationsOfMotion
from ..errors import ModelError
from . import outputs
from .catalogue import Catalogue, Function
from .parameters import sorted_parameters

# the functions of the equations, and what they compute
QUANTITIES = {"M": "mass matrix M(q)", "b": "Coriolis and centrifugal terms b(q, u)",
              "g": "gravity terms g(q) (left-hand side: M u̇ + b + g = τ + Sᵀ τ_a)", "nle": "b(q, u) + g(q)",
              "tau": "generalized forces τ(q, u) of the loads (right-hand side)",
              "T": "kinetic energy T(q, u)",
              "U": "potential energy U(q) (gravity, springs, bending)"}


def catalogue(eom: EquationsOfMotion) -> Catalogue:
    """The catalogue of `eom`, built once per equations: the quantities, the centre of mass and centroidal
    momentum, the constraint rows, the dynamics' derivatives, q̇, the numeric algorithms' building blocks
    and the families per frame, load and joint (kept in `eom.made`: a dictionary keyed weakly by the
    equations would keep them for ever, as the functions refer to them)."""
    if "catalogue" not in eom.made:
        missing = {k: f"{k} was not derived: derive it (quantities=...) to evaluate it"
                   for k in ("M", "b", "g", "T", "U") if k not in eom.compact}
        functions = [*quantities(eom), *outputs.centroidal(eom, missing), *outputs.constraints(eom, missing),
                     *outputs.dynamics(eom, missing),
                     *outputs.regressor(eom, missing), outputs.qdot(eom), *outputs.blocks(eom)]
        system = eom.system
        inputs = {"q": list(eom.q), "u": list(eom.u), "ud": list(system.ud),
                  "p": sorted_parameters(system.parameters)}
        families = outputs.families(eom, missing)
        eom.made["catalogue"] = Catalogue(eom.subexpressions, inputs, functions, families, missing,
                                          eager(eom))
    return eom.made["catalogue"]


def expect_equations(eom, entry: str, *others: type) -> None:
    """Refuse, naming `entry`, anything but an `EquationsOfMotion` (or one of `others`)."""
    if not isinstance(eom, (EquationsOfMotion, *others)):
        kinds = " or ".join(t.__name__ for t in (EquationsOfMotion, *others))
        raise ModelError(f"{entry}: expected {kinds}, got {type(eom).__name__} (derive the equations "
                         "first: eg.derive(system))")


def quantities(eom: EquationsOfMotion) -> list[Function]:
    """M, b, g, nle, T, U as derived, and tau."""
    n = len(eom.u)
    shapes = {"M": (n, n), "T": (1, 1), "U": (1, 1)}
    forms = {"M": "matrix", "T": "number", "U": "number"}
    return [Function(k, k, what, "q" if k in ("M", "g", "U") else "q, u", shapes.get(k, (n, 1)),
                     (lambda: eom.tau_compact) if k == "tau" else (lambda k=k: eom.compact[k]),
                     forms.get(k, "vector"), symmetric=k == "M")
            for k, what in QUANTITIES.items() if k in eom.compact or k == "tau"]


def eager(eom: EquationsOfMotion) -> list[str]:
    """The functions generated up front: those of M, b, g, b + g and the frames of derive(frames=...)."""
    return [k for k in eom.compact if k in ("M", "b", "g", "nle") or k.split(":")[0] in ("J", "Jdot_u")]
