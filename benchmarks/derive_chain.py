"""Derivation time of M, b, g for an n-link spatial chain: eomgen's methods (projected Newton-Euler,
Lagrange II, free cut, body-frame recursions) beside sympy.physics.mechanics.

The chain: link i turns about its parent's z (i even) or y (i odd) axis (relative angles, as in a
robot), sits at distance L_(i−1) along the parent's x axis, has its centre of mass at L_i/2 along its
own x axis, symbolic mass m_i and principal inertias Ixx_i, Iyy_i, Izz_i; gravity −g along z.
The same system is built for sympy's KanesMethod and LagrangesMethod; each sympy method runs for
growing n in a subprocess until one run exceeds the time limit. Results are compared numerically
(M and b + g at a random state) and the table is printed and written as JSON.

Run: python benchmarks/derive_chain.py [--max-n 20] [--limit 120] [--out benchmarks/results/derive_chain.json]"""
from __future__ import annotations

import argparse
import multiprocessing as mp
import sys
import time
from pathlib import Path

import numpy as np
import sympy as sp

import eomgen as eg

sys.path.insert(0, str(Path(__file__).parent))
import results_io  # noqa: E402


def parameters(n: int):
    L = sp.symbols(f"L0:{n}", positive=True)
    m = sp.symbols(f"m0:{n}", positive=True)
    I = [sp.symbols(f"Ixx{i} Iyy{i} Izz{i}", positive=True) for i in range(n)]
    return L, m, I, sp.Symbol("g")


def axis(i: int) -> tuple:
    return (0, 0, 1) if i % 2 == 0 else (0, 1, 0)


def eomgen_chain(n: int) -> eg.System:
    L, m, I, g = parameters(n)
    system, parent = eg.System(gravity=(0, 0, -g)), None
    for i in range(n):
        parent = system.add_body(f"link{i}", parent=parent, joint=eg.Revolute(f"q_{i}", axis=axis(i)), mass=m[i],
                                 com=(L[i] / 2, 0, 0), inertia=sp.diag(*I[i]),
                                 placement=eg.Placement(translation=(L[i - 1] if i else 0, 0, 0)))
    return system


def sympy_chain(n: int, for_lagrange: bool):
    """Frames, points and bodies of the same chain in sympy.physics.mechanics."""
    import sympy.physics.mechanics as me

    L, m, I, g = parameters(n)
    q, u = me.dynamicsymbols(f"q0:{n}"), me.dynamicsymbols(f"u0:{n}")
    N, O = me.ReferenceFrame("N"), me.Point("O")
    O.set_vel(N, 0)
    frame, point, bodies, loads = N, O, [], []
    for i in range(n):
        F = me.ReferenceFrame(f"F{i}")
        ax = frame.z if i % 2 == 0 else frame.y
        F.orient_axis(frame, ax, q[i])
        if not for_lagrange:
            F.set_ang_vel(frame, u[i] * ax)
        P = point.locatenew(f"P{i}", L[i - 1] * frame.x) if i else O
        if i:
            P.v2pt_theory(point, N, frame)
        C = P.locatenew(f"C{i}", L[i] / 2 * F.x)
        C.v2pt_theory(P, N, F)
        body = me.RigidBody(f"B{i}", C, F, m[i], (me.inertia(F, *I[i]), C))
        if for_lagrange:
            body.potential_energy = m[i] * g * C.pos_from(O).dot(N.z)
        bodies.append(body)
        loads.append((C, -m[i] * g * N.z))
        frame, point = F, P
    return q, u, N, bodies, loads


def run_sympy(method: str, n: int, state, conn) -> None:
    import sympy.physics.mechanics as me

    t0 = time.perf_counter()
    if method == "KanesMethod":
        q, u, N, bodies, loads = sympy_chain(n, for_lagrange=False)
        kane = me.KanesMethod(N, q_ind=q, u_ind=u, kd_eqs=[qi.diff() - ui for qi, ui in zip(q, u)])
        kane.kanes_equations(bodies, loads)
        M, F = kane.mass_matrix, kane.forcing
        speeds = u
    else:
        q, u, N, bodies, loads = sympy_chain(n, for_lagrange=True)
        lm = me.LagrangesMethod(me.Lagrangian(N, *bodies), q)
        lm.form_lagranges_equations()
        M, F = lm.mass_matrix, lm.forcing
        speeds = [qi.diff() for qi in q]
    seconds = time.perf_counter() - t0
    values = _numeric(M, F, q, speeds, n, state)
    conn.send((seconds, values))


def _numeric(M, F, q, speeds, n, state):
    """M and b + g (= −forcing) at the state, with placeholder symbols for q(t), q̇(t)."""
    qs, us = sp.symbols(f"_q0:{n}"), sp.symbols(f"_u0:{n}")
    rep = {**{s: us[i] for i, s in enumerate(speeds)}}
    M, F = M.xreplace(rep), F.xreplace(rep)
    M, F = M.xreplace(dict(zip(q, qs))), F.xreplace(dict(zip(q, qs)))
    args, vals = _arguments(n, state, qs, us)
    fM = sp.lambdify(args, M, cse=True)
    fF = sp.lambdify(args, F, cse=True)
    return np.array(fM(*vals), float), -np.array(fF(*vals), float).ravel()


