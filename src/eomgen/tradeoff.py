"""The speed-accuracy trade, measured: variants of one model side by side, each with its derivation
time, operation count, evaluation time per state (batched NumPy; with `c=True` compiled C too), and the
maximum and RMS relative error (and the maximum absolute error) of M, b, g and of the forward-dynamics
acceleration against the full float64 model over a fixed set of random states (u̇ with zero joint
torques). `pareto_plot` draws the error of u̇ against the evaluation time.

Variants: the simplification level of the code (eomgen's shared intermediates; the closed forms with
nothing shared; sympy's CSE of them; trigsimp of the closed-form entries then CSE), the derivation
(projected Newton-Euler), the precision (float32), and approximate models: Coriolis and centrifugal
terms neglected, light bodies dropped, links as point masses, small inertias neglected, joints locked;
with flexible links (derived by Lagrange II), their foreshortening dropped ("no stiffening") and their
modal reduction to the first k modes of each field ("k modes"; compared at states of the modes'
subspace, q = T q_k, u = T u_k with T = diag(1, Φ), the reduced u̇ as T u̇_k, its M, b, g as Tᵀ M T, Tᵀ b,
Tᵀ g of the full model)."""
from __future__ import annotations

import itertools
import time
from dataclasses import dataclass, field

import numpy as np
import sympy as sp

from .numeric import codegen
from .methods import derive
from .model import FlexibleLink, Fixed, Prismatic, Revolute, System
from .progress import progress
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
    abs_errors: dict = field(default_factory=dict)  # quantity -> max absolute error
    c_us_per_state: float | None = None  # compiled from C (tradeoff(c=True); float32: none, C is float64)

    def row(self) -> str:
        """The variant as a line of the table under `HEADER`."""
        e, c = self.errors, self.c_us_per_state
        return (f"{self.name:34s} {self.derive_seconds:7.2f} {self.ops:7d} {self.eval_us_per_state:8.2f} "
                + " ".join(f"{e[k][0]:9.1e}" for k in ("M", "b", "g", "ud")) + f" {e['ud'][1]:9.1e}"
                + (f" {c:8.2f}" if c is not None else f" {'-':>8s}"))


HEADER = (f"{'variant':34s} {'derive':>7s} {'ops':>7s} {'µs/state':>8s} {'max M':>9s} {'max b':>9s} "
          f"{'max g':>9s} {'max u̇':>9s} {'rms u̇':>9s} {'C µs':>8s}")


class Variants(list):
    """The variants of one run (a list of `Variant`), with the number of states and the unit of u̇."""

    def __init__(self, variants, states: int, unit: str) -> None:
        super().__init__(variants)
        self.states, self.unit = states, unit


def acceleration_unit(system: System) -> str:
    """The unit of u̇'s entries: rad/s² (revolute), m/s² (prismatic), both (free flyer, flexible link)."""
    kinds = {Revolute: ("rad/s²",), Prismatic: ("m/s²",), Fixed: ()}
    units = {x for j in system.joints for x in kinds.get(type(j), ("rad/s²", "m/s²"))}
    return ", ".join(sorted(units, reverse=True)) or "rad/s²"


def _relative(values, ref) -> tuple[float, float]:
    scale = max(np.abs(ref).max(), 1e-300)
    diff = np.abs(np.asarray(values) - ref) / scale
    return float(diff.max()), float(np.sqrt(np.mean(diff**2)))


def _numbers(expr) -> float:
    return float(sp.sympify(expr))


def tradeoff(system: System, states: int = 200, seed: int = 0, mass_fraction: float = 0.05,
             inertia_fraction: float = 0.05, lock: dict | None = None, levels=LEVELS,
             trig_max_ops: int = 300, c: bool = False, modes=(1, 2)) -> Variants:
    """Measure the variants of a numeric, fixed- or floating-base `system` (see the module doc).
    `levels`: the simplification levels to include (trigsimp is slow: it gets only the closed-form
    entries of at most `trig_max_ops` operations). `c`: also time each variant compiled from C
    (batched, best of 3; needs a C compiler, and compiles every variant). `modes`: the modal reductions
    to include where the system has flexible links (those every link allows; none where a link is modal
    already)."""
    last = system.joints[-1] if system.joints else None
    if lock is None and system.nv > 1 and not system.floating_base and len(last.coordinates) == 1:
        lock = {system.joints[-1].name: 0.0}
    flexible = [j for j in system.joints if isinstance(j, FlexibleLink)]
    modes = [k for k in modes if flexible and all(j.shapes is None and k <= j.most_modes  # (modal: none)
                                                  for j in flexible)]
    runs = _variants(system, states, seed, mass_fraction, inertia_fraction, lock, levels, trig_max_ops, c,
                     modes)
    stiffened = any(j.stiffening for j in flexible)
    count = 7 + len(levels) + bool(lock) + (len(modes) + stiffened - 1 if flexible else 0)
    done = progress(runs, "trade-off", total=count, unit="variant")
    return Variants(done, states, acceleration_unit(system))


