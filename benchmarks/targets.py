"""The four targets side by side in one run: NumPy, C, JAX and CasADi on ur5 and talos (CPU).

Per robot, for each function (M and nle by default; --keys adds ID, ID_derivatives, ...):

- construction: eg.derive; eg.codegen per backend: C including the compiles (the functions, and their
  vector functions on the first batch) in a fresh EOMGEN_CACHE (no cache hit); JAX (`jax_construction`)
  making the functions, then the first call of `jax.jit` of each function of one state and of its
  `jax.vmap`: with the C kernels (kernels="c", the default) in a fresh process and a fresh EOMGEN_CACHE
  (their compile included; in this process the C backend's modules are loaded already), then in a second
  process with that cache warm (`jax_processes`), and with kernels="xla"; CasADi building the SX
  `casadi.Function`s (codegen) and `f.casadi[key]`;
- per call (one state, µs): NumPy and C through `f.call`, JAX `jit(f.jax[key])` on device arrays
  (block_until_ready) with kernels="c" (JAX) and "xla" (XLA), CasADi `f.casadi[key]` called with numbers;
- batch (states per second over N states, N = --states, fewer where one output would pass --megabytes):
  C's vector batches and NumPy's arrays through `f.call`, JAX `jit(vmap(f.jax[key]))` (block_until_ready;
  both kernels), and CasADi `f.casadi[key].map(N, "thread", 2)` (two threads; the others run on one);
  the ratio of JAX's time per state to C's for both kernels (the issue's aim: within 3×);
- a GPU row (JAX jit(vmap)) when jax.devices() lists a GPU, else a line saying it was skipped.

Each backend's outputs at the first CHECKED states (one-state calls and batches) are compared with NumPy's:
max |difference| / max(1, max |NumPy|), printed; more than 1e-9 is reported and fails the run. Per-call
times are the best of 5 repeats of enough calls for 0.05 s, batch times the best of --repeat.

XLA's CPU compile of the large scalar graphs is slow because its fusion pass copies each shared
intermediate into every fusion that reads it (talos's M: 4216 operations printed, 5209 sin/cos and
27452 multiplications after XLA's optimisation; the compile and a one-state call grow with the copies).
The traced graph (kernels="xla") is jitted as the library does: that pass off for functions of more than
`FUSION_LIMIT` operations (`compiler_options={"xla_disable_hlo_passes": "fusion"}`): each operation once,
a much shorter compile and faster batches, slower one-state calls (one kernel per operation);
--xla-no-fusion turns it off for every function.

Run: python benchmarks/targets.py [names ...] [--keys M nle] [--states 100000] [--xla-no-fusion]
     [--out ...]"""

from __future__ import annotations

import argparse
import os
import subprocess
import sys
import tempfile
import time
import timeit
import warnings
from pathlib import Path

import numpy as np

import eomgen as eg
from eomgen.numeric.jax_functions import FUSION_LIMIT

sys.path.insert(0, str(Path(__file__).parent))
import results_io  # noqa: E402
from batch import best, machine  # noqa: E402

CHECKED, TOLERANCE = 5, 1e-9
NO_FUSION = {"xla_disable_hlo_passes": "fusion"}  # --xla-no-fusion
BACKENDS = ("numpy", "c", "jax", "casadi")
KERNELS = {"jax": "c", "xla": "xla"}  # the JAX columns: label → kernels


def seconds(fn) -> float:
    """Seconds of one call of fn."""
    t = time.perf_counter()
    fn()
    return time.perf_counter() - t


def per_call_us(fn) -> float:
    """µs per call: the best of 5 repeats of enough calls for 0.05 s."""
    number = max(1, int(0.05 / max(seconds(fn), 1e-7)))
    return min(timeit.repeat(fn, number=number, repeat=5)) / number * 1e6


def agreement(ours, numpy_values) -> float:
    """max |difference| / max(1, max |value|) against NumPy's outputs."""
    ours, theirs = np.asarray(ours, float).reshape(np.shape(numpy_values)), np.asarray(numpy_values)
    return float(np.max(np.abs(ours - theirs)) / max(1.0, np.max(np.abs(theirs))))


def inputs(f, key: str, q, u, ud) -> list:
    """The arguments of `f.casadi[key]`: its catalogue inputs (τ read as u̇), no parameters (robots)."""
    given = {"q": q, "u": u, "ud": ud, "tau": ud}
    return [given[x.strip()] for x in f.catalogue[key].inputs.split(",")]


