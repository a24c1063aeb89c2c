"""The result every method returns: M(q) u̇ + b(q, u) + g(q) = τ(q, u) + Sᵀ τ_a."""
from __future__ import annotations

from dataclasses import dataclass, field

import sympy as sp

from .display import equations_markdown, equations_math
from .errors import ByName, ModelError, unknown
from .kinematics import Kinematics
from .model.system import System
from .subexpressions import Subexpressions
from .symbols import Generated


class ClosedForms:
    """Results kept in named intermediates (`compact`), shown as closed forms on first use."""

    compact: dict
    kinematics: Kinematics
    _closed: dict

    @property
    def subexpressions(self) -> Subexpressions:
        """The named intermediates; refused once the system has changed since the derivation (the
        equations would silently miss the change)."""
        system = self.kinematics.system
        if self.kinematics.version != system.version:
            raise ModelError("the system changed after these equations were derived (a body, frame, load, "
                             "contact or motor was added): derive them again")
        return self.kinematics.sub

    def _closed_form(self, name: str):
        if name not in self.compact:
            raise ModelError(f"{name} was not derived (derived: {sorted(k for k in self.compact if ':' not in k)}); "
                             "derive it with quantities=...")
        if name not in self._closed:
            self._closed[name] = self.subexpressions.inline(self.compact[name])
        return self._closed[name]


def closed_form(name: str, doc: str = "") -> property:
    """A property giving the closed form of compact[name]."""
    return property(lambda self: self._closed_form(name), doc=doc)


