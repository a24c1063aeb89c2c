"""The numeric layer: the facade `eg.codegen` returns over a printed catalogue, and the numeric algorithms
on its public functions (forward and constrained dynamics, the state equations, assembly, reduction)."""
from .assembly import assemble, project
from .codegen import BACKENDS, codegen
from .compiled import CompiledEoM
from .equations import NumericEoM
from .facade import Functions
from .kane import CompiledKane, NumericKane
from .reduction import Reduced, reduce

__all__ = ["BACKENDS", "CompiledEoM", "CompiledKane", "Functions", "NumericEoM", "NumericKane", "Reduced",
           "assemble", "codegen", "project", "reduce"]
