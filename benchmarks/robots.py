"""eomgen on the robots of example-robot-data beside Pinocchio, in one run.

Per robot: derivation and code generation time, operations of the generated M, b, g, the per-call
time of the NumPy and C backends' M, b, g from Python beside Pinocchio's crba, nonLinearEffects and
computeGeneralizedGravity from Python (the C backend's ratio to Pinocchio in parentheses), and the
batched time per state (NumPy for N states, C for 10 N on one core and on all cores) beside a Python
loop over Pinocchio. Prints a table and writes JSON.

Run: python benchmarks/robots.py [names ...] [--method recursive] [--batch 10000] [--out ...]"""
from __future__ import annotations

import argparse
import ctypes
import os
import sys
import time
import timeit
import warnings
from pathlib import Path

import numpy as np
import pinocchio as pin

import eomgen as eg
from eomgen.model.urdf import pinocchio_configuration

sys.path.insert(0, str(Path(__file__).parent))
import results_io  # noqa: E402


def per_call(fn, number: int = 200, repeat: int = 5) -> float:
    """Best mean seconds per call over `repeat` runs of `number` calls."""
    return min(timeit.repeat(fn, number=number, repeat=repeat)) / number


def bench(name: str, batch: int, method: str) -> dict:
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # files with inertias Pinocchio takes as they are
        system = eg.robots.load(name)
    t0 = time.perf_counter()
    eom = eg.derive(system, method=method)
    t1 = time.perf_counter()
    f = eg.codegen(eom)
    t2 = time.perf_counter()
    model, rng = system.pinocchio_model, np.random.default_rng(0)
    data = model.createData()
    q, u, _ = eg.random_states(system, batch, rng)
    qp = pinocchio_configuration(system, q)
    q0, u0, qp0 = q[0], u[0], qp[0]
    row = {"robot": name, "nq": system.nq, "derive_s": t1 - t0, "codegen_s": t2 - t1,
           "ops_M": f.ops["M"], "ops_b": f.ops["b"], "ops_g": f.ops["g"]}
    calls = {"M": (lambda: f.M(q0), lambda: pin.crba(model, data, qp0)),
             "b": (lambda: f.b(q0, u0), lambda: pin.nonLinearEffects(model, data, qp0, u0)),
             "g": (lambda: f.g(q0), lambda: pin.computeGeneralizedGravity(model, data, qp0))}
    for key, (ours, theirs) in calls.items():
        row[f"{key}_us"], row[f"pin_{key}_us"] = per_call(ours) * 1e6, per_call(theirs) * 1e6
    t = time.perf_counter()
    f.M(q), f.b(q, u), f.g(q)
    row["batch_us_per_state"] = (time.perf_counter() - t) / batch * 1e6
    t = time.perf_counter()
    for k in range(batch):
        pin.crba(model, data, qp[k]), pin.nonLinearEffects(model, data, qp[k], u[k])
        pin.computeGeneralizedGravity(model, data, qp[k])
    row["pin_loop_us_per_state"] = (time.perf_counter() - t) / batch * 1e6
    t = time.perf_counter()
    fc = eg.codegen(eom, backend="c")
    row["c_compile_s"] = time.perf_counter() - t
    for key, call in (("M", lambda: fc.M(q0)), ("b", lambda: fc.b(q0, u0)), ("g", lambda: fc.g(q0))):
        row[f"c_{key}_us"] = per_call(call, number=2000) * 1e6
    big_q, big_u, _ = eg.random_states(system, 10 * batch, rng)
    for label, n in (("c_batch_us_per_state", 1), ("c_batch_all_cores_us_per_state", os.cpu_count())):
        threads(n)
        best = float("inf")
        for _ in range(3):  # the first pass also pays for touching fresh output memory
            t = time.perf_counter()
            fc.M(big_q), fc.b(big_q, big_u), fc.g(big_q)
            best = min(best, time.perf_counter() - t)
        row[label] = best / (10 * batch) * 1e6
    return row


def threads(n: int) -> None:
    """Threads of the compiled batched loops (OpenMP's runtime, shared by every extension module)."""
    ctypes.CDLL("libgomp.so.1").omp_set_num_threads(n)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("names", nargs="*", default=eg.robots.names(floating_base=False) + eg.robots.names(floating_base=True))
    ap.add_argument("--batch", type=int, default=10_000)
    ap.add_argument("--method", default="recursive", help="derivation whose code is timed (default: recursive)")
    ap.add_argument("--out", default=results_io.default_path("robots"))
    args = ap.parse_args()
    print(f"{'robot':26s} {'nq':>3s} {'derive':>7s} {'gen':>6s} {'ops M':>7s} {'ops b':>7s} {'ops g':>6s} "
          f"{'M µs':>7s} {'pin':>6s} {'b µs':>7s} {'pin':>6s} {'g µs':>7s} {'pin':>6s} "
          f"{'batch µs/state':>15s} {'pin loop':>9s} {'speed-up':>8s} "
          f"{'C M (÷pin)':>12s} {'C b (÷pin)':>12s} {'C g (÷pin)':>12s} {'C batch':>8s} {'C vs loop':>9s} "
          f"{'all cores':>9s} {'vs loop':>8s}")
    rows = []
    for name in args.names:
        r = bench(name, args.batch, args.method)
        rows.append(r)
        print(f"{name:26s} {r['nq']:3d} {r['derive_s']:6.2f}s {r['codegen_s']:5.2f}s {r['ops_M']:7d} {r['ops_b']:7d} "
              f"{r['ops_g']:6d} {r['M_us']:7.1f} {r['pin_M_us']:6.1f} {r['b_us']:7.1f} {r['pin_b_us']:6.1f} "
              f"{r['g_us']:7.1f} {r['pin_g_us']:6.1f} {r['batch_us_per_state']:15.2f} {r['pin_loop_us_per_state']:9.2f} "
              f"{r['pin_loop_us_per_state'] / r['batch_us_per_state']:7.1f}x "
              + "".join(f" {r[f'c_{k}_us']:5.2f} ({r[f'c_{k}_us'] / r[f'pin_{k}_us']:.2f})" for k in "Mbg") +
              f" {r['c_batch_us_per_state']:8.3f} "
              f"{r['pin_loop_us_per_state'] / r['c_batch_us_per_state']:8.1f}x "
              f"{r['c_batch_all_cores_us_per_state']:9.3f} "
              f"{r['pin_loop_us_per_state'] / r['c_batch_all_cores_us_per_state']:7.1f}x", flush=True)
    results_io.write(args.out, "robots", rows, pinocchio=pin.__version__, method=args.method, batch=args.batch)


if __name__ == "__main__":
    main()
