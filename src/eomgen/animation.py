"""`eg.animate`: a simulation as a stick figure (matplotlib), from the generated frame placements.

Each body is drawn as lines from its origin (its joint) to the origins of its children and of its named
frames (a body with neither: to its centre of mass), with a dot at its centre of mass (a massless body:
at its origin); the named frames are crosses. A motion whose points all stay in one plane (judged over the
whole trajectory) is drawn in 2D in that plane (a world plane where it is one), any other in 3D. The
positions at the animation's frames are interpolated linearly in time between the simulation's states."""

from __future__ import annotations

from collections.abc import Callable
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from .numeric import NumericEoM, NumericKane, codegen
from .errors import ModelError
from .methods import derive
from .model import System
from .simulate import Simulation, functions

if TYPE_CHECKING:
    from matplotlib.animation import FuncAnimation

PLANAR = 1e-9  # out-of-plane extent, relative to the motion's size, below which it is drawn in 2D
WRITERS = {".gif": "pillow", ".mp4": "ffmpeg"}


def placements(source) -> NumericEoM:
    """Numeric functions with `placement`: those given, or generated from the system alone (kinematics
    only) for a System or Kane's equations."""
    if isinstance(source, (System, NumericKane)):
        system = source if isinstance(source, System) else source.system
        return codegen(derive(system, method="recursive", quantities=()))
    return functions(source, "animate")


def stick_figure(
    f: NumericEoM, q, params
) -> tuple[np.ndarray, list[tuple[int, int]], list[int], list[int]]:
    """(points (N, K, 3), lines as pairs of point indices, dots, crosses) at the states q (N, nq): the body
    origins (`placement`), their centres of mass and the named frames' origins."""
    system = f.system
    bodies, frames = system.bodies, list(system.frames.values())
    origins = [f.placement(b.name, q, params)[1] for b in bodies]
    points = np.stack(
        [
            *origins,
            *np.moveaxis(f.call("centres", q, params=params), -1, 0),
            *(f.placement(x.name, q, params)[1] for x in frames),
        ],
        axis=1,
    )
    index = {b.name: k for k, b in enumerate(bodies)}
    lines = [(index[b.parent.name], k) for k, b in enumerate(bodies) if b.parent is not None]
    lines += [(index[x.body.name], 2 * len(bodies) + k) for k, x in enumerate(frames) if x.body is not None]
    ends = {i for i, _ in lines}
    lines += [
        (k, len(bodies) + k) for k, b in enumerate(bodies) if k not in ends and b.mass.is_zero is not True
    ]
    dots = [len(bodies) + k if b.mass.is_zero is not True else k for k, b in enumerate(bodies)]
    return points, lines, dots, list(range(2 * len(bodies), len(points[0])))


def plane(points: np.ndarray) -> tuple[np.ndarray, list[str]] | None:
    """(3 × 2 basis, axis labels) of the plane all points (…, 3) lie in, None if they span 3D: the world
    plane normal to z, y or x if one holds them, else the two principal directions."""
    X = points.reshape(-1, 3) - points.reshape(-1, 3).mean(axis=0)
    _, s, Vt = np.linalg.svd(X, full_matrices=False)
    flat = s <= PLANAR * max(1.0, s[0])
    if not flat.any():
        return None
    normal_space = Vt[flat]
    for k in (2, 1, 0):
        if np.linalg.norm(normal_space[:, k]) > 1 - PLANAR:
            axes = [i for i in range(3) if i != k]
            return np.eye(3)[:, axes], [f"{'xyz'[i]}" for i in axes]
    return Vt[:2].T, ["e1", "e2"]


