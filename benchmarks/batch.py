"""The C backend's batched M and nle on one core, before and after the vector batch path, beside the
time to just write the same output bytes, in one run.

Per robot: µs per state of M(q) and nle(q, u) over N states (OMP_NUM_THREADS=1), by the code of a git
revision (--before, the scalar batch loop: a fresh output per call) and by this tree (a fresh output,
and out= reusing one), beside a plain copy of the output's bytes into a reused buffer of the same size
(NumPy's copyto: the bound); and µs per call of one state, before and after. N is --states, fewer
where M's output would pass --megabytes. Each side
runs in its own process (its own eomgen), the two alternating --rounds times; each time is the best of
--repeat calls over the rounds. Prints a table (and the compiler, flags, CPU, load) and writes JSON.

Run: python benchmarks/batch.py [names ...] [--states 100000] [--before 4d071dc] [--out ...]"""

from __future__ import annotations

import argparse
import json
import os
import platform
import subprocess
import sys
import tarfile
import tempfile
import time
import timeit
import warnings
from io import BytesIO
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).parent))
import results_io  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]


def best(fn, repeat: int) -> float:
    """Best seconds of `repeat` calls."""
    times = []
    for _ in range(repeat):
        t = time.perf_counter()
        fn()
        times.append(time.perf_counter() - t)
    return min(times)


def measure(name: str, states: int, megabytes: float, repeat: int) -> dict:
    """One side's times (run in a worker process, with its own eomgen on sys.path)."""
    import eomgen as eg
    from eomgen.printers.build import extension

    try:
        from eomgen.printers.build.compile import COMPILE

        flags = ["-O2 (-O1 for large units)", *COMPILE]
    except ImportError:  # an eomgen of before the translation units
        flags = list(extension.FLAGS)

    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # files with inertias Pinocchio takes as they are
        system = eg.robots.load(name)
    fc = eg.codegen(eg.derive(system, method="recursive"), backend="c")
    n = min(states, int(megabytes * 2**20 / (8 * system.nv**2)))
    q, u, _ = eg.random_states(system, n, np.random.default_rng(0))
    row = {
        "robot": name,
        "nq": system.nq,
        "nv": system.nv,
        "states": n,
        "ops_M": fc.ops["M"],
        "ops_nle": fc.ops.get("nle"),
        "flags": " ".join(flags + list(extension.ATTEMPTS[0])),
    }
    calls = {
        "M": (lambda **o: fc.M(q, **o), lambda: fc.M(q[0])),
        "nle": (lambda **o: fc.nle(q, u, **o), lambda: fc.nle(q[0], u[0])),
    }
    for key, (call, one) in calls.items():
        row[f"{key}_call_us"] = min(timeit.repeat(one, number=2000, repeat=repeat)) / 2000 * 1e6
        result = call()
        row[f"{key}_us"] = best(call, repeat) / n * 1e6
        try:
            out = np.empty_like(result)
            row[f"{key}_out_us"] = best(lambda: call(out=out), repeat) / n * 1e6
        except TypeError:  # no out= before
            row[f"{key}_out_us"] = None
        source, target = np.random.default_rng(1).random(result.shape), np.empty_like(result)
        row[f"{key}_copy_us"] = best(lambda: np.copyto(target, source), repeat) / n * 1e6
    return row


def worker(src: str, args) -> None:
    sys.path.insert(0, src)
    print(json.dumps(measure(args.worker, args.states, args.megabytes, args.repeat)))


def checkout(ref: str, folder: Path) -> str:
    """src/ of git revision `ref`, extracted into `folder`."""
    archive = subprocess.run(
        ["git", "archive", ref, "src"], cwd=ROOT, capture_output=True, check=True
    ).stdout
    with tarfile.open(fileobj=BytesIO(archive)) as tar:
        tar.extractall(folder)
    return str(folder / "src")


