"""Rolling disks that their tree already keeps on the ground.

The textbook disk (rails x, y, yaw, the lean about the contact line, the centre ρ above it, the spin)
has the height residual r(q) = n · p − ρ s − h = ρ cos(lean) − ρ |cos(lean)| = 0 wherever its centre is
above the ground: the tree holds the contact, no coordinate depends on it, and its normal row J_n u = ṙ
is zero as well. Such a disk is `grounded`: its height and its normal row are dropped, its two no-slip
rows kept. r holds √(·) of trigonometric terms, which expand or cancel cannot reduce (only simplify
could), so zero is decided numerically: at SAMPLES random states (q uniform in [−π, π], parameters in
[0.5, 1.5]) with the centre above the ground (n · p − h > 0), |r| ≤ RTOL (ρ + |n · p − h|) at every one."""
from __future__ import annotations

import sympy as sp

from .linalg import dot
from .model.constraints import Rolling
from .subexpressions import samples

SAMPLES = 5  # states with the centre above the ground
CANDIDATES = 60  # random states drawn to find them
RTOL = 1e-10  # |r| relative to the disk's size and height (the states are evaluated to 15 digits)


def grounded(kin, heights: dict[Rolling, sp.Expr]) -> list[Rolling]:
    """The disks among `heights` (disk → its height residual r, in the intermediates of `kin.sub`)
    whose r is zero at SAMPLES random states with the centre above the ground (module rule)."""
    system = kin.system
    states = samples(system.q, system.parameters, CANDIDATES)
    return [disk for disk, r in heights.items() if _zero_above_ground(kin, disk, r, states)]


def _zero_above_ground(kin, disk: Rolling, r: sp.Expr, states: list[dict]) -> bool:
    n = disk.ground.rotation[:, 2]
    height = dot(n, kin.p[disk.body]) - dot(n, disk.ground.translation)
    found = 0
    for state in states:
        above, residual, radius = (x.real for x in kin.sub.evaluate([height, r, disk.radius], state))
        if above > 0:
            if abs(residual) > RTOL * (radius + above):
                return False
            found += 1
            if found == SAMPLES:
                return True
    return False
