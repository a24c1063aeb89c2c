"""The Python/NumPy target: a generated function's source run as a Python function."""
from __future__ import annotations

from functools import lru_cache

from ..engine import collection_paused


def compile_function(source: str, label: str, name: str = "f"):
    """The function `name` defined by `source` (our own generated arithmetic, nothing else): a new
    function object each time, from the code object compiled once per process (`_code`)."""
    namespace: dict = {}
    exec(_code(source, label), namespace)
    return namespace[name]


@lru_cache(maxsize=64)
def _code(source: str, label: str):
    """Python's code object of `source` (immutable), for where the same equations are generated again,
    e.g. one robot in several places of a program; the last 64 texts are kept, also after their model is
    gone (a few MB each for a humanoid's derivatives)."""
    with collection_paused():  # the compiler's syntax tree: many objects, none of them cyclic garbage
        return compile(source, f"<eomgen {ascii(label)}>", "exec")
