"""Numeric arguments of the numeric layer checked where they enter, each error naming the argument:
arrays of finite real numbers (no strings, which numpy would parse, no booleans, no None), positive
tolerances, counts and flags."""
from __future__ import annotations

import numbers

import numpy as np

from .errors import ModelError


def finite_array(x, shape: tuple[int, ...], what: str) -> np.ndarray:
    """x as a float64 array of `shape`, every entry a finite real number (not a bool or a string)."""
    try:
        entries = np.asarray(x, dtype=object)
    except ValueError:  # ragged nesting
        raise ModelError(f"{what}: expected {_numbers(shape)}, got {x!r}") from None
    kinds = {type(v) for v in entries.ravel()}
    if any(issubclass(k, (bool, np.bool_)) or not issubclass(k, numbers.Real) for k in kinds):
        got = ", ".join(sorted(k.__name__ for k in kinds))
        raise ModelError(f"{what}: expected {_numbers(shape)}, got {got} {x!r}")
    a = np.asarray(x, dtype=float)
    if a.shape != shape:
        raise ModelError(f"{what}: expected {_numbers(shape)}, got shape {a.shape}")
    if not np.isfinite(a).all():
        bad = a.tolist() if a.size <= 12 else f"{(~np.isfinite(a)).sum()} of its {a.size} entries"
        raise ModelError(f"{what}: contains NaN or infinite values: {bad}")
    return a


def _numbers(shape: tuple[int, ...]) -> str:
    if not shape:
        return "a finite number"
    if shape == (1,):
        return "1 finite number"
    if len(shape) == 1:
        return f"{shape[0]} finite numbers"
    return f"an array of shape {shape} of finite numbers"


def positive(x, what: str) -> float:
    """A finite real number > 0 (a tolerance, a gain)."""
    value = float(finite_array(x, (), what))
    if not value > 0:
        raise ModelError(f"{what}: expected a finite number > 0, got {x!r}")
    return value


def count(x, what: str, least: int = 1) -> int:
    """An integer ≥ `least` (not a bool)."""
    if isinstance(x, bool) or not isinstance(x, numbers.Integral) or x < least:
        raise ModelError(f"{what}: expected an integer ≥ {least}, got {x!r}")
    return int(x)


def flag(x, what: str) -> bool:
    """True or False, nothing else ("yes" and 1 are refused: a truthy value is not a choice)."""
    if not isinstance(x, (bool, np.bool_)):
        raise ModelError(f"{what}: expected True or False, got {x!r}")
    return bool(x)
