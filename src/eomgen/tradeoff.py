"""The speed-accuracy trade, measured: variants of one model side by side, each with its derivation
time, operation count, evaluation time per state (batched NumPy), and the maximum and RMS relative
error of M, b, g and of the forward-dynamics acceleration against the full float64 model over a fixed
set of random states (u̇ with zero joint torques).

Variants: the simplification level of the code (eomgen's shared intermediates; the closed forms with
nothing shared; sympy's CSE of them; trigsimp of the closed-form entries then CSE), the derivation
(projected Newton-Euler), the precision (float32), and approximate models: Coriolis and centrifugal
terms neglected, light bodies dropped, links as point masses, small inertias neglected, joints locked."""
from __future__ import annotations

import time
from dataclasses import dataclass, field

import numpy as np
import sympy as sp

from .codegen import codegen
from .methods import derive
from .model import System
from .simplification import LEVELS, simplified
from .state import random_states


@dataclass
class Variant:
    """One variant of a model as `tradeoff` measures it: derivation and code generation time, operations
    of M, b and g, evaluation time per state, and errors[quantity] = (max, RMS) relative error."""

    name: str
    derive_seconds: float
    ops: int
    eval_us_per_state: float
    errors: dict = field(default_factory=dict)  # quantity -> (max, rms) relative error

    def row(self) -> str:
        """The variant as a line of the table under `HEADER`."""
        e = self.errors
        return (f"{self.name:34s} {self.derive_seconds:7.2f} {self.ops:7d} {self.eval_us_per_state:8.2f} "
                + " ".join(f"{e[k][0]:9.1e}" for k in ("M", "b", "g", "ud")) + f" {e['ud'][1]:9.1e}")


HEADER = (f"{'variant':34s} {'derive':>7s} {'ops':>7s} {'µs/state':>8s} {'max M':>9s} {'max b':>9s} "
          f"{'max g':>9s} {'max u̇':>9s} {'rms u̇':>9s}")


def _relative(values, ref) -> tuple[float, float]:
    scale = max(np.abs(ref).max(), 1e-300)
    diff = np.abs(np.asarray(values) - ref) / scale
    return float(diff.max()), float(np.sqrt(np.mean(diff**2)))


def _numbers(expr) -> float:
    return float(sp.sympify(expr))


