"""eg.sweep of ur5's M over N random states on a local cluster of worker processes (1 thread each),
beside the direct batched C call on one core.

The states are made on the workers, chunk k by `RandomChunks(system, seed)` (eg.random_states seeded
by (seed, k); only q, into arrays each worker reuses), so the client holds none of them. N × 36 doubles
do not fit in memory for N = 10⁸ (29 GB), so the result is reduced on the workers: each chunk's sum of M
(`reduce=np.add`: slice by slice as M is evaluated, never stored), summed over the chunks (a checksum),
and a few states spot-checked (untimed) by a sweep without reduction against the direct batched call on their
chunk, made again on the client.
Throughput per core, against the direct call on one core alone (a new output array, as a user calls it;
and into a reused one, out=) and with making the states as the sweep does (q alone, into reused arrays),
by two clocks: wall (N / (wall time × workers): right on a machine of its own) and CPU
(the workers' CPU seconds / N against the direct call's: what counts on a machine shared with other
work, where wall time measures the others too; the workers' CPU includes Dask's own threads, whose
statistical profiler is switched off). Prints a table and writes JSON.

Beside them, the same making and call on every worker at once, outside Dask's tasks (`client.run`): the
cores as busy as in the sweep, the per-core cost without Dask.

Run: python benchmarks/sweep.py [--states 100000000] [--chunk 1000000] [--workers 2] [--out ...]"""
from __future__ import annotations

import argparse
import os
import sys
import time
from pathlib import Path

import numpy as np

os.environ["OMP_NUM_THREADS"] = "1"  # the direct call on one core, as each worker (dask sets it there)
sys.path.insert(0, str(Path(__file__).parent))
import results_io  # noqa: E402


def best(fn, clock, repeat: int = 3) -> float:
    """Best seconds of `repeat` calls of fn by `clock`."""
    times = []
    for _ in range(repeat):
        t = clock()
        fn()
        times.append(clock() - t)
    return min(times)


