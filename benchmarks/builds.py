"""How long `eg.codegen(eg.derive(robot), backend="c")` takes and how much memory it needs, per robot of
example-robot-data and for an n-link chain (benchmarks/derive_chain.py's) with projected Newton-Euler:
derivation, printing (the C text and the translation units) and compiling seconds, the compiler's CPU
seconds, and the peak memory of the process with its compilers (resident, sampled every 20 ms). Each
case runs in a fresh process under a memory limit (address space) and a time limit, so one that blows
up is reported, not the machine. The C numbers are checked against Pinocchio (crba, nonLinearEffects)
at one state.

Per case also the time per call of M and nle (one state, from Python), the seconds of the first call of b
(first-b: b and g compiled then where the build up front holds nle alone) and the compiler's CPU seconds
with it (gcc-all). With --before REF the same cases
run first on the eomgen of git revision REF (its src/ exported to a temp folder), and the table shows
both; --after REF measures revision REF instead of this working tree; --levels compiles every unit at
-O1, -O2 and -O3 in turn (compile time and speed by optimisation level).

Run: python benchmarks/builds.py [robots ...] [--method projected_newton_euler] [--chain 50]
     [--before main] [--after HEAD] [--levels] [--limit-gb 8] [--timeout 900]
     [--out benchmarks/results/builds.json]"""

from __future__ import annotations

import argparse
import json
import os
import platform
import resource
import signal
import subprocess
import sys
import tempfile
import threading
import time
from pathlib import Path

HERE = Path(__file__).parent
sys.path.insert(0, str(HERE))
if "--one" not in sys.argv:  # the parent runs this tree's eomgen; a case imports the one it is given
    sys.path.insert(0, str(HERE.parent / "src"))
import results_io  # noqa: E402


def peak_memory(pid: int, stop: threading.Event, peak: list[float]) -> None:
    """peak[0]: the largest resident memory (MB) of process `pid` with its children, until `stop`."""
    import psutil

    root = psutil.Process(pid)
    while not stop.wait(0.02):
        total = 0
        try:
            tree = [root, *root.children(recursive=True)]
        except psutil.Error:
            continue
        for p in tree:
            try:
                total += p.memory_info().rss
            except psutil.Error:
                pass
        peak[0] = max(peak[0], total / 1e6)


def one(case: str, method: str, level: str | None) -> dict:
    """Derive and compile one case in this process (`case`: a robot's name or chain<n>; `level`: every
    unit at this optimisation level), then time M and nle per call."""
    import timeit
    import warnings

    import numpy as np

    import eomgen as eg
    try:
        from eomgen.printers.build import extension
    except ImportError:  # a revision before the printers (--before)
        from eomgen.codegen import extension

    if level:
        extension.optimisation = lambda unit: level

    compile_s = []
    compile_module = extension.compile_module

    def timed(*args):
        t = time.perf_counter()
        compile_module(*args)
        compile_s.append(time.perf_counter() - t)

    extension.compile_module = timed
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # files with inertias Pinocchio takes as they are
        if case.startswith("chain"):
            from derive_chain import eomgen_chain

            system = eomgen_chain(int(case[5:]))
        else:
            system = eg.robots.load(case)
    t0 = time.perf_counter()
    eom = eg.derive(system, method=method)
    t1 = time.perf_counter()
    cpu0 = resource.getrusage(resource.RUSAGE_CHILDREN)
    f = eg.codegen(eom, backend="c")
    t2 = time.perf_counter()
    cpu1 = resource.getrusage(resource.RUSAGE_CHILDREN)
    row = {
        "derive_s": t1 - t0,
        "print_s": t2 - t1 - sum(compile_s),
        "compile_s": sum(compile_s),
        "total_s": t2 - t0,
        "compiler_cpu_s": cpu1.ru_utime + cpu1.ru_stime - cpu0.ru_utime - cpu0.ru_stime,
        "ops": sum(f.ops.values()),
    }
    f = f.bind({name: 1.0 + 0.01 * k for k, name in enumerate(f.parameters.names)}) if f.params else f
    q, u, _ = eg.random_states(system, 1, np.random.default_rng(0))
    t3 = time.perf_counter()
    f.b(q[0], u[0])  # b and g: compiled here where the build up front holds nle alone
    row["first_b_s"] = time.perf_counter() - t3
    cpu2 = resource.getrusage(resource.RUSAGE_CHILDREN)
    row["total_cpu_s"] = row["compiler_cpu_s"] + cpu2.ru_utime + cpu2.ru_stime - cpu1.ru_utime - cpu1.ru_stime
    for key, call in (("M_us", lambda: f.M(q[0])), ("nle_us", lambda: f.nle(q[0], u[0]))):
        row[key] = min(timeit.repeat(call, number=100, repeat=5)) / 100 * 1e6
    if not case.startswith("chain"):
        import pinocchio as pin

        from eomgen.model.urdf import pinocchio_configuration

        model = system.pinocchio_model
        data = model.createData()
        qp = pinocchio_configuration(system, q)[0]
        row["error"] = max(
            np.abs(f.M(q[0]) - pin.crba(model, data, qp)).max(),
            np.abs(f.nle(q[0], u[0]) - pin.nonLinearEffects(model, data, qp, u[0])).max(),
        )
    return row


