"""The derivatives of the dynamics per call beside Pinocchio's, on ur5 and talos.

Per robot: the inverse dynamics' derivatives (∂τ/∂q, ∂τ/∂u) and the forward dynamics' derivatives
(∂u̇/∂q, ∂u̇/∂u, ∂u̇/∂τ), timed as eomgen's C from Python (the compiled backend) beside Pinocchio from Python
(computeRNEADerivatives, computeABADerivatives), each the best of 7 runs of the mean over 100 random
states, and in loops without Python: write_c's code in a C loop beside Pinocchio in a C++ loop
(benchmarks/kernels.py's harnesses and flags; Pinocchio's left out with a note when Eigen's headers are
missing or --no-cpp). Also the operations of the
generated functions and the time to derive and compile them. Prints a table and writes JSON.

Run: python benchmarks/derivatives.py [names ...] [--no-cpp] [--out ...]"""

from __future__ import annotations

import argparse
import subprocess
import sys
import tempfile
import time
import timeit
import warnings
from pathlib import Path

import numpy as np
import pinocchio as pin

import eomgen as eg
from eomgen.model import pinocchio_configuration
from eomgen.verify import to_pinocchio

sys.path.insert(0, str(Path(__file__).parent))
import kernels  # noqa: E402
import results_io  # noqa: E402

STATES, REPEAT = 100, 7
LOOPED = ["ID_derivatives", "FD_derivatives"]


def per_call(fn, calls: list) -> float:
    """Best of REPEAT runs of the mean µs per call over the states."""
    return (
        min(timeit.repeat(lambda: [fn(*args) for args in calls], number=1, repeat=REPEAT))
        / len(calls)
        * 1e6
    )


def bench(name: str, harness: Path | str) -> dict:
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # files with inertias Pinocchio takes as they are
        system = eg.robots.load(name)
    rng = np.random.default_rng(0)
    q, u, ud = eg.random_states(system, STATES, rng)
    tau = rng.uniform(-10, 10, u.shape)
    t0 = time.perf_counter()
    eom = eg.derive(system, method="recursive")
    f = eg.codegen(eom, backend="c")
    f.forward_dynamics_derivatives(q[0], u[0], tau[0])  # derives and compiles the derivatives
    row = {
        "robot": name,
        "nv": len(system.u),
        "build_s": time.perf_counter() - t0,
        "ops_ID_derivatives": f.ops["ID_derivatives"],
        "ops_FD_parts": f.ops["FD_parts"],
    }
    model = getattr(system, "pinocchio_model", None) or to_pinocchio(system)  # continuous joints: cos, sin
    data = model.createData()
    qp = pinocchio_configuration(system, q)
    row["c_id_us"] = per_call(f.inverse_dynamics_derivatives, list(zip(q, u, ud)))
    row["c_fd_us"] = per_call(f.forward_dynamics_derivatives, list(zip(q, u, tau)))
    row["pin_id_us"] = per_call(
        lambda *a: pin.computeRNEADerivatives(model, data, *a), list(zip(qp, u, ud))
    )
    row["pin_fd_us"] = per_call(
        lambda *a: pin.computeABADerivatives(model, data, *a), list(zip(qp, u, tau))
    )
    with tempfile.TemporaryDirectory() as tmp:  # the loops of benchmarks/kernels.py, ns → µs
        ours = kernels.c_loop(eom, Path(tmp), list(zip(q, u, tau)), LOOPED, kernels.FLAGS)
        row["c_loop_id_us"], row["c_loop_fd_us"] = (ours[k][0] / 1e3 for k in LOOPED)
        if isinstance(harness, str):
            row["pin_loop_note"] = harness
        else:
            theirs = kernels.cpp_loop(harness, model, Path(tmp), list(zip(qp, u, tau)), LOOPED)
            row["pin_loop_id_us"], row["pin_loop_fd_us"] = (theirs[k][0] / 1e3 for k in LOOPED)
    return row


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("names", nargs="*", default=["ur5", "talos"])
    ap.add_argument(
        "--no-cpp", action="store_true", help="leave out Pinocchio's C++ loop (a few minutes to build)"
    )
    ap.add_argument("--out", default=results_io.default_path("derivatives"))
    args = ap.parse_args()
    eg.quiet()
    print(
        f"{'robot':8s} {'nv':>3s} {'build':>7s} {'ops':>7s}  {'':4s}{'C (Py)':>8s} {'pin (Py)':>9s}"
        f" {'ratio':>6s} {'C loop':>8s} {'pin C++':>8s} {'ratio':>6s}"
    )
    rows = []
    harness = "--no-cpp" if args.no_cpp else kernels.cpp_harness(LOOPED, kernels.FLAGS)
    for name in args.names:
        r = bench(name, harness)
        rows.append(r)
        for kind, label in (("id", "ID"), ("fd", "FD")):
            theirs = r.get(f"pin_loop_{kind}_us")
            loop = (
                f"{theirs:8.2f} {r[f'c_loop_{kind}_us'] / theirs:6.2f}" if theirs else f"{'—':>8s} {'':6s}"
            )
            print(
                f"{name:8s} {r['nv']:3d} {r['build_s']:6.1f}s {r['ops_ID_derivatives']:7d} "
                f" {label:4s}{r[f'c_{kind}_us']:8.2f} {r[f'pin_{kind}_us']:9.2f}"
                f" {r[f'c_{kind}_us'] / r[f'pin_{kind}_us']:6.2f} {r[f'c_loop_{kind}_us']:8.2f} {loop}",
                flush=True,
            )
        if "pin_loop_note" in r:
            print(f"  Pinocchio's C++ loop: {r['pin_loop_note']}")
    results_io.write(
        args.out,
        "derivatives",
        rows,
        pinocchio=pin.__version__,
        states=STATES,
        cc=subprocess.run(["cc", "--version"], capture_output=True, text=True).stdout.split("\n")[0],
    )


if __name__ == "__main__":
    main()
