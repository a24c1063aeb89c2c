"""Expressions of catalogue functions beyond the equations' own (`EquationsOfMotion.compact`), all in the
equations' intermediates."""
from __future__ import annotations

import sympy as sp

from ..eom import EquationsOfMotion
from ..model.loads import Actuator, Damper, Point, Spring


def placement(kin, frame: str) -> sp.Matrix:
    """[R | p] (3 × 4) of a frame or body in the world."""
    return sp.Matrix.hstack(*kin.frame_placement(frame))


def conservative(eom: EquationsOfMotion) -> list[str]:
    """The loads whose generalized force is −∂U/∂q: the springs, and the bending ("elastic")."""
    springs = {load.name for load in eom.system.loads if isinstance(load, Spring)}
    return [name for name in eom.load_names if name in springs or name == "elastic"]


def nonconservative(eom: EquationsOfMotion) -> sp.Matrix:
    """τ_nc: the sum of the generalized forces of the loads that are not `conservative`."""
    kept = [eom.compact[f"tau:{name}"] for name in eom.load_names if name not in conservative(eom)]
    return sum(kept, sp.zeros(len(eom.u), 1))


def forward_parts(eom: EquationsOfMotion) -> sp.Matrix:
    """[M | τ_loads − b − g] (n × (n + 1)), M's lower triangle only (what the C factorisation reads)."""
    n = len(eom.u)
    M = eom.compact["M"]
    h = eom.tau_compact - eom.nle_compact
    return sp.Matrix(n, n, lambda i, j: M[i, j] if j <= i else 0).row_join(h)


def line_loads(system) -> list:
    """The loads whose force needs the direction d/‖d‖: dampers, actuators with a force along the line,
    springs with a rest length (a zero-length spring's −k d needs none)."""
    return [x for x in system.loads
            if isinstance(x, Damper) or isinstance(x, Actuator) and x.force is not None
            or isinstance(x, Spring) and not x.rest_length.is_zero]


def lengths(eom: EquationsOfMotion) -> sp.Matrix:
    """‖r_a − r_b‖ of each of the `line_loads`."""
    kin = eom.kinematics
    return sp.Matrix([sp.sqrt(sum(x ** 2 for x in kin.position(x.a) - kin.position(x.b)))
                      for x in line_loads(eom.system)])


def centres(eom: EquationsOfMotion) -> sp.Matrix:
    """The centres of mass of the bodies (3 × bodies, world)."""
    kin = eom.kinematics
    return sp.Matrix.hstack(*(kin.position(Point(b, b.com)) for b in eom.system.bodies))


def closure_frames(eom: EquationsOfMotion) -> sp.Matrix:
    """The origins of the loops' frames and the rolling disks' centres (3 × points, world)."""
    kin, system = eom.kinematics, eom.system
    names = [n for x in system.loops for n in (x.frame_a, x.frame_b)] + [x.body.name for x in system.rolling]
    return sp.Matrix.hstack(*(kin.frame_placement(n)[1] for n in names))
