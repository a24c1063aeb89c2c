"""The worked solution of Kane's equations: speeds, the constraint solve, partial velocities, the
generalized active and inertia forces, and Kane's p equations F̃_r + F̃*_r = 0."""

from __future__ import annotations

import sympy as sp

from ..methods.kane import KaneEquations
from ..model.loads import Point
from .document import Solution
from .steps import Step, moving_bodies
from ..textbook import Simplifier


def solution(k: KaneEquations, simplifier: Simplifier, title: str | None) -> Solution:
    kin, n, p = k.kinematics, len(k.speeds), len(k.independent)
    u = k.joint_speeds
    P = u.jacobian(sp.Matrix(k.independent))  # ∂u/∂w_ind: the holonomic partial velocities' weights
    joint = {} if k.joint_speeds_are_rates else {"joint speeds": simplifier.matrix(u)}
    kinematic = (r"for $\dot q$." if k.joint_speeds_are_rates else r"for the joint speeds $u$, then "
                 r"$\dot q(q, u)$ (a quaternion ball joint's and a planar joint's $u$ are not rates).")
    h = len(k.dependent_coordinates)
    holonomic = {"holonomic constraints": simplifier.matrix(k.holonomic),
                 "dependent coordinates": sp.Matrix(k.dependent_coordinates)} if h else {}
    valid = (rf" The solves divide by the expressions stated nonzero: valid where ${k.nonzero.condition()}$."
             if k.assume_nonzero else "")
    derivatives = (f" ({h} of them the time derivatives of the holonomic constraints f(q) = 0, which fix "
                   f"{h} dependent coordinates)" if h else "")
    speeds = Step(
        "Speeds and constraints",
        f"{n} generalized speeds, {n - p} velocity constraints{derivatives}, so {p} independent speeds. The "
        "kinematic equations define the speeds, the velocity constraints (both = 0) are linear in them; "
        "the constraints are solved for the dependent speeds (a linear solve on pivots proven nonzero), "
        f"and the kinematic equations {kinematic}{valid}",
        {
            **holonomic,
            "speeds": sp.Matrix(k.speeds),
            "kinematic equations": simplifier.matrix(k.kinematic_equations),
            "velocity constraints": simplifier.matrix(k.velocity_constraints),
            "independent speeds": sp.Matrix(k.independent),
            "dependent speeds": sp.Matrix(k.dependent),
            "dependent speeds solved": simplifier.matrix(k.dependent_speeds),
            **joint,
            "qdot": simplifier.matrix(k.qdot),
        },
        "kane",
    )
    partial = {}
    inline = kin.sub.inline
    for b in moving_bodies(k.eom):
        partial[f"v_r[{b.name}]"] = simplifier.matrix(inline(kin.J_P(Point(b, b.com))) * P)
        partial[f"omega_r[{b.name}]"] = simplifier.matrix(inline(kin.J_R(b)) * P)
    partials = Step(
        "Nonholonomic partial velocities",
        "The velocity of each centre of mass and each angular velocity, written in the independent "
        r"speeds, are linear in them: $v_S = \sum_r v_r w_r + v_t$, $\Omega = \sum_r \omega_r w_r + "
        r"\omega_t$. Column $r$ of $v_r$ and $\omega_r$ is the partial velocity of speed $w_r$ (what "
        "remains after the constraints).",
        partial,
        "kane",
    )
    F_r = simplifier.matrix(k.active_forces)
    F_star = simplifier.matrix(k.inertia_forces())
    forces = Step(
        "Generalized active and inertia forces",
        "Projecting the applied forces and gravity on the partial velocities gives the nonholonomic "
        r"generalized active forces $\tilde F_r = \sum v_r \cdot F + \omega_r \cdot T$ (static "
        r"equilibrium if and only if they vanish); projecting the inertia forces $-m a_S$ and "
        r"$-(\Theta \alpha + \Omega \times \Theta \Omega)$ gives $\tilde F^*_r$.",
        {"F_r": F_r, "F*_r": F_star},
        "kane",
    )
    equations = Step(
        "Kane's equations",
        rf"$\tilde F_r + \tilde F^*_r = 0$, $r = 1, \dots, {p}$: as many equations as degrees of freedom "
        r"and no multipliers, written $\tilde M \dot w_{ind} = \tilde f$." + valid,
        {
            "F_r + F*_r": simplifier.matrix(F_r + F_star),
            "M~": simplifier.matrix(k.mass_matrix),
            "f~": simplifier.matrix(k.forcing),
        },
        "kane",
    )
    return Solution(
        title or "Kane's equations",
        k.system,
        [speeds, partials, forces, equations],
        ("kane",),
        "textbook",
        simplifier.left,
    )
