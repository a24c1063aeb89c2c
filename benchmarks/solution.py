"""Worked solutions: how long `eg.solution` takes, how small its textbook forms are, and what sympy's
own `trigsimp` does with the same closed forms.

Systems: the cart-pendulum, planar arms of 2, 3 and 4 links (symbolic masses, lengths, centres of
mass and inertias), the rolling disk by Kane, and ur5 (shared form). For the arms the table gives
the solution time (three methods, every step, the comparison), the operations of M, b, g in the
solution's textbook form against the raw closed forms of projected Newton-Euler, and sympy's
`trigsimp` applied entry by entry to those closed forms (in a subprocess, stopped after `--limit` s).

Run: python benchmarks/solution.py [--limit 120] [--out benchmarks/results/solution.json]"""

from __future__ import annotations

import argparse
import multiprocessing as mp
import sys
import time
from pathlib import Path

import sympy as sp

import eomgen as eg

sys.path.insert(0, str(Path(__file__).parent))
sys.path.insert(0, str(Path(__file__).parents[1] / "examples"))
sys.path.insert(0, str(Path(__file__).parents[1] / "tests"))
import nonholonomic  # noqa: E402
import results_io  # noqa: E402
from models import planar_arm  # noqa: E402


def cart_pendulum() -> eg.System:
    m_c, m_p, l, g = sp.symbols("m_c m_p l g", positive=True)
    system = eg.System(gravity=(0, -g, 0))
    cart = system.add_body("cart", joint=eg.Prismatic("x", axis=(1, 0, 0)), mass=m_c)
    system.add_body(
        "pendulum", parent=cart, joint=eg.Revolute("phi", axis=(0, 0, 1)), mass=m_p, com=(0, -l, 0)
    )
    return system


def _ops(matrices) -> int:
    return sum(sp.count_ops(e) for M in matrices for e in M)


def _trigsimp(system_builder, n, queue) -> None:
    eom = eg.derive(system_builder(n), method="projected_newton_euler")
    t0 = time.perf_counter()
    simplified = [sp.Matrix(getattr(eom, k)).applyfunc(sp.trigsimp) for k in ("M", "b", "g")]
    queue.put((time.perf_counter() - t0, _ops(simplified)))


def sympy_trigsimp(n: int, limit: float) -> tuple[float | None, int | None]:
    queue: mp.Queue = mp.Queue()
    process = mp.Process(target=_trigsimp, args=(planar_arm, n, queue))
    process.start()
    process.join(limit)
    if process.is_alive():
        process.terminate()
        return None, None
    return queue.get()


def measure(name: str, make, **options) -> dict:
    t0 = time.perf_counter()
    solution = eg.solution(make(), **options)
    seconds = time.perf_counter() - t0
    t0 = time.perf_counter()
    document = solution.latex()
    row = {
        "system": name,
        "form": solution.form,
        "solution_s": seconds,
        "latex_s": time.perf_counter() - t0,
        "latex_chars": len(document),
        "steps": len(solution.steps),
        "unsimplified": solution.unsimplified,
    }
    if solution.form == "textbook" and "kane" not in solution.methods:
        row["textbook_ops"] = _ops([solution[k] for k in ("M", "b", "g")])
    return row


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--limit", type=float, default=120.0, help="seconds for sympy's trigsimp per system")
    ap.add_argument("--out", default=results_io.default_path("solution"))
    args = ap.parse_args()
    rows = [measure("cart-pendulum", cart_pendulum)]
    for n in (2, 3, 4):
        row = measure(f"planar arm, {n} links", lambda n=n: planar_arm(n))
        eom = eg.derive(planar_arm(n), method="projected_newton_euler")
        row["closed_ops"] = _ops([eom.M, eom.b, eom.g])
        row["trigsimp_s"], row["trigsimp_ops"] = sympy_trigsimp(n, args.limit)
        rows.append(row)
    disk, kane_args = nonholonomic.rolling_disk(torques=True)
    rows.append(measure("rolling disk (Kane)", lambda: eg.kane(disk, **kane_args)))
    rows.append(measure("ur5 (shared form)", lambda: eg.robots.load("ur5")))

    def cell(value, fmt):
        return "—" if value is None else format(value, fmt)

    print(
        f"{'system':24s} {'form':9s} {'solution s':>10s} {'LaTeX s':>8s} {'M,b,g ops':>9s}"
        f" {'closed ops':>10s} {'trigsimp s':>10s} {'its ops':>7s}"
    )
    for r in rows:
        print(
            f"{r['system']:24s} {r['form']:9s} {r['solution_s']:10.2f} {r['latex_s']:8.2f} "
            f"{cell(r.get('textbook_ops'), '9d'):>9s} {cell(r.get('closed_ops'), '10d'):>10s} "
            f"{cell(r.get('trigsimp_s'), '10.1f'):>10s} {cell(r.get('trigsimp_ops'), '7d'):>7s}"
        )
    print(f"(— : not applicable, or sympy's trigsimp did not finish within {args.limit:.0f} s)")
    results_io.write(args.out, "solution", rows, trigsimp_limit_s=args.limit)


if __name__ == "__main__":
    main()
