"""The generated kernels beside Pinocchio's without Python: write_c's plain C in a C loop against
Pinocchio's C++ in a C++ loop, on the same states, both compiled here with the same flags.

Per robot (ur5, panda, solo12, talos, tiago, tiago_dual by default) and kernel:

| eomgen (write_c)        | Pinocchio                  |
|-------------------------|----------------------------|
| M                       | crba (LOCAL, symmetrised)  |
| nle                     | nonLinearEffects           |
| g                       | computeGeneralizedGravity  |
| ID (τ of q, u, u̇)      | rnea                       |
| ID_derivatives          | computeRNEADerivatives     |
| FD_derivatives          | computeABADerivatives      |
| Y (the regressor)       | computeJointTorqueRegressor (10 per link; eomgen: + armature, friction) |

Each time is the best of `REPEAT` runs of the mean over `STATES` random states (ns per call). The
outputs of the first `CHECKED` states are compared (max |difference| / max(1, max |value|)), and a
kernel that disagrees by more than 1e-9 is reported. Pinocchio is compiled from its headers (the pin
wheel ships them; Eigen's come from the cmeel-eigen package, which is not a dependency of eomgen: without
it the Pinocchio column is left out and said so) with the same -O3 -march=native as the generated C, so
neither side runs code built for another CPU. Also the derivation and build times and the operations.

Run: python benchmarks/kernels.py [names ...] [--kernels M nle ...] [--flags "-O3 -march=native"]"""

from __future__ import annotations

import argparse
import hashlib
import os
import platform
import shlex
import subprocess
import sys
import tempfile
import time
import warnings
from pathlib import Path

import numpy as np
import pinocchio as pin

import eomgen as eg
from eomgen.model import pinocchio_configuration
from eomgen.verify import to_pinocchio

sys.path.insert(0, str(Path(__file__).parent))
import results_io  # noqa: E402

STATES, REPEAT, CHECKED = 200, 21, 5
ROBOTS = ["ur5", "panda", "solo12", "talos", "tiago", "tiago_dual"]
FLAGS = "-O3 -march=native"
# kernel: (the states it reads, the output's size in nv, Pinocchio's call, Pinocchio's output)
KERNELS = {
    "M": ("q", 1, "pinocchio::crba(model, data, q[k])", "sym(data.M)"),
    "nle": ("qu", 0, "pinocchio::nonLinearEffects(model, data, q[k], v[k])", "data.nle"),
    "g": ("q", 0, "pinocchio::computeGeneralizedGravity(model, data, q[k])", "data.g"),
    "ID": ("qua", 0, "pinocchio::rnea(model, data, q[k], v[k], a[k])", "data.tau"),
    "ID_derivatives": (
        "qua",
        2,
        "pinocchio::computeRNEADerivatives(model, data, q[k], v[k], a[k])",
        "cat({data.dtau_dq, data.dtau_dv})",
    ),
    "FD_derivatives": (
        "qua",
        3,
        "pinocchio::computeABADerivatives(model, data, q[k], v[k], a[k])",
        "cat({data.ddq_dq, data.ddq_dv, sym(data.Minv)})",
    ),
    "Y": ("qua", "columns", "pinocchio::computeJointTorqueRegressor(model, data, q[k], v[k], a[k])",
          "data.jointTorqueRegressor"),
}
DEFAULT_KERNELS = ["M", "nle", "g", "ID"]
CACHE = Path.home() / ".cache" / "eomgen-benchmarks"  # the C++ harness, built once

C_LOOP = r"""#include <stdio.h>
#include <string.h>
#include <time.h>
#include "eom.h"
#define N @states@

static double q[N][EOM_NQ], u[N][EOM_NV], a[N][EOM_NV], p[EOM_NP + 1], out[@size@];
static volatile double sink;

static double now(void)
{
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return t.tv_sec * 1e9 + t.tv_nsec;
}

/* f over the states REPEAT times: the best mean ns per call; then the outputs of the first CHECKED */
static void run(const char *name, void (*f)(const double *, const double *, const double *, const double *,
                                          double *), int size)
{
    double best = 1e300;
    memset(out, 0, sizeof out);  /* only nonzero entries are written, the same ones every call */
    for (int r = 0; r < @repeat@; r++) {
        double t0 = now();
        for (int k = 0; k < N; k++) {
            f(q[k], u[k], a[k], p, out);
            sink = out[k % size];
        }
        double t = (now() - t0) / N;
        best = t < best ? t : best;
    }
    printf("%s %.3f", name, best);
    for (int k = 0; k < @checked@; k++) {
        memset(out, 0, sizeof out);
        f(q[k], u[k], a[k], p, out);
        for (int i = 0; i < size; i++) printf(" %.17g", out[i]);
    }
    printf("\n");
}

int main(void)
{
    for (int k = 0; k < N; k++) {
        for (int i = 0; i < EOM_NQ; i++) if (scanf("%lf", &q[k][i]) != 1) return 1;
        for (int i = 0; i < EOM_NV; i++) if (scanf("%lf", &u[k][i]) != 1) return 1;
        for (int i = 0; i < EOM_NV; i++) if (scanf("%lf", &a[k][i]) != 1) return 1;
    }
@runs@
    return 0;
}
"""