def run(case: str, method: str, source: Path, limit_gb: float, timeout: float, level: str = "") -> dict:
    """`one` in a fresh process importing eomgen from `source`, with a fresh cache, under the limits."""

    def limit():
        size = int(limit_gb * 1e9)
        resource.setrlimit(resource.RLIMIT_AS, (size, size))

    load = os.getloadavg()[0]
    with tempfile.TemporaryDirectory() as cache:
        env = {**os.environ, "PYTHONPATH": str(source), "EOMGEN_CACHE": cache, "EOMGEN_PROGRESS": "0"}
        command = [sys.executable, __file__, "--one", case, "--method", method, f"--level={level}"]
        child = subprocess.Popen(
            command,
            env=env,
            stdout=subprocess.PIPE,
            stderr=subprocess.PIPE,
            text=True,
            preexec_fn=limit,
            start_new_session=True,
        )  # its own group: killed whole
        stop, peak = threading.Event(), [0.0]
        threading.Thread(target=peak_memory, args=(child.pid, stop, peak), daemon=True).start()
        try:
            out, err = child.communicate(timeout=timeout)
            failed = None if child.returncode == 0 else (err.strip().splitlines() or ["?"])[-1]
        except subprocess.TimeoutExpired:
            os.killpg(child.pid, signal.SIGKILL)
            child.communicate()
            failed = f"not done in {timeout:.0f} s"
        stop.set()
    row = {"case": case, "load": load, "peak_mb": peak[0]}
    return {**row, "failed": failed[:60]} if failed else {**row, **json.loads(out.strip().splitlines()[-1])}


def export(revision: str, folder: Path) -> Path:
    """src/ of git `revision` in `folder`."""
    folder.mkdir()
    archive = subprocess.run(
        ["git", "-C", str(HERE.parent), "archive", revision, "src"], capture_output=True, check=True
    ).stdout
    subprocess.run(["tar", "-x", "-C", str(folder)], input=archive, check=True)
    return folder / "src"


def text(row: dict) -> str:
    """A case's columns in the table."""
    if "failed" in row:
        return f"{row['failed'][:44]:>44} {row['peak_mb']:6.0f} {'':28}"
    return (
        f"{row['derive_s']:6.1f} {row['print_s']:6.1f} {row['compile_s']:7.1f} {row['total_s']:6.1f} "
        f"{row['compiler_cpu_s']:7.1f} {row['peak_mb']:6.0f} {row['M_us']:5.1f} {row['nle_us']:6.1f} "
        f"{row.get('first_b_s', 0):7.1f} {row.get('total_cpu_s', 0):7.1f}"
    )


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("robots", nargs="*")
    parser.add_argument("--method", default="recursive")
    parser.add_argument(
        "--chain", type=int, nargs="*", default=[], help="n-link chains (projected Newton-Euler)"
    )
    parser.add_argument("--before", help="git revision to compare with")
    parser.add_argument("--after", help="git revision to measure (default: this working tree)")
    parser.add_argument("--limit-gb", type=float, default=8.0)
    parser.add_argument("--timeout", type=float, default=900.0)
    parser.add_argument("--levels", action="store_true", help="every unit at -O1, -O2, -O3 (this tree)")
    parser.add_argument("--one", help=argparse.SUPPRESS)
    parser.add_argument("--level", default="", help=argparse.SUPPRESS)
    parser.add_argument("--out", default=results_io.default_path("builds"))
    args = parser.parse_args()
    if args.one:
        print(json.dumps(one(args.one, args.method, args.level)))
        return
    import eomgen as eg

    cases = [(name, args.method) for name in args.robots or eg.robots.names()]
    cases += [(f"chain{n}", "projected_newton_euler") for n in args.chain]
    rows = []
    with tempfile.TemporaryDirectory() as folder:
        after = export(args.after, Path(folder) / "after") if args.after else HERE.parent / "src"
        versions = {"after": (after, "")}
        if args.before:
            versions = {"before": (export(args.before, Path(folder) / "before"), ""), **versions}
        if args.levels:
            versions = {level: (after, level) for level in ("-O1", "-O2", "-O3")}
        columns = "derive  print compile  total gcc-cpu peak-MB  M-us nle-us first-b gcc-all"
        print(f"{'case':22} {'method':8} " + "  |  ".join(f"{v}: {columns}" for v in versions) + "   load")
        for case, method in cases:
            found = {
                v: run(case, method, source, args.limit_gb, args.timeout, level)
                for v, (source, level) in versions.items()
            }
            rows.append({"case": case, "method": method, **found})
            last = found[list(versions)[-1]]
            error = last.get("error")
            print(
                f"{case:22} {method[:8]:8} "
                + "  |  ".join(f"{'':{len(v) + 2}}{text(r)}" for v, r in found.items())
                + f"   {last['load']:.1f}"
                + (f"   |C - Pinocchio| {error:.0e}" if error is not None else ""),
                flush=True,
            )
    compiler = subprocess.run(["cc", "--version"], capture_output=True, text=True).stdout.splitlines()[0]
    cpu = next(
        (
            line.split(":", 1)[1].strip()
            for line in Path("/proc/cpuinfo").read_text().splitlines()
            if line.startswith("model name")
        ),
        platform.processor(),
    )
    from eomgen.printers.build import compile as units

    results_io.write(
        args.out,
        "builds",
        rows,
        compiler=compiler,
        cpu=cpu,
        cores=os.cpu_count(),
        before=args.before,
        flags=units.COMPILE,
        large_unit_chars=units.LARGE,
        unit_chars=units.UNIT,
        limit_gb=args.limit_gb,
        timeout_s=args.timeout,
    )


if __name__ == "__main__":
    main()
