"""The Python/NumPy target: a generated function's source run as a Python function."""
from __future__ import annotations


def compile_function(source: str, label: str, name: str = "f"):
    """The function `name` defined by `source` (our own generated arithmetic, nothing else)."""
    namespace: dict = {}
    exec(compile(source, f"<eomgen {ascii(label)}>", "exec"), namespace)
    return namespace[name]
