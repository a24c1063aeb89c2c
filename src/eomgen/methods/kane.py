"""Kane's equations with generalized speeds and nonholonomic constraints (SEEDS.md §2).

Generalized speeds w are defined by kinematic equations linear in q̇ and w, so q̇ = W w + X. Velocity
constraints linear in w split the speeds: w_dep = A w_ind + B, hence q̇ = Γ w_ind + Θ. For every body
the velocities v_S = J_P q̇, Ω = J_R q̇ give the nonholonomic partial velocities ṽ_r = ∂v_S/∂w_r,
ω̃_r = ∂Ω/∂w_r (r over the p independent speeds), and Kane's p equations F̃_r + F̃*_r = 0 with

    F̃_r  = Σ ṽ_r · (m g⃗ + F) + ω̃_r · T                           (generalized active forces)
    F̃*_r = −Σ ṽ_r · m a_S + ω̃_r · (Θ α + Ω × Θ Ω)                 (generalized inertia forces)

a_S = Σ_s ṽ_s ẇ_s + d/dt v_S |_(ẇ=0) (chain rule with q̇ = Γ w + Θ). Written as M̃ ẇ_ind = f̃."""
from __future__ import annotations

from dataclasses import dataclass, field

import sympy as sp

from ..eom import ClosedForms, closed_form
from ..errors import ModelError
from ..kinematics import Kinematics
from ..linalg import cross, dot, matmul, scale
from ..model import FreeFlyer
from ..model.loads import Point
from ..model.system import System
from .applied import applied_wrenches


@dataclass(eq=False)
class KaneEquations(ClosedForms):
    """M̃(q) ẇ_ind = f̃(q, w_ind) and q̇ = Γ w_ind + Θ; closed forms on access, compact forms in
    `compact` (named intermediates of `subexpressions`)."""

    system: System
    kinematics: Kinematics
    speeds: list  # all generalized speeds w
    independent: list  # w_ind (p of them)
    dependent: list  # w_dep (m = n − p)
    compact: dict = field(default_factory=dict)  # mass_matrix, forcing, qdot, dependent_speeds, F_r
    _closed: dict = field(default_factory=dict, repr=False)

    mass_matrix = closed_form("mass_matrix", "M̃ (p × p), the coefficients of ẇ_ind in −F̃*_r.")
    forcing = closed_form("forcing", "f̃ = F̃_r + F̃*_r|_(ẇ=0), so that M̃ ẇ_ind = f̃.")
    active_forces = closed_form("F_r", "F̃_r: the nonholonomic generalized active forces (equilibrium iff 0).")
    qdot = closed_form("qdot", "The kinematic differential equations q̇ = Γ w_ind + Θ.")
    dependent_speeds = closed_form("dependent_speeds", "w_dep = A w_ind + B.")

    def inertia_forces(self) -> sp.Matrix:
        """F̃*_r = −M̃ ẇ_ind + (f̃ − F̃_r), in the symbols of ẇ_ind (w + 'dot')."""
        wdot = sp.Matrix([sp.Symbol(f"{w.name}dot") for w in self.independent])
        return -self.mass_matrix * wdot + self.forcing - self.active_forces



def _linear(exprs, symbols, what: str) -> tuple[sp.Matrix, sp.Matrix]:
    """(C, c0) with exprs = C symbols + c0; an error names an expression that is not linear."""
    exprs = sp.Matrix(exprs)
    C = exprs.jacobian(list(symbols))
    for i, e in enumerate(exprs):
        if any(sp.simplify(C[i, j].diff(s)) != 0 for j in range(len(symbols)) for s in symbols):
            raise ModelError(f"{what} {i} is not linear in {list(symbols)}: {e}")
    return C, exprs.xreplace({s: 0 for s in symbols})


def _invertible(C: sp.Matrix, what: str) -> None:
    if C.shape[0] != C.shape[1] or sp.simplify(C.det()) == 0:
        raise ModelError(f"{what} is not invertible: {C.tolist()}")


