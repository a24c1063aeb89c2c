"""The base parameters of every fixed-base robot of example-robot-data and the DH robots: their number
(the rank of the stacked regressor, QR with pivoting at the relative tolerance 1e-9), the SVD's rank
beside it, and how many the structural grouping gives in the model's symbols, without and with armature
and friction (viscous, Coulomb, offset); the regressor's operations. (Its time per call beside
Pinocchio's: kernels.py --kernels Y.)
Prints a table and writes JSON.

Run: python benchmarks/base_parameters.py [names ...] [--out ...]"""
from __future__ import annotations

import argparse
import sys
import time
import warnings
from pathlib import Path

import numpy as np

import eomgen as eg
from eomgen.identification import numeric_regressor
from eomgen.model.robots import ROBOTS, names as robot_names

sys.path.insert(0, str(Path(__file__).parent))
import results_io  # noqa: E402

OPTIONS = {"inertial": {"friction": (), "armature": False}, "with armature and friction": {}}


def svd_rank(W: np.ndarray) -> int:
    """The rank by singular values of the column-normalised stack (columns below 1e-9 dropped)."""
    norms = np.linalg.norm(W, axis=0)
    W = W[:, norms > 1e-9 * norms.max()] / norms[norms > 1e-9 * norms.max()]
    s = np.linalg.svd(W, compute_uv=False)
    return int(np.sum(s > 1e-9 * s[0]))


def row(name: str) -> dict:
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        system = eg.robots.load(name)
    out = {"robot": name, "nv": system.nv}
    for label, options in OPTIONS.items():
        t = time.perf_counter()
        Y = numeric_regressor(eg.regressor(system, **options))
        states = max(60, 4 * len(Y.names) // system.nv)
        base = eg.base_parameters(Y, states=states)
        out["ops"] = Y.functions.ops["Y"]  # the full regressor's operations (NumPy printer)
        out[label] = {"p": len(Y.names), "rank": base.rank, "seconds": time.perf_counter() - t,
                      "svd": svd_rank(Y(*Y.states(states, seed=9)).reshape(-1, len(Y.names))),
                      "grouped": None if base.grouping is None else len(base.grouping.names),
                      "note": base.note}
    return out


def main() -> None:
    fixed = [n for n in robot_names() if n in ROBOTS and not ROBOTS[n][2]] + ["puma560", "stanford"]
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("names", nargs="*", default=fixed)
    ap.add_argument("--out", default=results_io.default_path("base_parameters"))
    args = ap.parse_args()
    eg.quiet()
    print(f"{'robot':26s} {'nv':>3s} {'ops':>6s} | {'p':>4s} {'rank':>4s} {'SVD':>4s} {'grouped':>7s} | "
          f"{'p':>4s} {'rank':>4s} {'SVD':>4s} {'grouped':>7s}   (inertial | with armature and friction)")
    rows = []
    for name in args.names:
        r = row(name)
        rows.append(r)
        cells = " | ".join(f"{c['p']:4d} {c['rank']:4d} {c['svd']:4d} {str(c['grouped']):>7s}"
                           for c in (r[label] for label in OPTIONS))
        print(f"{name:26s} {r['nv']:3d} {r['ops']:6d} | {cells}", flush=True)
    results_io.write(args.out, "base_parameters", rows)


if __name__ == "__main__":
    main()