CPP_LOOP = r"""#include <pinocchio/multibody.hpp>
#include <pinocchio/algorithm/crba.hpp>
#include <pinocchio/algorithm/rnea.hpp>
#include <pinocchio/algorithm/rnea-derivatives.hpp>
#include <pinocchio/algorithm/aba-derivatives.hpp>
#include <pinocchio/algorithm/regressor.hpp>
#include <pinocchio/serialization.hpp>
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <iostream>
#include <vector>

using Matrix = Eigen::MatrixXd;

static Matrix sym(const Matrix &A)  // the upper triangle Pinocchio fills, mirrored
{
    Matrix S = A.triangularView<Eigen::Upper>();
    S.triangularView<Eigen::StrictlyLower>() = S.transpose();
    return S;
}

static Matrix cat(std::initializer_list<Matrix> blocks)  // side by side, as eomgen's [A | B | C]
{
    Eigen::Index cols = 0;
    for (const auto &b : blocks) cols += b.cols();
    Matrix S(blocks.begin()->rows(), cols);
    cols = 0;
    for (const auto &b : blocks) S.middleCols(cols, b.cols()) = b, cols += b.cols();
    return S;
}

template <typename Call, typename Output>
static void run(const char *name, int n, Call call, Output output)
{
    double best = 1e300;
    for (int r = 0; r < @repeat@; ++r) {
        auto t0 = std::chrono::steady_clock::now();
        for (int k = 0; k < n; ++k) call(k);
        best = std::min(best, std::chrono::duration<double, std::nano>(std::chrono::steady_clock::now() - t0)
                                  .count() / n);
    }
    std::printf("%s %.3f", name, best);
    for (int k = 0; k < @checked@; ++k) {
        call(k);
        Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> out = output();
        for (Eigen::Index i = 0; i < out.size(); ++i) std::printf(" %.17g", out.data()[i]);
    }
    std::printf("\n");
}

int main(int, char **argv)  // model.txt, the number of states (read from stdin)
{
    pinocchio::Model model;
    model.loadFromText(argv[1]);
    pinocchio::Data data(model);
    std::vector<Eigen::VectorXd> q, v, a;
    for (int k = 0, n = std::atoi(argv[2]); k < n; ++k) {
        Eigen::VectorXd x(model.nq), y(model.nv), z(model.nv);
        for (int i = 0; i < model.nq; ++i) std::cin >> x[i];
        for (int i = 0; i < model.nv; ++i) std::cin >> y[i];
        for (int i = 0; i < model.nv; ++i) std::cin >> z[i];
        q.push_back(x), v.push_back(y), a.push_back(z);
    }
@runs@
}
"""
PREFIX = next(p for p in Path(pin.__file__).parents if p.name == "cmeel.prefix")  # the pin wheel's files
# Pinocchio's compile definitions (its CMake package); its algorithms are compiled here from the headers
DEFINES = [
    "-DBOOST_MPL_LIMIT_LIST_SIZE=30",
    "-DBOOST_MPL_LIMIT_VECTOR_SIZE=30",
    "-DBOOST_FUSION_INVOKE_MAX_ARITY=12",
    "-DBOOST_MPL_CFG_NO_PREPROCESSED_HEADERS",
]


def text(states) -> str:
    return "".join(" ".join(repr(float(x)) for x in np.concatenate(s)) + "\n" for s in states)


def size(kernel: str, nv: int, columns: int = 0) -> int:
    """The entries of a kernel's output: nv for a vector, k nv² for k matrices side by side, nv × columns
    for the regressor (eomgen's columns)."""
    if KERNELS[kernel][1] == "columns":
        return nv * columns
    return KERNELS[kernel][1] * nv * nv or nv


