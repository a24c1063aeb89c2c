"""Progress bars: silent off a terminal, forced on by EOMGEN_PROGRESS=1, silenced by eg.quiet(); the
trade-off plot: its Pareto fronts and labels that do not overlap."""
import itertools
import os
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings, strategies as st

import eomgen as eg
from eomgen import progress as bars
from models import double_pendulum


@pytest.fixture
def instant(monkeypatch):
    """Bars appear at once (no delay), the environment does not decide, and quiet() is reset after."""
    monkeypatch.setattr(bars, "DELAY", 0)
    monkeypatch.delenv("EOMGEN_PROGRESS", raising=False)
    with eg.quiet(False):
        yield monkeypatch


def test_quiet_off_a_terminal(instant, capsys):
    """stderr captured (not a tty), no notebook: the iterable itself comes back, nothing is printed,
    in a derivation neither."""
    items = [1, 2, 3]
    assert bars.progress(items, "silent") is items
    eg.derive(double_pendulum(numeric=True), method="projected_newton_euler")
    assert capsys.readouterr().err == ""


def test_forced_on_and_quiet_again(instant, capsys):
    instant.setenv("EOMGEN_PROGRESS", "1")
    assert list(bars.progress(range(3), "counting", unit="step")) == [0, 1, 2]
    err = capsys.readouterr().err
    assert "counting" in err and "/3" in err and "step" in err
    eg.derive(double_pendulum(numeric=True), method="projected_newton_euler")  # the loop over bodies
    assert "projected Newton-Euler" in capsys.readouterr().err
    with eg.quiet():  # the context manager: silent in the block only
        items = [1, 2]
        assert bars.progress(items, "hushed") is items
        eg.derive(double_pendulum(numeric=True), method="projected_newton_euler")
    assert capsys.readouterr().err == ""
    list(bars.progress([1], "again"))
    assert "again" in capsys.readouterr().err
    eg.quiet(True)  # the function: silent until quiet(False)
    assert list(bars.progress(range(2), "hushed")) == [0, 1] and capsys.readouterr().err == ""
    eg.quiet(False)
    list(bars.progress(range(2), "back"))
    assert "back" in capsys.readouterr().err
    instant.setenv("EOMGEN_PROGRESS", "0")
    list(bars.progress(range(2), "off"))
    assert capsys.readouterr().err == ""


def test_one_slow_step_shows_its_time(instant, capsys):
    """After the delay the bar appears while the first (only) step still runs, as during a compile."""
    instant.setenv("EOMGEN_PROGRESS", "1")
    instant.setattr(bars, "DELAY", 0.05)
    for _ in bars.progress([None], "compiling"):
        time.sleep(0.4)
    assert "compiling:   0%" in capsys.readouterr().err  # drawn before the step ended


def test_notebook_without_ipywidgets_falls_back_quietly():
    """In a kernel (stand-ins for IPython and ipykernel, ipywidgets missing): the text bar on stderr
    and no warning (all would be shown)."""
    code = """if True:
        import sys, types
        ipython = types.ModuleType("IPython")
        ipython.get_ipython = lambda: types.SimpleNamespace(kernel=object())  # a kernel's shell
        sys.modules.update({"IPython": ipython, "ipywidgets": None, "ipykernel": types.ModuleType("k"),
                            "ipykernel.zmqshell": types.ModuleType("z")})
        from eomgen import progress as bars
        bars.DELAY = 0
        print(list(bars.progress(range(3), "in a notebook")))"""
    env = {**os.environ, "PYTHONPATH": str(Path(__file__).parents[1] / "src")}
    env.pop("EOMGEN_PROGRESS", None)
    run = subprocess.run([sys.executable, "-W", "always", "-c", code], capture_output=True, text=True,
                         env=env, timeout=120)
    assert run.returncode == 0, run.stderr
    assert run.stdout.strip() == "[0, 1, 2]" and "in a notebook" in run.stderr
    assert "Warning" not in run.stderr and "IProgress" not in run.stderr


def dominated(p, q) -> bool:
    """q dominates p: as fast and as accurate, better in one."""
    return q[0] <= p[0] and q[1] <= p[1] and q != p


