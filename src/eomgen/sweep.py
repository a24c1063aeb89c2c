"""`eg.sweep`: one generated function over more states than fit in memory, on a Dask cluster.

The states are split into chunks of `chunk` rows; chunk k is one task, run on a worker process, which
rebuilds the functions from the model itself: the client sends the pickled equations (their symbols and
expressions, never a compiled module), the worker calls `eg.codegen` on them once per process (the C
backend's cache on disk makes that a load) and keeps them for every later chunk. Chunk k's output rows
are the states k·chunk … k·chunk + n_k − 1, in order: a task run twice (its worker lost) writes the
same rows again, so no chunk is lost or repeated. States made on the workers (`RandomChunks`) and, with
`reduce`, the outputs go into arrays each worker thread reuses from chunk to chunk (no fresh pages)."""
from __future__ import annotations

import hashlib
import os
import pickle
import threading
import uuid
import weakref
from collections.abc import Callable
from dataclasses import dataclass, field, replace
from functools import cached_property

import numpy as np

from .errors import ModelError
from .model import System
from .numeric import CompiledEoM, CompiledKane, NumericEoM, NumericKane, codegen
from .numeric.parameters import BoundParameters
from .progress import progress as bar
from .state import random_states

_built: dict[str, object] = {}  # the functions this process rebuilt, by Model.token, for later chunks
_given = weakref.WeakValueDictionary()  # the functions swept from this process, by Model.token, while held
_clients: dict[str, object] = {}  # the clients sweep started, by cluster address ("" for its own)
SLICE = 1024  # the states of a chunk evaluated and reduced at a time: their outputs stay in the cache
ASSOCIATIVE = (np.add, np.multiply, np.maximum, np.minimum, np.fmax, np.fmin, np.logaddexp, np.logaddexp2,
               np.hypot)  # the reductions `reduce` takes: (a ∘ b) ∘ c = a ∘ (b ∘ c)
_reused = threading.local()  # each thread's arrays, by name: states made and outputs to be reduced


def reused(name: str, shape: tuple[int, ...]) -> np.ndarray:
    """A C-contiguous float64 array of `shape`, this thread's `name`: the first rows of one kept from an
    earlier chunk when it has as many columns and enough rows, else a new one kept for later chunks."""
    kept = getattr(_reused, name, None)
    if kept is None or kept.shape[1:] != shape[1:] or len(kept) < shape[0]:
        kept = np.empty(shape)
        setattr(_reused, name, kept)
    return kept[:shape[0]]


@dataclass(frozen=True)
class RandomChunks:
    """Chunk k of n random states of `system`, made where it is used: `eg.random_states` with the
    generator seeded by (seed, k), so a chunk is the same states wherever and however often it is made."""

    system: System
    seed: int = 0

    def __call__(self, k: int, n: int, out: tuple | None = None) -> tuple[np.ndarray, ...]:
        """(q, u, u̇) of chunk k; with `out`, its first arrays (see `eg.random_states`) filled."""
        return random_states(self.system, n, np.random.default_rng((self.seed, k)), out)


@dataclass(frozen=True)
class Model:
    """What a worker needs to rebuild the functions: the pickled equations, the backend, the bound
    parameter values ({name: value}, or None); and, never pickled, the functions swept (`local`)."""

    equations: bytes
    backend: str
    bound: dict | None
    local: object = field(default=None, compare=False, repr=False)

    def __getstate__(self) -> dict:
        return {k: v for k, v in self.__dict__.items() if k != "local"}

    @cached_property
    def token(self) -> str:
        return hashlib.sha256(pickle.dumps((self.equations, self.backend, self.bound))).hexdigest()

    def functions(self):
        """The functions swept, in the process that swept them (held by the sweep's tasks; found by token
        where a task is a copy), else built once per process."""
        given = self.local if self.local is not None else _given.get(self.token)
        if given is not None:
            return given
        if self.token not in _built:
            f = codegen(pickle.loads(self.equations), self.backend)
            _built[self.token] = f if self.bound is None else f.bind(self.bound)
        return _built[self.token]


def model(functions) -> Model:
    """The `Model` of numeric functions from `eg.codegen` (NumPy or C), else a ModelError naming them."""
    if isinstance(functions, (CompiledEoM, CompiledKane)):
        backend = "c"
    elif type(functions) in (NumericEoM, NumericKane):
        backend = "numpy"
    else:
        raise ModelError(f"functions: eg.sweep evaluates the functions of eg.codegen(eom) with the NumPy or "
                         f"C backend, got {type(functions).__name__}")
    equations = functions.kane if isinstance(functions, NumericKane) else functions.eom
    p = functions.parameters
    bound = None if not isinstance(p, BoundParameters) else \
        {n: float(v) for k, (n, v) in enumerate(zip(p.names, p.bound)) if k not in p.state}
    m = Model(pickle.dumps(equations), backend, bound, functions)
    _given.setdefault(m.token, functions)  # a chunk run in this process uses them as they are
    return m


