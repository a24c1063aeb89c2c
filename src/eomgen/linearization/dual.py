"""Forward mode over a numeric pipeline: a matrix x and its derivatives dx along n directions at once.

A `Dual` holds the value x (r × c) and the tangent dx (n × r × c, None for a constant), and its operations
apply the rules

    d(x ± y) = dx ± dy,   d(x y) = dx y + x dy,   d(A⁻¹ b) = A⁻¹ (db − dA A⁻¹ b),

so that a pipeline written once for the values (products, transposes, rows, solves) yields the columns
of its Jacobian. The `Algebra` does the solves: NumPy's LU with pivoting (numbers), or elimination on
pivots proven nonzero, the entries in lowest terms (`methods.kane.solve_proven` with sympy's cancel:
sympy expressions at a symbolic operating point), with Kane's stated assumptions (`assume_nonzero`)."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import sympy as sp

from ..errors import ModelError
from ..methods.kane import NoPivot, solve_proven
from ..methods.nonzero import Nonzero


class Algebra:
    """Numbers (float arrays) or, with `symbolic`, sympy expressions (object arrays); `nonzero`: the
    expressions stated nonzero (Kane's `assume_nonzero`; None where none can be stated)."""

    def __init__(self, symbolic: bool, nonzero: Nonzero | None = None) -> None:
        self.symbolic, self.nonzero = symbolic, nonzero
        self.dtype = object if symbolic else float

    def zeros(self, *shape: int) -> np.ndarray:
        return np.zeros(shape, dtype=self.dtype) if not self.symbolic else np.full(shape, sp.S.Zero)

    def eye(self, n: int) -> np.ndarray:
        return np.eye(n) if not self.symbolic else np.array(sp.eye(n).tolist(), dtype=object).reshape(n, n)

    def array(self, values) -> np.ndarray:
        """A 2-D array of numbers or of sympy expressions."""
        if not self.symbolic:
            return np.atleast_2d(np.asarray(values, dtype=float))
        a = np.atleast_2d(np.array(values, dtype=object))
        return np.vectorize(sp.sympify, otypes=[object])(a) if a.size else a

    def solve(self, A: np.ndarray, B: np.ndarray, what: str) -> np.ndarray:
        """A⁻¹ B for B of shape (r, c) or (n, r, c) (one factorization)."""
        if not self.symbolic:
            return np.linalg.solve(A, B)
        columns = np.moveaxis(B, -2, 0).reshape(B.shape[-2], -1)  # (r, n c)
        try:
            X = solve_proven(sp.Matrix(A), sp.Matrix(columns), what, sp.cancel, self.nonzero or Nonzero())
        except NoPivot as error:
            state = "" if self.nonzero is None else f", or state it nonzero: {error.hint}"
            raise ModelError(
                f"linearize: no closed form at this operating point: {what} has no pivot proven nonzero "
                f"(candidates {error.candidates}); linearize numerically (symbolic=False){state}"
            ) from None
        X = np.array(X.tolist(), dtype=object).reshape(columns.shape)
        return np.moveaxis(X.reshape((B.shape[-2],) + B.shape[:-2] + B.shape[-1:]), 0, -2)


@dataclass(frozen=True)
class Dual:
    """A matrix (value, r × c) and its derivatives along n directions (tangent, n × r × c; None: 0)."""

    value: np.ndarray
    tangent: np.ndarray | None = None

    @property
    def T(self) -> Dual:
        return Dual(self.value.T, None if self.tangent is None else np.swapaxes(self.tangent, 1, 2))

    def __getitem__(self, index) -> Dual:
        index = index if isinstance(index, tuple) else (index,)
        return Dual(
            self.value[index], None if self.tangent is None else self.tangent[(slice(None), *index)]
        )

    def __neg__(self) -> Dual:
        return Dual(-self.value, None if self.tangent is None else -self.tangent)

    def __add__(self, other: Dual) -> Dual:
        return Dual(self.value + other.value, _sum(self.tangent, other.tangent))

    def __sub__(self, other: Dual) -> Dual:
        return self + -other

    def __matmul__(self, other: Dual) -> Dual:
        left = None if self.tangent is None else self.tangent @ other.value
        right = None if other.tangent is None else self.value @ other.tangent
        return Dual(self.value @ other.value, _sum(left, right))

    def __mul__(self, other: Dual) -> Dual:
        """The entrywise product (broadcast as NumPy does)."""
        left = None if self.tangent is None else self.tangent * other.value
        right = None if other.tangent is None else self.value * other.tangent
        return Dual(self.value * other.value, _sum(left, right))


def _sum(a: np.ndarray | None, b: np.ndarray | None) -> np.ndarray | None:
    return b if a is None else a if b is None else a + b


def solve(algebra: Algebra, A: Dual, B: Dual, what: str) -> Dual:
    """X = A⁻¹ B, dX = A⁻¹ (dB − dA X)."""
    X = algebra.solve(A.value, B.value, what)
    rhs = _sum(B.tangent, None if A.tangent is None else -(A.tangent @ X))
    return Dual(X, None if rhs is None else algebra.solve(A.value, rhs, what))


def vstack(parts: list[Dual], n: int, algebra: Algebra) -> Dual:
    """The rows of `parts` one below the other (n directions)."""
    value = np.concatenate([p.value for p in parts], axis=0)
    if all(p.tangent is None for p in parts):
        return Dual(value)
    return Dual(
        value,
        np.concatenate(
            [algebra.zeros(n, *p.value.shape) if p.tangent is None else p.tangent for p in parts], axis=1
        ),
    )


def placed(parts: list[tuple[list[int], Dual]], n: int, algebra: Algebra) -> Dual:
    """One matrix from the rows of several: parts [(the row indices they take, Dual)], together every
    row index once."""
    order = np.argsort(np.concatenate([np.asarray(indices, dtype=int) for indices, _ in parts]))
    return vstack([d for _, d in parts], n, algebra)[order]
