"""Modal reduction of a flexible link: k clamped-free modes (FlexibleLink(modes=k)) against all the nodal
coordinates of the same elements. Per row: the coordinates, the operations of M and of b + g, µs per
right-hand side call (forward dynamics), the first three frequencies' relative error (joint locked)
and the largest tip-deflection error of a free swing (released at rest from the horizontal) against
the full model. eg.tradeoff does not take a flexible arm (it derives the recursive method, and its
variants are of rigid bodies), hence this table.

The full model is stiff (its highest frequency grows as n²), so its explicit reference simulation is
the slow part: keep the elements and seconds small on a small machine (6 elements: DOP853 stopped early on
the full model within 0.3 s on 2 shared cores).

Run: python benchmarks/flexible_modes.py [--elements 3] [--seconds 1.0] [--out ...flexible_modes.json]"""
from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

import numpy as np
import scipy.linalg as sla
from scipy.integrate import solve_ivp

import eomgen as eg

sys.path.insert(0, str(Path(__file__).parent))
import results_io  # noqa: E402


def model(elements: int, modes):
    system = eg.System(gravity=(0, -9.81, 0))
    joint = eg.FlexibleLink("theta", length=1.0, mass_per_length=5.0, EI=50.0, elements=elements, modes=modes)
    system.add_body("link", joint=joint)
    shapes = np.eye(2 * elements) if modes is None else joint.shapes
    return system, shapes, eg.codegen(eg.derive(system, method="lagrange"))


def frequencies(system, f) -> np.ndarray:
    """The joint locked: the eigenfrequencies of the nodal block of M and of the elastic stiffness."""
    n = system.nv
    K = np.column_stack([-f.tau_of("elastic", np.eye(n)[k], np.zeros(n))[1:] for k in range(1, n)])
    return np.sqrt(np.sort(sla.eigh(K, f.M(np.zeros(n))[1:, 1:], eigvals_only=True)))


def tip_swing(system, shapes, f, seconds: float) -> tuple[np.ndarray, float]:
    """The tip deflection (Φ η or the last node's) over a free swing, and µs per right-hand side call."""
    n = system.nv
    calls = [0, 0.0]

    def rhs(_, x):
        t0 = time.perf_counter()
        out = np.r_[x[n:], f.forward_dynamics(x[:n], x[n:])]
        calls[0] += 1
        calls[1] += time.perf_counter() - t0
        return out
    sol = solve_ivp(rhs, (0, seconds), np.zeros(2 * n), method="DOP853", rtol=1e-9, atol=1e-11,
                    t_eval=np.linspace(0, seconds, 201))
    if not sol.success:
        raise RuntimeError(f"the free swing of {system.nv} coordinates failed: {sol.message}")
    return (shapes @ sol.y[1:n])[-2], calls[1] / calls[0] * 1e6


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--elements", type=int, default=3)
    ap.add_argument("--seconds", type=float, default=1.0)
    ap.add_argument("--out", default=results_io.default_path("flexible_modes"))
    args = ap.parse_args()
    runs = {k: model(args.elements, k) for k in (*range(1, min(3, 2 * args.elements) + 1), None)}
    w_full = frequencies(*runs[None][::2])[:3]
    tip_full, _ = tip_swing(*runs[None], args.seconds)
    print(f"{args.elements} elements, free swing of {args.seconds} s; errors against the full model")
    print(f"{'model':>10s} {'coords':>6s} {'ops M':>6s} {'ops b+g':>7s} {'µs/rhs':>7s} "
          f"{'err ω1':>8s} {'err ω2':>8s} {'err ω3':>8s} {'max |Δ tip| [m]':>16s}")
    rows = []
    for k, (system, shapes, f) in runs.items():
        w = frequencies(system, f)[:3]
        tip, us = tip_swing(system, shapes, f, args.seconds)
        errors = [abs(w[i] / w_full[i] - 1) if i < len(w) else None for i in range(3)]
        row = {"modes": k, "coordinates": system.nv, "ops_M": f.ops["M"], "ops_bg": f.ops["b"] + f.ops["g"],
               "us_per_rhs": us, "frequency_errors": errors, "tip_error": float(np.abs(tip - tip_full).max()),
               "tip_max": float(np.abs(tip_full).max())}
        rows.append(row)
        name = "full" if k is None else f"{k} modes"
        cells = " ".join(f"{e:8.1e}" if e is not None else f"{'-':>8s}" for e in errors)
        print(f"{name:>10s} {system.nv:6d} {row['ops_M']:6d} {row['ops_bg']:7d} {us:7.1f} {cells} "
              f"{row['tip_error']:16.2e}")
    results_io.write(args.out, "flexible_modes", rows, elements=args.elements, seconds=args.seconds,
                     model="one link, m = 5 kg/m, L = 1 m, EI = 50 N m², gravity 9.81")


if __name__ == "__main__":
    main()
