"""The data of an identification: states and torques checked where they enter, and the regressor
Y(q, u, u̇) evaluated at every state and stacked.

A regressor is a callable Y(q, u, u̇) → (nv, p), or batched (N, nv, p) for N states at once, with one
name per column. It is called on the whole batch first; its answer is taken when it has the batched
shape and its first state agrees with a single call, otherwise it is called state by state (`batch`
decides once, for a caller that evaluates it many times)."""
from __future__ import annotations

from collections.abc import Callable, Sequence

import numpy as np

from ..errors import ModelError

Regressor = Callable[[np.ndarray, np.ndarray, np.ndarray], np.ndarray]


def rows(x, name: str, width: int | None = None) -> np.ndarray:
    """`x` as a finite (N, width) float array; one state (a 1-D array) is N = 1."""
    try:
        a = np.atleast_2d(np.asarray(x, dtype=float))
    except (TypeError, ValueError) as error:
        raise ModelError(f"argument '{name}' must be an array of numbers: {error}") from None
    if a.ndim != 2:
        raise ModelError(f"argument '{name}' must be (N, n) (one row per state), got shape {a.shape}")
    if width is not None and a.shape[1] != width:
        raise ModelError(f"argument '{name}' must have {width} columns, got shape {a.shape}")
    if not np.isfinite(a).all():
        raise ModelError(f"argument '{name}' has non-finite entries (nan or inf)")
    return a


def states(q, u, ud) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(q, u, u̇) as (N, nq), (N, nv), (N, nv) arrays with the same N."""
    q, u = rows(q, "q"), rows(u, "u")
    ud = rows(ud, "ud", u.shape[1])
    if not len(q) == len(u) == len(ud):
        raise ModelError(f"arguments 'q', 'u', 'ud' must have one row per state each, got {len(q)}, "
                         f"{len(u)} and {len(ud)} rows")
    return q, u, ud


def checked_names(names: Sequence[str]) -> tuple[str, ...]:
    """The parameters' names: strings, no repeats."""
    names = tuple(names)
    if not all(isinstance(n, str) for n in names) or len(set(names)) != len(names):
        raise ModelError(f"argument 'names' must be distinct strings, one per regressor column, got {names}")
    return names


def stack(regressor: Regressor, names: Sequence[str], q, u, ud) -> np.ndarray:
    """Y at every state: (N, nv, p), p = len(names), every entry finite."""
    q, u, ud = states(q, u, ud)
    Y = batch(regressor, q, u, ud)(q, u, ud)
    shape = (len(q), u.shape[1], len(names))
    if Y.shape != shape:
        raise ModelError(f"argument 'regressor' must return (nv, p) = {shape[1:]} per state (p = the "
                         f"number of names), got {Y.shape[1:]}")
    if not np.isfinite(Y).all():
        raise ModelError("argument 'regressor' returned non-finite entries (nan or inf)")
    return Y


def batch(regressor: Regressor, q: np.ndarray, u: np.ndarray, ud: np.ndarray) -> Regressor:
    """The regressor as a batched callable, (N, nq), (N, nv), (N, nv) → (N, nv, p): itself where its
    answer to the batch (q, u, u̇) has that shape and agrees with a single call at the first state,
    else a loop over the states."""
    def loop(q, u, ud) -> np.ndarray:  # copies: a regressor may answer in one buffer (Pinocchio's data)
        return np.stack([np.array(regressor(*x), dtype=float) for x in zip(q, u, ud)])

    def whole(q, u, ud) -> np.ndarray:
        return np.array(regressor(q, u, ud), dtype=float)

    if getattr(regressor, "batched", False):  # already decided
        return regressor
    loop.batched = whole.batched = True
    try:
        Y = whole(q, u, ud)
    except Exception:  # a regressor of one state at a time
        return loop
    first = np.asarray(regressor(q[0], u[0], ud[0]), dtype=float)
    if Y.ndim != 3 or Y.shape[0] != len(q) or Y[0].shape != first.shape or not np.allclose(
            Y[0], first, rtol=1e-12, atol=0):
        return loop
    return whole
