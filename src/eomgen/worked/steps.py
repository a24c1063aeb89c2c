"""The steps of a worked solution, one function per method, in the order the lecture shows them.

Every expression is in the user's symbols (q, q̇, q̈ print as the coordinate's dots): a closed form
in textbook form where the `Simplifier` manages it within its budget; otherwise, and for large
systems (form "shared"), the step lists shared definitions χ_k = ... (`Step.shared`) in order and
its expressions use them."""

from __future__ import annotations

import re
from dataclasses import dataclass, field
from typing import NamedTuple

import sympy as sp

from ..eom import EquationsOfMotion
from ..errors import ModelError
from ..kinematics import TIME
from ..model import FreeFlyer
from ..methods.free_cut import effort_symbols
from ..model.loads import Point
from ..textbook import Simplifier, chi, operations, shared

LARGE = 400  # a closed form with more operations than this is shown through shared definitions


class Equation(NamedTuple):
    """A numbered equation lhs = rhs (`eq`, a sympy Equality) under the heading `group` (prose)."""

    group: str
    eq: sp.Equality


def equation(group: str, lhs, rhs) -> Equation:
    return Equation(group, sp.Eq(sp.sympify(lhs), sp.sympify(rhs), evaluate=False))


@dataclass
class Step:
    """One step: a title, what is done and why, named expressions (sympy objects), the shared
    definitions χ_k they use, if any, and its scalar equations, one numbered line each. The text is
    prose with $math$ and `code`; names and other text from outside go in through `literal`."""

    title: str
    text: str
    expressions: dict[str, sp.Basic] = field(default_factory=dict)
    method: str | None = None  # the method this step belongs to (None: common to all)
    shared: list[tuple[sp.Symbol, sp.Expr]] = field(default_factory=list)
    equations: list[Equation] = field(default_factory=list)

    def __getitem__(self, name: str) -> sp.Basic:
        return self.expressions[name]


class Forms:
    """Turns one derivation's results (in its intermediates) into what a step shows."""

    def __init__(self, eom: EquationsOfMotion, simplifier: Simplifier, form: str) -> None:
        self.eom, self.simplifier, self.form = eom, simplifier, form
        self.kin, self.sub = eom.kinematics, eom.subexpressions

    def __call__(self, expr):
        """Textbook form: the closed form, simplified where cheap; shared form: as it is."""
        if self.form == "shared":
            return expr
        closed = self.sub.inline(expr)
        return (
            self.simplifier.matrix(closed) if isinstance(closed, sp.MatrixBase) else self.simplifier(closed)
        )

    def step(self, title: str, text: str, expressions: dict, method: str | None = None) -> Step:
        """A step whose large or compact expressions go through shared definitions χ_k."""
        if self.form == "shared":
            definitions, expressions = self._renamed(expressions)
            return Step(title, text, expressions, method, definitions)
        large = [k for k, e in expressions.items() if operations(e) > LARGE]
        if not large:
            return Step(title, text, expressions, method)
        definitions, reduced = shared([sp.Matrix(_entries(expressions[k])) for k in large])
        out = dict(expressions)
        for k, r in zip(large, reduced):
            out[k] = r if isinstance(expressions[k], sp.MatrixBase) else r[0]
        return Step(title, text, out, method, definitions)

    def _renamed(self, expressions: dict) -> tuple[list, dict]:
        """Intermediates renamed χ_1, χ_2, ... in definition order."""
        needed = self.sub.dependencies([e for x in expressions.values() for e in _entries(x)])
        names = {s: chi(k) for k, s in enumerate(needed)}
        definitions = [(names[s], self.sub.definitions[s].xreplace(names)) for s in needed]
        return definitions, {k: sp.sympify(x).xreplace(names) for k, x in expressions.items()}

    def result(self) -> dict[str, sp.Basic]:
        """M, b, g and each load's τ; kept in `results` as they are, before any shared definitions
        (what the comparison compares)."""
        out = {k: self(self.eom.compact[k]) for k in ("M", "b", "g")}
        out.update({f"tau[{name}]": self(self.eom.compact[f"tau:{name}"]) for name in self.eom.load_names})
        self.results = out
        return dict(out)