@dataclass(frozen=True)
class Evaluate:
    """The task of chunk k: `key` at its states, given as blocks or made by `make(k, n_k)` (n_k the
    chunk's rows: `chunk`, the last one the rest of `n`; a `RandomChunks` fills reused arrays); with
    `reduce` (a NumPy ufunc), the outputs reduced over the chunk's states, `reduce.reduce(outputs, axis=0)`,
    slice by slice of SLICE states (the outputs written into a reused array), returned as one row."""

    model: Model
    key: str
    inputs: tuple[str, ...]  # the states `key` reads, of "q", "u", "ud"
    columns: dict[str, int]  # the columns of q, u and ud
    params: dict | None
    make: Callable | None = None
    chunk: int = 0
    n: int = 0
    reduce: np.ufunc | None = None
    shape: tuple[int, ...] = ()  # of one state's output

    def __call__(self, *blocks, block_id=None) -> np.ndarray:
        if self.make is not None:
            k = block_id[0]
            n = min(self.chunk, self.n - k * self.chunk)
            reuse = isinstance(self.make, RandomChunks)
            made = self.make(k, n, self.buffers(n)) if reuse else self.make(k, n)
            blocks = picked(made, self.inputs, self.columns)
        f = self.model.functions()
        if self.reduce is None:
            return self.at(f, blocks)
        rows = len(blocks[0])
        out, total = reused("outputs", (min(SLICE, rows), *self.shape)), None
        for start in range(0, rows, SLICE):  # each slice's outputs reduced while they are in the cache
            part = [x[start:start + SLICE] for x in blocks]
            reduced = blockwise(self.reduce, self.at(f, part, out[:len(part[0])]))
            total = reduced if total is None else self.reduce(total, reduced, out=total)
        return total[np.newaxis]

    def buffers(self, n: int) -> tuple[np.ndarray, ...]:
        """This thread's arrays for the states q, u, u̇ up to the last one `key` reads, n rows each."""
        last = max(("q", "u", "ud").index(name) for name in self.inputs)
        return tuple(reused(name, (n, self.columns[name])) for name in ("q", "u", "ud")[:last + 1])

    def at(self, f, blocks, out: np.ndarray | None = None) -> np.ndarray:
        """`key` of functions f at the states `blocks` (one array per input), into `out` when given."""
        states = dict(zip(self.inputs, blocks))
        return f.call(self.key, states["q"], states.get("u"), states.get("ud"), self.params, out)


