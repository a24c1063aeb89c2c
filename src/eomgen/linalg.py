"""Small matrix products that never form 0 · x.

sympy answers `0 * (a + b)` by asking whether a + b is finite, which walks the whole expression;
robots have many structural zeros (axes, placements, Jacobian columns), so the products used in the
derivations skip them."""
from __future__ import annotations

import sympy as sp


def mul(a, b) -> sp.Expr:
    return sp.Integer(0) if a == 0 or b == 0 else a * b


def dot(a, b) -> sp.Expr:
    """Σ a_k b_k over the entries of two equally long sequences."""
    return sp.Add(*[x * y for x, y in zip(a, b) if x != 0 and y != 0])


def matmul(A: sp.Matrix, B: sp.Matrix) -> sp.Matrix:
    """A B."""
    rows = [A.row(i) for i in range(A.rows)]
    cols = [B.col(j) for j in range(B.cols)]
    return sp.Matrix(A.rows, B.cols, lambda i, j: dot(rows[i], cols[j]))


def scale(s, A: sp.Matrix) -> sp.Matrix:
    """s A."""
    return A.applyfunc(lambda x: mul(s, x))


def cross(a: sp.Matrix, b: sp.Matrix) -> sp.Matrix:
    """a × b."""
    return sp.Matrix([dot((a[1], -a[2]), (b[2], b[1])), dot((a[2], -a[0]), (b[0], b[2])),
                      dot((a[0], -a[1]), (b[1], b[0]))])