def literal(s: str) -> str:
    """Text that shows as it is in a step's text: its \\, $ and ` escaped by a \\."""
    return re.sub(r"([\\$`])", r"\\\1", s)


def _entries(x) -> list:
    return list(x) if isinstance(x, sp.MatrixBase) else [x]


def moving_bodies(eom: EquationsOfMotion) -> list:
    kin = eom.kinematics
    return [b for b in eom.system.bodies if kin.chain[b] and (b.mass != 0 or not b.inertia.is_zero_matrix)]


def kinematics(forms: Forms) -> Step:
    kin, expressions = forms.kin, {}
    for b in moving_bodies(forms.eom):
        S = Point(b, b.com)
        expressions[f"r_S[{b.name}]"] = forms(kin.com(b))
        expressions[f"J_P[{b.name}]"] = forms(kin.J_P(S))
        expressions[f"J_R[{b.name}]"] = forms(kin.J_R(b))
        expressions[f"Omega[{b.name}]"] = forms(kin.omega(b))
    return forms.step(
        "Kinematics of the bodies",
        r"Each body's centre of mass $r_S$ and its Jacobians $J_P = \partial \dot r_S / \partial \dot q$"
        r" and "
        r"$J_R = \partial \Omega / \partial \dot q$ (world axes), which map the speeds to the velocity "
        r"$v_S = J_P \dot q$ and the angular velocity $\Omega = J_R \dot q$.",
        expressions,
    )


def projected_newton_euler(forms: Forms) -> list[Step]:
    return [
        forms.step(
            "Projected Newton-Euler",
            r"Each body's momentum balance $m a_S = F$ and $\Theta \alpha + \Omega \times \Theta \Omega"
            r" = T$ "
            r"(about its centre of mass) is projected on the generalized directions with its "
            r"Jacobians: $M = \sum J_P^T m J_P + J_R^T \Theta J_R$, $b = \sum J_P^T m \dot J_P \dot q + "
            r"J_R^T (\Theta \dot J_R \dot q + \Omega \times \Theta \Omega)$, $g = -\sum J_P^T m \vec g$, "
            r"and each load enters as $\tau = \sum J_P^T F + J_R^T T$.",
            forms.result(),
            "projected_newton_euler",
        )
    ]


def recursive(forms: Forms) -> list[Step]:
    return [
        forms.step(
            "Recursive Newton-Euler and composite rigid bodies",
            "In body frames, velocities and accelerations go from the root to the leaves and "
            "forces back from the leaves to the root (RNEA gives $b$ and $g$); the composite "
            "inertias of the subtrees give $M$ (CRBA).",
            forms.result(),
            "recursive",
        )
    ]


def lagrange(forms: Forms) -> list[Step]:
    method, eom = "lagrange", forms.eom
    T, U = eom.compact["T"], eom.compact["U"]
    T_form, U_form = forms(T), forms(U)
    steps = [
        forms.step(
            "Energies",
            r"The kinetic energy $T = \sum \frac{1}{2} m v_S^T v_S + \frac{1}{2} \Omega^T \Theta "
            r"\Omega$ and the potential energy $U$ of gravity ($U = -\sum m \vec g^T r_S$) and of the "
            "springs.",
            {"T": T_form, "U": U_form},
            method,
        )
    ]
    if list(eom.system.qdot) == list(eom.system.u):  # q̇ = u: plain derivatives
        derivatives = (
            _energy_derivatives(forms, T_form, U_form)
            if forms.form != "shared"
            else _energy_derivatives_shared(forms, T, U)
        )
        steps.append(
            forms.step(
                "Derivatives of the energies",
                r"Lagrange's equations $\frac{d}{dt} \frac{\partial T}{\partial \dot q} - "
                r"\frac{\partial T}{\partial q} + \frac{\partial U}{\partial q} = \tau$ need these"
                r" derivatives.",
                derivatives,
                method,
            )
        )
    steps.append(
        forms.step(
            "Lagrange's equations",
            r"The terms of $\frac{d}{dt} \frac{\partial T}{\partial \dot q}$ in $\ddot q$ give "
            r"$M$; the rest of $\frac{d}{dt} \frac{\partial T}{\partial \dot q} - \frac{\partial"
            r" T}{\partial q}$ "
            r"gives $b$; $\frac{\partial U}{\partial q}$ of gravity gives $g$; springs and the "
            r"other loads give $\tau$.",
            forms.result(),
            method,
        )
    )
    return steps


