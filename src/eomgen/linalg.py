"""Small vector and matrix products on plain tuples of scalars that never form 0 · x or x + 0.

The hot core (kinematics, the recursions) keeps a 3-vector as a tuple (x, y, z) and a 3×3 matrix as
the tuple of its 9 entries row by row (the order in which `sp.Matrix` iterates them): indexing a
tuple is much cheaper than a `sp.Matrix`, which checks and converts every entry it gives or takes.
`engine.vector` takes a `sp.Matrix`'s entries in, `Subexpressions.matrix` gives one out. sympy
answers `0 * (a + b)` by asking whether a + b is finite, which walks the whole expression; robots have
many structural zeros (axes, placements, Jacobian columns), so the products skip them. `cross` and
`scale` take an `sp.Matrix` as well and then give one; `matmul` multiplies `sp.Matrix`es of any shape.
The scalars are sympy's or the hot core's engine's (`engine`); the constants are Python integers, which
either engine takes as its own (symengine's 0 is Python's too: symengine converts a Python integer at
three times the cost of a product, and compares its own 0 with Python's at that cost)."""
from __future__ import annotations

from collections.abc import Sequence

import sympy as sp

from .engine import total_of

Vector = tuple  # (x, y, z)
Matrix3 = tuple  # (A_00, A_01, A_02, A_10, ..., A_22)

ZEROS = frozenset({0})  # `x in ZEROS` is x == 0 (equal numbers hash equally), without building a 0 to compare
ZERO: Vector = (0,) * 3
IDENTITY: Matrix3 = tuple(int(i == j) for i in range(3) for j in range(3))


def mul(a, b) -> sp.Expr:
    return 0 if a in ZEROS or b in ZEROS else a * b


def dot(a, b) -> sp.Expr:
    """Σ a_k b_k over the entries of two equally long sequences."""
    return total_of([x * y for x, y in zip(a, b) if x not in ZEROS and y not in ZEROS])


def add(a: Sequence, b: Sequence) -> tuple:
    """a + b, entry by entry (x + 0 is x)."""
    return tuple(y if x in ZEROS else x if y in ZEROS else x + y for x, y in zip(a, b))


def subtract(a: Sequence, b: Sequence) -> tuple:
    """a − b, entry by entry (x − 0 is x, 0 − y is −y)."""
    return tuple(x if y in ZEROS else -y if x in ZEROS else x - y for x, y in zip(a, b))


def total(terms, start: Sequence = ZERO) -> tuple:
    """start + Σ terms, entry by entry, each entry summed once (a running sum would sort the terms it
    holds again at every step: quadratic in the terms)."""
    entries = [[] if x in ZEROS else [x] for x in start]
    for term in terms:
        for entry, x in zip(entries, term):
            entry.append(x)
    return tuple(map(total_of, entries))


def scale(s, A):
    """s A (an `sp.Matrix` for an `sp.Matrix`)."""
    if isinstance(A, sp.MatrixBase):
        return A.applyfunc(lambda x: mul(s, x))
    return tuple(mul(s, x) for x in A)


def cross(a: Sequence, b: Sequence):
    """a × b (an `sp.Matrix` where a or b is one)."""
    c = (dot((a[1], -a[2]), (b[2], b[1])), dot((a[2], -a[0]), (b[0], b[2])), dot((a[0], -a[1]), (b[1], b[0])))
    return sp.Matrix(c) if isinstance(a, sp.MatrixBase) or isinstance(b, sp.MatrixBase) else c


def apply(A: Matrix3, v: Sequence) -> Vector:
    """A v."""
    return dot(A[0:3], v), dot(A[3:6], v), dot(A[6:9], v)


def apply_T(A: Matrix3, v: Sequence) -> Vector:
    """Aᵀ v."""
    return dot(A[0::3], v), dot(A[1::3], v), dot(A[2::3], v)


def compose(A: Matrix3, B: Matrix3) -> Matrix3:
    """A B."""
    return tuple(dot(A[3 * i:3 * i + 3], B[j::3]) for i in range(3) for j in range(3))


def compose_T(A: Matrix3, B: Matrix3) -> Matrix3:
    """A Bᵀ."""
    return tuple(dot(A[3 * i:3 * i + 3], B[3 * j:3 * j + 3]) for i in range(3) for j in range(3))


def outer(a: Vector, b: Vector) -> Matrix3:
    """a bᵀ."""
    return tuple(mul(x, y) for x in a for y in b)


def diagonal(s) -> Matrix3:
    """s 1."""
    return tuple(mul(s, x) for x in IDENTITY)


def half_quadratic_form(A, x: Sequence) -> sp.Expr:
    """½ xᵀ A x (a kinetic energy ½ uᵀ M u) as (x/2) · (A x), of an `sp.Matrix` or a list of rows: for x of
    symbols, the ½ in each term where sympy puts it when it distributes ½ over xᵀ A x, without forming the
    sum twice."""
    rows = A.tolist() if isinstance(A, sp.MatrixBase) else A
    return dot([xi / 2 for xi in x], [dot(row, x) for row in rows])


def matmul(A: sp.Matrix, B: sp.Matrix) -> sp.Matrix:
    """A B of two `sp.Matrix`es."""
    rows = [A.row(i) for i in range(A.rows)]
    cols = [B.col(j) for j in range(B.cols)]
    return sp.Matrix(A.rows, B.cols, lambda i, j: dot(rows[i], cols[j]))
