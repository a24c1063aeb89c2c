"""Sphinx configuration of eomgen's documentation.

Build: sphinx-build -W --keep-going -b html docs docs/_build/html
The API reference is read from the source tree (src/), and the notebooks in notebooks/ are executed
at every build with the same source (PYTHONPATH is set for their kernels)."""
import os
import sys
from pathlib import Path

DOCS = Path(__file__).resolve().parent
SRC = DOCS.parent / "src"
sys.path.insert(0, str(SRC))
sys.path.insert(0, str(DOCS / "_ext"))
# the notebook kernels are subprocesses: they import eomgen from the same source tree
os.environ["PYTHONPATH"] = os.pathsep.join(p for p in (str(SRC), os.environ.get("PYTHONPATH")) if p)

import eomgen  # noqa: E402

project = "eomgen"
author = "the eomgen authors"
copyright = "the eomgen authors"
release = eomgen.__version__
version = ".".join(release.split(".")[:2])

extensions = [
    "myst_nb",
    "sphinx.ext.autodoc",
    "sphinx.ext.mathjax",
    "eomgen_docs",
]

root_doc = "index"
exclude_patterns = ["_build", "**.ipynb_checkpoints", "Thumbs.db", ".DS_Store"]
default_role = "literal"  # `x` in a docstring is code, as in the source's comments

# --- MyST -------------------------------------------------------------------------------------
myst_enable_extensions = ["dollarmath", "amsmath", "colon_fence", "deflist"]
myst_heading_anchors = 3

# --- notebooks (myst-nb): executed at every build, an error fails it --------------------------
nb_execution_mode = "force"
nb_execution_raise_on_error = True
nb_execution_show_tb = True
nb_execution_timeout = 600
nb_kernel_rgx_aliases = {".*": "python3"}
nb_merge_streams = True

# --- autodoc ----------------------------------------------------------------------------------
autodoc_member_order = "bysource"
autodoc_typehints = "signature"
autodoc_default_options = {"members": True}
autodoc_inherit_docstrings = True
autoclass_content = "both"  # the class docstring and __init__'s

# --- HTML -------------------------------------------------------------------------------------
html_theme = "furo"
html_title = f"eomgen {release}"
html_static_path = []
