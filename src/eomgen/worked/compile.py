"""A LaTeX document compiled to PDF, unable to run programs or to read and write files outside its
folder: pdflatex with -no-shell-escape, in a private temporary folder, with TeX Live's paranoid file
access (openin_any=p, openout_any=p: no absolute paths, no .. and no dot files), so that a name that
escaped its escaping still cannot read a file into the PDF."""

from __future__ import annotations

import os
import shutil
import subprocess
import tempfile
from pathlib import Path

from ..errors import ModelError

SAFE = {"openin_any": "p", "openout_any": "p", "shell_escape": "f"}
SECONDS = 300  # at most, for one document


def compile_pdf(document: str, path, engine: str = "pdflatex") -> Path:
    """`document` (LaTeX) compiled by `engine` to a PDF at `path`."""
    exe = shutil.which(engine)
    if exe is None:
        raise ModelError(
            f"no LaTeX engine {engine!r} on this machine: install one (TeX Live's pdflatex) "
            "or write the .tex with solution.latex(path)"
        )
    path = Path(path)
    with tempfile.TemporaryDirectory() as folder:  # mode 0700: this user's only
        (Path(folder) / "solution.tex").write_text(document, encoding="utf-8")
        try:
            run = subprocess.run(
                [exe, "-no-shell-escape", "-interaction=nonstopmode", "-halt-on-error", "solution.tex"],
                cwd=folder,
                capture_output=True,
                text=True,
                errors="replace",
                env={**os.environ, **SAFE},
                stdin=subprocess.DEVNULL,
                timeout=SECONDS,
            )
        except subprocess.TimeoutExpired:
            raise ModelError(f"{engine} did not finish within {SECONDS} s") from None
        if run.returncode != 0:
            raise ModelError(f"{engine} failed:\n{run.stdout[-2000:]}")
        shutil.copy(Path(folder) / "solution.pdf", path)
    return path
