"""The derivatives of the dynamics per call beside Pinocchio's, on ur5 and talos.

Per robot: the inverse dynamics' derivatives (∂τ/∂q, ∂τ/∂u) and the forward dynamics' derivatives
(∂u̇/∂q, ∂u̇/∂u, ∂u̇/∂τ), timed as eomgen's C from Python (the compiled backend), eomgen's C in a C loop
(write_c's code with a timing harness, cc -O2 as the extension), Pinocchio from Python
(computeRNEADerivatives, computeABADerivatives) and Pinocchio in a C++ loop (the pin wheel's headers and
library, Eigen's headers from the cmeel-eigen package; left out with a note when they are missing or
--no-cpp). Each time is the best of 7 runs of the mean over 100 random states. Also the operations of the
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
import results_io  # noqa: E402

STATES, REPEAT = 100, 7

C_LOOP = r"""#include <stdio.h>
#include <string.h>
#include <time.h>
#include "eom.h"
#define N @states@

static double q[N][EOM_NQ], u[N][EOM_NV], ud[N][EOM_NV], p[EOM_NP + 1];
static double D[2 * EOM_NV * EOM_NV], F[3 * EOM_NV * EOM_NV];

static double now(void)
{
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return t.tv_sec * 1e6 + t.tv_nsec * 1e-3;
}

int main(void)
{
    for (int k = 0; k < N; k++) {
        for (int i = 0; i < EOM_NQ; i++) if (scanf("%lf", &q[k][i]) != 1) return 1;
        for (int i = 0; i < EOM_NV; i++) if (scanf("%lf", &u[k][i]) != 1) return 1;
        for (int i = 0; i < EOM_NV; i++) if (scanf("%lf", &ud[k][i]) != 1) return 1;
    }
    double best_id = 1e300, best_fd = 1e300, sum = 0.0;
    for (int r = 0; r < @repeat@; r++) {
        double t0 = now();
        for (int k = 0; k < N; k++) {
            memset(D, 0, sizeof D);
            eom_ID_derivatives(q[k], u[k], ud[k], p, D);
            sum += D[k % (2 * EOM_NV * EOM_NV)];
        }
        double t1 = now();
        for (int k = 0; k < N; k++) {
            eom_FD_derivatives(q[k], u[k], ud[k], p, F);
            sum += F[k % (3 * EOM_NV * EOM_NV)];
        }
        double t2 = now();
        best_id = (t1 - t0) / N < best_id ? (t1 - t0) / N : best_id;
        best_fd = (t2 - t1) / N < best_fd ? (t2 - t1) / N : best_fd;
    }
    printf("%.4f %.4f %g\n", best_id, best_fd, sum);
    return 0;
}
"""

CPP_LOOP = r"""#include <pinocchio/multibody.hpp>
#include <pinocchio/algorithm/rnea-derivatives.hpp>
#include <pinocchio/algorithm/aba-derivatives.hpp>
#include <pinocchio/serialization.hpp>
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <iostream>
#include <vector>