def construction(name: str, eom, keys: list[str], states, options: dict) -> tuple[dict, dict]:
    """({backend: functions}, {what: seconds}): codegen per backend with the functions `keys` made; C in
    a fresh cache (never a cache hit), with its vector functions, compiled on the first batch; JAX by
    `jax_construction`: kernels="c" (timed in `jax_processes`) and kernels="xla"."""
    made, times = {}, jax_processes(name, keys)
    for backend in BACKENDS:
        with tempfile.TemporaryDirectory() as cache:
            os.environ["EOMGEN_CACHE"] = cache
            t = time.perf_counter()
            if backend == "jax":
                made["jax"] = jax_construction(eom, keys, states, "c", options)[0]
                made["xla"], times["xla_s"] = jax_construction(eom, keys, states, "xla", options)
                continue
            f = eg.codegen(eom, backend=backend)
            f.generate(keys)
            if backend == "c":
                for key in keys:
                    f.call(key, *(x[:2] for x in states))
            times[f"{backend}_codegen_s"] = time.perf_counter() - t
        made[backend] = f
    return made, times


def jax_processes(name: str, keys: list[str]) -> dict:
    """{"jax_cold_s", "jax_warm_s"}: `jax_construction` with the C kernels in a new process with a fresh
    EOMGEN_CACHE, then in another with that cache warm (the robot derived before the clock starts)."""
    with tempfile.TemporaryDirectory() as cache:
        command = [sys.executable, __file__, name, "--keys", *keys, "--jax-construction"]
        run = [subprocess.run(command, env={**os.environ, "EOMGEN_CACHE": cache}, capture_output=True,
                              text=True, check=True) for _ in range(2)]
    return {"jax_cold_s": float(run[0].stdout.split()[-1]), "jax_warm_s": float(run[1].stdout.split()[-1])}


def jax_construction(eom, keys: list[str], states, kernels: str, options: dict):
    """(the JAX functions, seconds): codegen with `kernels`, the functions `keys` made, the first call of
    jit of each of one state and of jit(vmap) over two states."""
    import jax

    t = time.perf_counter()
    f = eg.codegen(eom, backend="jax", kernels=kernels)
    f.generate(keys)
    for key in keys:
        j = Jax(f, key, jax.devices("cpu")[0], options)
        j.call(j.one, *(x[0] for x in states))
        j.call(j.many, *(x[:2] for x in states))
    return f, time.perf_counter() - t


class Jax:
    """The JAX side: jit of one state and jit(vmap) of N, on one device, with their compile times."""

    def __init__(self, f, key: str, device, options: dict) -> None:
        import jax

        self.jax, self.device = jax, device
        options = options or (NO_FUSION if f.ops[key] > FUSION_LIMIT and f.kernels == "xla" else {})
        self.one = jax.jit(f.jax[key], compiler_options=options)
        self.many = jax.jit(jax.vmap(f.jax[key], in_axes=(0, 0, 0, None)), compiler_options=options)
        self.p = jax.device_put(np.asarray(f.parameter_vector(None, key), float), device)

    def put(self, *xs):
        return [self.jax.device_put(x, self.device) for x in xs]

    def call(self, fn, q, u, ud):
        return fn(q, u, ud, self.p).block_until_ready()


def bench_key(f: dict, key: str, states, batch: int, repeat: int, cpu, gpu, options: dict) -> dict:
    """Per-call and batch times of `key` on every backend, the JAX compile times, the agreement."""
    q, u, ud = states
    Q, U, UD = (x[:batch] for x in states)
    numpy_one = f["numpy"].call(key, q[0], u[0], ud[0])
    numpy_checked = f["numpy"].call(key, q[:CHECKED], u[:CHECKED], ud[:CHECKED])
    row = {"key": key, "states": batch, "ops": f["numpy"].ops[key]}
    for name in ("numpy", "c"):
        fn = f[name]
        row[f"{name}_call_us"] = per_call_us(lambda: fn.call(key, q[0], u[0], ud[0]))
        row[f"{name}_batch_s"] = best(lambda: fn.call(key, Q, U, UD), repeat)
        row[f"{name}_error"] = agreement(fn.call(key, Q[:CHECKED], U[:CHECKED], UD[:CHECKED]), numpy_checked)
    for label, device in (("jax", cpu), ("xla", cpu), ("gpu", gpu)):
        if device is not None:
            row.update(bench_jax(f["xla" if label == "gpu" else label], key, states, batch, repeat, device,
                                 (numpy_one, numpy_checked), label, options))
    row.update(bench_casadi(f["casadi"], key, states, batch, repeat, numpy_one, numpy_checked))
    row["jax_over_c"] = row["jax_batch_s"] / row["c_batch_s"]
    row["xla_over_c"] = row["xla_batch_s"] / row["c_batch_s"]
    return row


