"""Recursive algorithms in body frames (Featherstone): the composite rigid body algorithm for M and
the recursive Newton-Euler algorithm for b, g and the inverse dynamics τ = M u̇ + b + g in one pass.
The cheapest code for numeric robots: joint axes are constant in their own frames, so every projection
picks a few entries.

Body i's frame sits in its parent's as x_p = R_i x_i + t_i (placement and joint motion).

RNEA, body axes, with the joint's motion (v, ω) = Σ_k S_k u_k and bias (a_rel, α_rel)
(`Joint.subspace`, `Joint.bias`, both in body axes) and Ω' = R_iᵀ Ω_p:
    Ω_i = Ω' + ω,   α_i = R_iᵀ α_p + Ω' × ω + α_rel + Σ_k ω_k u̇_k,
    a_i = R_iᵀ (a_p + α_p × t_i + Ω_p × (Ω_p × t_i)) + 2 Ω' × v + a_rel + Σ_k v_k u̇_k,
    f_i = m a_S,  n_i = Θ α_i + Ω_i × Θ Ω_i + c × f_i,   a_S = a_i + α_i × c + Ω_i × (Ω_i × c),
    F_i = f_i + Σ_c R_c F_c,  N_i = n_i + Σ_c (R_c N_c + t_c × R_c F_c),  τ_k = v_k · F_i + ω_k · N_i,
the base accelerating with −g⃗ (gravity as an acceleration of the world). b is the pass with u̇ = 0 and
g⃗ = 0, g the pass with u = u̇ = 0; the inverse dynamics adds the armature's I_a u̇ (as M's diagonal).
Every vector is named before it is rotated or crossed, which keeps the code and its derivatives
(`eomgen.derivatives`) short.
CRBA: composite (m, h = m c, I_O) from the leaves, moved to the parent by
    h' = R h + m t,  I_O' = R I_O Rᵀ + m (|t|² 1 − t tᵀ) + 2 (t · R h) 1 − t (R h)ᵀ − (R h) tᵀ;
    the momentum of the composite moved by u_j = 1, (m v_j + ω_j × h, I_O ω_j + h × v_j), carried to
    each ancestor k gives M_kj = v_k · linear + ω_k · angular part. Where many columns hang below few
    joints (a hand under an arm), the ancestors' subspaces come down to the columns instead,
    (v, ω) → (Rᵀ (v + ω × t), Rᵀ ω), and meet them there (`Recursion._meetings`)."""
from __future__ import annotations

import sympy as sp

from ..eom import EquationsOfMotion
from ..kinematics import Kinematics
from ..linalg import cross, dot, matmul, scale
from .applied import add_armature, applied_wrenches, armature, generalized_force, potential_energy


