"""Model only what a scene requires: derivation + code generation time, operations and evaluation
time (one state from Python, NumPy and C) of the full equations beside what a scene asks for:
gravity compensation (g alone), a contact scene (the contact frames' J and J̇ u alone), M alone, and
a model with locked joints (System.reduced, the arms of talos welded).

Run: python benchmarks/scene.py [names ...] [--out ...]"""
from __future__ import annotations

import argparse
import sys
import time
import timeit
import warnings
from pathlib import Path

import numpy as np

import eomgen as eg

sys.path.insert(0, str(Path(__file__).parent))
import results_io  # noqa: E402

FEET = {"talos": ["left_sole_link", "right_sole_link"], "solo12": ["FL_FOOT", "FR_FOOT", "HL_FOOT", "HR_FOOT"],
        "ur5": ["tool0"]}


def scenes(system, name):
    yield "full: M, b, g", system, {}
    yield "gravity compensation: g", system, {"quantities": ("g",)}
    yield "mass matrix: M", system, {"quantities": ("M",)}
    yield f"contact frames only ({len(FEET[name])})", system, {"quantities": (), "frames": FEET[name]}
    arms = [j.name for j in system.joints if "arm" in j.name or "gripper" in j.name]
    if arms:
        yield f"{len(arms)} arm joints locked: M, b, g", system.reduced({j: 0.0 for j in arms}), {}


def call_time(f, system) -> float:
    q, u, _ = eg.random_states(system, 1, np.random.default_rng(0))
    """µs for one state through every generated function."""
    keys = list(f.functions)
    return min(timeit.repeat(lambda: [f.call(k, q[0], u[0]) for k in keys], number=200, repeat=5)) / 200 * 1e6


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("names", nargs="*", default=["talos", "solo12"])
    ap.add_argument("--out", default=results_io.default_path("scene"))
    args = ap.parse_args()
    print(f"{'robot':8s} {'scene':36s} {'derive s':>9s} {'gen s':>6s} {'ops':>7s} {'NumPy µs':>9s} {'C µs':>7s}")
    rows = []
    for name in args.names:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            system = eg.robots.load(name)
        for scene, s, options in scenes(system, name):
            t0 = time.perf_counter()
            eom = eg.derive(s, method="recursive", **options)
            t1 = time.perf_counter()
            f = eg.codegen(eom)
            t2 = time.perf_counter()
            fc = eg.codegen(eom, backend="c")
            row = {"robot": name, "scene": scene, "derive_s": t1 - t0, "codegen_s": t2 - t1, "nq": s.nq,
                   "ops": sum(f.ops.values()), "functions": sorted(f.functions),
                   "numpy_us": call_time(f, s), "c_us": call_time(fc, s)}
            rows.append(row)
            print(f"{name:8s} {scene:36s} {row['derive_s']:9.2f} {row['codegen_s']:6.2f} {row['ops']:7d} "
                  f"{row['numpy_us']:9.1f} {row['c_us']:7.2f}", flush=True)
    results_io.write(args.out, "scene", rows)


if __name__ == "__main__":
    main()