def at_once(built, make, chunk: int, repeat: int = 3) -> float:
    """CPU seconds per state of making chunks' q and calling M into one array, on a worker, outside any
    task (every worker at once by `client.run`: the cores as busy as in the sweep, without Dask)."""
    f, q, out = built.functions(), np.empty((chunk, 6)), np.empty((chunk, 6, 6))
    f.call("M", make(0, chunk, (q,))[0], out=out)  # the arrays' pages touched once, untimed
    t = time.thread_time()
    for k in range(repeat):
        f.call("M", make(k, chunk, (q,))[0], out=out)
    return (time.thread_time() - t) / (repeat * chunk)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--states", type=int, default=10**8)
    parser.add_argument("--chunk", type=int, default=1_000_000)
    parser.add_argument("--workers", type=int, default=2)
    parser.add_argument("--spots", type=int, default=8)
    parser.add_argument("--out", default=results_io.default_path("sweep"))
    args = parser.parse_args()

    import dask
    from distributed import Client, LocalCluster

    import eomgen as eg
    from eomgen.sweep import RandomChunks, model

    system = eg.robots.load("ur5")
    f = eg.codegen(eg.derive(system), backend="c")
    make = RandomChunks(system, seed=2026)
    q = make(0, args.chunk)[0]
    f.M(q[:10])
    clocks = {"wall": time.perf_counter, "cpu": time.process_time}
    buffers, out = (np.empty_like(q),), np.empty((args.chunk, 6, 6))
    call = {c: best(lambda: f.call("M", q), clock) / args.chunk for c, clock in clocks.items()}
    into = {c: best(lambda: f.call("M", q, out=out), clock) / args.chunk for c, clock in clocks.items()}
    made = {c: best(lambda: f.call("M", make(0, args.chunk, buffers)[0], out=out), clock) / args.chunk
            for c, clock in clocks.items()}

    dask.config.set({"distributed.worker.profile.enabled": False})  # Dask's sampling of every thread
    with LocalCluster(n_workers=args.workers, threads_per_worker=1, processes=True,
                      dashboard_address=None) as cluster, Client(cluster) as client:
        t, built = time.perf_counter(), model(f)
        client.run(lambda: built.functions().call("M", np.zeros((64, 6))))  # on every worker, untimed
        eg.sweep(f, "M", make, n=args.workers * 1000, chunk=1000, cluster=client).sum().compute()
        warm = time.perf_counter() - t  # each worker imports eomgen and rebuilds the functions once
        sums = eg.sweep(f, "M", make, n=args.states, chunk=args.chunk, cluster=client, reduce=np.add)
        spots = np.sort(np.random.default_rng(1).choice(args.states, args.spots, replace=False))
        t, cpu = time.perf_counter(), client.run(time.process_time)
        total = sums.sum(axis=0).compute()  # each chunk reduced in its task, no chunk stored
        wall, after = time.perf_counter() - t, client.run(time.process_time)
        cpu = sum(after[w] - cpu[w] for w in cpu)  # the workers' CPU seconds: what the sweep used
        busy = float(np.mean(list(client.run(at_once, built, make, args.chunk).values())))
        x = eg.sweep(f, "M", make, n=args.states, chunk=args.chunk, cluster=client)
        swept = x[spots].compute()  # their chunks made and evaluated again, untimed

    direct = np.array([f.call("M", make(i // args.chunk, min(args.chunk, args.states - i // args.chunk
                                                              * args.chunk))[0])[i % args.chunk]
                       for i in spots])
    sweep_us = {"wall": wall * args.workers / args.states * 1e6, "cpu": cpu / args.states * 1e6}
    row = {"robot": "ur5", "function": "M", "states": args.states, "chunk": args.chunk,
           "workers": args.workers, "warm_s": warm, "wall_s": wall, "workers_cpu_s": cpu,
           "spots": spots.tolist(), "spots_equal": bool(np.array_equal(swept, direct)),
           "spots_max_abs_diff": float(np.max(np.abs(swept - direct))),
           "sum_M": total.tolist(), "workers_made_and_call_at_once_us_cpu": busy * 1e6,
           "ratio_to_workers_made_and_call_at_once_cpu": cpu / args.states / busy}
    print(f"{args.states} states of ur5's M, {args.workers} workers, chunks of {args.chunk}: "
          f"{wall:.1f} s wall, {cpu:.1f} s worker CPU; workers warm in {warm:.1f} s")
    print(f"{'clock':>6} {'sweep µs/state/core':>20} {'direct call µs':>15} {'call out= µs':>13} "
          f"{'made+call µs':>13} {'× call':>7} {'× made+call':>11}")
    for c in clocks:
        row.update({f"sweep_us_{c}": sweep_us[c], f"direct_call_us_{c}": call[c] * 1e6,
                    f"direct_call_into_out_us_{c}": into[c] * 1e6,
                    f"direct_made_and_call_us_{c}": made[c] * 1e6,
                    f"ratio_to_call_{c}": sweep_us[c] / (call[c] * 1e6),
                    f"ratio_to_made_and_call_{c}": sweep_us[c] / (made[c] * 1e6)})
        print(f"{c:>6} {sweep_us[c]:>20.3f} {call[c] * 1e6:>15.3f} {into[c] * 1e6:>13.3f} "
              f"{made[c] * 1e6:>13.3f} "
              f"{row[f'ratio_to_call_{c}']:>7.2f} {row[f'ratio_to_made_and_call_{c}']:>11.2f}")
    print(f"made+call on every worker at once (no Dask task): {busy * 1e6:.3f} µs CPU per state; the sweep "
          f"{row['ratio_to_workers_made_and_call_at_once_cpu']:.2f}× that")
    print(f"spot checks ({args.spots} states) equal to the direct batched call: {row['spots_equal']}; "
          f"Σ M00 over the states = {total[0, 0]:.6e}")
    results_io.write(args.out, "sweep", [row], load=list(os.getloadavg()))


if __name__ == "__main__":
    main()
