"""Simplification levels of the same equations, to measure what each buys (see `tradeoff`):

    "closed"  the closed forms of M, b, g with nothing shared (every intermediate inlined)
    "cse"     the closed forms through common-subexpression elimination (symengine's where installed, `cse`)
    "trig"    each closed-form entry of at most `max_ops` operations through sympy's trigsimp, then CSE

eomgen's derivations already write named, shared intermediates (the default level, no call needed);
`simplify` is never applied there: it is asked for here."""
from __future__ import annotations

import sympy as sp

from .cse import cse
from .eom import EquationsOfMotion
from .errors import ModelError
from .kinematics import Kinematics
from .progress import progress

LEVELS = ("closed", "cse", "trig")


def simplified(eom: EquationsOfMotion, level: str, max_ops: int = 3000) -> EquationsOfMotion:
    """M, b, g of `eom` at simplification `level`, as new equations for code generation;
    extras["trigsimp_entries"] = (entries simplified, entries) for "trig"."""
    if level not in LEVELS:
        raise ModelError(f"unknown simplification level {level!r}; levels are {LEVELS}")
    closed = {k: eom._closed_form(k) for k in eom.quantities}
    extras = {}
    if level == "trig":
        small = {k: [sp.count_ops(e) <= max_ops for e in M] for k, M in closed.items()}
        for k, M in closed.items():
            entries = progress(zip(M, small[k]), f"trigsimp of {k}", total=len(M), unit="entry")
            closed[k] = sp.Matrix(M.shape[0], M.shape[1], [sp.trigsimp(e) if s else e for e, s in entries])
        extras["trigsimp_entries"] = (sum(map(sum, small.values())), sum(map(len, small.values())))
    kin = Kinematics(eom.system)  # a fresh set of intermediates
    if level != "closed":
        keys = list(closed)
        replacements, reduced = cse([e for k in keys for e in closed[k]], sp.numbered_symbols(cls=sp.Dummy))
        names: dict = {}
        for x, e in replacements:
            names[x] = kin.sub.add(e.xreplace(names))
        flat = iter(r.xreplace(names) for r in reduced)
        closed = {k: sp.Matrix(closed[k].shape[0], closed[k].shape[1], [next(flat) for _ in closed[k]]) for k in keys}
    return EquationsOfMotion(kin, f"{eom.method}, {level}", closed, extras)
