"""Parameters per call: a 3-link arm with symbolic masses, lengths and g beside the same arm built with
numbers, time of one call of M (one state, from Python) through NumPy and C: parameters given as a
mapping {name: value} in each call, bound once (`f.bind(params)`), and none (the numeric arm).

Run: python benchmarks/params.py [--out benchmarks/results/params.json]"""
from __future__ import annotations

import argparse
import sys
import timeit
from pathlib import Path

import numpy as np
import sympy as sp

import eomgen as eg

sys.path.insert(0, str(Path(__file__).parent))
import results_io  # noqa: E402

VALUES = {"m1": 2.0, "m2": 1.5, "m3": 0.8, "l1": 0.5, "l2": 0.4, "l3": 0.3, "g": 9.81}


def arm(symbolic: bool) -> eg.System:
    """A spatial 3-link arm (joints about z, y, y), rods of mass m_i and length l_i."""
    v = {n: sp.Symbol(n, positive=True) if symbolic else x for n, x in VALUES.items()}
    system = eg.System(gravity=(0, 0, -v["g"]))
    parent, offset = None, 0
    for i, axis in enumerate([(0, 0, 1), (0, 1, 0), (0, 1, 0)], start=1):
        m, l = v[f"m{i}"], v[f"l{i}"]
        inertia = sp.diag(m * l**2 / 12, m * l**2 / 12, m * l**2 / 100)
        parent = system.add_body(f"link{i}", parent=parent, joint=eg.Revolute(f"q{i}", axis=axis), mass=m,
                                 com=(0, 0, l / 2), inertia=inertia,
                                 placement=eg.Placement(translation=(0, 0, offset)))
        offset = l
    return system


def per_call(fn, number: int = 20000) -> float:
    """Best of 5 of the mean time of one call, µs."""
    return min(timeit.repeat(fn, number=number, repeat=5)) / number * 1e6


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--out", default=results_io.default_path("params"))
    args = parser.parse_args()
    q = np.random.default_rng(0).uniform(-2, 2, 3)
    rows = []
    for backend in ("numpy", "c"):
        numeric = eg.codegen(eg.derive(arm(False), method="recursive"), backend=backend)
        symbolic = eg.codegen(eg.derive(arm(True), method="recursive"), backend=backend)
        bound = symbolic.bind(VALUES)
        assert np.allclose(bound.M(q), numeric.M(q), rtol=1e-13)
        assert np.allclose(symbolic.M(q, VALUES), numeric.M(q), rtol=1e-13)
        base = per_call(lambda: numeric.M(q))
        for case, fn in [("numbers in the model", None), ("symbolic, bound", lambda: bound.M(q)),
                         ("symbolic, mapping per call", lambda: symbolic.M(q, VALUES))]:
            us = base if case.startswith("numbers") else per_call(fn)
            rows.append({"backend": backend, "case": case, "us_per_call": us, "ratio": us / base})
    print(f"{'backend':8s} {'M(q), one state':30s} {'µs/call':>9s} {'× numbers':>10s}")
    for r in rows:
        print(f"{r['backend']:8s} {r['case']:30s} {r['us_per_call']:9.2f} {r['ratio']:10.2f}")
    results_io.write(args.out, "params", rows, model="3-link arm, 7 parameters", method="recursive")


if __name__ == "__main__":
    main()
