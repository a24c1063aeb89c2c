"""The example notebooks of docs/notebooks run from top to bottom without an error. Each asserts its
results against an independent truth (a closed form by hand, Pinocchio, a physical invariant), so
running a notebook is a test that can fail."""
import os
import subprocess
import sys
from pathlib import Path

import nbformat
import pytest
from nbclient import NotebookClient

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


@pytest.mark.parametrize("path", NOTEBOOKS, ids=lambda p: p.stem)
def test_notebook_runs(path, tmp_path, monkeypatch):
    if not _eomgen_importable(tmp_path):  # a source checkout: the kernel imports eomgen from src
        paths = [str(ROOT / "src"), *filter(None, [os.environ.get("PYTHONPATH")])]
        monkeypatch.setenv("PYTHONPATH", os.pathsep.join(paths))
    nb = nbformat.read(path, as_version=4)
    client = NotebookClient(nb, timeout=600, kernel_name="python3",
                            resources={"metadata": {"path": str(tmp_path)}})
    client.execute()  # raises CellExecutionError, naming the cell, on any error or failed assert