def _energy_derivatives(forms: Forms, T: sp.Expr, U: sp.Expr) -> dict:
    """∂T/∂q̇, d/dt ∂T/∂q̇ (chain rule, q̇ = u), ∂T/∂q, ∂U/∂q of the textbook T and U, simplified."""
    q, u, ud = list(forms.eom.q), list(forms.eom.u), list(forms.eom.system.ud)
    simplify = forms.simplifier.matrix
    p = simplify(sp.Matrix([T.diff(x) for x in u]))
    dp = p.applyfunc(lambda e: sum(e.diff(x) * y for x, y in zip(q + u, u + ud)))
    return {
        "dT/du": p,
        "d/dt dT/du": simplify(dp),
        "dT/dq": simplify(sp.Matrix([T.diff(x) for x in q])),
        "dU/dq": simplify(sp.Matrix([U.diff(x) for x in q])),
    }


def _energy_derivatives_shared(forms: Forms, T: sp.Expr, U: sp.Expr) -> dict:
    """The same through the derivation's intermediates (chain rule, as Lagrange's method derives)."""
    sub, kin = forms.sub, forms.kin
    q, u, ud = list(forms.eom.q), list(forms.eom.u), list(forms.eom.system.ud)
    p = sp.Matrix([sub.add(sub.derivative(T, {x: 1}, ("u", j))) for j, x in enumerate(u)])
    dp = sp.Matrix(
        [
            sub.derivative(e, kin.time_seeds, TIME)
            + sum(sub.derivative(e, {x: 1}, ("u", j)) * a for j, (x, a) in enumerate(zip(u, ud)))
            for e in p
        ]
    )
    return {
        "dT/du": p,
        "d/dt dT/du": dp,
        "dT/dq": sp.Matrix([sub.derivative(T, {x: 1}, ("q", j)) for j, x in enumerate(q)]),
        "dU/dq": sp.Matrix([sub.derivative(U, {x: 1}, ("q", j)) for j, x in enumerate(q)]),
    }


def free_cut(forms: Forms) -> list[Step]:
    method, eom = "free_cut", forms.eom
    steps = []
    numeric_axes = all(a.is_number for j in eom.system.joints if getattr(j, "axis", None) is not None
                       for a in j.axis)
    if forms.form != "shared" and numeric_axes:  # the cut-free balances: textbook form, numeric axes
        try:
            steps.append(_cut(forms))
        except ModelError as why:  # a mimic joint, or motion axes at changing angles
            steps.append(Step("Cut-free balances", f"Not written out: {literal(str(why))}.", {}, method))
    results = forms.result()
    wrenches = eom.extras["reactions"]
    results.update({f"reaction[{joint}]": forms(W) for joint, W in wrenches.items()})
    steps.append(
        forms.step(
            "Elimination of the reactions",
            r"Eliminating the reactions from the leaves to the root leaves one equation per "
            r"joint, along the direction it lets move: $M$, $b$, $g$, $\tau$; the reactions follow "
            r"(force, then torque, at the joint origin in world axes, in $q$, $\dot q$, $\ddot q$ "
            r"and the loads).",
            results,
            method,
        )
    )
    return steps


