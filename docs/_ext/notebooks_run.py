"""The notebooks executed afresh at every build, as many at a time as the machine has cores, into the
build's jupyter cache, which myst-nb then reads (nb_execution_mode = "cache"): the pages show outputs of
this build's run, never of an earlier one. Each runs in its own folder with the environment conf.py set;
one that raises fails the build with its traceback, as myst-nb's own execution would."""
from __future__ import annotations

import shutil
from pathlib import Path


def run_notebooks(folder: Path, cache_path: Path, timeout: int) -> None:
    """Execute every notebook of `folder` into a new jupyter cache at `cache_path` (in parallel); a
    RuntimeError naming each one that raised, with its traceback."""
    from jupyter_cache import get_cache
    from jupyter_cache.executors import load_executor

    shutil.rmtree(cache_path, ignore_errors=True)  # nothing of an earlier build is read
    cache = get_cache(str(cache_path))
    for notebook in sorted(folder.glob("*.ipynb")):
        cache.add_nb_to_project(str(notebook))
    result = load_executor("local-parallel", cache=cache).run_and_cache(timeout=timeout)
    failed = result.excepted + result.errored
    if failed:
        tracebacks = {r.uri: r.traceback for r in cache.list_project_records()}
        raise RuntimeError("notebooks that raised:\n" + "\n\n".join(
            f"{uri}:\n{tracebacks.get(uri) or '(no traceback: see the log above)'}" for uri in failed))
