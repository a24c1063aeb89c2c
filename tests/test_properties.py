"""Property-based tests: random trees with adversarial names (see `strategies`).

(a) Every derivation method equals Pinocchio built with its own API: M (crba), b + g
    (nonLinearEffects), g (computeGeneralizedGravity), T and U (computeKineticEnergy,
    computePotentialEnergy, plus each spring's ½ k (ℓ − l0)²), the Jacobians of every body origin and frame
    (getFrameJacobian, LOCAL_WORLD_ALIGNED) and each load's generalized force (Jᵀ F from Pinocchio's
    Jacobians), relative 1e-9.
(b) Every output path gives the same numbers (1e-12): NumPy, the module of `write_module` imported
    from a temp folder, the compiled extension, and `write_c` compiled with cc and a small driver.
(c) The four derivation methods agree with each other.

The default run is bounded (derandomized, a few dozen examples; compiled code for a handful);
`pytest -m slow` runs the same properties on 2,000 examples (200 for the compiled ones)."""
from __future__ import annotations

import importlib.util
import os
import subprocess

import numpy as np
import pytest
from hypothesis import HealthCheck, Phase, given, settings
from hypothesis import strategies as st

import eomgen as eg
import strategies as S
from models import close

METHODS = ["projected_newton_euler", "lagrange", "free_cut", "recursive"]
# Shrinking a failure re-derives the model hundreds of times (minutes): on only with
# EOMGEN_SHRINK=1, to get a minimal reproduction of a failure found in the default run.
PHASES = [Phase.explicit, Phase.reuse, Phase.generate] + ([Phase.shrink] if os.environ.get("EOMGEN_SHRINK") else [])
COMMON = dict(deadline=None, derandomize=True, database=None, print_blob=True, phases=PHASES,
              suppress_health_check=[HealthCheck.too_slow, HealthCheck.data_too_large, HealthCheck.filter_too_much])
SLOW = 2000


def states(tree, n: int, seed: int = 0):
    rng = np.random.default_rng(seed)
    return [S.random_state(tree, rng) for _ in range(n)]


def frame_names(tree) -> list[str]:
    return [b.name for b in tree.bodies] + [f.name for f in tree.frames]


# --- (a) against Pinocchio --------------------------------------------------------------------
def equations(tree, method: str) -> eg.EquationsOfMotion:
    return eg.derive(S.eomgen_system(tree), method=method)


def check_pinocchio(tree, eom: eg.EquationsOfMotion) -> None:
    ref = S.PinocchioTree(tree)
    f = eg.codegen(eom)
    for k, (q, u) in enumerate(states(tree, 5, seed=len(tree.bodies))):
        M, b, g = ref.dynamics(q, u)
        close(f.M(q), M, 1e-9, f"M, state {k}")
        close(f.b(q, u), b, 1e-9, f"b, state {k}")
        close(f.g(q), g, 1e-9, f"g, state {k}")
        T, U = ref.energies(q, u)
        close(np.ravel(f.T(q, u)), [T], 1e-9, f"T, state {k}")
        close(np.ravel(f.U(q)), [U], 1e-9, f"U, state {k}")
        close(f.nle(q, u), b + g, 1e-9, f"b + g, state {k}")
        for name, J in ref.jacobians(q).items():
            close(f.jacobian(name, q), J, 1e-9, f"J of {name!r}, state {k}")
        if tree.loads and min(ref.spring_lengths(q), default=1.0) > 1e-3:
            forces = ref.load_forces(q)
            for name, tau in forces.items():
                close(f.tau_of(name, q, u), tau, 1e-9, f"tau of load {name!r}, state {k}")
            close(f.tau(q, u), sum(forces.values()), 1e-9, f"tau, state {k}")


@settings(max_examples=30, **COMMON)  # more: the slow _many variant
@given(tree=S.trees(), method=st.sampled_from(METHODS))
def test_equals_pinocchio(tree, method):
    check_pinocchio(tree, equations(tree, method))


@pytest.mark.slow
@settings(max_examples=SLOW, **COMMON)
@given(tree=S.trees(), method=st.sampled_from(METHODS))
def test_equals_pinocchio_many(tree, method):
    check_pinocchio(tree, equations(tree, method))


