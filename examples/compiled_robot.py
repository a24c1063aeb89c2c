"""A robot's equations as compiled code, and only what a task needs (issue 7).

1. ur5: derive, compile to C (a CPython extension module, cached), check against Pinocchio, time one
   call of M, b, g beside Pinocchio's own, and evaluate 10⁵ states in one call.
2. Gravity compensation derives and compiles g alone; a controller gets plain C with no Python
   (`write_c`), here for g and the tool frame's Jacobian.

Run: python examples/compiled_robot.py [folder for the C files, default examples/output/ur5_c]"""
import sys
import time
import timeit
from pathlib import Path

import numpy as np
import pinocchio as pin

import eomgen as eg


def per_call(fn) -> float:
    return min(timeit.repeat(fn, number=1000, repeat=5)) / 1000 * 1e6


OUTPUT = Path(__file__).parent / "output"


def main(folder: str = str(OUTPUT / "ur5_c")) -> None:
    system = eg.robots.load("ur5")
    t0 = time.perf_counter()
    f = eg.codegen(eg.derive(system, method="recursive"), backend="c")
    print(f"ur5: derived and compiled in {time.perf_counter() - t0:.2f} s; operations {f.ops}")
    print(eg.verify(system, method="recursive", backend="c", states=10))

    model = system.pinocchio_model
    data = model.createData()
    q, u, _ = eg.random_states(system, 100_000, np.random.default_rng(0))
    print("\nper call from Python [µs]:   eomgen C   Pinocchio")
    for name, ours, theirs in [("M", lambda: f.M(q[0]), lambda: pin.crba(model, data, q[0])),
                               ("b + g", lambda: f.nle(q[0], u[0]), lambda: pin.nonLinearEffects(model, data, q[0], u[0])),
                               ("g", lambda: f.g(q[0]), lambda: pin.computeGeneralizedGravity(model, data, q[0]))]:
        print(f"  {name:6s}                     {per_call(ours):7.2f}   {per_call(theirs):9.2f}")
    seconds = min(timeit.repeat(lambda: (f.M(q), f.b(q, u), f.g(q)), number=1, repeat=3))
    print(f"10⁵ states in one call each: {seconds / len(q) * 1e6:.3f} µs per state for M, b, g "
          f"(M of shape {f.M(q[:3]).shape} for 3 states)")

    gravity = eg.derive(system, method="recursive", quantities=("g",), frames=["tool0"])
    fg = eg.codegen(gravity, backend="c")
    print(f"\ngravity compensation: derived {gravity.quantities} and frames {gravity.frames}; "
          f"{fg.ops['g']} operations for g (all of M, b, g: {sum(f.ops[k] for k in 'Mbg')})")
    print(f"  g(q) = {np.round(fg.g(q[0]), 4)} N m, |g − Pinocchio| = "
          f"{np.abs(fg.g(q[0]) - pin.computeGeneralizedGravity(model, data, q[0])).max():.1e}")
    c_file, h_file = eg.write_c(gravity, folder, name="ur5")
    print(f"  plain C for a controller: {c_file} and {h_file} (functions ur5_g, ur5_J_0, ur5_Jdot_u_0)")


if __name__ == "__main__":
    main(*sys.argv[1:])
