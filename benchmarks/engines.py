"""Derivation speed by engine (`eg.derive(..., engine=)`): sympy, symengine, and the eomgen of earlier git
revisions (--before REF ..., each with its own default), side by side in one run.

Cases: tiago_dual and talos (M, b, g by the body-frame recursions), the 30-link spatial chain of
derive_chain.py, the 25-link pendulum on a cart (derivation and NumPy code: a cart on x carrying 25
links about z, point masses at the links' ends, symbolic lengths and masses), the 10-link chain with its
closed forms formed (derivation, then M, b, g inlined to expressions in q, u and the parameters, as sympy's
KanesMethod gives them; KanesMethod's own time on the same chain, once, beside it). Each case and
variant runs in a fresh process (sympy's lazy imports done before the clock starts), `--repeat` times
interleaved; the table shows the least CPU seconds and the speed-ups of the symengine engine over each
earlier revision and over the sympy engine.

Run: python benchmarks/engines.py [--before 3001cb3^1 1339c1b] [--repeat 3] [--cases tiago_dual ...]
     [--out benchmarks/results/engines.json]"""
from __future__ import annotations

import argparse
import json
import subprocess
import sys
import tempfile
import time
from pathlib import Path

HERE = Path(__file__).parent
sys.path.insert(0, str(HERE))
CASES = ("tiago_dual", "talos", "chain30", "cart25", "chain10_closed", "talos_frames")


def cart_pendulum(n: int):
    """A cart on x carrying n links about z, each a point mass at its end (PyDy's n-pendulum benchmark)."""
    import sympy as sp

    import eomgen as eg

    m, L, g = sp.symbols(f"m0:{n + 1}", positive=True), sp.symbols(f"l0:{n}", positive=True), sp.Symbol("g")
    system = eg.System(gravity=(0, -g, 0))
    parent = system.add_body("cart", joint=eg.Prismatic("x", axis=(1, 0, 0)), mass=m[0])
    for i in range(n):
        parent = system.add_body(f"link{i}", parent=parent, joint=eg.Revolute(f"q{i}", axis=(0, 0, 1)),
                                 mass=m[i + 1], com=(0, -L[i], 0),
                                 placement=eg.Placement(translation=(0, -L[i - 1] if i else 0, 0)))
    return system


def one(case: str, engine: str | None) -> dict:
    """CPU seconds of one case in this process (`engine` None: the revision's default)."""
    import warnings

    import eomgen as eg
    options = {} if engine is None else {"engine": engine}
    if case in ("tiago_dual", "talos", "talos_frames"):
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            system = eg.robots.load(case.removesuffix("_frames"))
    elif case == "cart25":
        system = cart_pendulum(25)
    else:
        import derive_chain
        system = derive_chain.eomgen_chain(30 if case == "chain30" else 10)
    import sympy as sp
    sp.Add(*sp.symbols("a b")) * sp.Matrix([1])  # sympy's lazy imports (sympy.tensor: 0.25 s) not timed
    if case == "talos_frames":
        import numpy as np
        eom = eg.derive(system, **options)
        t0 = time.process_time()
        f, (q, u, _) = eg.codegen(eom), (x[0] for x in eg.random_states(system, 1, np.random.default_rng(0)))
        for name in system.frames:
            f.jacobian(name, q), f.jacobian_dot_u(name, q, u)
        return {"cpu_s": time.process_time() - t0, "intermediates": len(eom.kinematics.sub)}
    t0 = time.process_time()
    eom = eg.derive(system, **options)
    if case == "cart25":
        eg.codegen(eom)
    if case == "chain10_closed":
        eom.M, eom.b, eom.g
    return {"cpu_s": time.process_time() - t0, "intermediates": len(eom.kinematics.sub)}


def kanes_method(n: int) -> float:
    """CPU seconds of sympy's KanesMethod on the n-link chain (mass matrix and forcing)."""
    import sympy.physics.mechanics as me

    import derive_chain
    t0 = time.process_time()
    q, u, N, bodies, loads = derive_chain.sympy_chain(n, for_lagrange=False)
    km = me.KanesMethod(N, q_ind=q, u_ind=u, kd_eqs=[qi.diff() - ui for qi, ui in zip(q, u)])
    km.kanes_equations(bodies, loads)
    km.mass_matrix, km.forcing
    return time.process_time() - t0


def measure(case: str, variant: str, src: Path) -> dict:
    engine = variant if variant in ("sympy", "symengine") else None
    code = (f"import sys, json; sys.path[:0] = [{str(src)!r}, {str(HERE)!r}]; import engines; "
            f"print(json.dumps(engines.one({case!r}, {engine!r})))")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    return json.loads(out.stdout.splitlines()[-1])


def main() -> None:
    import builds
    import results_io

    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--before", nargs="*", default=["3001cb3^1", "1339c1b"],
                        help="git revisions to compare with")
    parser.add_argument("--repeat", type=int, default=3)
    parser.add_argument("--cases", nargs="*", default=list(CASES))
    parser.add_argument("--out", default=results_io.default_path("engines"))
    args = parser.parse_args()
    with tempfile.TemporaryDirectory() as tmp:
        sources = {rev: builds.export(rev, Path(tmp) / f"before{k}") for k, rev in enumerate(args.before)}
        sources.update({"sympy": HERE.parent / "src", "symengine": HERE.parent / "src"})
        rows = []
        for case in args.cases:
            best: dict = {}
            for _ in range(args.repeat):
                for variant, src in sources.items():
                    r = measure(case, variant, src)
                    if variant not in best or r["cpu_s"] < best[variant]["cpu_s"]:
                        best[variant] = r
            row = {"case": case, **{f"{v}_s": r["cpu_s"] for v, r in best.items()},
                   "intermediates": best["symengine"]["intermediates"]}
            for v in sources:
                row[f"speedup_{v}"] = row[f"{v}_s"] / row["symengine_s"]
            if case == "chain10_closed":
                row["KanesMethod_s"] = kanes_method(10)
                row["KanesMethod_over_symengine"] = row["KanesMethod_s"] / row["symengine_s"]
            rows.append(row)
            print(json.dumps(row), flush=True)
    print("\n| case | " + " | ".join(f"{v} s" for v in sources) + " | "
          + " | ".join(f"symengine × {v}" for v in sources if v != "symengine") + " | note |")
    print("|---" * (2 * len(sources) + 1) + "|")
    for r in rows:
        note = (f"KanesMethod {r['KanesMethod_s']:.1f} s = {r['KanesMethod_over_symengine']:.0f}× symengine"
                if "KanesMethod_s" in r else f"{r['intermediates']} intermediates")
        print(f"| {r['case']} | " + " | ".join(f"{r[f'{v}_s']:.3f}" for v in sources) + " | "
              + " | ".join(f"{r[f'speedup_{v}']:.2f}" for v in sources if v != "symengine") + f" | {note} |")
    results_io.write(args.out, "engines", rows, before=args.before, repeat=args.repeat)


if __name__ == "__main__":
    main()
