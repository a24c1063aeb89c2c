"""Loads along the line between two points at a state where their ends meet.

A damper, a line actuator (a force along the line) and a spring with a rest length act along
n = d/|d|, d = r_a − r_b, which is 0/0 where the ends coincide. There the damper's force −c (n·v) n
(v the ends' relative velocity) has a limit along the motion through that state (−c v: the ends move
apart along v), but none as a function of the state, which is what the generated functions are: the
states d = ε e nearby give −c (e·v) e, a different force for every direction e, however small ε. A
line actuator's f n and a spring's −k (|d| − l0) n have no limit at all. So no value would be right:
where an output of the generated code is not finite, the lengths |d| of these loads are evaluated, and a
load whose ends meet is named with the state in a ModelError (the NaN of 0/0, and NumPy's warning about
it, never reach the caller). Checking finiteness costs one pass over the output, only for systems with
such loads."""
from __future__ import annotations

import numpy as np

from ..errors import ModelError


def check_ends(f, result: np.ndarray, q, params) -> np.ndarray:
    """`result` when finite; else a ModelError naming a line load whose ends meet at q (the first such
    state of a batch), if one does (other causes are reported where they are known)."""
    if not f.line_loads or np.isfinite(result).all():
        return result
    d = np.atleast_2d(f.call("line_lengths", q, params=params)[..., 0])
    met = np.argwhere(d == 0)
    if met.size:
        k, i = met[0]
        load, state = f.line_loads[i], np.atleast_2d(np.asarray(q, dtype=float))[k]
        kind, batch = type(load).__name__.lower(), f" (state {k} of the batch)" if np.ndim(q) == 2 else ""
        raise ModelError(f"{kind} '{load.name}': its ends meet at q = {state.tolist()}{batch} "
                         "(|r_a − r_b| = 0 in float64), where the line it acts along is undefined (0/0; see "
                         "eomgen.numeric.lines)")
    return result