def _variants(system, states, seed, mass_fraction, inertia_fraction, lock, levels, trig_max_ops, with_c,
              modes):
    """The variants of `tradeoff`, one at a time."""
    rng = np.random.default_rng(seed)
    q, u, _ = random_states(system, states, rng)

    def build(s, method=None):
        t0 = time.perf_counter()
        f = codegen(derive(s, method=method))
        return f, time.perf_counter() - t0

    def timing(f, q_, u_, dtype=float, keys=("M", "b", "g")):
        fns = [f.functions[k] for k in keys]
        args = [np.ascontiguousarray(x.T, dtype=dtype) for x in (q_, u_, np.zeros_like(u_))]
        p = [float(x) for x in f.parameter_vector(None, "M")]
        t0 = time.perf_counter()
        outs = [g.function(*args, p, np.zeros(g.shape + q_.shape[:1], dtype=dtype),
                           np.sin, np.cos, np.sqrt, np) for g in fns]
        seconds = time.perf_counter() - t0
        return [np.moveaxis(o, (0, 1), (-2, -1)).astype(float) for o in outs], seconds / len(q_) * 1e6

    def c_timing(f, q_, u_, keys=("M", "b", "g"), compiled=None):
        """µs per state of `keys` compiled from C (batched, best of 3), None unless `with_c`."""
        if not with_c:
            return None
        fc = compiled or codegen(f.eom, backend="c")
        fc.generate(list(keys))
        best = np.inf
        for _ in range(3):
            t0 = time.perf_counter()
            for k in keys:
                fc.call(k, q_, u_)
            best = min(best, time.perf_counter() - t0)
        return best / len(q_) * 1e6

    full, t_full = build(system)
    (M0, b0, g0), us = timing(full, q, u)
    b0, g0 = b0[..., 0], g0[..., 0]
    ud0 = np.linalg.solve(M0, -(b0 + g0)[..., None])[..., 0]
    full_c = codegen(full.eom, backend="c") if with_c else None

    def variant(name, f, seconds, M, b, g, us_, c_us, rows=slice(None), ud=None, reference=None):
        if ud is None:  # pinv: an approximate model may lose rank (point masses on a joint axis)
            ud = (np.linalg.pinv(M) @ -(b + g)[..., None])[..., 0]
        idx = np.arange(system.nv)[rows]
        pairs = dict(zip(("M", "b", "g", "ud"), zip((M, b, g, ud), reference or (
            M0[:, idx][:, :, idx], b0[:, idx], g0[:, idx], ud0[:, idx]))))
        errors = {k: _relative(x, ref) for k, (x, ref) in pairs.items()}
        absolute = {k: float(np.abs(np.asarray(x) - ref).max()) for k, (x, ref) in pairs.items()}
        return Variant(name, seconds, sum(f.ops[k] for k in ("M", "b", "g")), us_, errors, absolute, c_us)

    yield variant(f"full model ({full.eom.method}, float64)", full, t_full, M0, b0, g0, us,
                  c_timing(full, q, u, compiled=full_c))
    titles = {"closed": "closed forms, nothing shared", "cse": "closed forms + CSE", "trig": "trigsimp"}
    for level in levels:
        t0 = time.perf_counter()
        f = codegen(simplified(full.eom, level, trig_max_ops))
        seconds = t_full + time.perf_counter() - t0
        (M, b, g), us_l = timing(f, q, u)
        title = titles[level]
        if level == "trig":
            done, total = f.eom.extras["trigsimp_entries"]
            title = f"trigsimp ({done}/{total} entries) + CSE"
        yield variant(title, f, seconds, M, b[..., 0], g[..., 0], us_l, c_timing(f, q, u))
    flexible = [j for j in system.joints if isinstance(j, FlexibleLink)]
    if not flexible:  # (projected Newton-Euler has no flexible links)
        pne, t_pne = build(system, "projected_newton_euler")
        (M, b, g), us_pne = timing(pne, q, u)
        yield variant("projected Newton-Euler code", pne, t_pne, M, b[..., 0], g[..., 0], us_pne,
                      c_timing(pne, q, u))
    (M, b, g), us32 = timing(full, q, u, np.float32)
    yield variant("float32", full, t_full, M, b[..., 0], g[..., 0], us32, None)  # C is float64 only
    _, us_no_b = timing(full, q, u, keys=("M", "g"))  # b is not evaluated at all
    yield variant("Coriolis and centrifugal neglected", full, t_full, M0, 0 * b0, g0, us_no_b,
                  c_timing(full, q, u, ("M", "g"), full_c))
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
        yield variant(name, f, seconds, M, b[..., 0], g[..., 0], us_v, c_timing(f, q, u))
    def links(**choices):
        return system.rebuilt(lambda b: {"joint": b.joint.changed(**choices)}
                              if isinstance(b.joint, FlexibleLink) else {})
    if any(j.stiffening for j in flexible):
        f, seconds = build(links(stiffening=False))
        (M, b, g), us_s = timing(f, q, u)
        yield variant("no stiffening", f, seconds, M, b[..., 0], g[..., 0], us_s, c_timing(f, q, u))
    for k in modes:
        f, seconds = build(links(modes=k))
        T_q, T_v = _modal_map(f.eom.system)
        q_k, u_k, _ = random_states(f.eom.system, states, np.random.default_rng(seed))
        (M, b, g), us_k = timing(f, q_k, u_k)
        (M_f, b_f, g_f), _ = timing(full, q_k @ T_q.T, u_k @ T_v.T)
        ud = np.linalg.solve(M, -(b + g))[..., 0] @ T_v.T
        reference = (T_v.T @ M_f @ T_v, (b_f[..., 0] @ T_v), (g_f[..., 0] @ T_v),
                     np.linalg.solve(M_f, -(b_f + g_f))[..., 0])
        yield variant(f"{k} mode{'s' * (k > 1)} of each field", f, seconds, M, b[..., 0], g[..., 0], us_k,
                      c_timing(f, q_k, u_k), ud=ud, reference=reference)
    if lock:
        reduced = system.reduced(lock)
        owner = {x: [j.name for j in system.joints for _ in getattr(j, f)] for x, f in
                 (("q", "coordinates"), ("u", "speeds"))}  # a locked joint: one coordinate, one speed
        keep = {x: [k for k, name in enumerate(names) if name not in lock] for x, names in owner.items()}
        locked = {x: [k for k, name in enumerate(names) if name in lock] for x, names in owner.items()}
        q_l, u_l = q.copy(), u.copy()
        q_l[:, locked["q"]] = [lock[owner["q"][k]] for k in locked["q"]]
        u_l[:, locked["u"]] = 0.0
        (M0, b0, g0), _ = timing(full, q_l, u_l)  # the reference at the locked states
        b0, g0 = b0[..., 0], g0[..., 0]
        ud0 = np.linalg.solve(M0, -(b0 + g0)[..., None])[..., 0]
        f, seconds = build(reduced)
        q_r, u_r = np.ascontiguousarray(q_l[:, keep["q"]]), np.ascontiguousarray(u_l[:, keep["u"]])
        (M, b, g), us_r = timing(f, q_r, u_r)
        yield variant(f"joints locked: {', '.join(lock)}", f, seconds, M, b[..., 0], g[..., 0], us_r,
                      c_timing(f, q_r, u_r), keep["u"])


