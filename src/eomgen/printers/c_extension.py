"""The C extension target: catalogue functions printed as C (`syntax.C_TRIG`, named e<i> in the order
asked), compiled into one CPython extension module (`build.extension`) and called directly, one state
per call or N states in one call; their vector functions (`vector`) compiled into a second module on the
first batch. A composite (the forward dynamics' derivatives) is printed from its parts' C
(`forward_c`), which must be printed in the same module. With ffi=True the module also holds the
functions as XLA FFI handlers (`ffi`: its `_ffi()`), for JAX."""
from __future__ import annotations

import dataclasses
import warnings
import weakref
from collections.abc import Callable

from ..errors import ModelError
from ..functions import Catalogue
from ..progress import progress
from .build.extension import build, compile_module, compiled
from .ffi import handlers
from .forward_c import forward_derivatives_source
from .syntax import C_TRIG
from .vector import C_VECTOR, lanes_source, vector_sources
from .walker import Generated, writer


class ExtensionPrinter:
    """Prints functions of one catalogue into extension modules (`print`)."""

    def __init__(self, catalogue: Catalogue, batches: bool = True, ffi: bool = False) -> None:
        self.catalogue, self.ffi = catalogue, ffi
        self._c, self._lanes = writer(catalogue, C_TRIG), writer(catalogue, C_VECTOR) if batches else None
        self.sizes = tuple(len(catalogue.inputs[x]) for x in ("q", "u", "p"))

    def print(self, keys: list[str]) -> dict[str, Generated]:
        """The functions `keys`, compiled into one module (with `batches`, vector functions on the first
        batch)."""
        written, exprs, index = [], [], {}
        for i, key in enumerate(progress(keys, "printing C", unit="function")):
            fn, index[key] = self.catalogue[key], i
            if fn.composite:
                parts = [written[index[k]] for k in fn.parts]
                source = forward_derivatives_source(f"e{i}", *(f"e{index[k]}" for k in fn.parts),
                                                    self.sizes[1], C_TRIG)
                trig = sorted(set().union(*(part[4] for part in parts)))
                written.append((key, source, fn.shape, sum(part[3] for part in parts), trig))
                exprs.append(None)
                continue
            exprs.append((fn.expression(), fn.symmetric))
            source, shape, ops = self._c.source(f"e{i}", *exprs[-1])
            written.append((key, source, shape, ops, self._c.trig_indices))

        def lanes() -> list[str | None]:  # on the first batch
            printing = progress(exprs, "printing vector C", unit="function")
            return vector_sources(self._lanes, printing, len(exprs))
        functions = extension_functions(written, *self.sizes, lanes if self._lanes else None, self.ffi)
        for key, i in index.items():  # a composite reads the parameters its parts read
            fn = self.catalogue[key]
            if fn.composite:
                source = "".join(written[index[k]][1] for k in fn.parts) + written[i][1]
                functions[key] = dataclasses.replace(functions[key], source=source)
        return functions


def extension_functions(written: list, nq: int, nv: int, n_params: int,
                        lanes: Callable[[], list[str | None]] | None = None,
                        ffi: bool = False) -> dict[str, Generated]:
    """The written functions [(key, C source of e<i>, shape, operations, trig indices)], compiled into
    one extension module (with `ffi`, their XLA FFI handlers too); with `lanes`, the C of their vector
    functions w<i> (`vector.vector_sources`), compiled into a second module on the first batch."""
    functions = [(source, shape, trig) for _, source, shape, _, trig in written]
    if ffi:
        import jax.ffi
        import jaxlib

        glue = handlers([(shape, len(trig)) for _, shape, trig in functions], jaxlib.__version__)
        module = build(functions, nq, nv, n_params, glue, (jax.ffi.include_dir(),))
    else:
        module = build(functions, nq, nv, n_params)

    if lanes is not None:
        module._hook(first_batch(module, lanes, nq, nv, n_params))
    return {key: Generated(source, shape, ops, getattr(module, f"m{i}"), getattr(module, f"v{i}"), lanes)
            for i, (key, source, shape, ops, _) in enumerate(written)}


_waiting: dict[str, weakref.WeakSet] = {}  # by module name: the printings of its vector functions queued


def first_batch(module, lanes: Callable[[], list[str | None]], nq: int, nv: int, n_params: int):
    """The hook of `module` (`_hook`): on its first batch, the vector functions of a printing queued for
    it attached. The module, cached for the process, holds its hook; the queue holds `lanes` weakly (the
    module's `Generated` hold it), so dropped functions free their equations. Each codegen of the module
    queues its printing: whichever is still alive prints (their C is the same)."""
    waiting = _waiting.setdefault(module.__name__, weakref.WeakSet())
    waiting.add(lanes)

    def attach() -> None:
        alive = list(waiting)  # a collection or another thread may drop one while this runs
        if not alive:  # no function of the module is left to run a batch
            return
        try:
            module._attach(lanes_module(alive[0](), nq, nv, n_params).lanes)
        except ModelError as error:  # the compiler refuses vector types: one state at a time
            warnings.warn(f"batches run one state at a time: {error}", stacklevel=3)
        except BaseException:  # interrupted (Ctrl-C while printing): the next batch tries again
            module._hook(attach)
            raise
        waiting.clear()
    return attach


def lanes_module(sources: list[str | None], nq: int, nv: int, n_params: int):
    """The module of the vector functions `sources` (`vector.lanes_source`)."""
    def source(name: str) -> str:
        return lanes_source(name, sources, nq, nv, n_params)

    return compiled(source(""), lambda name, target: compile_module(source(name), [], target))
