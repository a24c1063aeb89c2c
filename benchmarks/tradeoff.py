"""The speed-accuracy trade of ur5, talos and a flexible arm (eg.tradeoff): per variant, derivation time,
operations, evaluation time per state (batched NumPy, and C when a C compiler is found), max error of
M, b, g, u̇ and RMS error of u̇ against the full float64 model. Prints the tables, writes JSON and a
Pareto plot per robot.

The closed-form levels (nothing shared, CSE, trigsimp) need the closed forms of M, b, g: for
ur5 b alone has ~1.3e5 operations closed; talos's closed forms are too large to form, so talos gets
the other variants only. The flexible arm (a flexible link of 2 elements carrying a rigid link) gets the
rows "no stiffening" and "k modes of each field" for k = 1, 2, 4 (4 = all: the full model in modal
coordinates).

Run: python benchmarks/tradeoff.py [--trig-max-ops 300] [--states 200] [--out ...]"""
from __future__ import annotations

import argparse
import sys
import warnings
from dataclasses import asdict
from pathlib import Path

import eomgen as eg
from eomgen.printers.build.extension import compiler, python_headers
from eomgen.tradeoff import HEADER, pareto_plot

sys.path.insert(0, str(Path(__file__).parent))
import results_io  # noqa: E402

LEVELS = {"ur5": ("closed", "cse", "trig"), "talos": (), "flexible_arm": ()}


def flexible_arm() -> eg.System:
    arm = eg.System(gravity=(0, -9.81, 0))
    link = arm.add_body("link", joint=eg.FlexibleLink("q1", length=1.0, mass_per_length=2.0, EI=20.0,
                                                       elements=2), mass=0)
    arm.add_body("hand", parent=link, joint=eg.Revolute("q2"), mass=0.5, com=(0.2, 0, 0),
                 inertia=[[0.001, 0, 0], [0, 0.002, 0], [0, 0, 0.003]])
    return arm


def c_available() -> bool:
    try:
        compiler(), python_headers()
    except eg.ModelError:
        return False
    return True


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("names", nargs="*", default=list(LEVELS))
    ap.add_argument("--states", type=int, default=200)
    ap.add_argument("--trig-max-ops", type=int, default=300)
    ap.add_argument("--out", default=results_io.default_path("tradeoff"))
    args = ap.parse_args()
    rows, c = [], c_available()
    Path(args.out).parent.mkdir(parents=True, exist_ok=True)  # the plots go beside the JSON
    for name in args.names:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            system = flexible_arm() if name == "flexible_arm" else eg.robots.load(name)
        variants = eg.tradeoff(system, states=args.states, levels=LEVELS.get(name, ("closed", "cse", "trig")),
                               trig_max_ops=args.trig_max_ops, c=c, modes=(1, 2, 4))
        print(f"\n{name}\n{HEADER}")
        for v in variants:
            print(v.row(), flush=True)
            rows.append({"robot": name, **asdict(v)})
        pareto_plot(variants, Path(args.out).with_name(f"pareto_{name}.png"), name)
    results_io.write(args.out, "tradeoff", rows, states=args.states, trig_max_ops=args.trig_max_ops, c=c)


if __name__ == "__main__":
    main()