def _cut(forms: Forms) -> Step:
    """The lecture's free cut: the kinematic relations, then per body its Newton and Euler rows with
    them substituted, one scalar equation lhs = rhs each."""
    eom, simplify = forms.eom, forms.simplifier
    cut = eom.cut_equations
    eqs, unknowns = cut.with_kinematics()
    accelerations = {a: simplify(a - row) for a, row in zip(cut.accelerations, cut.kinematic)}
    heading = r"The kinematic relations of the accelerations, $a_S = J_P \ddot q + \dot J_P \dot q$ and "
    heading += r"$\alpha = J_R \ddot q + \dot J_R \dot q$ (world axes):"
    equations = [equation(heading, a, e) for a, e in accelerations.items()]
    for x in cut.balances:
        body = f"Body `{literal(x.body)}`: Newton (world axes) and Euler (about its centre of mass):"
        equations.append(equation(body, x.lhs.xreplace(accelerations), simplify(x.rhs)))
    plane = (
        ""
        if cut.planar_normal is None
        else (
            f" The motion stays in the plane normal to the world's ${'xyz'[cut.planar_normal]}$ axis, so"
            " each body keeps 3 equations (2 forces, 1 moment)."
        )
    )
    axes, in_body_axes = _axes(cut)
    actuation, efforts = _actuation(eom.system)
    expressions = {
        **in_body_axes,
        **efforts,
        "equations": sp.Integer(len(cut.equations)),
        "unknowns": sp.Matrix([cut.unknowns]),
        "equations with kinematics": sp.Integer(len(eqs)),
        "unknowns with kinematics": sp.Integer(len(unknowns)),
    }
    step = forms.step(
        "Cut free",
        r"Every body is cut free; the joints' reaction forces and torques enter as unknowns: "
        r"$F_{i,x}$, $T_{i,z}$, ... act on body $i$ at its joint's origin, from its parent, which gets "
        rf"$-F_i$, $-T_i$. {axes} {actuation} "
        r"Newton $m a_S = m \vec g + F$ and Euler $\Theta \alpha + \Omega \times \Theta \Omega = T$ "
        rf"about the centre of mass.{plane} {len(cut.equations)} dynamic equations in "
        rf"{len(cut.unknowns)} unknowns (the reactions and $\ddot q$); {len(eqs)} equations in "
        rf"{len(unknowns)} unknowns with the kinematic relations of the accelerations.",
        expressions,
        "free_cut",
    )
    step.equations = equations
    return step


def _axes(cut) -> tuple[str, dict]:
    """Which axes the reaction unknowns are in (world axes unless the joint's blocked directions turn)."""
    if not cut.body_axes:
        return "They are in world axes.", {}
    return (
        "They are in world axes except those in their body's axes (primed, below).",
        {"unknowns in body axes": sp.Matrix([cut.body_axes])},
    )


def _actuation(system) -> tuple[str, dict]:
    """The actuated joints, whose efforts τ enter, and the passive ones (`actuated=False`)."""
    active = [j for j in system.joints if j.actuated and j.dof]
    passive = [j for j in system.joints if not j.actuated and j.dof]
    text, expressions = "", {}
    if active:
        text += "The actuated joints add their efforts (below). "
        expressions["efforts"] = sp.Matrix([[t for j in active for t in effort_symbols(j)]])
    if passive:
        text += "Passive joints (no effort): " + ", ".join(f"`{literal(j.name)}`" for j in passive) + "."
    return text.strip(), expressions