# --- (c) the methods agree --------------------------------------------------------------------
def check_methods_agree(tree) -> None:
    system = S.eomgen_system(tree)
    fs = {m: eg.codegen(eg.derive(system, method=m)) for m in METHODS}
    for k, (q, u) in enumerate(states(tree, 3, seed=1)):
        ref = fs[METHODS[0]]
        out0 = {"M": ref.M(q), "b": ref.b(q, u), "g": ref.g(q), "tau": ref.tau(q, u)}
        out0.update({f"tau of {n!r}": ref.tau_of(n, q, u) for n in (load.name for load in tree.loads)})
        for m in METHODS[1:]:
            f = fs[m]
            out = {"M": f.M(q), "b": f.b(q, u), "g": f.g(q), "tau": f.tau(q, u)}
            out.update({f"tau of {n!r}": f.tau_of(n, q, u) for n in (load.name for load in tree.loads)})
            for key in out0:
                close(out[key], out0[key], 1e-10, f"{key}: {m} vs {METHODS[0]}, state {k}")


@settings(max_examples=8, **COMMON)
@given(tree=S.trees(max_bodies=5))
def test_methods_agree(tree):
    check_methods_agree(tree)


@pytest.mark.slow
@settings(max_examples=SLOW, **COMMON)
@given(tree=S.trees())
def test_methods_agree_many(tree):
    check_methods_agree(tree)


# --- (b) every output path gives the same numbers ---------------------------------------------
def import_written_module(eom, folder, tag: str):
    path = eg.write_module(eom, folder / f"written_{tag}.py")
    spec = importlib.util.spec_from_file_location(f"eomgen_written_{tag}", path)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def check_numpy_and_module(tree, eom: eg.EquationsOfMotion, folder, tag: str) -> None:
    system, f = eom.system, eg.codegen(eom)
    mod = import_written_module(eom, folder, tag)
    moving = [b.name for b, s in zip(system.bodies, tree.bodies) if s.kind != "fixed"]
    assert list(mod.FRAMES) == moving + [fr.name for fr in tree.frames]
    assert list(mod.COORDINATES) == [str(x) for x in system.q]
    pairs = states(tree, 4, seed=2)
    qs, us = np.array([q for q, _ in pairs]), np.array([u for _, u in pairs])
    for k, (q, u) in enumerate(pairs):
        close(mod.M(q), f.M(q), 1e-12, f"module M, state {k}")
        close(mod.b(q, u), f.b(q, u), 1e-12, f"module b, state {k}")
        close(mod.g(q), f.g(q), 1e-12, f"module g, state {k}")
        for name in mod.FRAMES:
            close(mod.jacobian(name, q), f.jacobian(name, q), 1e-12, f"module J of {name!r}, state {k}")
    close(f.M(qs), np.array([f.M(q) for q in qs]), 1e-12, "NumPy batched M")
    close(f.b(qs, us), np.array([f.b(q, u) for q, u in pairs]), 1e-12, "NumPy batched b")
    close(mod.g(qs), np.array([f.g(q) for q in qs]), 1e-12, "module batched g")


@settings(max_examples=12, **COMMON)
@given(tree=S.trees(), method=st.sampled_from(METHODS))
def test_numpy_and_written_module_agree(tree, method, tmp_path_factory):
    folder = tmp_path_factory.mktemp("module")
    check_numpy_and_module(tree, equations(tree, method), folder, folder.name)


@pytest.mark.slow
@settings(max_examples=SLOW, **COMMON)
@given(tree=S.trees(), method=st.sampled_from(METHODS))
def test_numpy_and_written_module_agree_many(tree, method, tmp_path_factory):
    folder = tmp_path_factory.mktemp("module")
    check_numpy_and_module(tree, equations(tree, method), folder, folder.name)


