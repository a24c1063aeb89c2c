"""Base parameters in the user's own symbols, from the structure of the tree (the grouping of Khalil and
Kleinfinger, for frames of any orientation whose joint axes lie along a coordinate axis of the body frame).

Each body's inertial parameters π_j = (m, h = m c, I_O) (Pinocchio's order, about the body frame's origin
O_j, in the body frame) enter the equations only through the energies, which are linear in π_j. Parts of
π_j whose energies depend on the parent's motion alone can be moved onto the parent, leaving the
equations unchanged (β = K π with Y π = Y_R β, Y_R the retained columns):

    revolute about a = e_k (i, j, k cyclic):  m, h_k a and I_jj (1 − a aᵀ) move; the body keeps
        I_ii − I_jj (at I_ii), I_kk, I_ij, I_ik, I_jk, h_i, h_j (seven)
    prismatic along a = e_k:  the rotational inertia I_O moves; the body keeps m and h (four)
    fixed:  everything moves

A part (m, h, I) at O_j becomes, on the parent (x_parent = R x + p, the joint's placement),

    m,  R h + m p,  R I Rᵀ + m (pᵀp 1 − p pᵀ) + 2 (pᵀ h') 1 − p h'ᵀ − h' pᵀ   (h' = R h),

since a revolute joint's rotation leaves a, h_k a and (1 − a aᵀ) in place. What moves onto the world
has no effect (it is not identifiable). A revolute joint with a = e_k whose parent's angular velocity is
always perpendicular to a (the world, or a link turning about a fixed axis b ⊥ a): a·ω_j = q̇_j, so its
armature enters as the body's I_kk does (½ I_a q̇²) and is grouped with I_kk. Bodies whose joint is of
another kind (spherical, free, helical, several axes) and axes off the coordinate axes keep their ten
parameters.

What is left may still hold columns that never move (a body turning about a fixed axis: its I_ii − I_jj,
I_ij, ...; first moments along gravity) or dependencies beyond these rules: `check` finds them on the
numerical regressor."""
from __future__ import annotations

from dataclasses import dataclass

import sympy as sp

from ..model.joints import Fixed, Prismatic, Revolute
from ..model.system import System

NAMES = ("m", "mx", "my", "mz", "Ixx", "Ixy", "Iyy", "Ixz", "Iyz", "Izz")  # Pinocchio's order
INERTIA = {(0, 0): 4, (0, 1): 5, (1, 1): 6, (0, 2): 7, (1, 2): 8, (2, 2): 9}


def body_parameters(body) -> list[sp.Expr]:
    """π_j = (m, m c, I_O) of a body, I_O = I_c + m (cᵀc 1 − c cᵀ), in Pinocchio's order."""
    m, c = body.mass, body.com
    I_O = body.inertia + m * ((c.T * c)[0] * sp.eye(3) - c * c.T)
    return [m, *(m * c), *(I_O[i, j] for (i, j) in INERTIA)]


def inertia_matrix(x: list) -> sp.Matrix:
    """The symmetric 3×3 inertia of a parameter vector (entries 4..9)."""
    return sp.Matrix(3, 3, lambda i, j: x[INERTIA[(min(i, j), max(i, j))]])


def moved(part: list, R: sp.Matrix, p: sp.Matrix) -> list:
    """A part (m, h, I) at a body's origin, written on its parent (x_parent = R x + p)."""
    m, h = part[0], R * sp.Matrix(part[1:4])
    I = R * inertia_matrix(part) * R.T + m * ((p.T * p)[0] * sp.eye(3) - p * p.T) \
        + 2 * (p.T * h)[0] * sp.eye(3) - p * h.T - h * p.T
    return [m, *(h + m * p), *(I[i, j] for (i, j) in INERTIA)]


def coordinate_axis(joint) -> int | None:
    """k where the joint's axis is ±e_k, else None."""
    axis = [sp.nsimplify(x) if x.is_number else x for x in joint.axis]
    for k in range(3):
        if all(axis[n] == 0 for n in range(3) if n != k) and axis[k] in (1, -1):
            return k
    return None