def kane(system: System, speeds=None, kinematic_equations=None, nonholonomic=None,
         independent=None) -> KaneEquations:
    """Kane's equations of `system` in the generalized `speeds` w, defined by `kinematic_equations`
    (expressions = 0, linear in q̇ = system.u and w; default w = q̇), with the velocity constraints
    `nonholonomic` (expressions in q and w = 0, linear in w) and the `independent` speeds."""
    if any(isinstance(j, FreeFlyer) for j in system.joints):
        raise ModelError("kane: a free-flyer base is not supported; give the base its own joints")
    qd = list(system.u)  # q̇ of the joints
    speeds = qd if speeds is None else list(speeds)
    if len(speeds) != len(qd) or len(set(speeds)) != len(speeds):
        raise ModelError(f"kane: give {len(qd)} distinct speeds, got {speeds}")
    if kinematic_equations is None:
        if speeds != qd:
            raise ModelError("kane: new speeds need kinematic_equations (w − Y q̇ − Z = 0)")
        kinematic_equations = []
    # q̇ = W w + X from the kinematic equations
    if kinematic_equations:
        if len(kinematic_equations) != len(qd):
            raise ModelError(f"kane: {len(qd)} kinematic equations needed, got {len(kinematic_equations)}")
        Y, rest = _linear(kinematic_equations, qd, "kinematic equation")
        _invertible(Y, "the speed map (∂ kinematic equations / ∂q̇)")
        qdot_w = Y.LUsolve(-rest)  # small and linear: q̇ in terms of q and w
    else:
        qdot_w = sp.Matrix(speeds)
    nonholonomic = list(nonholonomic or [])
    independent = speeds if independent is None else list(independent)
    unknown = [s for s in independent if s not in speeds]
    if unknown:
        raise ModelError(f"kane: independent speeds {unknown} are not among the speeds {speeds}")
    dependent = [s for s in speeds if s not in independent]
    if len(dependent) != len(nonholonomic):
        raise ModelError(f"kane: {len(nonholonomic)} constraints need as many dependent speeds, got {dependent}")
    if nonholonomic:
        C, c0 = _linear(nonholonomic, speeds, "nonholonomic constraint")
        C_dep = C[:, [speeds.index(s) for s in dependent]]
        C_ind = C[:, [speeds.index(s) for s in independent]]
        _invertible(C_dep, "the constraints' matrix of the dependent speeds")
        w_dep = C_dep.LUsolve(-(C_ind * sp.Matrix(independent) + c0))  # w_dep = A w_ind + B
        qdot_w = qdot_w.xreplace(dict(zip(dependent, w_dep)))
    else:
        w_dep = sp.zeros(0, 1)

    kin = Kinematics(system)
    sub = kin.sub
    qdot_w = sub.add_matrix(qdot_w)
    p = len(independent)
    seeds = dict(zip(kin.q, qdot_w))  # d/dt with ẇ = 0

    def partials(v: sp.Matrix) -> list[sp.Matrix]:
        return [v.applyfunc(lambda e: sub.add(sub.derivative(e, {w: 1}, ("w", r)))) for r, w in enumerate(independent)]

    def bias(v: sp.Matrix) -> sp.Matrix:
        return v.applyfunc(lambda e: sub.add(sub.derivative(e, seeds, "kane_t")))

    M, f = sp.zeros(p, p), sp.zeros(p, 1)
    F_r = sp.zeros(p, 1)
    for body in system.bodies:
        if not kin.chain[body]:
            continue
        S = Point(body, body.com)
        v = sub.add_matrix(matmul(kin.J_P(S), qdot_w))
        w = sub.add_matrix(matmul(kin.J_R(body), qdot_w))
        vt, wt = partials(v), partials(w)
        Theta = kin.inertia_world(body)
        a0, alpha0 = bias(v), bias(w)
        gyro = matmul(Theta, alpha0) + cross(w, sub.add_matrix(matmul(Theta, w)))
        for r in range(p):
            gravity = dot(vt[r], scale(body.mass, system.gravity))
            F_r[r] += gravity
            f[r] += gravity - dot(vt[r], scale(body.mass, a0)) - dot(wt[r], gyro)
            for s in range(p):
                M[r, s] += body.mass * dot(vt[r], vt[s]) + dot(wt[r], matmul(Theta, wt[s]))
    for b in system.bodies:  # rotor inertia at the joints: ½ I_a q̇_i²
        if b.index is not None and b.joint.armature != 0:
            qdi = sp.Matrix([qdot_w[b.index]])
            part = partials(qdi)
            for r in range(p):
                f[r] -= b.joint.armature * part[r][0] * bias(qdi)[0]
                for s in range(p):
                    M[r, s] += b.joint.armature * part[r][0] * part[s][0]
    qd_sub = dict(zip(qd, qdot_w))
    for load in system.loads:
        for point, F, T in applied_wrenches(kin, load):
            F, T = (sub.substitute(x, qd_sub) for x in (F, T))  # a damper's force depends on q̇
            vt = partials(sub.add_matrix(matmul(kin.J_P(point), qdot_w)))
            wt = partials(sub.add_matrix(matmul(kin.J_R(point.body), qdot_w)))
            for r in range(p):
                F_r[r] += dot(vt[r], F) + dot(wt[r], T)
                f[r] += dot(vt[r], F) + dot(wt[r], T)
    compact = {"mass_matrix": M, "forcing": f, "F_r": F_r, "qdot": qdot_w, "dependent_speeds": w_dep}
    return KaneEquations(system, kin, speeds, independent, dependent, compact)