def run(src: str, name: str, args) -> dict:
    env = {**os.environ, "OMP_NUM_THREADS": "1", "EOMGEN_PROGRESS": "0", "PYTHONPATH": src}
    command = [
        sys.executable,
        __file__,
        "--worker",
        name,
        "--src",
        src,
        "--states",
        str(args.states),
        "--megabytes",
        str(args.megabytes),
        "--repeat",
        str(args.repeat),
    ]
    done = subprocess.run(command, env=env, capture_output=True, text=True)
    if done.returncode:
        raise SystemExit(f"{name} ({src}) failed:\n{done.stderr[-3000:]}")
    return json.loads(done.stdout.strip().splitlines()[-1])


def merged(rows: list[dict]) -> dict:
    """The best of each time over the rounds."""
    out = dict(rows[0])
    for k, v in out.items():
        if k.endswith("_us") and v is not None:
            out[k] = min(r[k] for r in rows)
    return out


def machine() -> dict:
    cpu = next(
        (
            line.split(":", 1)[1].strip()
            for line in Path("/proc/cpuinfo").read_text().splitlines()
            if line.startswith("model name")
        ),
        platform.processor(),
    )
    cc = subprocess.run([os.environ.get("CC", "cc"), "--version"], capture_output=True, text=True).stdout
    return {"cpu": cpu, "compiler": cc.splitlines()[0] if cc else "?", "load_start": os.getloadavg()}


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("names", nargs="*", default=["ur5", "talos"])
    ap.add_argument("--states", type=int, default=100_000)
    ap.add_argument("--megabytes", type=float, default=256.0, help="largest output of M (fewer states)")
    ap.add_argument("--before", default="4d071dc", help="git revision of the scalar batch loop")
    ap.add_argument("--rounds", type=int, default=2)
    ap.add_argument("--repeat", type=int, default=5)
    ap.add_argument("--out", default=results_io.default_path("batch"))
    ap.add_argument("--worker", help=argparse.SUPPRESS)
    ap.add_argument("--src", help=argparse.SUPPRESS)
    args = ap.parse_args()
    if args.worker:
        return worker(args.src, args)
    meta = machine()
    print(
        f"CPU: {meta['cpu']}; compiler: {meta['compiler']}; one core (OMP_NUM_THREADS=1); "
        f"load {meta['load_start']}"
    )
    print(
        f"{'robot':8s} {'N':>7s} {'':4s} {'ops':>6s} {'before':>8s} {'after':>8s} {'out=':>8s} {'copy':>8s}"
        f" {'speed-up':>8s} {'out=/copy':>9s} {'1 state before':>14s} {'after':>6s}   (µs per state)"
    )
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        old, new = checkout(args.before, Path(tmp)), str(ROOT / "src")
        for name in args.names:
            sides = {"before": [], "after": []}
            for _ in range(args.rounds):
                for side, src in (("before", old), ("after", new)):
                    sides[side].append(run(src, name, args))
            before, after = merged(sides["before"]), merged(sides["after"])
            for key in ("M", "nle"):
                row = {
                    "robot": name,
                    "quantity": key,
                    "states": after["states"],
                    "ops": after[f"ops_{key}"],
                    "before_ops": before[f"ops_{key}"],
                    "before_us": before[f"{key}_us"],
                    "after_us": after[f"{key}_us"],
                    "after_out_us": after[f"{key}_out_us"],
                    "copy_us": after[f"{key}_copy_us"],
                    "before_call_us": before[f"{key}_call_us"],
                    "after_call_us": after[f"{key}_call_us"],
                    "flags": after["flags"],
                    "before_flags": before["flags"],
                }
                rows.append(row)
                print(
                    f"{name:8s} {row['states']:7d} {key:4s} {row['ops']:6d} {row['before_us']:8.4f} "
                    f"{row['after_us']:8.4f} {row['after_out_us']:8.4f} {row['copy_us']:8.4f} "
                    f"{row['before_us'] / row['after_out_us']:7.2f}x "
                    f"{row['after_out_us'] / row['copy_us']:8.2f}x {row['before_call_us']:14.3f} "
                    f"{row['after_call_us']:6.3f}",
                    flush=True,
                )
    meta["load_end"] = os.getloadavg()
    print(
        f"flags: {rows[0]['flags']} (before: {rows[0]['before_flags']}); load at the end {meta['load_end']}"
    )
    results_io.write(args.out, "batch", rows, before=args.before, **meta)


if __name__ == "__main__":
    main()