def animate(
    simulation: Simulation,
    system_or_functions=None,
    path=None,
    frames: int | None = None,
    fps: float = 25.0,
    size: tuple[float, float] = (6.0, 6.0),
) -> FuncAnimation:
    """The motion of `simulation` as a stick figure (see the module doc), drawn from the placements of
    `system_or_functions` (default: the simulation's functions): `frames` images evenly spaced in time
    (default real time at `fps`), saved to `path` when given (".gif": Pillow, ".mp4": ffmpeg). Returns the
    `FuncAnimation`, which a notebook shows as a player by itself (`eomgen.figures.ShownAnimation`)."""
    from matplotlib.animation import writers  # matplotlib only when drawing

    if not isinstance(simulation, Simulation):
        raise ModelError(f"animate: expected a Simulation (eg.simulate), got {type(simulation).__name__}")
    f = placements(simulation.functions if system_or_functions is None else system_or_functions)
    if f.nq != simulation.q.shape[1]:
        raise ModelError(
            f"animate: the functions have {f.nq} coordinates, the simulation {simulation.q.shape[1]}"
        )
    if not fps > 0:
        raise ModelError(f"animate: fps must be positive, got {fps!r}")
    suffix = None if path is None else Path(path).suffix.lower()
    if path is not None and suffix not in WRITERS:
        raise ModelError(f"animate: path must end in {list(WRITERS)}, got {str(path)!r}")
    if suffix == ".mp4" and not writers.is_available("ffmpeg"):
        raise ModelError(
            f"animate: {str(path)!r}: writing MP4 needs ffmpeg on the PATH; write a .gif instead"
        )
    t = simulation.t
    frames = int(round(abs(t[-1] - t[0]) * fps)) + 1 if frames is None else frames
    if not isinstance(frames, (int, np.integer)) or frames < 1:
        raise ModelError(f"animate: frames must be a positive integer, got {frames!r}")
    params = simulation.params if f is simulation.functions else simulation_parameters(f, simulation)
    points, lines, dots, crosses = stick_figure(f, simulation.q, params)
    times = np.linspace(t[0], t[-1], frames)
    order = np.argsort(t, kind="stable")
    at = np.stack(
        [
            np.stack([np.interp(times, t[order], points[order, k, i]) for i in range(3)], -1)
            for k in range(points.shape[1])
        ],
        1,
    )
    anim, draw = _drawing(at, times, lines, dots, crosses, plane(points), size, fps)
    if path is not None:
        anim.save(str(path), writer=WRITERS[suffix], fps=fps)
        draw(0)  # the figure as it starts
    return anim


def simulation_parameters(f: NumericEoM, simulation: Simulation) -> dict:
    """The simulation's parameter values (given, or bound) that the functions `f` have (Kane's may have
    more)."""
    given = simulation.functions.parameters
    values = simulation.params or dict(zip(given.names, getattr(given, "bound", ())))
    return {k: v for k, v in values.items() if str(k) in f.parameters.names}


def _drawing(at, times, lines, dots, crosses, basis, size, fps) -> tuple[FuncAnimation, Callable]:
    """The animation of `at` (frames, K, 3) world points, projected on `basis` if planar, at its first
    frame, and the function drawing frame n."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    from .figures import ShownAnimation

    fig = Figure(figsize=size, dpi=80)  # no layout engine: the frames are drawn fast, all alike
    FigureCanvasAgg(fig)
    if basis is not None:
        B, labels = basis
        at = at @ B
        ax = fig.add_subplot()
        ax.set_aspect("equal")
    else:
        labels = ["x", "y", "z"]
        ax = fig.add_subplot(projection="3d")
        ax.set_box_aspect((1, 1, 1))
    lo, hi = at.reshape(-1, at.shape[-1]).min(0), at.reshape(-1, at.shape[-1]).max(0)
    centre, half = (lo + hi) / 2, max((hi - lo).max() / 2, 1e-3) * 1.1
    for k, label in enumerate(labels):
        getattr(ax, f"set_{'xyz'[k]}lim")(centre[k] - half, centre[k] + half)
        getattr(ax, f"set_{'xyz'[k]}label")(label)
    drawn = [ax.plot(*np.zeros((len(labels), 2)), "-", color="C0", lw=2)[0] for _ in lines]
    body = ax.plot(*np.zeros((len(labels), 1)), "o", color="C1", ms=6, ls="")[0]
    frame = ax.plot(*np.zeros((len(labels), 1)), "x", color="C2", ms=6, ls="")[0]
    clock = ax.set_title("")

    def draw(n: int):
        P = at[n]
        for line, (i, j) in zip(drawn, lines):
            _set(line, P[[i, j]])
        _set(body, P[dots])
        _set(frame, P[crosses])
        clock.set_text(f"t = {times[n]:.2f} s")
        return [*drawn, body, frame, clock]

    draw(0)
    return ShownAnimation(fig, draw, frames=len(times), interval=1000 / fps, blit=False), draw


def _set(artist, P: np.ndarray) -> None:
    """Put the points P (n, 2 or 3) into a line of a 2D or 3D axes."""
    if P.shape[1] == 3:
        artist.set_data_3d(*P.T)
    else:
        artist.set_data(*P.T)