def parse(out: str, kernels: list[str]) -> dict[str, tuple[float, np.ndarray]]:
    """{kernel: (ns per call, the checked outputs, one row per state)} from a harness's lines."""
    result = {}
    for line, kernel in zip(out.splitlines(), kernels):
        name, ns, *values = line.split()
        assert name == kernel, (name, kernel)
        result[kernel] = float(ns), np.array(values, float).reshape(CHECKED, -1)
    return result


def c_loop(eom, folder: Path, states, kernels: list[str], flags: str) -> dict:
    """{kernel: (ns per call, outputs)} of write_c's functions in a C loop, and the build's seconds."""
    t0 = time.perf_counter()
    c_path, _ = eg.write_c(eom, folder, name="eom", derivatives=any("derivatives" in k for k in kernels))
    written = time.perf_counter() - t0
    nv, columns = len(eom.u), regressor_columns(eom, kernels)
    runs = "\n".join(f'    run("{k}", eom_{k}, {size(k, nv, columns)});' for k in kernels)
    harness = folder / "loop.c"
    harness.write_text(
        C_LOOP.replace("@states@", str(len(states)))
        .replace("@size@", str(max(size(k, nv, columns) for k in [*kernels, "FD_derivatives"])))
        .replace("@repeat@", str(REPEAT))
        .replace("@checked@", str(CHECKED))
        .replace("@runs@", runs)
    )
    exe = folder / "loop"
    t0 = time.perf_counter()
    subprocess.run(
        [
            "cc",
            *shlex.split(flags),
            "-fno-math-errno",
            f"-I{folder}",
            str(harness),
            str(c_path),
            "-o",
            str(exe),
        ]
        + ["-lm"],
        check=True,
    )
    compiled = time.perf_counter() - t0
    out = subprocess.run([str(exe)], input=text(states), capture_output=True, text=True, check=True).stdout
    return {"write_c_s": written, "cc_s": compiled, **parse(out, kernels)}


def regressor_columns(eom, kernels: list[str]) -> int:
    """The columns of eomgen's full regressor (10 per link, armature, three friction kinds), if asked."""
    return len(eg.regressor(eom).names) if "Y" in kernels else 0


def cpp_harness(kernels: list[str], flags: str) -> Path | str:
    """Pinocchio's C++ loop over the kernels, or why not. The model is read at run time, so one build
    (minutes, a few GB) serves every robot and later runs: it is kept in CACHE by a hash of its source,
    flags, compiler and Pinocchio."""
    include = PREFIX / "include"
    if not (include / "eigen3").is_dir() or not (include / "pinocchio").is_dir():
        return "no Pinocchio or Eigen headers (pip install cmeel-eigen)"
    runs = "\n".join(
        f'    run("{k}", int(q.size()), [&](int k) {{ {KERNELS[k][2]}; }}, [&] {{ return Matrix('
        f"{KERNELS[k][3]}); }});"
        for k in kernels
    )
    text = CPP_LOOP.replace("@repeat@", str(REPEAT)).replace("@checked@", str(CHECKED))
    text = text.replace("@runs@", runs)
    compiler = subprocess.run(["c++", "--version"], capture_output=True, text=True).stdout
    key = hashlib.sha256(repr((text, flags, compiler, pin.__version__)).encode()).hexdigest()[:16]
    folder = CACHE / key
    source, exe = folder / "loop.cpp", folder / "loop_cpp"
    if exe.exists():
        return exe
    folder.mkdir(parents=True, exist_ok=True)
    source.write_text(text)
    command = ["c++", *shlex.split(flags), "-DNDEBUG", "-std=c++17", *DEFINES, f"-I{include}"]
    command += [f"-I{include / 'eigen3'}", str(source), "-o", str(exe), f"-L{PREFIX / 'lib'}"]
    command += ["-lpinocchio_default", "-lboost_serialization", f"-Wl,-rpath,{PREFIX / 'lib'}"]
    build = subprocess.run(command, capture_output=True, text=True)
    if build.returncode != 0:
        return f"the C++ harness does not build: {build.stderr[-300:]}"
    return exe


def cpp_loop(exe: Path, model, folder: Path, states, kernels: list[str]) -> dict:
    """{kernel: (ns per call, outputs)} of Pinocchio in the C++ loop `exe`."""
    model.saveToText(str(folder / "model.txt"))
    out = subprocess.run(
        [str(exe), str(folder / "model.txt"), str(len(states))],
        input=text(states),
        capture_output=True,
        text=True,
        check=True,
    ).stdout
    return parse(out, kernels)