def _modal_map(reduced: System) -> tuple[np.ndarray, np.ndarray]:
    """(T_q, T_v): q = T_q q_k, u = T_v u_k from a system's modal flexible links to the same links' nodes
    (per joint: the identity, or diag(1, Φ) for a link's angle and amplitudes)."""
    from scipy.linalg import block_diag

    blocks = [(np.eye(len(j.coordinates)), np.eye(j.dof)) if not isinstance(j, FlexibleLink) else
              2 * (block_diag(np.eye(len(j.coordinates) - len(j.nodal)), j.shapes),)
              for j in reduced.joints]
    return block_diag(*[q for q, _ in blocks]), block_diag(*[v for _, v in blocks])


def pareto_front(points) -> list[int]:
    """Indices of the non-dominated (time, error) points, by increasing time: no other point is at
    least as fast and as accurate, and better in one."""
    order = sorted(range(len(points)), key=lambda k: points[k])
    front, best = [], np.inf
    for k in order:
        if points[k][1] < best:
            front.append(k)
            best = points[k][1]
    return front


def pareto_plot(variants: Variants, path, robot: str = ""):
    """Max absolute error of u̇ (zero torques) against the evaluation time of M, b, g per state, log-log:
    NumPy, and C where measured (joined to NumPy by a line of the variant's colour), each with its
    Pareto front, and one label per variant placed clear of the other labels, the markers, the lines
    and the legend. Written as PNG to `path`; returns the Figure."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure
    from matplotlib.lines import Line2D

    fig = Figure(figsize=(10, 6.5), dpi=110)
    FigureCanvasAgg(fig)
    ax = fig.add_subplot()
    ax.set_xscale("log")
    ax.set_yscale("log")
    errors = [v.abs_errors["ud"] for v in variants]
    floor = min([e for e in errors if e > 0] or [1e-15]) / 10  # where an error of 0 is drawn
    y = [max(e, floor) for e in errors]
    colors = [_color(k) for k in range(len(variants))]
    states = getattr(variants, "states", None)
    points, segments, handles = [], [], []
    for kind, times, marker, style in (("NumPy", [v.eval_us_per_state for v in variants], "o", "-"),
                                       ("C", [v.c_us_per_state for v in variants], "s", "--")):
        measured = [k for k, t in enumerate(times) if t is not None]
        if not measured:
            continue
        ax.scatter([times[k] for k in measured], [y[k] for k in measured], c=[colors[k] for k in measured],
                   marker=marker, s=36, zorder=3, edgecolors="black", linewidths=0.5)
        front = [measured[k] for k in pareto_front([(times[k], y[k]) for k in measured])]
        fx, fy = [times[k] for k in front], [y[k] for k in front]
        ax.plot(fx, fy, drawstyle="steps-post", color="black", ls=style, lw=1, zorder=2,
                gid=f"pareto front {kind}")
        segments += [((a, b), (c, b)) for a, b, c in zip(fx, fy, fx[1:])]
        segments += [((c, b), (c, d)) for b, c, d in zip(fy, fx[1:], fy[1:])]
        points += [(times[k], y[k]) for k in measured]
        handles += [Line2D([], [], ls="none", marker=marker, mfc="white", mec="black",
                           label=f"{kind}" + (f", batches of {states} states" if states else "")),
                    Line2D([], [], color="black", ls=style, lw=1, label=f"Pareto front, {kind}")]
    for v, yv, color in zip(variants, y, colors):  # a variant's C and NumPy times, joined
        if v.c_us_per_state is not None:
            ax.plot([v.c_us_per_state, v.eval_us_per_state], [yv, yv], color=color, lw=0.8, alpha=0.6,
                    zorder=1)
            segments.append(((v.c_us_per_state, yv), (v.eval_us_per_state, yv)))
    if floor in y:
        ax.axhline(floor, color="0.6", ls=":", lw=0.8, zorder=0)
    xs, ys = [p[0] for p in points], [p[1] for p in points]
    ax.set_xlim(min(xs) / 3, max(xs) * 3)
    ax.set_ylim(min(ys) / 100, max(ys) * 30)
    ax.set_xlabel("evaluation time of M, b and g [µs per state]")
    ax.set_ylabel(f"max |u̇ − u̇ of the full model| [{getattr(variants, 'unit', 'rad/s²')}]")
    ax.set_title(f"{robot + ': ' if robot else ''}error of the acceleration u̇ = M⁻¹ (−b − g) against "
                 f"evaluation time{f', {states} random states' if states else ''}", fontsize=10)
    ax.grid(True, which="major", lw=0.4, alpha=0.5)
    legend = ax.legend(handles=handles, loc="upper right", fontsize=7, framealpha=0.9)
    fig.tight_layout()
    names = [v.name + (" (error 0)" if e == 0 else "") for v, e in zip(variants, errors)]
    anchors = list(zip([v.eval_us_per_state for v in variants], y))
    _place_labels(ax, anchors, names, colors, points, segments, legend)
    fig.savefig(path)
    return fig


def _color(k: int):
    """Distinct colours: tab20's dark ones, then its light ones."""
    import matplotlib

    return matplotlib.colormaps["tab20"]((2 * k) % 20 + (2 * k) // 20)


def _place_labels(ax, anchors, names, colors, points, segments, legend) -> None:
    """One label per anchor (data coordinates), framed in its colour, at the first offset (nearest first:
    rings of 12 directions up to 120 pt around its point, then a grid over the whole axes) where nothing
    clashes: the label inside the axes, its box on no label, marker, line segment, leader or the legend,
    and its leader (a thin line to a label set further off) across no label. Where every offset clashes,
    the least bad (`_clashes`)."""
    from matplotlib.transforms import Bbox, offset_copy

    fig = ax.figure
    renderer = fig.canvas.get_renderer()
    frame = ax.get_window_extent(renderer)
    to_display, pixels = ax.transData.transform, fig.dpi / 72  # pixels per point
    markers = [Bbox.from_bounds(*(to_display(p) - 5), 10, 10) for p in points]
    lines = [Bbox(to_display([a, b])).padded(1) for a, b in segments] + [legend.get_window_extent(renderer)]
    labels, leaders = [], []
    angles = np.deg2rad([0, 180, 90, -90, 30, 150, -30, -150, 60, 120, -60, -120])
    rings = [(r * np.cos(a), r * np.sin(a)) for r in (6, 12, 20, 30, 45, 65, 90, 120) for a in angles]
    step_x, step_y = 24 * pixels, 16 * pixels
    grid = [(x, y) for x in np.arange(frame.x0, frame.x1, step_x)
            for y in np.arange(frame.y0, frame.y1, step_y)]
    for (x, y), name, color in zip(anchors, names, colors):
        text = ax.text(x, y, name, fontsize=7, gid="variant label", zorder=4,
                       bbox={"boxstyle": "round,pad=0.25", "fc": "white", "ec": color, "lw": 0.8,
                             "alpha": 0.9})
        here, best = to_display((x, y)), None
        far = [((gx - here[0]) / pixels, (gy - here[1]) / pixels) for gx, gy in grid]
        far = sorted((d for d in far if np.hypot(*d) > 120), key=lambda d: np.hypot(*d))
        boxes = {}  # the label's box at its point by alignment: an offset moves it rigidly
        for dx, dy in rings + far:
            align = ("left" if dx > 1 else "right" if dx < -1 else "center",
                     "bottom" if dy > 1 else "top" if dy < -1 else "center")
            if align not in boxes:
                text.set_ha(align[0])
                text.set_va(align[1])
                boxes[align] = text.get_window_extent(renderer).padded(5)
            box = boxes[align].translated(dx * pixels, dy * pixels)
            leader = (here, here + np.array([dx, dy]) * pixels) if np.hypot(dx, dy) > 10 else None
            clashes = _clashes(box, leader, frame, markers, labels, lines, leaders,
                               np.inf if best is None else best[0])
            if best is None or clashes < best[0]:
                best = (clashes, dx, dy, align, box, leader)
            if clashes == 0:
                break
        _, dx, dy, (ha, va), box, leader = best
        text.set_transform(offset_copy(ax.transData, fig=fig, x=dx, y=dy, units="points"))
        text.set_ha(ha)
        text.set_va(va)
        labels.append(box)
        if leader is not None:
            leaders.append(leader)
            ax.annotate("", (x, y), xytext=(dx, dy), textcoords="offset points", zorder=1,
                        arrowprops={"arrowstyle": "-", "color": "0.4", "lw": 0.6, "shrinkA": 0,
                                    "shrinkB": 4})


def _clashes(box, leader, frame, markers, labels, lines, leaders, enough: float) -> float:
    """How badly a label's box and leader would clash, counted until the sum reaches `enough`: outside the
    axes 1000; each label or marker under the box 10; each line segment or the legend under it, leader
    through it, or label its leader crosses 1."""
    total = 0.0 if frame.contains(box.x0, box.y0) and frame.contains(box.x1, box.y1) else 1000.0
    for weight, hits in ((10, (box.overlaps(b) for b in itertools.chain(labels, markers))),
                         (1, (box.overlaps(b) for b in lines)),
                         (1, (_crosses(s, box) for s in leaders)),
                         (1, (leader is not None and _crosses(leader, b) for b in labels))):
        for hit in hits:
            total += weight * hit
            if total >= enough:
                return total
    return total


def _crosses(segment, box) -> bool:
    """Whether the segment (two display points) passes through the box (sampled)."""
    (x0, y0), (x1, y1) = segment
    return any(box.contains(x0 + t * (x1 - x0), y0 + t * (y1 - y0)) for t in np.linspace(0, 1, 25))
