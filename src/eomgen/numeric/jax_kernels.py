"""The C kernels under JAX: on CPU, a catalogue function's values come from the C backend's compiled
function, called by XLA through its FFI (`printers.ffi`: a handler in the extension module that reads
XLA's input buffers and writes into its output buffer; no host callback, no copy); its derivatives
are those of the traced graph (`printers.traced`):

    f(x) = C(x) on CPU, traced(x) on any other platform   (`jax.lax.platform_dependent`, at lowering;
           where JAX sees CPUs only, C(x) alone: the graph is then traced for derivatives only, which
           halves a big robot's first jit — lowering such a function for a GPU elsewhere, by
           `jax.export`, then fails naming the FFI target, never computes a wrong value)
    jvp:  (f(x), ∂f(x)·ẋ) = jax.jvp(traced, (x,), (ẋ,))    (so jit, vmap, jacfwd and grad go through)

One state is one FFI call (11 µs for ur5's M under jit). Under `jax.vmap` the call receives the inputs
with their batch axes (`vmap_method="expand_dims"`: an input not mapped has axes of size 1): the
states' axes are broadcast into ONE batch of the C function (nested vmaps too); a parameter vector not
mapped is passed once, mapped ones state by state. The C functions are compiled when the first of them
is traced (jit): those printed until then in one module (`Kernels`; as the C backend groups them: M,
b, g, nle and the frames of derive(frames=...) together, `generate(keys)` together), their handlers
registered with XLA. The C function checks its inputs: a NaN or infinite value raises (naming q, u,
ud or p; a ValueError or a JaxRuntimeError) where the traced graph returns NaN. float32: the kernels
compute in float64, their values rounded to float32."""
from __future__ import annotations

import threading
import warnings

import numpy as np

from ..errors import ModelError
from ..functions import Catalogue
from ..printers.build.extension import compiler, python_headers
from ..printers.c_extension import ExtensionPrinter

KERNELS = ("c", "xla")
REGISTERED: set[str] = set()  # the FFI targets registered with XLA in this process


def kernels_for(kernels: str | None) -> str:
    """The kernels asked for, checked: "c" or "xla"; None: "c" where a C compiler and Python's headers are
    found (as the C backend finds them), else "xla"; "c" without them a ModelError saying what is
    missing."""
    if kernels is not None and kernels not in KERNELS:
        raise ModelError(f"kernels: expected one of {list(KERNELS)} or None, got {kernels!r}")
    if kernels == "xla":
        return kernels
    try:
        compiler(), python_headers()
    except ModelError as missing:
        if kernels == "c":
            raise ModelError(f"kernels='c': {missing}; kernels='xla' computes without them") from None
        return "xla"
    return "c"


class Kernels:
    """The C functions of a catalogue as XLA FFI targets, compiled on the first trace of one of them:
    every function added until then in one extension module (`printers.ffi`), once (threads wait on a
    lock), its handlers registered with XLA as "<module>_m<i>". Where the module does not build (an XLA
    FFI header this glue does not know, say): a ModelError if the kernels were asked for (`required`),
    else a warning, once, and the traced graph on CPU too (`target` None)."""

    def __init__(self, catalogue: Catalogue, required: bool = False) -> None:
        self.catalogue, self.required, self.failed = catalogue, required, False
        self.pending: list[str] = []
        self.compiled: dict[str, str] = {}
        self._lock = threading.Lock()

    def add(self, key: str) -> None:
        with self._lock:
            if key not in self.compiled and key not in self.pending:
                self.pending.append(key)

    def target(self, key: str) -> str | None:
        """The name of the FFI target of function `key`: (q, u, ud, p) → out (`printers.ffi`); None where
        the module does not build (the class's text)."""
        import jax.ffi

        with self._lock:
            if self.failed:
                return None
            if key not in self.compiled:
                keys = list(dict.fromkeys([*self.pending, key]))
                try:
                    functions = ExtensionPrinter(self.catalogue, ffi=True).print(keys)
                except ModelError as failure:
                    reason = f"the C kernels do not build with JAX {jax.__version__}: {failure}"[:1500]
                    if self.required:
                        raise ModelError(f"kernels='c': {reason}") from None
                    warnings.warn(f"{reason}; the JAX functions evaluate the traced graph on CPU too "
                                  "(kernels='xla')", stacklevel=2)
                    self.failed = True
                    return None
                module = next(iter(functions.values())).function.__self__
                for (k, generated), handler in zip(functions.items(), module._ffi()):
                    target = f"{module.__name__}_{generated.function.__name__}"
                    if target not in REGISTERED:  # once per process
                        jax.ffi.register_ffi_target(target, handler, platform="cpu")
                        REGISTERED.add(target)
                    self.compiled[k] = target
                self.pending = []
            return self.compiled[key]


def only_cpu() -> bool:
    """Whether JAX's devices here are CPUs only (then a function is lowered for CPU alone)."""
    import jax

    return {d.platform for d in jax.devices()} == {"cpu"}


def kernel_function(traced, key: str, shape: tuple[int, int], kernels: Kernels):
    """`traced` (q, u, ud, p) → array of `shape`, with its values from the C function `key` on CPU (module
    doc), jitted (its first call compiles the branch of the platform only)."""
    import jax
    import jax.ffi

    kernels.add(key)

    def on_cpu(q, u, ud, p):
        target = kernels.target(key)
        if target is None:
            return traced(q, u, ud, p)
        dtype = jax.dtypes.canonicalize_dtype(np.float32 if q.dtype == np.float32 else np.float64)
        c = jax.ffi.ffi_call(target, jax.ShapeDtypeStruct(shape, dtype), vmap_method="expand_dims")
        return c(*(x.astype(dtype) for x in (q, u, ud, p)))

    @jax.custom_jvp
    def f(q, u, ud, p):
        if only_cpu():  # no other platform to lower for: the graph is traced for derivatives only
            return on_cpu(q, u, ud, p)
        return jax.lax.platform_dependent(q, u, ud, p, cpu=on_cpu, default=traced)

    # the tangent needs the traced graph's intermediates: its primal comes with them at no extra cost
    f.defjvp(lambda primals, tangents: jax.jvp(traced, primals, tangents))
    return jax.jit(f)