def split(joint, x: list) -> tuple[list, list]:
    """(what the body keeps, what moves onto the parent) of its accumulated parameters x."""
    zero = [sp.S.Zero] * 10
    if isinstance(joint, Fixed):
        return zero, list(x)
    k = coordinate_axis(joint) if isinstance(joint, (Revolute, Prismatic)) else None
    if k is None:
        return list(x), zero
    keep, move = list(x), list(zero)
    if isinstance(joint, Prismatic):
        for n in range(4, 10):
            keep[n], move[n] = sp.S.Zero, x[n]
        return keep, move
    i, j = (k + 1) % 3, (k + 2) % 3
    ii, jj = INERTIA[(i, i)], INERTIA[(j, j)]
    move[0], keep[0] = x[0], sp.S.Zero
    move[1 + k], keep[1 + k] = x[1 + k], sp.S.Zero
    y = x[jj]
    keep[ii], keep[jj] = x[ii] - y, sp.S.Zero
    move[ii], move[jj] = y, y  # y (1 − a aᵀ) = y (e_i e_iᵀ + e_j e_jᵀ)
    return keep, move


@dataclass(frozen=True)
class Grouping:
    """β = K π: `names[r]` stands on the regressor's column `columns[r]` (Y π = Y[:, columns] β);
    `expressions[r]` is β_r in the user's symbols; `K` has entries in the geometry's symbols."""

    names: list
    columns: list
    expressions: list
    K: sp.Matrix

    def restrict(self, kept) -> "Grouping":
        """The grouping of the parameters `kept` (booleans, one per β) alone."""
        rows = [r for r, k in enumerate(kept) if k]
        return Grouping([self.names[r] for r in rows], [self.columns[r] for r in rows],
                        [self.expressions[r] for r in rows], self.K.extract(rows, list(range(self.K.cols))))


def moving(system: System) -> list:
    """The bodies that carry parameters: those that move relative to their parent (a fixed body's are
    its moving ancestor's, as in Pinocchio)."""
    return [b for b in system.bodies if b.speed_indices]


def carrier(body):
    """(the moving ancestor of `body`'s joint or None for the world, R, p of the joint frame on it)."""
    R, p, parent = body.placement.rotation, body.placement.translation, body.parent
    while parent is not None and not parent.speed_indices:
        R, p = parent.placement.rotation * R, parent.placement.rotation * p + parent.placement.translation
        parent = parent.parent
    return parent, R, p


def spins_alone(body) -> bool:
    """Whether a·ω_j = q̇_j always: the parent's angular velocity ω_p is perpendicular to the joint's axis a,
    because the parent is the world or turns about a world-fixed axis b with a·b = 0 (to 1e-9, the
    round-off of files' angles)."""
    parent, R, _ = carrier(body)
    if parent is None:
        return True
    if not isinstance(parent.joint, Revolute) or carrier(parent)[0] is not None:
        return False
    dot = (R * body.joint.axis).dot(parent.joint.axis)
    return dot.is_number and abs(float(dot)) < 1e-9


def group(system: System, parameter_names: list[str], pi: list, armature: bool) -> Grouping:
    """The structural grouping of the inertial parameters (and armatures) of `system`'s tree.

    `parameter_names`/`pi`: the regressor's parameters, ten per moving body (`moving`), then
    (armature=True) one armature per speed, then anything else (friction), kept as it is."""
    bodies = moving(system)
    P = len(pi)
    placeholders = sp.symbols(f"_pi0:{P}", real=True)
    acc = {b.name: list(placeholders[10 * n:10 * n + 10]) for n, b in enumerate(bodies)}
    kept: dict = {}
    for body in reversed(bodies):
        keep, move = split(body.joint, acc[body.name])
        kept[body.name] = keep
        parent, R, p = carrier(body)
        if parent is not None:
            acc[parent.name] = [a + b for a, b in zip(acc[parent.name], moved(move, R, p))]
    beta = [x for b in bodies for x in kept[b.name]]
    rest = list(placeholders[10 * len(bodies):])
    if armature:
        joints = [b for b in bodies if b.index is not None]
        for n, body in enumerate(joints):
            k = coordinate_axis(body.joint) if isinstance(body.joint, Revolute) else None
            if k is not None and body.joint.mimic is None and spins_alone(body):
                beta[10 * bodies.index(body) + INERTIA[(k, k)]] += rest[n]
                rest[n] = sp.S.Zero
    beta += rest
    K = sp.Matrix([[sp.expand(b).coeff(s) for s in placeholders] for b in beta])
    rows = [r for r in range(len(beta)) if any(K[r, c] != 0 for c in range(P))]
    values = dict(zip(placeholders, pi))
    names = [grouped_name(parameter_names, K, r) for r in rows]
    return Grouping(names, rows, [sp.expand(sp.expand(beta[r]).xreplace(values)) for r in rows],
                    K.extract(rows, list(range(P))))


def grouped_name(names: list[str], K: sp.Matrix, r: int) -> str:
    """The column's own name, with "R" when others are grouped into it."""
    others = any(K[r, c] != 0 for c in range(K.cols) if c != r)
    return names[r] + ("R" if others else "")
