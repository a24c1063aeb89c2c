"""The tuple products of `eomgen.linalg` (the hot core's 3-vectors and row-major 3×3 matrices) against
sympy's Matrix arithmetic on the same entries: symbols, numbers and the structural zeros they skip."""
from __future__ import annotations

import sympy as sp
from hypothesis import given, settings
from hypothesis import strategies as st

from eomgen.engine import vector
from eomgen.linalg import (add, apply, apply_T, compose, compose_T, cross, diagonal, dot, half_quadratic_form,
                           outer, scale, subtract, total)

a, b, c = sp.symbols("a b c")
ENTRIES = st.sampled_from([sp.Integer(0), sp.Integer(0), sp.Integer(2), sp.Rational(-1, 3), a, b, -c, a + b,
                           sp.cos(c), a * b])  # exact: no rounding between the two orders of summation
VECTORS = st.tuples(ENTRIES, ENTRIES, ENTRIES)
MATRICES = st.tuples(*[ENTRIES] * 9)


def same(tuple_result, matrix_result: sp.Matrix) -> bool:
    """Equal entry by entry (expanded: sympy may group a product differently)."""
    return len(tuple_result) == len(matrix_result) and all(
        sp.expand(x - y) == 0 for x, y in zip(tuple_result, matrix_result))


@settings(max_examples=25, deadline=None)
@given(A=MATRICES, B=MATRICES, u=VECTORS, v=VECTORS, s=ENTRIES)
def test_products_equal_sympy_matrices(A, B, u, v, s):
    MA, MB, Mu, Mv = sp.Matrix(3, 3, A), sp.Matrix(3, 3, B), sp.Matrix(u), sp.Matrix(v)
    assert vector(MA) == A and sp.Matrix(vector(Mu)) == Mu
    assert same(apply(A, u), MA * Mu)
    assert same(apply_T(A, u), MA.T * Mu)
    assert same(compose(A, B), MA * MB)
    assert same(compose_T(A, B), MA * MB.T)
    assert same(outer(u, v), Mu * Mv.T)
    assert same(cross(u, v), Mu.cross(Mv)) and isinstance(cross(u, v), tuple)
    assert isinstance(cross(Mu, v), sp.MatrixBase) and same(cross(Mu, v), Mu.cross(Mv))
    assert same(add(u, v), Mu + Mv) and same(subtract(A, B), MA - MB)
    assert same(total([u, v, u]), 2 * Mu + Mv)
    assert same(scale(s, A), s * MA) and isinstance(scale(s, MA), sp.MatrixBase)
    assert same(diagonal(s), s * sp.eye(3))
    assert sp.expand(half_quadratic_form(MA, u) - (Mu.T * MA * Mu)[0] / 2) == 0
    speeds = sp.symbols("u0:3")  # of symbols: the very sum sympy forms from ½ (uᵀ A u)
    assert half_quadratic_form(MA, speeds) == sp.Rational(1, 2) * sp.Add(*[x * dot(row, speeds) for x, row in
                                                                           zip(speeds, MA.tolist())])


def test_zero_products_are_not_formed():
    """0 · (a + b) is 0 without asking sympy (a zero entry of an axis or placement)."""
    assert apply((0, 0, 0, 0, 1, 0, 0, 0, 0), (a + b, c, a)) == (0, c, 0)
    assert cross((0, 0, 1), (a, b, 0)) == (-b, a, 0)