def blockwise(ufunc: np.ufunc, x: np.ndarray) -> np.ndarray:
    """ufunc.reduce(x, axis=0) for x of r rows, as r = k·m rows: the k blocks of m rows reduced into one
    first (k the largest divisor of r up to √r: k − 1 ufunc calls over m rows at once), then its m rows.
    NumPy's own reduction over rows pays a loop per row: this pays ~2√r. (np.add sums in another order.)"""
    r = len(x)
    k = int(np.sqrt(r))
    while r % k:
        k -= 1
    return ufunc.reduce(ufunc.reduce(x.reshape(k, -1), axis=0).reshape(r // k, *x.shape[1:]), axis=0)


def picked(states, inputs: tuple[str, ...], columns: dict[str, int]) -> list:
    """The arrays `inputs` (of "q", "u", "ud") of states q, (q, u) or (q, u, u̇); each array given 2-D,
    with the rows of q and its `columns`; else a ModelError naming states."""
    if not isinstance(states, (tuple, list)):
        states = (states,)
    if not 1 <= len(states) <= 3:
        raise ModelError(f"states: expected q, (q, u) or (q, u, ud), got {len(states)} arrays")
    given = {name: x for name, x in zip(("q", "u", "ud"), states) if x is not None}
    for name, x in given.items():
        if np.shape(x) != (*np.shape(given["q"])[:1], columns[name]):
            raise ModelError(f"states: {name} must have shape (N, {columns[name]}), N the rows of q, got "
                             f"{np.shape(x)}")
    if missing := [name for name in inputs if name not in given]:
        raise ModelError(f"states: the function reads {', '.join(inputs)}; {', '.join(missing)} missing")
    return [given[name] for name in inputs]


def client(cluster):
    """A dask.distributed Client: of `cluster` (a Client, a cluster object or a scheduler address), else
    the default client, else one of a LocalCluster of worker processes (1 thread each) started once."""
    from distributed import Client, LocalCluster, default_client

    if isinstance(cluster, Client):
        return cluster
    if cluster is None:
        try:
            return default_client()
        except ValueError:
            pass
    name = "" if cluster is None else getattr(cluster, "scheduler_address", cluster)
    if not isinstance(name, str):
        raise ModelError(f"cluster: expected a scheduler address, a dask cluster or Client, got {cluster!r}")
    if name not in _clients or _clients[name].status != "running":
        target = cluster if cluster is not None else LocalCluster(
            n_workers=os.cpu_count(), threads_per_worker=1, processes=True, dashboard_address=None)
        _clients[name] = Client(target)
    return _clients[name]


def reads(functions, key) -> tuple[str, ...]:
    """The states function `key` reads (of "q", "u", "ud"), printed now on the client (a bad frame refused
    here, a C module compiled once, into the cache the workers load it from); else a ModelError naming key."""
    if not isinstance(key, str):
        raise ModelError(f"key: expected a function's key such as 'M', 'nle' or 'J:<frame>', got {key!r}")
    try:
        functions.generate([key])
        return tuple(s.strip() for s in functions.catalogue[key].inputs.split(","))
    except ModelError as error:
        raise ModelError(f"key: {error}") from None


def count(n, name: str) -> int:
    """n, a positive integer, else a ModelError naming it."""
    if not isinstance(n, (int, np.integer)) or isinstance(n, bool) or n < 1:
        raise ModelError(f"{name}: expected a positive number of states, got {n!r}")
    return int(n)


def sweep(functions, key: str, states, chunk: int = 100_000, cluster=None, out: str | None = None,
          progress: bool = True, params: dict | None = None, n: int | None = None,
          reduce: np.ufunc | None = None):
    """`functions.call(key, q, u, ud, params)` at N states, chunk by chunk on the workers of `cluster`
    (see `client`). `states`: q, (q, u) or (q, u, ud), NumPy or Dask arrays of N rows; or a callable
    `make(k, n_k)` returning chunk k's states (e.g. `RandomChunks(system, seed)`), with `n` = N. Returns
    a lazy Dask array of shape (N, ...) (it computes on the cluster), or, with `out` a path, writes it to
    Zarr there (a progress bar over the chunks) and returns the Zarr array. With `reduce` an associative
    NumPy ufunc (`ASSOCIATIVE`: np.add, np.maximum, ...), each chunk's outputs are reduced over its states
    where they are evaluated (`reduce.reduce(outputs, axis=0)`, grouped in slices; never stored): the
    result has one row per chunk (e.g. `eg.sweep(f, "M", states, reduce=np.add).sum(axis=0)` is Σ M over the states)."""
    try:
        import dask.array as da
        import distributed  # noqa: F401
    except ImportError:
        raise ModelError("eg.sweep needs dask.distributed (and zarr for out=): pip install 'eomgen[sweep]'") \
            from None
    if reduce is not None and not any(reduce is u for u in ASSOCIATIVE):
        raise ModelError(f"reduce: expected an associative NumPy ufunc of two floats (the chunks and their "
                         f"slices are reduced in any grouping): one of "
                         f"{', '.join('np.' + u.__name__ for u in ASSOCIATIVE)}, got {reduce!r}")
    built = model(functions)
    columns = {name: len(functions.catalogue.inputs[name]) for name in ("q", "u", "ud")}
    task = Evaluate(built, key, reads(functions, key), columns, params)
    chunk = count(chunk, "chunk")
    if callable(states):
        n = count(n, "n")
        sample = picked(states(0, 1), task.inputs, columns)
        rows, blocks = (chunk,) * (n // chunk) + ((n % chunk,) if n % chunk else ()), []
        task = replace(task, make=states, chunk=chunk, n=n)
    else:
        blocks = [da.asarray(x).rechunk((chunk, -1)) for x in picked(states, task.inputs, columns)]
        rows, sample = blocks[0].chunks[0], [np.asarray(x[:1]) for x in blocks]
        if n is not None and n != sum(rows):
            raise ModelError(f"n: {n!r} given for states of {sum(rows)} rows")
    shape = task.at(functions, sample).shape[1:]
    if reduce is not None:
        task, rows = replace(task, reduce=reduce, shape=shape), (1,) * len(rows)
    pool = client(cluster)  # dask's default client from now on: the lazy array computes there
    result = da.map_blocks(task, *blocks, name=f"eomgen-sweep-{key}-{uuid.uuid4().hex}", dtype=float,
                           chunks=(rows, *((s,) for s in shape)), meta=np.empty((0, *shape)),
                           **({"drop_axis": 1, "new_axis": list(range(1, 1 + len(shape)))} if blocks else {}))
    return result if out is None else written(result, out, pool, progress)


def store(block: np.ndarray, path: str, start: int) -> tuple[int, int]:
    """Write one chunk's rows at `start` of the Zarr array at `path`; the rows written (start, stop)."""
    import zarr

    zarr.open_array(path, mode="r+")[start:start + len(block)] = block
    return start, start + len(block)


def written(result, path: str, pool, shown: bool):
    """The sweep `result` computed chunk by chunk and written to a new Zarr array at `path` (one Zarr
    chunk per sweep chunk: no two tasks write the same chunk); the rows written are checked to cover
    the N states once."""
    import dask
    import zarr
    from distributed import as_completed

    rows = result.chunks[0]
    target = zarr.create_array(path, shape=result.shape, chunks=(rows[0], *result.shape[1:]), dtype="f8",
                               overwrite=True)
    starts = np.cumsum((0,) + rows[:-1])
    futures = pool.compute([dask.delayed(store)(b, path, int(s))
                            for b, s in zip(result.to_delayed().ravel(), starts)])
    done = as_completed(futures, with_results=True)
    marks = sorted(mark for _, mark in (bar(done, "sweep", len(futures), "chunk") if shown else done))
    if marks != [(int(s), int(s) + r) for s, r in zip(starts, rows)]:
        raise ModelError(f"out: the chunks written, {marks}, do not cover the {len(result)} states once")
    return target