def contacts(forms: Forms) -> Step:
    """Floating base and contacts: S, J_c and the formulas of F_c and N_c (evaluated numerically)."""
    system, kin = forms.eom.system, forms.kin
    floating = any(isinstance(j, FreeFlyer) for j in system.joints)
    expressions = {"S": system.S}
    if system.constraint_rows():
        J_c = kin.constraint_jacobian()[0]
        expressions["J_c"] = forms(J_c)
        n, k = len(system.u), J_c.rows
        M, J = sp.MatrixSymbol("M", n, n), sp.MatrixSymbol("J_c", k, n)
        h = sp.MatrixSymbol("h", n, 1)
        Jdu = sp.MatrixSymbol("Jdot_c qdot", k, 1)
        Lambda = (J * M.I * J.T).I
        expressions["F_c"] = -Lambda * (J * M.I * h + Jdu)
        expressions["N_c"] = sp.Identity(n) - M.I * J.T * Lambda * J
    return forms.step(
        "Floating base and contacts",
        (r"The base is not actuated: $S = [0 \; I]$ selects the actuated joints, " if floating else
         r"$S$ selects the actuated joints, ")
        + r"$M \ddot q + b + g = S^T \tau + J_c^T F_c$. A contact (a loop closure, a rolling disk) holds "
        r"$J_c \dot q = 0$ and "
        r"$J_c \ddot q + \dot J_c \dot q = 0$, which gives the contact forces $F_c$ "
        r"($h = S^T \tau + \tau_{loads} - b - g$); the support projector $N_c$ ($J_c N_c = 0$) gives the "
        r"support-consistent dynamics $N_c^T (M \ddot q + b + g) = N_c^T S^T \tau$. Both involve $M^{-1}$: "
        r"eomgen evaluates them numerically (`f.constrained_dynamics`, `f.support_projector`), never by "
        r"symbolic inversion.",
        expressions,
    )


LOAD_FORMULAS = {  # how each kind of load enters τ (the lecture's τ = Σ J_Pᵀ F + J_Rᵀ T)
    "Force": r"a force $F$ at a point $P$: $\tau = J_P^T F$",
    "Torque": r"a torque $T$ on a body: $\tau = J_R^T T$",
    "Actuator": r"an actuator on body $A$ with reaction on $B$: $\tau = (J_{R,A} - J_{R,B})^T T + "
    r"(J_{P,A} - J_{P,B})^T F$",
    "Spring": r"a spring from $P_a$ to $P_b$: $\tau = (J_{P_b} - J_{P_a})^T F_s$, "
    r"$F_s = -k (\lVert r_b - r_a \rVert - l_0) e_{ab}$ the force on $P_b$",
    "Damper": r"a damper from $P_a$ to $P_b$: $\tau = (J_{P_b} - J_{P_a})^T F_d$, "
    r"$F_d = -c (e_{ab}^T (v_b - v_a)) e_{ab}$",
}


def assembled(forms: Forms) -> Step:
    """The equations of motion M(q) q̈ + b + g = Sᵀ τ + Σ τ_load, one row per coordinate (textbook
    form), with each load's τ."""
    system, results = forms.eom.system, forms.results
    loads = {k: v for k, v in results.items() if k.startswith("tau[")}
    active = [b.joint for b in system.bodies if b.index is not None and b.joint.actuated]
    efforts = [t for j in active for t in effort_symbols(j)[: j.efforts]]
    rhs = (system.S.T * sp.Matrix(efforts) if efforts else sp.zeros(len(system.u), 1))
    rhs += sum((sp.Matrix(t) for t in loads.values()), sp.zeros(len(system.u), 1))
    kinds = dict.fromkeys(type(load).__name__ for load in system.loads)
    how = "; ".join(LOAD_FORMULAS[k] for k in kinds if k in LOAD_FORMULAS)
    text = (
        r"Collected: $M(q) \ddot q + b(q, \dot q) + g(q) = S^T \tau + \sum \tau_{load}$, the efforts $\tau$ "
        "of the actuated joints only"
        + (f", and each load through the Jacobians of its points of action ({how})." if how else ".")
    )
    step = forms.step("Equations of motion", text, dict(loads))
    if forms.form != "shared":
        M, b, g = (sp.Matrix(results[k]) for k in ("M", "b", "g"))
        heading = "One row per coordinate:"
        lhs = M * sp.Matrix(system.ud) + b + g
        step.equations = [equation(heading, lhs[i], rhs[i]) for i in range(len(system.u))]
    return step
