"""The values a model accepts: numbers, sympy expressions and symbols, and arrays of them.

Every field of a model passes through here where it enters, so that a value eomgen cannot handle is
refused with an error naming the field, never turned into a wrong number later: strings are refused
(sympy would evaluate them as Python), as are non-finite and complex numbers, noncommutative symbols,
functions of time, derivatives, integrals and relations."""
from __future__ import annotations

import numbers

import numpy as np
import sympy as sp
from sympy.core.function import AppliedUndef

from ..errors import ModelError

_UNHANDLED = (AppliedUndef, sp.Derivative, sp.Integral)
LARGEST = 1e150  # its square is still a float64


def scalar(value, what: str) -> sp.Expr:
    """A number or a sympy expression, checked (see the module); `what` names the field."""
    if isinstance(value, np.generic) or isinstance(value, np.ndarray) and value.ndim == 0:
        value = value.item()  # numpy scalars as Python numbers (sympy cannot take a float32 NaN)
    if isinstance(value, bool) or not isinstance(value, (numbers.Number, sp.Expr)):
        raise ModelError(f"{what}: expected a number or a sympy expression, got {type(value).__name__} "
                         f"{value!r}" + (" (strings are not parsed: use sympy.Symbol or a number)"
                                         if isinstance(value, str) else ""))
    expr = sp.sympify(value)
    if expr.has(sp.nan, sp.zoo, sp.oo, -sp.oo):
        raise ModelError(f"{what}: must be finite, got {expr}")
    if not expr.is_commutative:
        raise ModelError(f"{what}: {expr} does not commute; use plain sympy Symbols")
    if expr.is_number and expr.is_real is False:
        raise ModelError(f"{what}: must be real, got {expr}")
    if expr.is_number and abs(float(expr)) > LARGEST:
        raise ModelError(f"{what}: {float(expr):.3g} is too large: products of two model values must stay "
                         f"finite in float64 (|value| ≤ {LARGEST:.0e})")
    unhandled = expr.atoms(*_UNHANDLED)
    if unhandled:
        raise ModelError(f"{what}: {sorted(map(str, unhandled))[0]} is not a value eomgen handles; use plain "
                         "sympy Symbols for parameters (coordinates and speeds come from the joints)")
    return expr


def nonnegative(value, what: str) -> sp.Expr:
    """A checked scalar that is not negative."""
    value = scalar(value, what)
    if value.is_negative:
        raise ModelError(f"{what} must be non-negative, got {value}")
    return value


def matrix(value, shape: tuple[int, int], what: str) -> sp.Matrix:
    """A sympy matrix of checked scalars with the given shape (a 3-vector may be a row or a column)."""
    if isinstance(value, sp.MatrixBase):
        entries, got = list(value), value.shape
    elif isinstance(value, (str, bytes)) or np.ndim(value) == 0 and not isinstance(value, (list, tuple)):
        raise ModelError(f"{what}: expected an array of shape {shape}, got {value!r}")
    else:  # nested sequences and arrays
        try:
            array = np.asarray(value, dtype=object)
        except ValueError as exc:  # ragged nesting
            raise ModelError(f"{what}: expected an array of shape {shape}, got {value!r}") from exc
        entries, got = array.ravel().tolist(), array.shape
    vector = shape[1] == 1 and got in ((shape[0],), (1, shape[0]))
    if got != shape and not vector:
        kind = f"a {shape[0]}-vector" if shape[1] == 1 else f"a {shape[0]}×{shape[1]} matrix"
        raise ModelError(f"{what}: expected {kind}, got shape {got}")
    return sp.Matrix(*shape, [scalar(x, f"{what}[{k}]") for k, x in enumerate(entries)])


def vector3(value, what: str) -> sp.Matrix:
    """A 3×1 column of checked scalars; `what` names the field."""
    return matrix(value, (3, 1), what)


def matrix3(value, what: str) -> sp.Matrix:
    """A 3×3 matrix of checked scalars; `what` names the field."""
    return matrix(value, (3, 3), what)


def is_numeric(m: sp.Matrix) -> bool:
    return all(x.is_number for x in m)
