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

since a revolute joint's rotation leaves a, h_k a and (1 − a aᵀ) in place. What moves onto the world has
no effect (it is not identifiable). A revolute joint with a = e_k whose parent's angular velocity is
always perpendicular to a (nothing above it turns, or one revolute joint alone, about b ⊥ a): a·ω_j =
q̇_j, so its armature enters as the body's I_kk does (½ I_a q̇²) and is grouped with I_kk. A prismatic
joint on the world: its armature enters as the link's (total) mass does, less a constant force along the
axis, which the offset friction takes. Bodies whose joint is of another kind (spherical, free, helical,
several axes) and axes off the coordinate axes keep their ten parameters.

What is left may still hold columns that never move (a body turning about a fixed axis: its I_ii − I_jj,
I_ij, ...; first moments along gravity) or dependencies beyond these rules: `eg.base_parameters` finds
them on the numerical regressor and keeps the grouping only where it has the numerical rank."""
from __future__ import annotations

from dataclasses import dataclass

import sympy as sp

from ..methods.recursive import moved
from ..model.joints import Fixed, Prismatic, Revolute
from ..regressor import INERTIAL, UNIT, Regressor, links, speeds, ten, up_to_link
from .pseudo_inertia import inertia

INERTIA = {jk: 4 + n for n, jk in enumerate(UNIT)}  # (j, k), j ≤ k → its entry in a link's ten


def on_parent(part: list, R: sp.Matrix, p: sp.Matrix) -> list:
    """A part (m, h, I) at a link's origin, written on its parent (x_parent = R x + p)."""
    return ten(*moved((part[0], sp.Matrix(part[1:4]), sp.Matrix(inertia(part))), R, p))


def coordinate_axis(joint) -> int | None:
    """k where the joint's axis is ±e_k, else None."""
    axis = [sp.nsimplify(x) if x.is_number else x for x in joint.axis]
    for k in range(3):
        if all(axis[n] == 0 for n in range(3) if n != k) and axis[k] in (1, -1):
            return k
    return None


def split(joint, x: list) -> tuple[list, list]:
    """(what the link keeps, what moves onto the parent) of its accumulated parameters x."""
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


def carrier(body):
    """(the link carrying `body`'s parent or None for the world, R, p of `body`'s joint frame on it)."""
    return up_to_link(body, body.placement.rotation, body.placement.translation)


def spins_alone(body) -> bool:
    """Whether a·ω_j = q̇_j always: the parent's angular velocity ω_p is perpendicular to the joint's axis a,
    because nothing above turns (prismatic and fixed joints up to the world) or one revolute joint alone
    does, about an axis b with a·b = 0 (to 1e-9, the round-off of files' angles)."""
    R, turning, part = body.placement.rotation, None, body.parent
    while part is not None:
        if isinstance(part.joint, Revolute):
            if turning is not None:
                return False
            turning = R * body.joint.axis, part.joint.axis
        elif not isinstance(part.joint, (Prismatic, Fixed)):
            return False
        R, part = part.placement.rotation * R, part.parent
    if turning is None:
        return True
    dot = turning[0].dot(turning[1])
    return dot.is_number and abs(float(dot)) < 1e-9


def armature(beta: list, x, column: dict, body, name: str, gravity: sp.Matrix) -> None:
    """Group joint `name`'s armature I_a where its column is another's (the module's text): a revolute
    joint that spins alone, with I_kk; a prismatic joint on the world along a (world axes) with the mass,
    τ = (m + I_a)(ü − g⃗·a) + (F_o + I_a g⃗·a), the offset F_o taking I_a g⃗·a (without an offset column,
    only where g⃗·a = 0)."""
    k, Ia = coordinate_axis(body.joint), x[column[f"Ia_{name}"]]
    if isinstance(body.joint, Revolute) and k is not None and spins_alone(body):
        beta[column[f"I_{'xyz'[k] * 2}_{body.name}"]] += Ia
    elif isinstance(body.joint, Prismatic) and carrier(body)[0] is None:
        along = (carrier(body)[1] * body.joint.axis).dot(gravity)
        if not (along.is_number and abs(float(along)) < 1e-9) and f"Fo_{name}" not in column:
            return
        beta[column[f"m_{body.name}"]] += Ia
        if f"Fo_{name}" in column:
            beta[column[f"Fo_{name}"]] += along * Ia
    else:
        return
    beta[column[f"Ia_{name}"]] = sp.S.Zero


def group(regressor: Regressor) -> Grouping:
    """The structural grouping of the regressor's inertial parameters and armatures (the module's rules);
    friction columns stay as they are."""
    system, names = regressor.equations.system, regressor.names
    P, column = len(names), {name: k for k, name in enumerate(names)}
    x = sp.symbols(f"_pi0:{P}", real=True)  # π's entries, placeholders
    beta = list(x)
    acc = {link: [x[column[f"{n}_{link.name}"]] for n in INERTIAL] for link in links(system)}
    for link in reversed(list(acc)):
        keep, move = split(link.joint, acc[link])
        for n, value in zip(INERTIAL, keep):
            beta[column[f"{n}_{link.name}"]] = value
        parent, R, p = carrier(link)
        if parent is not None:
            acc[parent] = [a + b for a, b in zip(acc[parent], on_parent(move, R, p))]
    owner = {b.index: b for b in acc if b.index is not None and b.joint.dof == 1 and b.joint.mimic is None}
    for i, name in speeds(system):
        body = owner.get(i)
        if f"Ia_{name}" in column and body is not None:
            armature(beta, x, column, body, name, system.gravity)
    K = sp.Matrix([[b.coeff(s) for s in x] for b in map(sp.expand, beta)])
    rows = [r for r in range(P) if any(K[r, c] != 0 for c in range(P))]
    return Grouping([names[r] + ("R" if any(K[r, c] != 0 for c in range(P) if c != r) else "")
                     for r in rows], rows, [in_symbols(K.row(r), regressor.pi) for r in rows],
                    K.extract(rows, list(range(P))))


def in_symbols(k: sp.Matrix, pi: sp.Matrix) -> sp.Expr:
    """β = k π in the model's symbols, expanded; a number as a float (a file's parameters are exact
    rationals of their decimals)."""
    value = sp.expand(sum((c * v for c, v in zip(k, pi) if c != 0), sp.S.Zero))
    return value if value.free_symbols or value == 0 else sp.Float(value, 15)
