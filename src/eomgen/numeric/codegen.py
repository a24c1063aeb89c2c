"""`eg.codegen`: the numeric functions of equations, printed for a backend."""
from __future__ import annotations

from collections.abc import Mapping

from ..errors import ModelError
from ..functions import expect_equations
from ..methods.kane import KaneEquations
from .equations import NumericEoM
from .kane import CompiledKane, NumericKane
from .parameters import bind

BACKENDS = ("numpy", "c", "jax", "casadi")


def codegen(eom, backend: str = "numpy", params: Mapping | None = None, dtype: str = "float64",
            kernels: str | None = None):
    """Numeric functions of an `EquationsOfMotion` (or of `KaneEquations`): backend "numpy", "c"
    (compiled with the machine's C compiler; same functions, per call and batched), "jax" (JAX functions:
    jit, vmap, grad; `dtype` "float64" or "float32"; `kernels` "c": on CPU the values from the C
    backend's compiled kernels, one C call per vmapped batch, the default where a C compiler is found,
    or "xla": the traced graph on every platform) or "casadi" (CasADi functions on SX, `f.casadi`).
    With `params` ({name: value}, every parameter but the motor currents) the values are bound once and
    the calls take no params."""
    expect_equations(eom, "codegen", KaneEquations)
    if backend not in BACKENDS:
        raise ModelError(f"unknown backend {backend!r}; available: {list(BACKENDS)}")
    if dtype != "float64" and backend != "jax":
        raise ModelError(f"dtype: only the JAX backend computes in {dtype!r}; {backend!r} computes in "
                         "float64")
    if kernels is not None and backend != "jax":
        raise ModelError(f"kernels: only the JAX backend chooses its kernels; {backend!r} takes none")
    kane = isinstance(eom, KaneEquations)
    if backend == "c":
        from .compiled import CompiledEoM

        f = CompiledKane(eom) if kane else CompiledEoM(eom)
    elif backend == "jax":
        from .jax_functions import JaxEoM
        from .jax_kane import JaxKane

        f = JaxKane(eom, dtype, kernels) if kane else JaxEoM(eom, dtype, kernels)
    elif backend == "casadi":
        from .casadi_functions import CasadiEoM
        from .casadi_kane import CasadiKane

        f = CasadiKane(eom) if kane else CasadiEoM(eom)
    else:
        f = NumericKane(eom) if kane else NumericEoM(eom)
    return f if params is None else bind(f, params)