int main(int, char **argv)
{
    pinocchio::Model model;
    model.loadFromText(argv[1]);
    pinocchio::Data data(model);
    std::vector<Eigen::VectorXd> q, v, a;
    for (int k = 0; k < @states@; ++k) {
        Eigen::VectorXd x(model.nq), y(model.nv), z(model.nv);
        for (int i = 0; i < model.nq; ++i) std::cin >> x[i];
        for (int i = 0; i < model.nv; ++i) std::cin >> y[i];
        for (int i = 0; i < model.nv; ++i) std::cin >> z[i];
        q.push_back(x), v.push_back(y), a.push_back(z);
    }
    double best_rnea = 1e300, best_aba = 1e300;
    for (int r = 0; r < @repeat@; ++r) {
        auto t0 = std::chrono::steady_clock::now();
        for (std::size_t k = 0; k < q.size(); ++k)
            pinocchio::computeRNEADerivatives(model, data, q[k], v[k], a[k]);
        auto t1 = std::chrono::steady_clock::now();
        for (std::size_t k = 0; k < q.size(); ++k)
            pinocchio::computeABADerivatives(model, data, q[k], v[k], a[k]);
        auto t2 = std::chrono::steady_clock::now();
        double n = q.size();
        best_rnea = std::min(best_rnea, std::chrono::duration<double, std::micro>(t1 - t0).count() / n);
        best_aba = std::min(best_aba, std::chrono::duration<double, std::micro>(t2 - t1).count() / n);
    }
    std::printf("%.4f %.4f\n", best_rnea, best_aba);
}
"""
PREFIX = next(p for p in Path(pin.__file__).parents if p.name == "cmeel.prefix")  # the pin wheel's files
# Pinocchio's compile definitions (its CMake package), and the instantiations its library holds
DEFINES = [
    "-DBOOST_MPL_LIMIT_LIST_SIZE=30",
    "-DBOOST_MPL_LIMIT_VECTOR_SIZE=30",
    "-DBOOST_FUSION_INVOKE_MAX_ARITY=12",
    "-DBOOST_MPL_CFG_NO_PREPROCESSED_HEADERS",
    "-DPINOCCHIO_ENABLE_TEMPLATE_INSTANTIATION",
]


def per_call(fn, calls: list) -> float:
    """Best of REPEAT runs of the mean µs per call over the states."""
    return (
        min(timeit.repeat(lambda: [fn(*args) for args in calls], number=1, repeat=REPEAT))
        / len(calls)
        * 1e6
    )


def text(states) -> str:
    return "".join(" ".join(repr(float(x)) for x in np.concatenate(s)) + "\n" for s in states)


def c_loop(eom, folder: Path, states) -> tuple[float, float]:
    """(ID derivatives, FD derivatives) µs per call from write_c's code in a C loop."""
    c_path, _ = eg.write_c(eom, folder, name="eom")
    harness = folder / "loop.c"
    harness.write_text(C_LOOP.replace("@states@", str(STATES)).replace("@repeat@", str(REPEAT * 5)))
    exe = folder / "loop"
    subprocess.run(
        [
            "cc",
            "-O2",
            "-fno-math-errno",
            "-ftree-vectorize",
            f"-I{folder}",
            str(harness),
            str(c_path),
            "-o",
            str(exe),
            "-lm",
        ],
        check=True,
    )
    out = subprocess.run([str(exe)], input=text(states), capture_output=True, text=True, check=True).stdout
    return tuple(float(x) for x in out.split()[:2])


def cpp_loop(model, folder: Path, states) -> tuple[float, float] | str:
    """(computeRNEADerivatives, computeABADerivatives) µs per call in a C++ loop, or why not."""
    include = PREFIX / "include"
    if not (include / "eigen3").is_dir() or not (include / "pinocchio").is_dir():
        return "no Pinocchio or Eigen headers (pip install cmeel-eigen)"
    source, exe = folder / "loop.cpp", folder / "loop_cpp"
    source.write_text(CPP_LOOP.replace("@states@", str(STATES)).replace("@repeat@", str(REPEAT * 5)))
    build = subprocess.run(
        [
            "c++",
            "-O3",
            "-DNDEBUG",
            "-std=c++17",
            *DEFINES,
            f"-I{include}",
            f"-I{include / 'eigen3'}",
            str(source),
            "-o",
            str(exe),
            f"-L{PREFIX / 'lib'}",
            "-lpinocchio_default",
            "-lboost_serialization",
            f"-Wl,-rpath,{PREFIX / 'lib'}",
        ],
        capture_output=True,
        text=True,
    )
    if build.returncode != 0:
        return f"the C++ harness does not build: {build.stderr[-300:]}"
    model.saveToText(str(folder / "model.txt"))
    out = subprocess.run(
        [str(exe), str(folder / "model.txt")],
        input=text(states),
        capture_output=True,
        text=True,
        check=True,
    ).stdout
    return tuple(float(x) for x in out.split()[:2])


def bench(name: str, cpp: bool) -> dict:
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
    model = to_pinocchio(system)
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
    with tempfile.TemporaryDirectory() as tmp:
        row["c_loop_id_us"], row["c_loop_fd_us"] = c_loop(eom, Path(tmp), list(zip(q, u, tau)))
        looped = cpp_loop(model, Path(tmp), list(zip(qp, u, tau))) if cpp else "--no-cpp"
    if isinstance(looped, str):
        row["pin_loop_note"] = looped
    else:
        row["pin_loop_id_us"], row["pin_loop_fd_us"] = looped
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
    for name in args.names:
        r = bench(name, not args.no_cpp)
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