DRIVER = r"""#include <stdio.h>
#include <string.h>
#include "eom.h"
/* reads states (NQ numbers of q, NV of u) from stdin; prints M, b, g and each frame's J per state */
int main(void)
{
    double q[NQ], u[NV], ud[NV] = {0}, p[NP + 1], M[NV * NV], b[NV], g[NV], J[6 * NV];
    memset(p, 0, sizeof p);
    for (;;) {
        for (int i = 0; i < NQ; i++) if (scanf("%lf", &q[i]) != 1) return 0;
        for (int i = 0; i < NV; i++) if (scanf("%lf", &u[i]) != 1) return 1;
        memset(M, 0, sizeof M); memset(b, 0, sizeof b); memset(g, 0, sizeof g);
        eom_M(q, u, ud, p, M); eom_b(q, u, ud, p, b); eom_g(q, u, ud, p, g);
        for (int i = 0; i < NV * NV; i++) printf("%.17g ", M[i]);
        for (int i = 0; i < NV; i++) printf("%.17g ", b[i]);
        for (int i = 0; i < NV; i++) printf("%.17g ", g[i]);
FRAMES
        printf("\n");
    }
}
"""


def run_write_c(eom, folder, pairs, n_frames: int) -> np.ndarray:
    """M, b, g and the frames' J from the plain C of write_c, compiled with cc and a driver (without the
    derivatives, the largest functions, which test_derivatives compiles and checks); at -O0, which compiles
    a megabyte of C in a third of -O1's time: the numbers are under test here, the extension's own
    optimised build in `check_compiled`."""
    c_path, h_path = eg.write_c(eom, folder, name="eom", derivatives=False)
    nq, nv = len(eom.q), len(eom.u)
    frames = "".join(f"        memset(J, 0, sizeof J); eom_J_{k}(q, u, ud, p, J);\n"
                     f"        for (int i = 0; i < 6 * NV; i++) printf(\"%.17g \", J[i]);\n" for k in range(n_frames))
    (folder / "driver.c").write_text(DRIVER.replace("FRAMES\n", frames))
    exe = folder / "driver"
    build = subprocess.run(["cc", "-O0", f"-DNQ={nq}", f"-DNV={nv}", f"-DNP={len(eom.system.parameters)}",
                            "-Wall", "-Werror=implicit-function-declaration", str(folder / "driver.c"), str(c_path),
                            "-o", str(exe), "-lm"], capture_output=True, text=True)
    assert build.returncode == 0, f"write_c output does not compile:\n{build.stderr[-3000:]}"
    text = "".join(" ".join(repr(float(x)) for x in (*q, *u)) + "\n" for q, u in pairs)
    run = subprocess.run([str(exe)], input=text, capture_output=True, text=True, timeout=60)
    assert run.returncode == 0, run.stderr
    return np.array([[float(x) for x in line.split()] for line in run.stdout.splitlines()])


def check_compiled(tree, eom: eg.EquationsOfMotion, folder) -> None:
    system, f, fc = eom.system, eg.codegen(eom), eg.codegen(eom, backend="c")
    # one extension module for all (the modules built on first use: test_c_backend)
    fc.generate(["tau", *(f"tau:{load.name}" for load in tree.loads), *(f"J:{n}" for n in frame_names(tree))])
    pairs = states(tree, 4, seed=3)
    qs, us = np.array([q for q, _ in pairs]), np.array([u for _, u in pairs])
    nv = len(system.u)
    for k, (q, u) in enumerate(pairs):
        close(fc.M(q), f.M(q), 1e-12, f"C extension M, state {k}")
        close(fc.b(q, u), f.b(q, u), 1e-12, f"C extension b, state {k}")
        close(fc.g(q), f.g(q), 1e-12, f"C extension g, state {k}")
        close(fc.nle(q, u), f.nle(q, u), 1e-12, f"C extension b + g, state {k}")
        close(fc.tau(q, u), f.tau(q, u), 1e-12, f"C extension tau, state {k}")
        for load in tree.loads:
            close(fc.tau_of(load.name, q, u), f.tau_of(load.name, q, u), 1e-12, f"C extension tau of {load.name!r}")
        for name in frame_names(tree):
            close(fc.jacobian(name, q), f.jacobian(name, q), 1e-12, f"C extension J of {name!r}, state {k}")
    close(fc.M(qs), np.array([f.M(q) for q in qs]), 1e-12, "C extension batched M")
    close(fc.b(qs, us), np.array([f.b(q, u) for q, u in pairs]), 1e-12, "C extension batched b")
    frames = list(system.frames)
    out = run_write_c(eom, folder, pairs, len(frames))
    assert out.shape == (len(pairs), nv * nv + 2 * nv + 6 * nv * len(frames)), out.shape
    for k, (q, u) in enumerate(pairs):
        row = iter(np.split(out[k], np.cumsum([nv * nv, nv, nv] + [6 * nv] * len(frames))))
        close(next(row).reshape(nv, nv), f.M(q), 1e-12, f"write_c M, state {k}")
        close(next(row), f.b(q, u), 1e-12, f"write_c b, state {k}")
        close(next(row), f.g(q), 1e-12, f"write_c g, state {k}")
        for name in frames:
            close(next(row).reshape(6, nv), f.jacobian(name, q), 1e-12, f"write_c J of {name!r}, state {k}")
    header = (folder / "eom.h").read_text()
    for k, name in enumerate(frames):  # the header says which J_k is which frame, and stays a comment
        assert f"eom_J_{k}(" in header


