"""Command line: `eomgen verify NAME_OR_URDF`, `eomgen generate NAME_OR_URDF -o FILE.py` (or `-o DIR --c`),
`eomgen tradeoff NAME_OR_URDF [--png FILE]`, `eomgen solve FILE.py -o solution.tex|.md|.pdf`."""
from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

from .printers import write_c, write_module
from .errors import ModelError
from .methods import METHODS, derive
from .model import System, from_urdf, robots


def load(name_or_urdf: str) -> System:
    """A robot of example-robot-data by name, or a URDF file by path."""
    if name_or_urdf in robots.ROBOTS or name_or_urdf in robots.DH_ROBOTS:
        return robots.load(name_or_urdf)
    if name_or_urdf.endswith(".urdf") or Path(name_or_urdf).exists():
        return from_urdf(name_or_urdf)
    raise ModelError(f"{name_or_urdf!r} is neither a robot name ({', '.join(robots.names())}) nor a URDF file")


def solve(args) -> int:
    """`eomgen solve FILE.py -o OUT`: the worked solution as LaTeX, Markdown or PDF (by OUT's suffix)."""
    import runpy

    from .worked import solution

    suffix = Path(args.output).suffix
    if suffix not in (".tex", ".md", ".pdf"):
        raise ModelError(f"solve: the output must end in .tex, .md or .pdf, not {args.output!r}")
    if not Path(args.file).is_file():
        raise ModelError(f"solve: no such file {args.file!r}")
    namespace = runpy.run_path(args.file)
    if "system" not in namespace:
        raise ModelError(f"solve: {args.file} must define `system` (an eomgen.System or KaneEquations)")
    methods = [m for m in args.methods.split(",") if m]
    result = solution(namespace["system"], methods=methods, form=args.form, title=args.title)
    if suffix == ".pdf":
        result.pdf(args.output, digits=args.digits)
    else:
        (result.latex if suffix == ".tex" else result.markdown)(args.output, digits=args.digits)
    print(f"wrote {args.output} ({len(result.steps)} steps)")
    return 0


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(prog="eomgen", description="Equations of motion: derive, generate, verify.")
    sub = ap.add_subparsers(dest="command", required=True)
    v = sub.add_parser("verify", help="derive, generate and compare with Pinocchio")
    v.add_argument("robot", help="example-robot-data name (e.g. ur5) or URDF path")
    v.add_argument("--method", default=None, choices=sorted(METHODS),
                   help="default: the cheapest that applies")
    v.add_argument("--states", type=int, default=20)
    v.add_argument("--backend", default="numpy", choices=["numpy", "c"])
    v.add_argument("--frames", nargs="*", help="frames whose Jacobians to check (default: the end frames)")
    tr = sub.add_parser("tradeoff", help="measure approximate variants of a model against the full one")
    tr.add_argument("robot", help="example-robot-data name or URDF path")
    tr.add_argument("--states", type=int, default=200)
    tr.add_argument("--png", help="write the Pareto plot (error against evaluation time) here")
    tr.add_argument("--json", help="write the table as JSON here")
    tr.add_argument("--levels", default="closed,cse,trig", help="simplification levels to include (comma-separated)")
    tr.add_argument("--trig-max-ops", type=int, default=300, help="trigsimp only closed-form entries this small")
    tr.add_argument("--c", action="store_true",
                    help="also time the variants compiled from C (needs a C compiler)")
    gen = sub.add_parser("generate", help="write a numpy-only Python module, or plain C for a controller")
    gen.add_argument("robot", help="example-robot-data name or URDF path")
    gen.add_argument("-o", "--output", required=True, help="the .py file to write (with --c: the folder)")
    gen.add_argument("--method", default="recursive", choices=sorted(METHODS))
    gen.add_argument("--c", action="store_true", help="write <name>.c and <name>.h (M, b, g, end-frame J, J̇u)")
    gen.add_argument("--name", default="eom", help="with --c: the C prefix and file name (default eom)")
    gen.add_argument("--frames", nargs="+", metavar="NAME",
                     help="frames whose J, J̇u and placement to write (default: with --c the end frames, "
                          "else every body and frame)")
    so = sub.add_parser("solve", help="a worked solution of the system defined in a Python file")
    so.add_argument("file", help="a Python file that defines `system` (an eomgen.System or KaneEquations)")
    so.add_argument("-o", "--output", required=True, help="solution.tex, solution.md or solution.pdf")
    so.add_argument("--methods", default="free_cut,projected_newton_euler,lagrange",
                    help="comma-separated methods (default: the lecture's three)")
    so.add_argument("--form", default="auto", choices=["auto", "textbook", "shared"])
    so.add_argument("--digits", type=int, default=4, help="significant digits of decimal numbers")
    so.add_argument("--title", help="the document's title")
    args = ap.parse_args(argv)
    try:
        if args.command == "solve":
            return solve(args)
        system = load(args.robot)
        if args.command == "verify":
            from .verify import verify

            report = verify(system, method=args.method, backend=args.backend, states=args.states, frames=args.frames)
            print(report)
            return 0 if report.ok() else 1
        if args.command == "tradeoff":
            import json
            from dataclasses import asdict

            from .tradeoff import HEADER, pareto_plot, tradeoff

            levels = [x for x in args.levels.split(",") if x]
            variants = tradeoff(system, states=args.states, levels=levels, trig_max_ops=args.trig_max_ops,
                                c=args.c)
            print(HEADER)
            for v in variants:
                print(v.row())
            if args.png:
                pareto_plot(variants, args.png, args.robot)
            if args.json:
                Path(args.json).write_text(json.dumps([asdict(v) for v in variants], indent=2))
            return 0
        t0 = time.perf_counter()
        if args.c:
            from .verify import end_frames

            frames = args.frames or end_frames(system)
            paths = write_c(derive(system, method=args.method, frames=frames), args.output, name=args.name)
        else:
            paths = [write_module(derive(system, method=args.method), args.output, frames=args.frames)]
        print(f"wrote {', '.join(map(str, paths))} ({system.nq} coordinates) in {time.perf_counter() - t0:.2f} s")
        return 0
    except ModelError as exc:
        print(f"eomgen: error: {exc}", file=sys.stderr)
        return 2


if __name__ == "__main__":
    sys.exit(main())