def tradeoff(system: System, states: int = 200, seed: int = 0, mass_fraction: float = 0.05,
             inertia_fraction: float = 0.05, lock: dict | None = None, levels=LEVELS,
             trig_max_ops: int = 300) -> list[Variant]:
    """Measure the variants of a numeric, fixed- or floating-base `system` (see the module doc).
    `levels`: the simplification levels to include (trigsimp is slow: it gets only the closed-form
    entries of at most `trig_max_ops` operations)."""
    rng = np.random.default_rng(seed)
    q, u, _ = random_states(system, states, rng)

    def build(s, method="recursive"):
        t0 = time.perf_counter()
        f = codegen(derive(s, method=method))
        return f, time.perf_counter() - t0

    def timing(f, q_, u_, dtype=float, keys=("M", "b", "g")):
        fns = [f.functions[k] for k in keys]
        args = [np.ascontiguousarray(x.T, dtype=dtype) for x in (q_, u_, np.zeros_like(u_))]
        p = [float(x) for x in f._p(None, "M")]
        t0 = time.perf_counter()
        outs = [g.function(*args, p, np.zeros(g.shape + q_.shape[:1], dtype=dtype),
                           np.sin, np.cos, np.sqrt, np) for g in fns]
        seconds = time.perf_counter() - t0
        return [np.moveaxis(o, (0, 1), (-2, -1)).astype(float) for o in outs], seconds / len(q_) * 1e6

    full, t_full = build(system)
    (M0, b0, g0), us = timing(full, q, u)
    b0, g0 = b0[..., 0], g0[..., 0]
    ud0 = np.linalg.solve(M0, -(b0 + g0)[..., None])[..., 0]

    def variant(name, f, seconds, M, b, g, us_, rows=slice(None), ud=None):
        if ud is None:  # pinv: an approximate model may lose rank (point masses on a joint axis)
            ud = (np.linalg.pinv(M) @ -(b + g)[..., None])[..., 0]
        idx = np.arange(system.nv)[rows]
        errors = {"M": _relative(M, M0[:, idx][:, :, idx]), "b": _relative(b, b0[:, idx]),
                  "g": _relative(g, g0[:, idx]), "ud": _relative(ud, ud0[:, idx])}
        return Variant(name, seconds, sum(f.ops[k] for k in ("M", "b", "g")), us_, errors)

    out = [variant("full model (recursive, float64)", full, t_full, M0, b0, g0, us)]
    titles = {"closed": "closed forms, nothing shared", "cse": "closed forms + sympy CSE", "trig": "trigsimp"}
    for level in levels:
        t0 = time.perf_counter()
        f = codegen(simplified(full.eom, level, trig_max_ops))
        seconds = t_full + time.perf_counter() - t0
        (M, b, g), us_l = timing(f, q, u)
        title = titles[level]
        if level == "trig":
            done, total = f.eom.extras["trigsimp_entries"]
            title = f"trigsimp ({done}/{total} entries) + CSE"
        out.append(variant(title, f, seconds, M, b[..., 0], g[..., 0], us_l))
    pne, t_pne = build(system, "projected_newton_euler")
    (M, b, g), us_pne = timing(pne, q, u)
    out.append(variant("projected Newton-Euler code", pne, t_pne, M, b[..., 0], g[..., 0], us_pne))
    (M, b, g), us32 = timing(full, q, u, np.float32)
    out.append(variant("float32", full, t_full, M, b[..., 0], g[..., 0], us32))
    _, us_no_b = timing(full, q, u, keys=("M", "g"))  # b is not evaluated at all
    out.append(variant("Coriolis and centrifugal neglected", full, t_full, M0, 0 * b0, g0, us_no_b))
    masses = [_numbers(b.mass) for b in system.bodies]
    light = mass_fraction * max(masses)
    for name, change in [
        (f"bodies below {light:.3g} kg dropped", lambda b: {"mass": 0, "inertia": sp.zeros(3)}
         if _numbers(b.mass) < light else {}),
        ("links as point masses", lambda b: {"inertia": sp.zeros(3)}),
        ("small inertias neglected", lambda b: {"inertia": sp.zeros(3)}
         if max(abs(_numbers(x)) for x in b.inertia) < inertia_fraction * max(
             max(abs(_numbers(x)) for x in c.inertia) for c in system.bodies) else {})]:
        f, seconds = build(system.rebuilt(change))
        (M, b, g), us_v = timing(f, q, u)
        out.append(variant(name, f, seconds, M, b[..., 0], g[..., 0], us_v))
    if lock is None and system.nv > 1 and not system.floating_base:
        lock = {system.joints[-1].name: 0.0}
    if lock:
        reduced = system.reduced(lock)
        keep = [k for k, j in enumerate(system.joints) if j.name not in lock]
        locked = [k for k, j in enumerate(system.joints) if j.name in lock]
        q_l, u_l = q.copy(), u.copy()
        q_l[:, locked] = [lock[system.joints[k].name] for k in locked]
        u_l[:, locked] = 0.0
        (M0, b0, g0), _ = timing(full, q_l, u_l)  # the reference at the locked states
        b0, g0 = b0[..., 0], g0[..., 0]
        ud0 = np.linalg.solve(M0, -(b0 + g0)[..., None])[..., 0]
        f, seconds = build(reduced)
        (M, b, g), us_r = timing(f, q_l[:, keep], u_l[:, keep])
        out.append(variant(f"joints locked: {', '.join(lock)}", f, seconds, M, b[..., 0], g[..., 0], us_r, keep))
    return out


def pareto_plot(variants: list[Variant], path, title: str = "") -> None:
    """Error of u̇ against evaluation time per state, log-log, as PNG."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(7, 5))
    for v in variants:
        err = max(v.errors["ud"][0], 1e-17)
        ax.loglog(v.eval_us_per_state, err, "o")
        ax.annotate(v.name, (v.eval_us_per_state, err), fontsize=7, xytext=(4, 2), textcoords="offset points")
    ax.set_xlabel("evaluation time of M, b, g per state [µs] (batched NumPy)")
    ax.set_ylabel("max relative error of u̇")
    ax.set_title(title or "speed against accuracy")
    fig.tight_layout()
    fig.savefig(path, dpi=100)