@settings(max_examples=3, **COMMON)
@given(tree=S.trees(max_bodies=4), method=st.sampled_from(METHODS))
def test_compiled_outputs_agree(tree, method, tmp_path_factory):
    check_compiled(tree, equations(tree, method), tmp_path_factory.mktemp("c"))


@pytest.mark.slow
@settings(max_examples=200, **COMMON)
@given(tree=S.trees(), method=st.sampled_from(METHODS))
def test_compiled_outputs_agree_many(tree, method, tmp_path_factory):
    check_compiled(tree, equations(tree, method), tmp_path_factory.mktemp("c"))


# --- plain names: the numbers alone, so a name bug cannot hide a numeric one -------------------
def plain(tree):
    """The same tree with names b0, j0, f0, l0, ..."""
    for i, b in enumerate(tree.bodies):
        b.name, b.joint = f"b{i}", f"j{i}"
    for k, f in enumerate(tree.frames):
        f.name = f"f{k}"
    for k, load in enumerate(tree.loads):
        load.name = f"l{k}"
    return tree


@settings(max_examples=15, **COMMON)
@given(tree=S.trees().map(plain), method=st.sampled_from(METHODS))
def test_equals_pinocchio_plain_names(tree, method):
    check_pinocchio(tree, equations(tree, method))


# --- every joint type at once, through every output ------------------------------------------
def every_joint() -> S.Tree:
    """A chain of one body per joint type (skew axes, rotated placements), with a side branch."""
    rng = np.random.default_rng(12)
    tree = S.Tree(gravity=(0.2, -0.3, -9.81))
    kinds = ["revolute", "prismatic", *sorted(S.JOINTS)]
    for i, kind in enumerate(kinds):
        axis = rng.normal(size=3)
        q = rng.normal(size=4)
        q /= np.linalg.norm(q)
        inertia = np.diag(rng.uniform(0.1, 0.15, 3))
        tree.bodies.append(S.BodySpec(
            name=f"b{i}", parent=i - 1 if i != 4 else 1, kind=kind, joint=f"j{i}",
            axis=tuple(axis / np.linalg.norm(axis)),
            rotation=tuple(map(tuple, S.rotation_from_quaternion(q))),
            translation=tuple(rng.uniform(-0.3, 0.3, 3)), mass=float(rng.uniform(0.5, 2)),
            com=tuple(rng.uniform(-0.2, 0.2, 3)), inertia=tuple(map(tuple, inertia)),
            axis2=(0.0, 0.6, 0.8) if abs(axis[0]) > 0.1 else (1.0, 0.0, 0.0), pitch=0.15))
    identity = ((1, 0, 0), (0, 1, 0), (0, 0, 1))
    tree.frames.append(S.FrameSpec("tool", len(kinds) - 1, identity, (0.1, 0.2, 0.0)))
    return tree


def test_every_joint_type_through_every_output(tmp_path):
    """Pinocchio's joint models (its own API), then NumPy, the written module, the C extension and
    write_c on one chain that holds every joint type (the other methods: the random trees above); derived
    once for the three."""
    tree = every_joint()
    eom = equations(tree, "recursive")
    check_pinocchio(tree, eom)
    check_numpy_and_module(tree, eom, tmp_path, "every_recursive")
    check_compiled(tree, eom, tmp_path)
