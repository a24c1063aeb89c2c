"""The Python/NumPy target: a generated function's source run as a Python function."""
from __future__ import annotations

from ..engine import collection_paused


def compile_function(source: str, label: str, name: str = "f"):
    """The function `name` defined by `source` (our own generated arithmetic, nothing else)."""
    namespace: dict = {}
    with collection_paused():  # the compiler's syntax tree: many objects, none of them cyclic garbage
        exec(compile(source, f"<eomgen {ascii(label)}>", "exec"), namespace)
    return namespace[name]
