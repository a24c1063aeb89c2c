"""The example notebooks of docs/notebooks run from top to bottom without an error. Each asserts its
results against an independent truth (a closed form by hand, Pinocchio, a physical invariant), so
running a notebook is a test that can fail. And a plain kernel (no `%matplotlib inline`) shows what
eg.plot and eg.animate return: a PNG, an HTML player."""
import base64
import io
import os
import subprocess
import sys
from pathlib import Path

import nbformat
import pytest
from nbclient import NotebookClient
from PIL import Image

ROOT = Path(__file__).parents[1]
NOTEBOOKS = sorted((ROOT / "docs" / "notebooks").glob("*.ipynb"))


def test_notebooks_are_there_without_outputs():
    assert len(NOTEBOOKS) >= 6, NOTEBOOKS
    for path in NOTEBOOKS:
        nb = nbformat.read(path, as_version=4)
        nbformat.validate(nb)
        code = [c for c in nb.cells if c.cell_type == "code"]
        assert code and all(not c.outputs and c.execution_count is None for c in code), path.name


def _eomgen_importable(cwd: Path) -> bool:
    """Whether the kernel (this Python, this environment, started in `cwd`) imports eomgen without
    help (a relative PYTHONPATH=src does not reach from there)."""
    run = subprocess.run([sys.executable, "-c", "import eomgen"], capture_output=True, cwd=cwd)
    return run.returncode == 0


def _execute(nb, tmp_path, monkeypatch):
    """Run `nb` in a fresh python3 kernel started in `tmp_path`, importing this eomgen."""
    if not _eomgen_importable(tmp_path):  # a source checkout: the kernel imports eomgen from src
        paths = [str(ROOT / "src"), *filter(None, [os.environ.get("PYTHONPATH")])]
        monkeypatch.setenv("PYTHONPATH", os.pathsep.join(paths))
    client = NotebookClient(nb, timeout=600, kernel_name="python3",
                            resources={"metadata": {"path": str(tmp_path)}})
    client.execute()  # raises CellExecutionError, naming the cell, on any error or failed assert


@pytest.mark.slow  # the docs build executes every notebook and fails on an error (.ci/run builds them)
@pytest.mark.parametrize("path", NOTEBOOKS, ids=lambda p: p.stem)
def test_notebook_runs(path, tmp_path, monkeypatch):
    _execute(nbformat.read(path, as_version=4), tmp_path, monkeypatch)


PENDULUM = """import eomgen as eg
system = eg.System(gravity=(0, -9.81, 0))
system.add_body("rod", joint=eg.Revolute("phi", axis=(0, 0, 1)), mass=1.0, com=(0.5, 0, 0))
sim = eg.simulate(eg.codegen(eg.derive(system)), ([0.3], [0.0]), (0.0, 1.0))"""


def test_plain_kernel_shows_plot_and_animation(tmp_path, monkeypatch):
    """eg.plot(sim) as the last line of a cell: a PNG of the figure's size (3 rows of 2.5 by 8 inches at
    matplotlib's 100 dpi: 800 × 750 px); eg.animate(sim, frames=3): a player with its 3 frames as PNGs that
    loads nothing from the network (no http(s) address in it)."""
    cells = [PENDULUM, "eg.plot(sim)", "eg.animate(sim, frames=3)"]
    nb = nbformat.v4.new_notebook(cells=[nbformat.v4.new_code_cell(c) for c in cells])
    _execute(nb, tmp_path, monkeypatch)
    (figure,), (player,) = (nb.cells[k].outputs for k in (1, 2))
    png = Image.open(io.BytesIO(base64.b64decode(figure.data["image/png"])))
    assert png.format == "PNG" and png.size == (800, 750)
    html = player.data["text/html"]
    assert html.count("data:image/png;base64") == 3 and "Animation" in html
    assert "http:" not in html and "https:" not in html
