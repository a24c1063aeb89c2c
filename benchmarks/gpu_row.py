"""The GPU row of benchmarks/targets.py, for a machine with a GPU but without the robots' files: JAX's
jit(vmap) of M and nle on the GPU beside the C backend's vector batches on the same machine's CPU cores.

    here:              python benchmarks/gpu_row.py save ur5 talos --dir DIR   (derive, pickle the equations)
    on the GPU machine: python benchmarks/gpu_row.py run --dir DIR [--states 100000 1000000] [--out ...]

`run` needs only numpy, scipy, sympy, jax (with its GPU plugin) and a C compiler for the C column; it
unpickles the equations (no URDF, no Pinocchio), makes random states, and per robot and function prints:
JAX's compile of jit(vmap) on the GPU (first call), per call of one state (µs, jit, on the GPU, transfers
excluded: inputs already on the device), states per second over each N (best of --repeat, inputs on the
device, block_until_ready), C's states per second over the same N (OpenMP over the machine's cores) and
the ratio; each output at the first CHECKED states agrees with NumPy's (max |difference| / max(1, |x|)).
XLA's fusion is on (GPU kernels); --no-fusion-above OPS compiles larger functions without it, as the
JAX backend does on the CPU."""

from __future__ import annotations

import argparse
import json
import os
import pickle
import sys
import time
from pathlib import Path

import numpy as np

import eomgen as eg

sys.path.insert(0, str(Path(__file__).parent))
import results_io  # noqa: E402
from batch import best  # noqa: E402

CHECKED, KEYS = 5, ("M", "nle")


def agreement(ours, theirs) -> float:
    ours, theirs = np.asarray(ours, float).reshape(np.shape(theirs)), np.asarray(theirs)
    return float(np.max(np.abs(ours - theirs)) / max(1.0, np.max(np.abs(theirs))))


def save(names: list[str], folder: Path) -> None:
    folder.mkdir(parents=True, exist_ok=True)
    for name in names:
        eom = eg.derive(eg.robots.load(name))
        eom.system.pinocchio_model = None  # the URDF's Pinocchio model: not needed there, nor installed
        (folder / f"{name}.pickle").write_bytes(pickle.dumps(eom))
        print(f"{name}: {(folder / f'{name}.pickle').stat().st_size / 1e6:.1f} MB")


def jax_row(f, key: str, states, sizes, repeat: int, gpu, options: dict, reference) -> dict:
    import jax

    p = jax.device_put(np.asarray(f.parameter_vector(None, key), float), gpu)
    one = jax.jit(f.jax[key], compiler_options=options)
    many = jax.jit(jax.vmap(f.jax[key], in_axes=(0, 0, 0, None)), compiler_options=options)
    put = [jax.device_put(x[0], gpu) for x in states]
    t = time.perf_counter()
    first = one(*put, p).block_until_ready()
    row = {"gpu_jit_s": time.perf_counter() - t}
    number = 200
    row["gpu_call_us"] = best(lambda: [one(*put, p).block_until_ready() for _ in range(number)], repeat) \
        / number * 1e6
    error = agreement(first, reference[0])
    for n in sizes:
        batch = [jax.device_put(x[:n], gpu) for x in states]
        t = time.perf_counter()
        out = many(*batch, p).block_until_ready()
        row[f"gpu_vmap_jit_s_{n}"] = time.perf_counter() - t
        row[f"gpu_per_s_{n}"] = n / best(lambda: many(*batch, p).block_until_ready(), repeat)
        error = max(error, agreement(np.asarray(out[:CHECKED]), reference[1]))
    row["gpu_error"] = error
    return row


def run(args) -> None:
    import jax

    gpus = [d for d in jax.devices() if d.platform == args.platform]
    if not gpus:
        sys.exit(f"no {args.platform}: jax.devices() = {jax.devices()}")
    rows, meta = [], {"gpu": str(gpus[0]), "jax": jax.__version__, "cores": os.cpu_count(),
                      "states": args.states}
    print(f"{meta['gpu']}, jax {jax.__version__}, {os.cpu_count()} CPU cores")
    for path in sorted(Path(args.dir).glob("*.pickle")):
        eom = pickle.loads(path.read_bytes())
        states = eg.random_states(eom.system, max(args.states), np.random.default_rng(0))
        fn = eg.codegen(eom)
        fj = eg.codegen(eom, backend="jax")
        try:
            fc = eg.codegen(eom, backend="c")
            fc.generate(list(KEYS))
        except Exception as failure:  # noqa: BLE001 (said in the table and the JSON)
            fc, meta[f"c_{path.stem}"] = None, f"{type(failure).__name__}: {failure}"[:300]
        for key in KEYS:
            reference = (fn.call(key, *(x[0] for x in states)), fn.call(key, *(x[:CHECKED] for x in states)))
            ops = fn.ops[key]
            options = {"xla_disable_hlo_passes": "fusion"} if ops > args.no_fusion_above else {}
            row = {"robot": path.stem, "key": key, "ops": ops, "fusion": not options}
            row.update(jax_row(fj, key, states, args.states, args.repeat, gpus[0], options, reference))
            if fc is not None:
                for n in args.states:
                    batch = [x[:n] for x in states]
                    fc.call(key, *batch)
                    row[f"c_per_s_{n}"] = n / best(lambda: fc.call(key, *batch), args.repeat)
                row["c_error"] = agreement(fc.call(key, *(x[:CHECKED] for x in states)), reference[1])
            rows.append(row)
            print(json.dumps(row))
            results_io.write(args.out, "gpu_row", rows, **meta)
    print(f"{'robot':6s} {'f':4s} {'ops':>5s} {'jit s':>6s} {'call µs':>8s} " + " ".join(
        f"{'GPU/s ' + str(n):>13s} {'C/s ' + str(n):>13s} {'GPU/C':>6s}" for n in args.states))
    for r in rows:
        cells = []
        for n in args.states:
            c = r.get(f"c_per_s_{n}", float("nan"))
            cells.append(f"{r[f'gpu_per_s_{n}']:13.3g} {c:13.3g} {r[f'gpu_per_s_{n}'] / c:6.2f}")
        jit = r["gpu_jit_s"] + r[f"gpu_vmap_jit_s_{args.states[0]}"]
        print(f"{r['robot']:6s} {r['key']:4s} {r['ops']:5d} {jit:6.1f} {r['gpu_call_us']:8.1f}",
              " ".join(cells))


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("what", choices=("save", "run"))
    ap.add_argument("names", nargs="*", default=["ur5", "talos"])
    ap.add_argument("--dir", default="gpu_equations")
    ap.add_argument("--states", type=int, nargs="+", default=[100_000, 1_000_000])
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--no-fusion-above", type=int, default=10**9)
    ap.add_argument("--out", default=results_io.default_path("gpu_row"))
    ap.add_argument("--platform", default="gpu", help="the JAX device (cpu: a dry run of the script)")
    args = ap.parse_args()
    eg.quiet()
    save(args.names, Path(args.dir)) if args.what == "save" else run(args)


if __name__ == "__main__":
    main()
