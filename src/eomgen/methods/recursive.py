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
g⃗ = 0, g the pass with u = u̇ = 0; the inverse dynamics adds the armature's I_a u̇ (as M's diagonal). The
potential energy reads the gravity pass too (a_i is −g⃗ in body i's axes), so the world placements of
the bodies are never formed: U = Σ m_i (σ_i + a_i · c_i), σ_i = −g⃗ · p_i = σ_p + a_p · t_i.
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

from ..engine import Sympy, Symengine, total_of, vector
from ..eom import EquationsOfMotion
from ..kinematics import Kinematics
from ..linalg import (ZERO, add, apply, apply_T, compose, compose_T, cross, diagonal, dot,
                      half_quadratic_form, mul, outer, scale, subtract, total)
from .applied import applied_wrenches, armature, generalized_force, spring_energies


class Recursion:
    """The bodies' transforms (R, t), motion subspaces S and joint biases in body axes, and the two
    recursions over them (3-vectors and 3×3 matrices as tuples of the engine's scalars, `linalg`; sympy
    matrices out)."""

    def __init__(self, kin: Kinematics) -> None:
        self.kin, self.sub, self.n = kin, kin.sub, kin.n
        bodies = self.bodies = kin.system.bodies
        self.X = {b: _transform(kin, b) for b in bodies}
        self.children = {b: [c for c in bodies if c.parent is b] for b in bodies}
        e = self.sub.vector
        self.S = {b: [(i, self.sub.add_matrix(e(v)), self.sub.add_matrix(e(w)))
                      for i, (v, w) in zip(b.speed_indices, b.joint.subspace())] for b in bodies}
        self.biases = {b: tuple(self.sub.add_matrix(e(x)) for x in b.joint.bias())
                       for b in bodies if self.S[b]}
        self._moved: dict = {}  # (a, k): body a's subspace in body k's frame
        self._motions: dict = {}  # (u, u̇, g⃗): `motions`

    def up(self, b, lin, ang) -> tuple[tuple, tuple]:
        """A force (lin, ang) in body b's frame, expressed in its parent's frame."""
        R, t = self.X[b]
        lin = self.sub.add_matrix(apply(R, lin))
        return lin, self.sub.add_matrix(add(apply(R, ang), cross(t, lin)))

    def _motion(self, b, parent: tuple, u, ud) -> tuple[tuple, tuple, tuple]:
        """(Ω, α, a) of body b from its parent's (module formulas)."""
        sub = self.sub
        (R, t), (w_p, al_p, a_p) = self.X[b], parent
        w = sub.add_matrix(apply_T(R, w_p))
        al = apply_T(R, al_p)
        a_t = add(add(a_p, cross(al_p, t)), cross(w_p, sub.add_matrix(cross(w_p, t))))
        a = apply_T(R, sub.add_matrix(a_t))
        if any(u[i] != 0 for i, _, _ in self.S[b]):
            v_rel = total(scale(u[i], v) for i, v, _ in self.S[b])
            w_rel = sub.add_matrix(total(scale(u[i], x) for i, _, x in self.S[b]))
            a_rel, al_rel = self.biases[b]
            al = add(add(al, cross(w, w_rel)), al_rel)
            a = add(add(a, scale(2, cross(w, sub.add_matrix(v_rel)))), a_rel)
            w = add(w, w_rel)
        al = add(al, total(scale(ud[i], x) for i, _, x in self.S[b]))
        a = add(a, total(scale(ud[i], v) for i, v, _ in self.S[b]))
        return sub.add_matrix(w), sub.add_matrix(al), sub.add_matrix(a)

    def motions(self, u, ud, gravity: sp.Matrix) -> dict:
        """(Ω, α, a) of every body in its own axes, parents first, the base accelerating with −g⃗ (once per
        u, u̇ and g⃗)."""
        key = u, ud, gravity = self.sub.vector(u), self.sub.vector(ud), self.sub.vector(gravity)
        if key not in self._motions:
            motion = self._motions[key] = {}
            for b in self.bodies:
                parent = (ZERO, ZERO, tuple(-x for x in gravity)) if b.parent is None else motion[b.parent]
                motion[b] = self._motion(b, parent, u, ud)
        return self._motions[key]

    def gravity_energy(self, gravity: sp.Matrix) -> sp.Expr:
        """−Σ m_i g⃗ · r_Si in body axes, from the gravity pass (u = u̇ = 0), whose a_i is −g⃗ in body i's
        axes: Σ m_i (σ_i + a_i · c_i), σ_i = −g⃗ · p_i = σ_p + a_p · t_i (σ = 0 and a = −g⃗ at the base)."""
        sub, rest = self.sub, [0] * self.n
        motion, sigma, U = self.motions(rest, rest, gravity), {}, []
        base = tuple(-x for x in sub.vector(gravity))
        for b in self.bodies:
            a_p, s_p = (base, 0) if b.parent is None else (motion[b.parent][2], sigma[b.parent])
            sigma[b] = sub.add(s_p + dot(a_p, self.X[b][1]))
            U.append(mul(sub.scalar(b.mass), sigma[b] + dot(motion[b][2], sub.vector(b.com))))
        return sub.engine.to_sympy(total_of(U))

    def rnea(self, u, ud, gravity: sp.Matrix, loads: bool = False) -> sp.Matrix:
        """τ_k = v_k · F_i + ω_k · N_i of the pass with speeds u, accelerations ud and gravity g⃗; with
        `loads` less their generalized forces: each force F at r and torque T on body i (world axes,
        `applied_wrenches`) taken off its balance, f_i −= Rᵀ F, n_i −= r × Rᵀ F + Rᵀ T (R the body's rotation
        in the world, r in body axes)."""
        sub, e = self.sub, self.sub.vector
        F, N = {}, {}
        for b, (w, al, a) in self.motions(u, ud, gravity).items():
            c, inertia = e(b.com), e(b.inertia)
            a_S = add(add(a, cross(al, c)), cross(w, sub.add_matrix(cross(w, c))))
            f = sub.add_matrix(scale(sub.scalar(b.mass), a_S))
            N[b] = add(add(apply(inertia, al), cross(w, sub.add_matrix(apply(inertia, w)))), cross(c, f))
            F[b] = f
        for point, F_ext, T_ext in (w for load in self.kin.system.loads if loads
                                    for w in applied_wrenches(self.kin, load)):
            if point.body is not None:  # a force on the world moves nothing
                R = self.kin._R[point.body]
                f = sub.add_matrix(apply_T(R, sub.add_matrix(e(F_ext))))
                F[point.body] = subtract(F[point.body], f)
                N[point.body] = subtract(subtract(N[point.body], cross(e(point.offset), f)),
                                         apply_T(R, sub.add_matrix(e(T_ext))))
        tau = [0] * self.n
        for b in reversed(self.bodies):
            for c in self.children[b]:
                lin, ang = self.up(c, F[c], N[c])
                F[b], N[b] = add(F[b], lin), add(N[b], ang)
            F[b], N[b] = sub.add_matrix(F[b]), sub.add_matrix(N[b])
            for i, v, w in self.S[b]:
                tau[i] += dot(v, F[b]) + dot(w, N[b])
        return sub.matrix(tau)

    def crba(self) -> tuple[sp.Matrix, sp.Expr]:
        """(M, T = ½ uᵀ M u): composite inertias from the leaves, then each joint's column up to the root,
        plus the armature on the diagonal."""
        sub, S = self.sub, self.S
        comp = {}
        for b in reversed(self.bodies):
            m, h, I_O = about_origin(b, sub.engine)
            for ch in self.children[b]:
                m_c, h_c, I_c = moved(comp[ch], *self.X[ch], sub.add_matrix)
                m, h, I_O = m + m_c, add(h, h_c), add(I_O, I_c)
            comp[b] = (sub.add(m), sub.add_matrix(h), _symmetric(sub, I_O))
        M, down = [[0] * self.n for _ in range(self.n)], self._meetings()
        for b in self.bodies:
            m, h, I_O = comp[b]
            for j, v, w in S[b]:  # the momentum of the composite moved by u_j = 1: (m v + ω × h, I_O ω + h × v)
                F = (sub.add_matrix(add(scale(m, v), cross(w, h))),
                     sub.add_matrix(add(apply(I_O, w), cross(h, v))))
                k = b
                while k is not None:
                    above = k.parent is not None and down[k]  # the ancestors' subspaces come down to k
                    for a in [k, *(self._ancestors(k) if above else [])]:
                        for i, v_i, w_i in self._subspace(a, k):
                            if k is b and a is b and i > j:
                                continue
                            M_ij = dot(v_i, F[0]) + dot(w_i, F[1])
                            M[i][j] += M_ij
                            if a is not b or i != j:  # a mimic below its driver meets it twice on M_jj
                                M[j][i] += M_ij
                    if above or k.parent is None:
                        break
                    F, k = self.up(k, *F), k.parent
        for i, inertia in armature(self.kin):
            M[i][i] += sub.scalar(inertia)
        T = sub.engine.to_sympy(half_quadratic_form(M, sub.vector(self.kin.u)))
        return sub.matrix([x for row in M for x in row], self.n), T

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
                    (i, self.sub.add_matrix(apply_T(R, self.sub.add_matrix(add(v, cross(w, t))))),
                     self.sub.add_matrix(apply_T(R, w))) for i, v, w in self._subspace(a, k.parent)]
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
    # only what is asked: g alone needs one gravity pass (which U reads)
    compact = {"U": sp.Add(recursion.gravity_energy(system.gravity), *spring_energies(kin))}
    if "M" in quantities:
        compact["M"], compact["T"] = recursion.crba()
    if "b" in quantities:
        compact["b"] = recursion.rnea(kin.u, rest, zero)
    if "g" in quantities:
        compact["g"] = recursion.rnea(rest, rest, system.gravity)
    if "b" in quantities and "g" in quantities:  # Pinocchio's nonLinearEffects: both in one pass
        compact["nle"] = recursion.rnea(kin.u, rest, system.gravity)
    for load in system.loads:
        compact[f"tau:{load.name}"] = generalized_force(kin, load)
    return EquationsOfMotion(kin, "recursive", compact)