def bench_jax(f, key: str, states, batch: int, repeat: int, device, reference: tuple, label: str,
              options: dict) -> dict:
    """JAX on `device`: compile of jit and of jit(vmap) (first call), per call, batch, agreement with
    `reference` (NumPy's outputs at one state and at the first CHECKED)."""
    numpy_one, numpy_checked = reference
    j = Jax(f, key, device, options)
    one, many = j.put(*(x[0] for x in states)), j.put(*(x[:batch] for x in states))
    row = {f"{label}_jit_s": seconds(lambda: j.call(j.one, *one)),
           f"{label}_vmap_jit_s": seconds(lambda: j.call(j.many, *many))}
    row[f"{label}_call_us"] = per_call_us(lambda: j.call(j.one, *one))
    row[f"{label}_batch_s"] = best(lambda: j.call(j.many, *many), repeat)
    row[f"{label}_error"] = max(agreement(j.call(j.one, *one), numpy_one),
                                agreement(j.call(j.many, *many)[:CHECKED], numpy_checked))
    return row


def bench_casadi(f, key: str, states, batch: int, repeat: int, numpy_one, numpy_checked) -> dict:
    """CasADi: building f.casadi[key], a call with numbers, the map over N states on two threads."""
    import casadi as ca

    row = {}
    row["casadi_function_s"] = seconds(lambda: f.casadi[key])
    function = f.casadi[key]
    one = inputs(f, key, *(x[0] for x in states))
    row["casadi_call_us"] = per_call_us(lambda: function(*one))
    error = agreement(function(*one).full(), numpy_one)
    try:
        mapped = function.map(batch, "thread", 2)
        many = [ca.DM(x.T) for x in inputs(f, key, *(x[:batch] for x in states))]
        row["casadi_batch_s"] = best(lambda: mapped(*many), repeat)
        out = mapped(*many).full()  # [f(x0) | f(x1) | ...]
        rows, cols = numpy_one.shape
        checked = out[:, : CHECKED * cols].reshape(rows, CHECKED, cols).transpose(1, 0, 2)
        error = max(error, agreement(checked, numpy_checked))
    except Exception as failure:  # noqa: BLE001 (said in the table and the JSON)
        row["casadi_map_note"] = f"map(N, 'thread', 2) failed: {type(failure).__name__}: {failure}"[:300]
    row["casadi_error"] = error
    return row


def load(name: str):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # files with inertias Pinocchio takes as they are
        return eg.robots.load(name)


def bench(name: str, keys: list[str], args, cpu, gpu) -> tuple[dict, list[dict]]:
    """The robot's construction times and one row per function."""
    system = load(name)
    t = time.perf_counter()
    eom = eg.derive(system)
    robot = {"robot": name, "nq": system.nq, "nv": system.nv, "method": eom.method,
             "derive_s": time.perf_counter() - t}
    states = eg.random_states(system, args.states, np.random.default_rng(0))
    f, times = construction(name, eom, keys, states, args.xla)
    robot.update(times)
    rows = []
    for key in keys:
        rows_, cols = f["numpy"].generated(key).shape
        batch = min(args.states, int(args.megabytes * 2**20 / (8 * rows_ * cols)))
        rows.append({"robot": name, **bench_key(f, key, states, batch, args.repeat, cpu, gpu, args.xla)})
    robot["casadi_construction_s"] = robot["casadi_codegen_s"] + sum(r["casadi_function_s"] for r in rows)
    return robot, rows


def show_robot(r: dict) -> None:
    print(f"\n{r['robot']} (nq {r['nq']}, nv {r['nv']}, {r['method']}): derive {r['derive_s']:.1f} s; "
          f"codegen NumPy {r['numpy_codegen_s']:.2f} s, C {r['c_codegen_s']:.1f} s (with the compile); JAX "
          f"(functions + first jit and jit(vmap) of each): C kernels {r['jax_cold_s']:.1f} s in a fresh "
          f"process and cache, {r['jax_warm_s']:.1f} s with the cache warm, XLA {r['xla_s']:.1f} s; CasADi "
          f"{r['casadi_construction_s']:.2f} s")


HEADER = (f"{'robot':6s} {'key':4s} {'ops':>5s} | {'per call µs:':>12s} {'NumPy':>7s} {'C':>6s} {'JAX':>6s} "
          f"{'XLA':>6s} {'CasADi':>7s} | {'N':>6s} {'states/s:':>9s} {'NumPy':>8s} {'C':>8s} {'JAX':>8s} "
          f"{'XLA':>8s} {'CasADi':>8s} {'JAX/C':>6s} {'XLA/C':>6s} | max rel. diff. to NumPy\n"
          "(JAX: kernels='c', the default; XLA: kernels='xla', the traced graph)")