class Recursion:
    """The bodies' transforms (R, t), motion subspaces S and joint biases in body axes, and the two
    recursions over them."""

    def __init__(self, kin: Kinematics) -> None:
        self.kin, self.sub, self.n = kin, kin.sub, kin.n
        bodies = self.bodies = kin.system.bodies
        self.X = {b: _transform(kin, b) for b in bodies}
        self.children = {b: [c for c in bodies if c.parent is b] for b in bodies}
        self.S = {b: [(i, self.sub.add_matrix(v), self.sub.add_matrix(w))
                      for i, (v, w) in zip(b.speed_indices, b.joint.subspace())] for b in bodies}
        self.biases = {b: tuple(self.sub.add_matrix(x) for x in b.joint.bias()) for b in bodies if self.S[b]}
        self._moved: dict = {}  # (a, k): body a's subspace in body k's frame

    def up(self, b, lin: sp.Matrix, ang: sp.Matrix) -> tuple[sp.Matrix, sp.Matrix]:
        """A force (lin, ang) in body b's frame, expressed in its parent's frame."""
        R, t = self.X[b]
        lin = self.sub.add_matrix(matmul(R, lin))
        return lin, self.sub.add_matrix(matmul(R, ang) + cross(t, lin))

    def _motion(self, b, parent: tuple, u, ud) -> tuple[sp.Matrix, sp.Matrix, sp.Matrix]:
        """(Ω, α, a) of body b from its parent's (module formulas)."""
        sub, zero = self.sub, sp.zeros(3, 1)
        (R, t), (w_p, al_p, a_p) = self.X[b], parent
        w = sub.add_matrix(matmul(R.T, w_p))
        al = matmul(R.T, al_p)
        a_t = a_p + cross(al_p, t) + cross(w_p, sub.add_matrix(cross(w_p, t)))
        a = matmul(R.T, sub.add_matrix(a_t))
        if any(u[i] != 0 for i, _, _ in self.S[b]):
            v_rel = sum((scale(u[i], v) for i, v, _ in self.S[b]), zero)
            w_rel = sub.add_matrix(sum((scale(u[i], x) for i, _, x in self.S[b]), zero))
            a_rel, al_rel = self.biases[b]
            al = al + cross(w, w_rel) + al_rel
            a = a + scale(2, cross(w, sub.add_matrix(v_rel))) + a_rel
            w = w + w_rel
        al = al + sum((scale(ud[i], x) for i, _, x in self.S[b]), zero)
        a = a + sum((scale(ud[i], v) for i, v, _ in self.S[b]), zero)
        return sub.add_matrix(w), sub.add_matrix(al), sub.add_matrix(a)

    def motions(self, u, ud, gravity: sp.Matrix) -> dict:
        """(Ω, α, a) of every body in its own axes, parents first, the base accelerating with −g⃗."""
        zero, motion = sp.zeros(3, 1), {}
        for b in self.bodies:
            parent = (zero, zero, -gravity) if b.parent is None else motion[b.parent]
            motion[b] = self._motion(b, parent, u, ud)
        return motion

    def rnea(self, u, ud, gravity: sp.Matrix, loads: bool = False) -> sp.Matrix:
        """τ_k = v_k · F_i + ω_k · N_i of the pass with speeds u, accelerations ud and gravity g⃗; with
        `loads` less their generalized forces: each force F at r and torque T on body i (world axes,
        `applied_wrenches`) taken off its balance, f_i −= Rᵀ F, n_i −= r × Rᵀ F + Rᵀ T (R the body's rotation
        in the world, r in body axes)."""
        sub = self.sub
        F, N = {}, {}
        for b, (w, al, a) in self.motions(u, ud, gravity).items():
            c = b.com
            a_S = a + cross(al, c) + cross(w, sub.add_matrix(cross(w, c)))
            f = sub.add_matrix(scale(b.mass, a_S))
            N[b] = matmul(b.inertia, al) + cross(w, sub.add_matrix(matmul(b.inertia, w))) + cross(c, f)
            F[b] = f
        for point, F_ext, T_ext in (w for load in self.kin.system.loads if loads
                                    for w in applied_wrenches(self.kin, load)):
            if point.body is not None:  # a force on the world moves nothing
                R = self.kin.R[point.body]
                f = sub.add_matrix(matmul(R.T, sub.add_matrix(F_ext)))
                F[point.body] = F[point.body] - f
                N[point.body] = N[point.body] - cross(point.offset, f) - matmul(R.T, sub.add_matrix(T_ext))
        tau = sp.zeros(self.n, 1)
        for b in reversed(self.bodies):
            for c in self.children[b]:
                lin, ang = self.up(c, F[c], N[c])
                F[b], N[b] = F[b] + lin, N[b] + ang
            F[b], N[b] = sub.add_matrix(F[b]), sub.add_matrix(N[b])
            for i, v, w in self.S[b]:
                tau[i] += dot(v, F[b]) + dot(w, N[b])
        return tau

    def crba(self) -> sp.Matrix:
        """M: composite inertias from the leaves, then each joint's column up to the root."""
        sub, S = self.sub, self.S
        comp = {}
        for b in reversed(self.bodies):
            m, h, I_O = about_origin(b)
            for ch in self.children[b]:
                m_c, h_c, I_c = moved(comp[ch], *self.X[ch], sub.add_matrix)
                m, h, I_O = m + m_c, h + h_c, I_O + I_c
            comp[b] = (sub.add(m), sub.add_matrix(h), _symmetric(sub, I_O))
        M, down = sp.zeros(self.n, self.n), self._meetings()
        for b in self.bodies:
            m, h, I_O = comp[b]
            for j, v, w in S[b]:  # the momentum of the composite moved by u_j = 1: (m v + ω × h, I_O ω + h × v)
                F = (sub.add_matrix(scale(m, v) + cross(w, h)), sub.add_matrix(matmul(I_O, w) + cross(h, v)))
                k = b
                while k is not None:
                    above = k.parent is not None and down[k]  # the ancestors' subspaces come down to k
                    for a in [k, *(self._ancestors(k) if above else [])]:
                        for i, v_i, w_i in self._subspace(a, k):
                            if k is b and a is b and i > j:
                                continue
                            M_ij = dot(v_i, F[0]) + dot(w_i, F[1])
                            M[i, j] += M_ij
                            if a is not b or i != j:  # a mimic below its driver meets it twice on M_jj
                                M[j, i] += M_ij
                    if above or k.parent is None:
                        break
                    F, k = self.up(k, *F), k.parent
        add_armature(self.kin, M)
        return M

    def _meetings(self) -> dict:
        """Where each column's momentum meets the subspaces of the joints above it: it moves up across
        body k's joint (a spatial transform, ~42 operations, per column), or the ancestors' subspaces come
        down to k (`down[k]`: a transform per subspace and edge, shared by the columns below, and dense
        dot products of ~11 operations per pair where the subspace in its own frame has a few entries).
        Below a body whose subspaces came down, one edge compares the columns with the subspaces."""
        dofs = {b: len(self.S[b]) for b in self.bodies}
        below = dict(dofs)
        for b in reversed(self.bodies):
            for c in self.children[b]:
                below[b] += below[c]
        down = {}
        for k in self.bodies:  # parents first
            edges = {a: n for n, a in enumerate(self._ancestors(k), 1) if dofs[a]}  # ancestor: edges up to it
            above = sum(dofs[a] for a in edges)
            if not above:
                down[k] = False
            elif down[k.parent]:
                down[k] = above < below[k]
            else:
                moves = sum(dofs[a] * n for a, n in edges.items())
                up = below[k] * (42 * max(edges.values()) + 2 * above)
                down[k] = 42 * moves + 11 * below[k] * above < up
        return down

    def _ancestors(self, b) -> list:
        out, k = [], b.parent
        while k is not None:
            out.append(k)
            k = k.parent
        return out

    def _subspace(self, a, k) -> list:
        """The motion subspace of body a's joint expressed in body k's frame (a = k or an ancestor):
        (v, ω) in the parent's axes at its origin becomes (Rᵀ (v + ω × t), Rᵀ ω) in the child's."""
        key = (a, k)
        if key not in self._moved:
            if a is k:
                self._moved[key] = self.S[k]
            else:
                R, t = self.X[k]
                self._moved[key] = [
                    (i, self.sub.add_matrix(matmul(R.T, self.sub.add_matrix(v + cross(w, t)))),
                     self.sub.add_matrix(matmul(R.T, w))) for i, v, w in self._subspace(a, k.parent)]
        return self._moved[key]