def test_pareto_plot_front_and_labels(tmp_path):
    """A real run (ur5, C timed too): each front is the step line through exactly the non-dominated
    points; one label per variant, inside the axes, no two label boxes meet, none covers a marker."""
    from eomgen.tradeoff import pareto_plot

    with eg.quiet():
        variants = eg.tradeoff(eg.robots.load("ur5"), states=20, levels=("cse",), c=True)
    png = tmp_path / "pareto.png"
    fig = pareto_plot(variants, png, "ur5")
    assert png.stat().st_size > 20_000
    ax = fig.axes[0]
    assert "ur5" in ax.get_title() and "u̇" in ax.get_title()
    assert "µs" in ax.get_xlabel() and "[rad/s²]" in ax.get_ylabel() and "max |u̇" in ax.get_ylabel()
    errors = [max(v.abs_errors["ud"], 1e-300) for v in variants]
    for kind, times in (("NumPy", [v.eval_us_per_state for v in variants]),
                        ("C", [v.c_us_per_state for v in variants])):
        points = [(t, e) for t, e in zip(times, errors) if t is not None]
        assert len(points) >= len(variants) - 1  # C: all but float32
        front = sorted(p for p in points if not any(dominated(p, q) for q in points))
        line, = [x for x in ax.get_lines() if x.get_gid() == f"pareto front {kind}"]
        assert line.get_drawstyle() == "steps-post"
        drawn = list(zip(line.get_xdata(), line.get_ydata()))
        floor = min(y for _, y in drawn)
        assert [(t, max(e, floor)) for t, e in front] == drawn
    labels_apart(fig, variants)


def labels_apart(fig, variants) -> None:
    """One label per variant, inside the axes, no two label boxes meet, none covers a marker."""
    ax, renderer = fig.axes[0], fig.canvas.get_renderer()
    labels = [t for t in ax.texts if t.get_gid() == "variant label"]
    names = sorted(t.get_text().removesuffix(" (error 0)") for t in labels)
    assert names == sorted(v.name for v in variants)
    boxes = [t.get_window_extent(renderer) for t in labels]
    frame = ax.get_window_extent(renderer)
    for box in boxes:
        assert frame.contains(box.x0, box.y0) and frame.contains(box.x1, box.y1)
    for (i, a), (j, b) in itertools.combinations(enumerate(boxes), 2):
        assert not a.overlaps(b), (labels[i].get_text(), labels[j].get_text())
    markers = np.concatenate([c.get_offsets() for c in ax.collections])
    for x, y in ax.transData.transform(markers):
        assert not any(box.contains(x, y) for box in boxes)


def test_labels_of_points_that_tie_in_accuracy_keep_apart(tmp_path):
    """Four variants of equal error side by side near the floor of the axes (the double pendulum's
    variants as one run measured them): the rings around a point are all taken, so a label goes to the
    nearest free place of the axes, with a leader, not onto another label."""
    from eomgen.tradeoff import Variant, Variants, pareto_plot

    rows = [("full model (recursive, float64)", 4.55e-13, 7.14, 0.4015),
            ("closed forms + CSE", 4.55e-13, 6.64, 0.3660),
            ("projected Newton-Euler code", 5.26e-13, 11.6, 0.4127),
            ("float32", 1.96e-4, 5.23, None),
            ("Coriolis and centrifugal neglected", 11.2, 2.76, 0.2569),
            ("bodies below 0.0166 kg dropped", 4.55e-13, 9.23, 0.4211),
            ("links as point masses", 238, 7.83, 0.3700),
            ("small inertias neglected", 4.55e-13, 6.98, 0.4407),
            ("joints locked: joint2", 61.4, 4.68, 0.4853)]
    variants = Variants([Variant(name, 0.1, 1, us, abs_errors={"ud": error}, c_us_per_state=c_us)
                         for name, error, us, c_us in rows], 20, "rad/s²")
    labels_apart(pareto_plot(variants, tmp_path / "pareto.png", "double_pendulum"), variants)


@settings(max_examples=6, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(n=st.integers(9, 20),
       errors=st.lists(st.sampled_from([0.0, 4.55e-13, 5.3e-13, 2e-4, 11.2, 61.4, 238.0]),
                       min_size=20, max_size=20),
       times=st.lists(st.floats(0.5, 80.0), min_size=20, max_size=20), compiled=st.booleans(),
       crowded=st.booleans())
def test_random_variants_get_labels_apart(tmp_path_factory, n, errors, times, compiled, crowded):
    """Random variants, many tied in accuracy, some at one time (crowded): every label finds a place."""
    from eomgen.tradeoff import Variant, Variants, pareto_plot

    variants = Variants([Variant(f"variant {k}" + " with a longer name" * (k % 3), 0.1, 1,
                                 6.0 if crowded and k % 2 else times[k], abs_errors={"ud": errors[k]},
                                 c_us_per_state=times[k] / 20 if compiled else None)
                         for k in range(n)], 20, "rad/s²")
    path = tmp_path_factory.mktemp("pareto") / "pareto.png"
    labels_apart(pareto_plot(variants, path, "random"), variants)