def rate(row: dict, side: str) -> str:
    return f"{row['states'] / row[f'{side}_batch_s']:8.2e}" if f"{side}_batch_s" in row else f"{'—':>8s}"


def show(row: dict) -> None:
    errors = " ".join(f"{b}={row[f'{b}_error']:.0e}" for b in ("c", "jax", "xla", "gpu", "casadi")
                      if f"{b}_error" in row)
    print(f"{row['robot']:6s} {row['key']:4s} {row['ops']:5d} | {'':12s} {row['numpy_call_us']:7.1f} "
          f"{row['c_call_us']:6.2f} {row['jax_call_us']:6.1f} {row['xla_call_us']:6.1f} "
          f"{row['casadi_call_us']:7.1f} | {row['states']:6d} {'':9s} {rate(row, 'numpy')} {rate(row, 'c')} "
          f"{rate(row, 'jax')} {rate(row, 'xla')} {rate(row, 'casadi')} {row['jax_over_c']:5.1f}x "
          f"{row['xla_over_c']:5.1f}x | {errors}", flush=True)
    if "gpu_batch_s" in row:
        print(f"{'':11s} GPU: {row['gpu_call_us']:.1f} µs per call, {rate(row, 'gpu')} states/s, jit "
              f"{row['gpu_jit_s']:.1f} s, vmap jit {row['gpu_vmap_jit_s']:.1f} s")
    if "casadi_map_note" in row:
        print(f"{'':11s} CasADi: {row['casadi_map_note']}")


def devices():
    """(the CPU device, a GPU device or None with why not)."""
    import jax

    gpus = [d for d in jax.devices() if d.platform == "gpu"]
    why = None if gpus else f"jax.devices() lists no GPU ({jax.devices()})"
    return jax.devices("cpu")[0], (gpus[0] if gpus else None), why


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("names", nargs="*", default=["ur5", "talos"])
    ap.add_argument("--keys", nargs="+", default=["M", "nle"])
    ap.add_argument("--states", type=int, default=100_000)
    ap.add_argument("--megabytes", type=float, default=256.0, help="largest batch output (fewer states)")
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--xla-no-fusion", action="store_true",
                    help="jit the traced graph with XLA's fusion pass off for every function (see the "
                         "module's docstring)")
    ap.add_argument("--out", default=results_io.default_path("targets"))
    ap.add_argument("--jax-construction", action="store_true", help=argparse.SUPPRESS)  # jax_processes
    args = ap.parse_args()
    args.xla = NO_FUSION if args.xla_no_fusion else {}
    eg.quiet()
    if args.jax_construction:
        eom = eg.derive(load(args.names[0]))
        states = eg.random_states(eom.system, 2, np.random.default_rng(0))
        print(jax_construction(eom, args.keys, states, "c", args.xla)[1])
        return
    import casadi
    import jax

    cpu, gpu, why = devices()
    meta = {**machine(), "jax": jax.__version__, "casadi": casadi.__version__, "states": args.states,
            "gpu": str(gpu) if gpu else why, "xla_compiler_options": args.xla}
    threads = subprocess.run(["nproc"], capture_output=True, text=True).stdout.strip()
    print(f"CPU: {meta['cpu']} ({threads} cores); {meta['compiler']}; jax {jax.__version__} (x64), casadi "
          f"{casadi.__version__}; XLA compiler options {args.xla}; load {meta['load_start']}")
    if gpu is None:
        print(f"GPU row skipped: {why}")
    robots, rows = [], []
    for name in args.names:
        robot, bench_rows = bench(name, args.keys, args, cpu, gpu)
        robots.append(robot)
        rows += bench_rows
        show_robot(robot)
        print(HEADER)
        for row in bench_rows:
            show(row)
    meta["load_end"] = os.getloadavg()
    print(f"load at the end {meta['load_end']}")
    results_io.write(args.out, "targets", rows, robots=robots, **meta)
    bad = [f"{r['robot']} {r['key']} {b}" for r in rows for b in ("c", "jax", "xla", "gpu", "casadi")
           if r.get(f"{b}_error", 0) > TOLERANCE]
    if bad:
        sys.exit(f"differ from NumPy beyond {TOLERANCE}: {', '.join(bad)}")


if __name__ == "__main__":
    main()
