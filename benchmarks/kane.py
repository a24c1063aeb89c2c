"""Kane's method: eomgen's `kane` beside sympy.physics.mechanics.KanesMethod, derivation time on the
rolling disk (nonholonomic), a Whipple-like bicycle (five nonholonomic constraints, a dense 5 × 5
C_dep; eomgen only: derivation, and code generation separately) and the n-link chain of
derive_chain.py (holonomic), in one run, checking that the chain's equations agree numerically.
Prints a table and writes JSON.

Run: python benchmarks/kane.py [--max-n 10] [--out benchmarks/results/kane.json]"""
from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

import numpy as np
import sympy as sp
import sympy.physics.mechanics as me

import eomgen as eg

sys.path.insert(0, str(Path(__file__).parent))
sys.path.insert(0, str(Path(__file__).parents[1] / "tests"))
import derive_chain  # noqa: E402
import kane_systems  # noqa: E402
import results_io  # noqa: E402


def timed(fn):
    t0 = time.perf_counter()
    out = fn()
    return time.perf_counter() - t0, out


def rolling_disk() -> dict:
    system, args = kane_systems.rolling_disk(torques=True)
    t_ours, k = timed(lambda: eg.kane(system, **args))
    t_sympy, (km, qs, ws) = timed(lambda: kane_systems.rolling_disk_sympy(torques=True))
    return {"system": "rolling disk", "eomgen_s": t_ours, "KanesMethod_s": t_sympy}


def bicycle() -> dict:
    system, args, _ = kane_systems.bicycle()
    t_ours, k = timed(lambda: eg.kane(system, **args))
    t_code, f = timed(lambda: eg.codegen(k))
    x = np.r_[np.zeros(system.nq), 0.05, 15.0, 0.02]
    t_rhs, _ = timed(lambda: [f.rhs(0, x, params={"m_b": 85.0, "g": 9.81}) for _ in range(100)])
    return {"system": "bicycle (5 constraints)", "eomgen_s": t_ours, "KanesMethod_s": float("nan"),
            "codegen_s": t_code, "rhs_us": t_rhs * 1e4}


def chain(n: int, state) -> dict:
    system = derive_chain.eomgen_chain(n)
    t_ours, k = timed(lambda: eg.kane(system))
    q, u, N, bodies, loads = derive_chain.sympy_chain(n, for_lagrange=False)

    def sympy_kane():
        km = me.KanesMethod(N, q_ind=q, u_ind=u, kd_eqs=[qi.diff() - ui for qi, ui in zip(q, u)])
        km.kanes_equations(bodies, loads)
        return km.mass_matrix, km.forcing
    t_sympy, (M, F) = timed(sympy_kane)
    f = eg.codegen(k)
    L, m, I, g = derive_chain.parameters(n)
    names = [*L, *m, *[x for row in I for x in row], g]
    params = {str(s): v for s, v in zip(names, state["p"])}
    M_ref, bg_ref = derive_chain._numeric(M, F, q, u, n, state)
    diff = max(np.abs(f.mass_matrix(state["q"], state["u"], params) - M_ref).max(),
               np.abs(-f.forcing(state["q"], state["u"], params) - bg_ref).max())
    return {"system": f"{n}-link chain", "eomgen_s": t_ours, "KanesMethod_s": t_sympy, "max_abs_diff": float(diff)}


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--max-n", type=int, default=8)
    ap.add_argument("--out", default=results_io.default_path("kane"))
    args = ap.parse_args()
    rng = np.random.default_rng(0)
    rows = [rolling_disk(), bicycle()]
    rows += [chain(n, derive_chain.random_state(n, rng)) for n in range(1, args.max_n + 1)]
    print(f"{'system':24s} {'eomgen [s]':>11s} {'KanesMethod [s]':>16s} {'ratio':>7s} {'max diff':>9s}")
    for r in rows:
        print(f"{r['system']:24s} {r['eomgen_s']:11.3f} {r['KanesMethod_s']:16.3f} "
              f"{r['KanesMethod_s'] / r['eomgen_s']:6.1f}x {r.get('max_abs_diff', float('nan')):9.1e}"
              + (f"  codegen {r['codegen_s']:.2f} s, rhs {r['rhs_us']:.0f} µs" if "codegen_s" in r else ""))
    results_io.write(args.out, "kane", rows, sympy=sp.__version__)


if __name__ == "__main__":
    main()