@dataclass(eq=False)
class EquationsOfMotion(ClosedForms):
    """M, b, g, the generalized forces of the loads, S, and the energies T and U.

    The `compact` forms are written in named intermediates (`subexpressions`), which is what code
    generation prints; the attributes M, b, g, tau, T, U are the closed forms in q, u and the
    parameters, built on first use (for large robots use the compact forms or code generation)."""

    kinematics: Kinematics
    method: str
    compact: dict[str, sp.Basic]  # M, b, g, T, U and the loads' generalized forces under "tau:<name>"
    extras: dict = field(default_factory=dict)  # method-specific results (free cut: reactions, ...)
    _closed: dict = field(default_factory=dict, repr=False)
    # what the layers above build once per equations (the function catalogue), gone with them
    made: dict = field(default_factory=dict, repr=False)

    def __getstate__(self) -> dict:
        """Pickled without `made`, which holds functions and is built again on demand."""
        return {**self.__dict__, "made": {}}

    @property
    def system(self) -> System:
        """The system these equations were derived from."""
        return self.kinematics.system

    @property
    def q(self) -> sp.Matrix:
        """The coordinates q (`System.q`)."""
        return self.system.q

    @property
    def u(self) -> sp.Matrix:
        """The speeds u (`System.u`)."""
        return self.system.u

    @property
    def S(self) -> sp.Matrix:
        """Selection matrix of the actuated joints."""
        return self.system.S

    @property
    def tau_actuated(self) -> sp.Matrix:
        """Symbols of the actuated joints' torques / forces τ_a (one per row of S)."""
        joints = [j for j in self.system.joints if j.actuated]
        return sp.Matrix([Generated(f"tau_{j.name}", ("tau", j.name)) for j in joints])

    M = closed_form("M", "Mass matrix M(q).")
    b = closed_form("b", "Centrifugal and Coriolis terms b(q, u).")
    g = closed_form("g", "Gravity terms g(q) (left-hand side).")
    T = closed_form("T", "Kinetic energy.")
    U = closed_form("U", "Potential energy: gravity, springs, bending.")

    @property
    def load_names(self) -> list[str]:
        """The names of the loads whose generalized forces were derived (see `tau_of`)."""
        return [k.split(":", 1)[1] for k in self.compact if k.startswith("tau:")]

    def tau_of(self, load: str) -> sp.Matrix:
        """Generalized force of one load (by name); an unknown name is refused with the loads' names."""
        if load not in self.load_names:
            if any(x.name == load for x in self.system.loads):
                raise ModelError(f"load '{load}' was added after these equations were derived: "
                                 "derive them again")
            raise unknown("load", load, self.load_names)
        return self._closed_form(f"tau:{load}")

    @property
    def tau_compact(self) -> sp.Matrix:
        """Σ of the loads' generalized forces, in intermediates."""
        return sum((self.compact[f"tau:{name}"] for name in self.load_names), sp.zeros(len(self.u), 1))

    @property
    def nle_compact(self) -> sp.Matrix:
        """b + g in intermediates (the one-pass "nle" where derived)."""
        return self.compact["nle"] if "nle" in self.compact else self.compact["b"] + self.compact["g"]

    @property
    def tau(self) -> sp.Matrix:
        """Generalized forces of all loads: forces, torques, actuators, springs, dampers."""
        return self.subexpressions.inline(self.tau_compact)

    def free_cut_result(self, key: str):
        """The free cut's result `key` (joint_wrenches, reactions, cut_equations), refused naming the method
        for equations of another."""
        if key not in self.extras:
            raise ModelError(f"{key} are a result of the free cut with all of M, b, g: derive with "
                             f"method='free_cut' and no quantities= (these equations come from {self.method!r}"
                             f"{'' if self.method != 'free_cut' else ' with quantities ' + str(self.quantities)})")
        return self.extras[key]

    @property
    def joint_wrenches(self) -> dict[str, tuple[sp.Matrix, sp.Matrix]]:
        """Per joint, the force and torque the parent exerts on the body at the joint origin (world
        axes), in q, u, u̇ and the loads: the reaction plus the joint force along the free direction."""
        return ByName("joint", {j: self._split(self.subexpressions.inline(W))
                                for j, W in self.free_cut_result("joint_wrenches").items()})

    @property
    def reactions(self) -> dict[str, tuple[sp.Matrix, sp.Matrix]]:
        """Per joint, the reaction force and torque (world axes, at the joint origin): the joint
        wrench without its component along the joint's free direction."""
        return ByName("joint", {j: self._split(self.subexpressions.inline(W))
                                for j, W in self.free_cut_result("reactions").items()})

    @property
    def cut_equations(self):
        """The free cut before elimination (see `methods.free_cut.CutEquations`)."""
        if "_cut" not in self._closed:
            self._closed["_cut"] = self.free_cut_result("cut_equations")()
        return self._closed["_cut"]

    @staticmethod
    def _split(W: sp.Matrix) -> tuple[sp.Matrix, sp.Matrix]:
        return W[:3, :], W[3:, :]

    def coriolis_matrix(self) -> sp.Matrix:
        """C with C u = b, from the Christoffel symbols of M:
        C_ij = Σ_k ½ (∂M_ij/∂q_k + ∂M_ik/∂q_j − ∂M_jk/∂q_i) u_k (closed form; small systems)."""
        if list(self.system.qdot) != list(self.u):
            raise ModelError("coriolis_matrix: the Christoffel symbols need u = q̇; this system has speeds "
                             "that are not coordinate rates (a quaternion or planar joint's twist)")
        M, q, u = self.M, self.q, self.u
        n = len(q)
        dM = [M.diff(qk) for qk in q]
        return sp.Matrix(n, n, lambda i, j: sum(
            (dM[k][i, j] + dM[j][i, k] - dM[i][j, k]) * u[k] for k in range(n)) / 2)

    def equations(self) -> sp.Matrix:
        """The residual M u̇ + b + g − τ − Sᵀ τ_a (= 0), closed form."""
        return self.M * self.system.ud + self.b + self.g - self.tau - self.S.T * self.tau_actuated

    @property
    def quantities(self) -> tuple[str, ...]:
        """Which of M, b, g were derived."""
        return tuple(k for k in ("M", "b", "g") if k in self.compact)

    @property
    def frames(self) -> list[str]:
        """The frames whose Jacobian J and J̇ u were derived with the equations (derive(frames=...))."""
        return [k[2:] for k in self.compact if k.startswith("J:")]

    def __repr__(self) -> str:
        return f"EquationsOfMotion(method={self.method!r}, q={list(self.q)})"

    def _repr_markdown_(self) -> str:  # Jupyter
        return equations_markdown(self)

    def _repr_latex_(self) -> str:
        return f"$$ {equations_math(self)} $$"
