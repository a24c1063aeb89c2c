"""Sphinx configuration of eomgen's documentation.

Build: sphinx-build -W --keep-going -b html docs docs/_build/html
The API reference is read from the source tree (src/), and the notebooks in notebooks/ are executed
at every build, in parallel, with the same source (PYTHONPATH is set for their kernels, and
EOMGEN_PROGRESS=0: no progress bars in the stored outputs). MathJax is served from the build
(sphinx-mathjax-offline), so the pages typeset their math without a network."""
import os
import sys
from pathlib import Path

DOCS = Path(__file__).resolve().parent
SRC = DOCS.parent / "src"
sys.path.insert(0, str(SRC))
sys.path.insert(0, str(DOCS / "_ext"))
# the notebook kernels are subprocesses: they import eomgen from the same source tree
os.environ["PYTHONPATH"] = os.pathsep.join(p for p in (str(SRC), os.environ.get("PYTHONPATH")) if p)
os.environ["EOMGEN_PROGRESS"] = "0"  # a bar the kernel shows would be stored in the page

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
    "sphinx-mathjax-offline",  # MathJax 3 copied into _static/mathjax: no CDN
    "eomgen_docs",
    "notebooks_run",  # the notebooks run in parallel before the pages are read
]

root_doc = "index"
exclude_patterns = ["_build", "**.ipynb_checkpoints", "Thumbs.db", ".DS_Store"]
default_role = "literal"  # `x` in a docstring is code, as in the source's comments

# --- MyST -------------------------------------------------------------------------------------
myst_enable_extensions = ["dollarmath", "amsmath", "colon_fence", "deflist"]
myst_heading_anchors = 3
myst_update_mathjax = False  # MathJax reads the whole page (no mathjax_ignore): outputs' math included

# --- notebooks (myst-nb): executed at every build, an error fails it --------------------------
nb_execution_mode = "force"  # notebooks_run: all of them run first, in parallel; myst-nb reads their outputs
nb_execution_raise_on_error = True
nb_execution_show_tb = True
nb_execution_timeout = 600
nb_kernel_rgx_aliases = {".*": "python3"}
nb_merge_streams = True
nb_render_markdown_format = "myst"  # outputs' Markdown (eg.solution): tables, $$ math with its \\ kept

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
mathjax_path = "mathjax/tex-chtml.js"  # in _static, where sphinx-mathjax-offline puts MathJax
mathjax3_config = {  # Sphinx writes math as \(...\) and \[...\]: only these are math ("$$" in prose is text)
    "tex": {"inlineMath": [["\\(", "\\)"]], "displayMath": [["\\[", "\\]"]], "processEnvironments": False,
            "packages": {"[+]": ["textmacros"]}},  # \text{cart\_force} as LaTeX writes it
    "loader": {"load": ["[tex]/textmacros"]},
}
