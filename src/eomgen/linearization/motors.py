"""The DC motors' circuits in a linearization: L di/dt = U − R i − k N q̇ (`System.add_motor`), written
di/dt = a − b i with a = (U − k N q̇)/L and b = R/L, a piece of q, u and the parameters (the voltage U
may be a parameter, an input, or depend on q and u)."""

from __future__ import annotations

import sympy as sp

from ..model.system import System
from .dual import Dual
from .pieces import Pieces, Point


def motor_pieces(system: System) -> dict:
    """{"motor": ([a, b] per motor, in u)}, or nothing without motors."""
    if not system.motors:
        return {}
    circuits = [m.circuit(system.u) for m in system.motors]
    return {"motor": (sp.Matrix([[drive / L, R / L] for drive, R, L in circuits]), {"u"})}


def current_rates(pieces: Pieces, point: Point, u: Dual, currents: Dual) -> Dual:
    """di/dt = a − b i (entrywise)."""
    c = pieces.dual("motor", point, u)
    return c[:, 0:1] - c[:, 1:2] * currents