def about_origin(body, engine: Sympy | Symengine = Sympy()) -> tuple:
    """(m, h = m c, I_O = I_c + m (cᵀc 1 − c cᵀ)) of a body about its frame's origin, in its axes (tuples,
    `linalg`, of the `engine`'s scalars)."""
    m, c = engine.scalar(body.mass), engine.scalars(body.com)
    I_O = add(engine.scalars(body.inertia), scale(m, subtract(diagonal(dot(c, c)), outer(c, c))))
    return m, scale(m, c), I_O


def moved(inertia: tuple, R, t, name=lambda x: x) -> tuple:
    """(m, h, I_O) of a body in the axes of a frame where x = R x_body + t:
    h' = R h + m t,  I_O' = R I_O Rᵀ + m (|t|² 1 − t tᵀ) + 2 (t · R h) 1 − t (R h)ᵀ − (R h) tᵀ;
    `name` names R h and R I_O (the recursion's intermediates). Tuples (`linalg`) or `sp.Matrix`es in,
    tuples out."""
    m, h, I_O = inertia
    R, t = vector(R), vector(t)
    Rh = name(apply(R, vector(h)))
    RI = name(compose(R, vector(I_O)))
    I_moved = add(compose_T(RI, R), scale(m, subtract(diagonal(dot(t, t)), outer(t, t))))
    I_moved = subtract(subtract(add(I_moved, diagonal(2 * dot(t, Rh))), outer(t, Rh)), outer(Rh, t))
    return m, add(Rh, scale(m, t)), I_moved


def _transform(kin: Kinematics, body) -> tuple[tuple, tuple]:
    """(R, t) with x_parent = R x_body + t."""
    R_q, t_q = body.joint.motion()
    e = kin.sub.vector
    R_P = e(body.placement.rotation)
    R = kin.sub.add_matrix(compose(R_P, e(R_q)))
    return R, kin.sub.add_matrix(add(e(body.placement.translation), apply(R_P, e(t_q))))


def _symmetric(sub, A: tuple) -> tuple:
    """The symmetric matrix of A's upper triangle, each entry named."""
    S = [None] * 9
    for i in range(3):
        for j in range(i, 3):
            S[3 * i + j] = S[3 * j + i] = sub.add(A[3 * i + j])
    return tuple(S)
