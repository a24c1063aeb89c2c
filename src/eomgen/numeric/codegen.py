"""`eg.codegen`: the numeric functions of equations, printed for a backend."""
from __future__ import annotations

from collections.abc import Mapping

from ..errors import ModelError
from ..functions import expect_equations
from ..methods.kane import KaneEquations
from .equations import NumericEoM
from .kane import CompiledKane, NumericKane
from .parameters import bind

BACKENDS = ("numpy", "c")


def codegen(eom, backend: str = "numpy", params: Mapping | None = None):
    """Numeric functions of an `EquationsOfMotion` (or of `KaneEquations`): backend "numpy", or "c"
    (compiled with the machine's C compiler; same functions, per call and batched). With `params`
    ({name: value}, every parameter but the motor currents) the values are bound once and the calls
    take no params."""
    expect_equations(eom, "codegen", KaneEquations)
    if backend not in BACKENDS:
        raise ModelError(f"unknown backend {backend!r}; available: {list(BACKENDS)}")
    kane = isinstance(eom, KaneEquations)
    if backend == "c":
        from .compiled import CompiledEoM

        f = CompiledKane(eom) if kane else CompiledEoM(eom)
    else:
        f = NumericKane(eom) if kane else NumericEoM(eom)
    return f if params is None else bind(f, params)