def _arguments(n, state, qs, us):
    L, m, I, g = parameters(n)
    params = [*L, *m, *[x for row in I for x in row], g]
    return [*qs, *us, *params], [*state["q"], *state["u"], *state["p"]]


def random_state(n: int, rng) -> dict:
    L, m, I, g = parameters(n)
    p = [*rng.uniform(0.3, 1.0, n), *rng.uniform(0.5, 2.0, n)]
    for _ in range(n):
        a, b = rng.uniform(0.01, 0.1, 2)
        p += [a + b, a + 0.5 * b, 0.5 * a + b]  # triangle inequality holds
    p.append(9.81)
    return {"q": rng.uniform(-np.pi, np.pi, n), "u": rng.uniform(-2, 2, n), "p": p}


def run_eomgen(method: str, n: int, state) -> tuple[float, float, np.ndarray, np.ndarray]:
    system = eomgen_chain(n)
    t0 = time.perf_counter()
    eom = eg.derive(system, method=method)
    seconds = time.perf_counter() - t0
    t0 = time.perf_counter()
    f = eg.codegen(eom)
    codegen_seconds = time.perf_counter() - t0
    L, m, I, g = parameters(n)
    names = [*L, *m, *[x for row in I for x in row], g]
    params = {str(s): v for s, v in zip(names, state["p"])}
    return seconds, codegen_seconds, f.M(state["q"], params), f.b(state["q"], state["u"], params) + f.g(state["q"], params)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--max-n", type=int, default=20)
    ap.add_argument("--limit", type=float, default=120.0, help="seconds per sympy run before giving up")
    ap.add_argument("--out", default=results_io.default_path("derive_chain"))
    args = ap.parse_args()
    rng = np.random.default_rng(0)
    ctx = mp.get_context("fork")
    alive = {"KanesMethod": True, "LagrangesMethod": True}
    rows = []
    header = (f"{'n':>3} {'PNE [s]':>8} {'Lag [s]':>8} {'cut [s]':>8} {'rec [s]':>8} {'gen [s]':>8} {'Kane [s]':>9} "
              f"{'LagM [s]':>9} {'Kane/PNE':>9} {'LagM/Lag':>9} {'max rel diff':>13}")
    print(header, flush=True)
    for n in range(1, args.max_n + 1):
        state = random_state(n, rng)
        row = {"n": n}
        ref = None
        for method, key in (("projected_newton_euler", "pne"), ("lagrange", "lagrange"), ("free_cut", "free_cut"),
                            ("recursive", "recursive")):
            t, tg, M, bg = run_eomgen(method, n, state)
            row[key], row[f"{key}_codegen"] = t, tg
            ref = (M, bg) if ref is None else ref
            row["max_rel_diff"] = max(row.get("max_rel_diff", 0.0), _rel(M, ref[0]), _rel(bg, ref[1]))
        for method, key in (("KanesMethod", "kane"), ("LagrangesMethod", "sympy_lagrange")):
            row[key] = None
            if not alive[method]:
                continue
            recv, send = ctx.Pipe(duplex=False)
            proc = ctx.Process(target=run_sympy, args=(method, n, state, send))
            proc.start()
            ready = recv.poll(args.limit * 3)  # derivation under the limit, plus numeric evaluation
            if ready:
                seconds, (M, bg) = recv.recv()
                row[key] = seconds
                row["max_rel_diff"] = max(row["max_rel_diff"], _rel(M, ref[0]), _rel(bg, ref[1]))
            proc.kill()
            proc.join()
            if not ready or row[key] > args.limit:
                alive[method] = False
        row["kane_over_pne"] = row["kane"] / row["pne"] if row["kane"] else None
        row["sympy_lagrange_over_lagrange"] = row["sympy_lagrange"] / row["lagrange"] if row["sympy_lagrange"] else None
        rows.append(row)
        print(f"{n:>3} {row['pne']:>8.2f} {row['lagrange']:>8.2f} {row['free_cut']:>8.2f} {row['recursive']:>8.2f} "
              f"{row['pne_codegen']:>8.2f} "
              f"{_f(row['kane']):>9} "
              f"{_f(row['sympy_lagrange']):>9} {_f(row['kane_over_pne'], 'x'):>9} "
              f"{_f(row['sympy_lagrange_over_lagrange'], 'x'):>9} {row['max_rel_diff']:>13.1e}", flush=True)
    results_io.write(args.out, "derive_chain", rows, sympy=sp.__version__, limit_seconds=args.limit)


def _rel(a, b) -> float:
    return float(np.abs(np.asarray(a) - np.asarray(b)).max() / max(1.0, np.abs(b).max()))


def _f(x, unit="") -> str:
    return "-" if x is None else (f"{x:.1f}{unit}" if unit else f"{x:.2f}")


if __name__ == "__main__":
    main()
