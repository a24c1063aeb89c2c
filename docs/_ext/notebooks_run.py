"""Sphinx extension: with nb_execution_mode "force" (every notebook run at every build), the notebooks run
before any page is read, as many at a time as the machine has cores, into a new jupyter cache of this
build (beside its doctrees); myst-nb then reads their outputs from it ("cache" mode, for this build only).
Each runs in its own notebook's folder, with the environment conf.py set, the timeout and allow_errors
of the configuration; a notebook whose kernel an alias of nb_kernel_rgx_aliases renames is left to
myst-nb, which runs it alone. A notebook that raises stops the build, named, with its traceback."""
from __future__ import annotations

import json
import logging
import re
import shutil
import time
from pathlib import Path

from sphinx.errors import ExtensionError
from sphinx.util import logging as sphinx_logging
from sphinx.util.matching import Matcher

LOG = sphinx_logging.getLogger(__name__)
COLOURS = re.compile(r"\x1b\[[0-9;]*m")  # the ANSI colours of a traceback


def own_kernel(path: Path, aliases: dict[str, str]) -> bool:
    """Whether the notebook names a kernel that no alias renames (the kernel myst-nb would start)."""
    name = json.loads(path.read_text(encoding="utf-8")).get("metadata", {}).get("kernelspec", {}).get("name")
    return name is not None and not any(re.fullmatch(pattern, name) and alias != name
                                        for pattern, alias in aliases.items())


def run_notebooks(app) -> None:
    """Run the build's notebooks in parallel into its cache and hand myst-nb the cache (module doc)."""
    config = app.config
    if config.nb_execution_mode != "force":
        return
    from jupyter_cache import get_cache
    from jupyter_cache.executors import load_executor

    path = Path(app.doctreedir) / "jupyter_cache"
    if path.exists():
        shutil.rmtree(path)  # nothing of an earlier build is read (a failed removal raises)
    cache, source = get_cache(str(path)), Path(app.srcdir)
    excluded = Matcher([*config.exclude_patterns, *config.nb_execution_excludepatterns])
    for notebook in sorted(source.rglob("*.ipynb")):
        if not excluded(notebook.relative_to(source).as_posix()) \
                and own_kernel(notebook, config.nb_kernel_rgx_aliases):
            cache.add_nb_to_project(str(notebook))
    quiet = logging.getLogger(f"{__name__}.executor")
    quiet.setLevel(logging.WARNING)  # the executor's failures only, not its progress
    start = time.perf_counter()
    result = load_executor("local-parallel", cache=cache, logger=quiet).run_and_cache(
        timeout=config.nb_execution_timeout, allow_errors=config.nb_execution_allow_errors)
    failed = result.excepted + result.errored
    if failed:
        tracebacks = {r.uri: r.traceback for r in cache.list_project_records()}
        raise ExtensionError("notebooks that raised:\n" + "\n\n".join(
            f"{uri}:\n{COLOURS.sub('', tracebacks.get(uri) or '(no traceback: see the log above)')}"
            for uri in failed))
    LOG.info(f"notebooks: {len(result.succeeded)} run in {time.perf_counter() - start:.1f} s, in parallel")
    config.nb_execution_mode, config.nb_execution_cache_path = "cache", str(path)


def setup(app):
    app.setup_extension("myst_nb")
    app.connect("builder-inited", run_notebooks, priority=400)  # before myst-nb reads its configuration
    return {"parallel_read_safe": True, "parallel_write_safe": True}