def inverse_dynamics(kin: Kinematics, loads: bool = False) -> sp.Matrix:
    """τ = M u̇ + b + g in one RNEA pass with u, u̇ (`System.ud`) and gravity, plus I_a u̇ of the
    armature (as Pinocchio's rnea); with `loads` τ − τ_loads (the loads as external forces)."""
    system = kin.system
    tau = Recursion(kin).rnea(kin.u, list(system.ud), system.gravity, loads)
    for i, inertia in armature(kin):
        tau[i] += inertia * system.ud[i]
    return tau


def derive(kin: Kinematics, quantities=("M", "b", "g")) -> EquationsOfMotion:
    system, n = kin.system, kin.n
    recursion, zero, rest = Recursion(kin), sp.zeros(3, 1), [0] * n
    u = sp.Matrix(kin.u)
    compact = {"U": potential_energy(kin)}  # only what is asked: g alone needs one gravity pass
    if "M" in quantities:
        M = compact["M"] = recursion.crba()
        compact["T"] = dot(u, matmul(M, u)) / 2
    if "b" in quantities:
        compact["b"] = recursion.rnea(kin.u, rest, zero)
    if "g" in quantities:
        compact["g"] = recursion.rnea(rest, rest, system.gravity)
    if "b" in quantities and "g" in quantities:  # Pinocchio's nonLinearEffects: both in one pass
        compact["nle"] = recursion.rnea(kin.u, rest, system.gravity)
    for load in system.loads:
        compact[f"tau:{load.name}"] = generalized_force(kin, load)
    return EquationsOfMotion(kin, "recursive", compact)


def about_origin(body) -> tuple:
    """(m, h = m c, I_O = I_c + m (cᵀc 1 − c cᵀ)) of a body about its frame's origin, in its axes."""
    m, c = body.mass, body.com
    return m, scale(m, c), body.inertia + scale(m, dot(c, c) * sp.eye(3) - matmul(c, c.T))


def moved(inertia: tuple, R: sp.Matrix, t: sp.Matrix, name=lambda x: x) -> tuple:
    """(m, h, I_O) of a body in the axes of a frame where x = R x_body + t:
    h' = R h + m t,  I_O' = R I_O Rᵀ + m (|t|² 1 − t tᵀ) + 2 (t · R h) 1 − t (R h)ᵀ − (R h) tᵀ;
    `name` names R h and R I_O (the recursion's intermediates)."""
    m, h, I_O = inertia
    Rh = name(matmul(R, h))
    RI = name(matmul(R, I_O))
    return (m, Rh + scale(m, t), matmul(RI, R.T) + scale(m, dot(t, t) * sp.eye(3) - matmul(t, t.T))
            + 2 * dot(t, Rh) * sp.eye(3) - matmul(t, Rh.T) - matmul(Rh, t.T))


def _transform(kin: Kinematics, body) -> tuple[sp.Matrix, sp.Matrix]:
    """(R, t) with x_parent = R x_body + t."""
    R_q, t_q = body.joint.motion()
    P = body.placement
    R = kin.sub.add_matrix(matmul(P.rotation, R_q))
    return R, kin.sub.add_matrix(P.translation + matmul(P.rotation, t_q))


def _symmetric(sub, A: sp.Matrix) -> sp.Matrix:
    S = sp.zeros(3, 3)
    for i in range(3):
        for j in range(i, 3):
            S[i, j] = S[j, i] = sub.add(A[i, j])
    return S
