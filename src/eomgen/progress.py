"""Progress bars for long work (large derivations, C compiles, trigsimp, trade-off runs).

`progress(iterable, desc)` shows a tqdm bar on stderr when stderr is a terminal, or as a widget in
a Jupyter notebook (the text bar there when ipywidgets is missing). Otherwise it returns the
iterable itself: no tqdm object, nothing printed. A bar appears only after `DELAY` seconds, so short
work shows nothing, then keeps its elapsed time current, so one slow step (a compile) still shows
it ticking; it vanishes when the loop ends.

Who decides, first match wins: `eomgen.quiet()` silences; the environment variable
`EOMGEN_PROGRESS=0` silences and `EOMGEN_PROGRESS=1` forces the bars on (logs, CI); else the
terminal or notebook test above."""
from __future__ import annotations

import os
import sys
import threading
import warnings

DELAY = 0.5  # seconds before a bar appears

_silenced = False


class quiet:
    """`quiet()` or `quiet(True)` silences every bar from now on, `quiet(False)` ends that (the
    environment and the terminal decide again); as a context manager, `with eomgen.quiet(): ...`,
    the setting holds in the block only."""

    def __init__(self, on: bool = True) -> None:
        global _silenced
        self._before, _silenced = _silenced, bool(on)

    def __enter__(self) -> quiet:
        return self

    def __exit__(self, *exc) -> None:
        global _silenced
        _silenced = self._before


def shown() -> bool:
    """Whether a bar would be shown now."""
    if _silenced:
        return False
    setting = os.environ.get("EOMGEN_PROGRESS", "").strip()
    if setting in ("0", "1"):
        return setting == "1"
    return _in_kernel() or bool(getattr(sys.stderr, "isatty", lambda: False)())


def _in_kernel() -> bool:
    """Running in a Jupyter kernel: IPython's shell has a kernel (ipykernel merely imported, as by a
    test runner that executes notebooks, is not enough)."""
    ipython = sys.modules.get("IPython")
    shell = getattr(ipython, "get_ipython", lambda: None)() if ipython is not None else None
    return getattr(shell, "kernel", None) is not None


def progress(iterable, desc: str, total: int | None = None, unit: str = "it"):
    """`iterable` with a progress bar labelled `desc` (`total` items, default len(iterable)), or
    `iterable` unchanged when bars are not shown (see the module doc)."""
    if not shown():
        return iterable
    return _bar(iterable, desc, total, unit)


def _bar(iterable, desc, total, unit):
    with warnings.catch_warnings():  # tqdm.auto warns when a notebook lacks ipywidgets
        warnings.simplefilter("ignore")
        from tqdm.auto import tqdm
    if total is None and hasattr(iterable, "__len__"):
        total = len(iterable)
    bar = tqdm(total=total, desc=desc, unit=unit, delay=DELAY, leave=False, miniters=0,
               smoothing=0, file=sys.stderr)
    lock, done = threading.Lock(), threading.Event()

    def tick():  # update(0) redraws the elapsed time (once DELAY has passed); rates: overall means
        while not done.wait(0.2):
            with lock:
                bar.update(0)

    threading.Thread(target=tick, daemon=True).start()
    try:
        for item in iterable:
            yield item
            with lock:
                bar.update()
    finally:
        done.set()
        with lock:
            bar.close()