def agreement(ours: np.ndarray, theirs: np.ndarray) -> float:
    """max |difference| / max(1, max |value|) over the checked states."""
    return float(np.max(np.abs(ours - theirs)) / max(1.0, np.max(np.abs(theirs))))


def bench(name: str, kernels: list[str], flags: str, harness: Path | str) -> dict:
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # files with inertias Pinocchio takes as they are
        system = eg.robots.load(name)
    rng = np.random.default_rng(0)
    q, u, ud = eg.random_states(system, STATES, rng)
    t0 = time.perf_counter()
    eom = eg.derive(system)
    row = {"robot": name, "nv": len(system.u), "method": eom.method, "derive_s": time.perf_counter() - t0}
    model = getattr(system, "pinocchio_model", None) or to_pinocchio(system)  # continuous joints: cos, sin
    with tempfile.TemporaryDirectory() as tmp:
        ours = c_loop(eom, Path(tmp), list(zip(q, u, ud)), kernels, flags)
        row["write_c_s"], row["cc_s"] = ours.pop("write_c_s"), ours.pop("cc_s")
        if isinstance(harness, str):
            row["pinocchio_note"], theirs = harness, {}
        else:
            theirs = cpp_loop(
                harness, model, Path(tmp), list(zip(pinocchio_configuration(system, q), u, ud)), kernels
            )
    for k in kernels:
        row[f"{k}_ns"] = ours[k][0]
        if k in theirs:
            mine, pins = ours[k][1], theirs[k][1]
            if k == "Y":  # Pinocchio's 10 per link: the first columns of eomgen's
                mine = mine.reshape(CHECKED, len(system.u), -1)[..., : pins.shape[1] // len(system.u)]
            row[f"{k}_pin_ns"] = theirs[k][0]
            row[f"{k}_ratio"] = ours[k][0] / theirs[k][0]
            row[f"{k}_error"] = agreement(mine.reshape(CHECKED, -1), pins)
    return row


def cpu() -> str:
    for line in Path("/proc/cpuinfo").read_text().splitlines() if Path("/proc/cpuinfo").exists() else []:
        if line.startswith("model name"):
            return line.split(":", 1)[1].strip()
    return platform.processor()


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("names", nargs="*", default=ROBOTS)
    ap.add_argument("--kernels", nargs="+", default=DEFAULT_KERNELS, choices=list(KERNELS))
    ap.add_argument("--flags", default=FLAGS, help="compiler flags of both loops")
    ap.add_argument("--no-cpp", action="store_true", help="leave out Pinocchio's C++ loop")
    ap.add_argument("--out", default=results_io.default_path("kernels"))
    args = ap.parse_args()
    eg.quiet()
    cc = subprocess.run(["cc", "--version"], capture_output=True, text=True).stdout.split("\n")[0]
    print(
        f"{cc}; flags {args.flags}; {cpu()}; load {os.getloadavg()[0]:.2f}; {STATES} states, best of"
        f" {REPEAT}"
    )
    print(
        f"{'robot':11s} {'nv':>3s} {'kernel':15s} {'eomgen ns':>10s} {'pin ns':>10s} {'ratio':>6s}"
        f" {'error':>8s}"
    )
    rows, bad = [], []
    harness = "--no-cpp" if args.no_cpp else cpp_harness(args.kernels, args.flags)
    for name in args.names:
        r = bench(name, args.kernels, args.flags, harness)
        rows.append(r)
        for k in args.kernels:
            theirs = (
                f"{r[f'{k}_pin_ns']:10.1f} {r[f'{k}_ratio']:6.2f} {r[f'{k}_error']:8.1e}"
                if f"{k}_pin_ns" in r
                else f"{'—':>10s}"
            )
            print(f"{name:11s} {r['nv']:3d} {k:15s} {r[f'{k}_ns']:10.1f} {theirs}", flush=True)
            if r.get(f"{k}_error", 0) > 1e-9:
                bad.append(f"{name} {k}")
        if "pinocchio_note" in r:
            print(f"  Pinocchio's C++ loop: {r['pinocchio_note']}")
    results_io.write(
        args.out,
        "kernels",
        rows,
        pinocchio=pin.__version__,
        states=STATES,
        repeat=REPEAT,
        cc=cc,
        flags=args.flags,
        cpu=cpu(),
        load=os.getloadavg()[0],
    )
    if bad:
        sys.exit(f"disagree with Pinocchio beyond 1e-9: {', '.join(bad)}")


if __name__ == "__main__":
    main()
