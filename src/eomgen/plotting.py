"""`eg.plot`: a simulation's coordinates, speeds, actuator efforts and energy balance over time in one
matplotlib figure (no pyplot: it works headless, and a notebook shows the figure it returns, as a PNG,
without `%matplotlib inline`)."""

from __future__ import annotations

from typing import TYPE_CHECKING

from .numeric import NumericKane
from .errors import ModelError
from .simulate import Simulation

if TYPE_CHECKING:
    from matplotlib.figure import Figure

LEGEND = 12  # most curves a legend names


def labels(f) -> tuple[list[str], list[str], list[str]]:
    """The names of the coordinates, of the speeds in the state (Kane's: w_ind), of the actuated joints."""
    if isinstance(f, NumericKane):
        speeds = f.kane.independent
    else:
        speeds = f.eom.u
    system = f.system
    return [str(x) for x in system.q], [str(x) for x in speeds], system.actuated


def plot(simulation: Simulation, path=None, size: tuple[float, float] = (8.0, 2.5)) -> Figure:
    """Rows over t: q; u; τ_a (when efforts were applied); E − E(t0), W and (right axis) the balance
    E − E(t0) − W, zero but for the integration error. Each row `size` (width, height) inches; saved to
    `path` when given (any format matplotlib writes: .png, .pdf, .svg)."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg  # matplotlib only when drawing

    from .figures import ShownFigure

    if not isinstance(simulation, Simulation):
        raise ModelError(f"plot: expected a Simulation (eg.simulate), got {type(simulation).__name__}")
    s, (q_names, u_names, tau_names) = simulation, labels(simulation.functions)
    rows = [("q", s.q, q_names), ("u", s.u, u_names)] + (
        [("τ_a", s.tau, tau_names)] if s.tau is not None else []
    )
    fig = ShownFigure(figsize=(size[0], size[1] * (len(rows) + 1)), layout="constrained")
    FigureCanvasAgg(fig)
    axes = fig.subplots(len(rows) + 1, 1, sharex=True)
    for ax, (name, values, names) in zip(axes, rows):
        for column, label in zip(values.T, names):
            ax.plot(s.t, column, label=label)
        ax.set_ylabel(name)
        if 0 < len(names) <= LEGEND:
            ax.legend(loc="upper right", fontsize="small", ncol=min(len(names), 4))
    ax = axes[-1]
    ax.plot(s.t, s.energy - s.energy[0], label="E − E(t0)")
    ax.plot(s.t, s.work, "--", label="W")
    ax.set_ylabel("energy")
    right = ax.twinx()
    if not s.functions.system.prescribed:  # else the drive's work is not in W (`Simulation.balance`)
        right.plot(s.t, s.balance, color="C3", lw=1, label="E − E(t0) − W (right)")
        right.set_ylabel("balance")
    handles = [h for a in (ax, right) for h in a.get_legend_handles_labels()[0]]
    ax.legend(handles=handles, loc="upper left", fontsize="small")
    ax.set_xlabel("t")
    if path is not None:
        fig.savefig(path)
    return fig
