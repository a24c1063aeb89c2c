"""Numeric functions from the equations of motion."""
from __future__ import annotations

import re
import warnings
from collections.abc import Callable, Mapping
from contextlib import nullcontext
from dataclasses import dataclass

import numpy as np
import sympy as sp

from ..constraint_rows import tilts
from ..eom import EquationsOfMotion
from ..errors import ByName, ModelError, unknown
from ..methods.kane import KaneEquations
from ..state import random_states
from .contacts import contact_dynamics, refuse_flat, support_projector
from .derivative_functions import DerivativeFunctions
from .kinematic_functions import KinematicFunctions
from .lines import check_ends, line_loads
from .numpy_backend import PYTHON, FunctionWriter, Syntax, compile_function
from .parameters import Parameters, actuated, bind
from .rhs import StateFunctions
from .runtime import mpmath_functions, runtime_namespace
from .singular import singular_mass_matrix

_runtime = runtime_namespace()
_call, _inputs = _runtime["_call"], _runtime["_inputs"]

BACKENDS = ("numpy", "c")


@dataclass
class Generated:
    """One generated function: its source, output shape and operation count."""

    source: str
    shape: tuple
    ops: int
    function: Callable
    vector: Callable | None = None  # compiled: the column output as a vector

    def __post_init__(self) -> None:
        self.params_used = frozenset(reads(self.source)["p"])


def reads(source: str) -> dict[str, list[int]]:
    """The entries of q, u, ud and p a generated function reads, each once, in order."""
    found: dict[str, set[int]] = {"q": set(), "u": set(), "ud": set(), "p": set()}
    for arg, k in re.findall(r"\b_(q|u|ud|p)(\d+) =", source):
        found[arg].add(int(k))
    return {arg: sorted(ks) for arg, ks in found.items()}


def listed(used: dict[str, list[int]]) -> str:
    """The entries read, as a header lists them: "q[0, 2]; p[1]" (or "nothing")."""
    return "; ".join(f"{arg}[{', '.join(map(str, ks))}]" for arg, ks in used.items() if ks) or "nothing"


# the functions of the equations, and what they compute
QUANTITIES = {"M": "mass matrix M(q)", "b": "Coriolis and centrifugal terms b(q, u)",
              "g": "gravity terms g(q) (left-hand side: M u̇ + b + g = τ + Sᵀ τ_a)", "nle": "b(q, u) + g(q)",
              "tau": "generalized forces τ(q, u) of the loads (right-hand side)",
              "T": "kinetic energy T(q, u)",
              "U": "potential energy U(q) (gravity, springs, bending)"}


def quantities(eom: EquationsOfMotion) -> list[str]:
    """The quantities written for `eom`: M, b, g, nle, T, U as derived, and tau."""
    return [k for k in QUANTITIES if k in eom.compact or k == "tau"]


def expression(eom: EquationsOfMotion, key: str) -> sp.Basic:
    """The compact expression of a quantity (in the intermediates)."""
    return eom.tau_compact if key == "tau" else eom.compact[key]


def writer(eom: EquationsOfMotion, syntax: Syntax = PYTHON) -> FunctionWriter:
    """A function writer over the equations' intermediates, inputs q, u, u̇ and the parameters."""
    return FunctionWriter(eom.subexpressions, {"q": list(eom.q), "u": list(eom.u), "ud": list(eom.system.ud),
                                               "p": Parameters(eom.system.parameters).symbols}, syntax)


def written(result: np.ndarray, out: np.ndarray | None, **inputs) -> np.ndarray:
    """`result`, copied into `out` when given: a writeable C-contiguous float64 array of its shape (a
    batch reuses its buffers; the C backend writes there directly) that shares no memory with the
    `inputs` {name: q, u or ud} (the C backend would write over states it has not read yet), else a
    ModelError naming out."""
    if out is None:
        return result
    for name, x in inputs.items():
        if isinstance(out, np.ndarray) and isinstance(x, np.ndarray) and np.shares_memory(out, x):
            raise ModelError(f"out: shares memory with the input {name}; give an output array apart from "
                             "the inputs")
    if not isinstance(out, np.ndarray):
        got = type(out).__name__
    elif out.dtype != np.float64 or out.shape != result.shape or not out.flags.c_contiguous \
            or not out.flags.writeable:
        flags = out.flags
        kind = " non-contiguous" if not flags.c_contiguous else " read-only" if not flags.writeable else ""
        got = f"a{kind} {out.dtype} array of shape {out.shape}"
    else:
        out[...] = result
        return out
    raise ModelError(f"out: expected a writeable C-contiguous float64 array of shape {result.shape}, "
                     f"got {got}")


def eager(eom: EquationsOfMotion) -> list[str]:
    """The functions generated up front: those of M, b, g, b + g and the frames of derive(frames=...)."""
    return [k for k in eom.compact if k in ("M", "b", "g", "nle") or k.split(":")[0] in ("J", "Jdot_u")]


class NumericEoM(KinematicFunctions, StateFunctions, DerivativeFunctions):
    """Numeric M(q), b(q, u), g(q), tau(q, u), T(q, u), U(q), frame Jacobians, forward dynamics, the
    state equations `rhs`, the inverse dynamics and the derivatives of the dynamics, and (free cut) joint
    reactions of one `EquationsOfMotion`.

    q and u are arrays of shape (n,), or (N, n) for N states at once (evaluated without a Python
    loop). Symbolic parameters are given by name in a mapping {name: value} in each call (a function
    asks only for the ones it uses), or fixed once with `bind` (see `eomgen.codegen.parameters`)."""

    def __init__(self, eom: EquationsOfMotion) -> None:
        self.eom = eom
        self.system = eom.system  # the model the functions were generated from
        self.nq, self.nv = len(eom.q), len(eom.u)
        self._lines = line_loads(eom.system)  # checked where the output is not finite (`lines`)
        self.parameters = Parameters(eom.system.parameters, state=[m.current for m in eom.system.motors])
        self.params = self.parameters.symbols  # p[k] of the generated code, sorted by name
        self.S = np.array(eom.S.tolist(), dtype=float).reshape(-1, self.nv)
        self._writer = writer(eom)
        self.functions: dict[str, Generated] = {}
        self._python: dict[str, Callable] = {}  # Python versions for mpmath references
        self._built: dict[str, tuple[Callable, bool]] = {}  # how each function was built
        self._row_size: dict = {}  # size of each row of J_c per parameter values (`_row_sizes`)
        for name in eager(eom):  # T, U, tau and other frames are written when first asked for
            self._function(name, lambda name=name: eom.compact[name], symmetric=name == "M")

    @property
    def sources(self) -> dict[str, str]:
        """The Python source of each generated function, by key."""
        return {k: f.source for k, f in self.functions.items()}

    @property
    def ops(self) -> dict[str, int]:
        """Floating-point operations of each generated function (after sharing the intermediates)."""
        return {k: f.ops for k, f in self.functions.items()}

    @property
    def multiplications(self) -> dict[str, int]:
        """Multiplications written in each generated function (the '*' of its source, powers excluded)."""
        return {k: f.source.count("*") - 2 * f.source.count("**") for k, f in self.functions.items()}

    def _function(self, key: str, build: Callable[[], sp.Basic], symmetric: bool = False) -> Generated:
        """The generated function `key`, written on first request."""
        self._built.setdefault(key, (build, symmetric))
        if key not in self.functions:
            source, shape, ops = self._writer.source("f", build(), symmetric)
            self.functions[key] = Generated(source, shape, ops, compile_function(source, key))
        return self.functions[key]

    def _on_demand(self, key: str) -> None:
        """Write T, U or tau on first use; anything else missing was not derived."""
        if key in quantities(self.eom):
            self._function(key, lambda: expression(self.eom, key))
        else:
            raise ModelError(f"{key} was not derived: derive it (quantities=...) to evaluate it")

    def _p(self, params: Mapping | None, key: str) -> list[float] | np.ndarray:
        """The parameter vector p for function `key` (the bound values, or those it uses from params)."""
        return self.parameters.vector(params, self.functions[key].params_used)

    def bind(self, params: Mapping) -> NumericEoM:
        """The same functions with the parameter values fixed once ({name: value}, every parameter but
        the motor currents, which are state): their calls take no params."""
        return bind(self, params)

    def call(self, key: str, q, u=None, ud=None, params=None, out=None) -> np.ndarray:
        """Evaluate generated function `key` at q, u, u̇ (one state, or N states along axis 0); into
        `out` when given (see `written`)."""
        if key not in self.functions:
            self._on_demand(key)
        f = self.functions[key]
        with np.errstate(divide="ignore", invalid="ignore") if self._lines else nullcontext():
            result = _call(f.function, f.shape, self.nq, self.nv, q, u, ud, self._p(params, key))
        return written(check_ends(self, result, q, params), out, q=q, u=u, ud=ud)

    def reference(self, key: str, q, u=None, ud=None, params=None, digits: int = 50) -> np.ndarray:
        """The same generated expressions evaluated in mpmath with `digits` significant digits (one
        state; the constants are the float64 numbers of the model): the high-precision reference for
        measuring float64 round-off."""
        import mpmath

        if key not in self.functions:
            self._on_demand(key)
        if key not in self._python:  # the Python text runs with any number type
            expr, symmetric = self._built[key]
            self._python[key] = compile_function(self._writer.source("f", expr(), symmetric)[0], key)
        with mpmath.workdps(digits):
            def mp(x, n):
                return [mpmath.mpf(float(v)) for v in (np.zeros(n) if x is None else np.asarray(x, dtype=float))]
            out, m = np.zeros(self.functions[key].shape, dtype=object), mpmath_functions()
            self._python[key](mp(q, self.nq), mp(u, self.nv), mp(ud, self.nv),
                              [mpmath.mpf(v) for v in self._p(params, key)], out, m.sin, m.cos, m.sqrt, m)
            return out

    def M(self, q, params=None, out=None) -> np.ndarray:
        """Mass matrix M(q), shape (nv, nv) per state; into `out` when given (see `written`), as b, g,
        nle."""
        return self.call("M", q, params=params, out=out)

    def b(self, q, u, params=None, out=None) -> np.ndarray:
        """Coriolis and centrifugal terms b(q, u), shape (nv,) per state."""
        return written(self.call("b", q, u, params=params)[..., 0], out, q=q, u=u)

    def g(self, q, params=None, out=None) -> np.ndarray:
        """Gravity terms g(q) (left-hand side), shape (nv,) per state."""
        return written(self.call("g", q, params=params)[..., 0], out, q=q)

    def nle(self, q, u, params=None, out=None) -> np.ndarray:
        """b + g in one pass (method "recursive"), like Pinocchio's nonLinearEffects."""
        if "nle" not in self.functions:
            return written(self.b(q, u, params) + self.g(q, params), out, q=q, u=u)
        return written(self.call("nle", q, u, params=params)[..., 0], out, q=q, u=u)

    def tau(self, q, u, params=None) -> np.ndarray:
        """Generalized forces of all loads."""
        return self.call("tau", q, u, params=params)[..., 0]

    def T(self, q, u, params=None):
        """Kinetic energy T(q, u), a number per state."""
        return self.call("T", q, u, params=params)[..., 0, 0]

    def U(self, q, params=None):
        """Potential energy U(q) (gravity, springs, bending), a number per state."""
        return self.call("U", q, params=params)[..., 0, 0]

    def jacobian(self, frame: str, q, params=None) -> np.ndarray:
        """6 × n Jacobian [J_P; J_R] of a frame or body origin, world-aligned axes."""
        self._function(key := f"J:{frame}", lambda: self.eom.kinematics.jacobian(frame))
        return self.call(key, q, params=params)

    def jacobian_dot_u(self, frame: str, q, u, params=None) -> np.ndarray:
        """J̇ u (6-vector, [linear; angular]) of a frame or body origin."""
        self._function(key := f"Jdot_u:{frame}", lambda: self.eom.kinematics.jacobian_dot_u(frame))
        return self.call(key, q, u, params=params)[..., 0]

    def tau_of(self, load: str, q, u, params=None) -> np.ndarray:
        """Generalized force of one load, by name."""
        if load not in self.eom.load_names:
            raise unknown("load", load, self.eom.load_names)
        self._function(key := f"tau:{load}", lambda: self.eom.compact[f"tau:{load}"])
        return self.call(key, q, u, params=params)[..., 0]

    def joint_wrench(self, joint: str, q, u, ud, params=None) -> tuple[np.ndarray, np.ndarray]:
        """(F, T) the parent exerts on the body of `joint` at the joint origin, world axes (free cut)."""
        self._function(key := f"W:{joint}", lambda: self._free_cut("joint_wrenches", joint))
        W = self.call(key, q, u, ud, params)[..., 0]
        return W[..., :3], W[..., 3:]

    def reactions(self, q, u, tau_a=None, params=None, ud=None) -> dict[str, tuple[np.ndarray, np.ndarray]]:
        """Reaction force and torque of every joint (world axes, at the joint origin), with u̇ from
        the forward dynamics unless given (free cut)."""
        ud = self.forward_dynamics(q, u, tau_a, params) if ud is None else ud
        out = ByName("joint", {})
        for joint in self._free_cut("reactions", None):
            self._function(key := f"R:{joint}", lambda: self._free_cut("reactions", joint))
            W = self.call(key, q, u, ud, params)[..., 0]
            out[joint] = (W[..., :3], W[..., 3:])
        return out

    def _free_cut(self, key: str, joint: str | None):
        results = self.eom._free_cut_result(key)
        if joint is not None and joint not in results:
            raise unknown("joint", joint, results)
        return results[joint] if joint is not None else results

    def _h(self, q, u, tau_a, params) -> np.ndarray:
        """h = τ_loads + Sᵀ τ_a − b − g."""
        return actuated(self.tau(q, u, params) - self.nle(q, u, params), tau_a, self.S)

    def euler_singularity(self, q, tol: float = 1e-3, params=None) -> float | None:
        """For ZYX Euler angles (an Euler base, a ZYX ball joint): warn when a pitch is within `tol` of
        ±90° (where the angle rates are undefined and M is singular) and return cond(M); None when the
        state is regular."""
        for b in self.eom.system.bodies:
            if b.joint.pitch_index is not None:
                pitch = float(np.asarray(q, float)[b.q_index + b.joint.pitch_index])
                if abs(np.cos(pitch)) < tol:
                    cond = float(np.linalg.cond(self.M(q, params)))
                    warnings.warn(f"joint '{b.joint.name}': pitch {pitch:.6f} rad is {abs(np.cos(pitch)):.1e} "
                                  f"from ±90°, where ZYX Euler angles are singular; cond(M) = {cond:.1e}",
                                  stacklevel=3)
                    return cond
        return None

    def forward_dynamics(self, q, u, tau_a=None, params=None) -> np.ndarray:
        """u̇ = M⁻¹ (τ + Sᵀ τ_a − b − g), solved numerically (no contacts); warns near an Euler-base
        singularity."""
        if np.ndim(q) == 1:
            self.euler_singularity(q, params=params)
        M = self.M(q, params)
        try:
            return np.linalg.solve(M, self._h(q, u, tau_a, params)[..., None])[..., 0]
        except np.linalg.LinAlgError:
            raise singular_mass_matrix(self.eom.system, M, "forward_dynamics") from None

    def qdot(self, q, u, params=None) -> np.ndarray:
        """q̇(q, u) (`System.qdot`: u itself but for quaternions, whose rates depend on q)."""
        self._function("qdot", lambda: self.eom.system.qdot)
        return self.call("qdot", q, u, params=params)[..., 0]

    # --- contacts, loops, rolling disks (one state at a time) ------------------------------------
    def contact_jacobian(self, q, params=None) -> np.ndarray:
        """J_c: the stacked rows of every constraint: contacts (3 per point, 6 per frame), loops, rolling
        disks (`constraint_rows` names them)."""
        self._function("J_c", lambda: self.eom.kinematics.constraint_jacobian()[0])
        return self.call("J_c", q, params=params)

    def contact_jacobian_dot_u(self, q, u, params=None) -> np.ndarray:
        """J̇_c u, stacked like J_c's rows."""
        self._function("Jdot_c_u", lambda: self.eom.kinematics.constraint_jacobian()[1])
        return self.call("Jdot_c_u", q, u, params=params)[..., 0]

    def closure_residual(self, q, params=None) -> np.ndarray:
        """The loops' and rolling disks' position residuals (`closure_rows`), zero when closed."""
        self._contacts()
        if not self.closure_rows:
            raise ModelError("the system has no loops or rolling disks: add them with System.add_loop or "
                             "System.add_rolling")
        self._function("closure", lambda: self.eom.kinematics.closure_residual())
        return self.call("closure", q, params=params)[..., 0]

    @property
    def constraint_rows(self) -> list[str]:
        """Names of the rows of J_c and of the constraint forces."""
        return self.eom.system.constraint_rows()

    @property
    def closure_rows(self) -> list[str]:
        """Names of the rows of `closure_residual`."""
        return self.eom.system.closure_rows()

    @property
    def closure_index(self) -> list[int]:
        """For each row of `closure_residual`, its row of J_c (d r / dt = J_c u there): a loop's rows are
        its own, a rolling disk's height goes with its normal row n."""
        system, rows = self.eom.system, self.constraint_rows
        return [rows.index(r) for r in [*(r for x in system.loops for r in x.row_names),
                                         *(x.row_names[2] for x in system.rolling)]]

    def _contacts(self):
        if self.eom.kinematics.version != self.eom.system.version:
            raise ModelError("the system changed after these functions were generated (a body, frame, "
                             "contact, loop or rolling disk was added): derive and generate them again")
        if not self.constraint_rows:
            raise ModelError("the system has no contacts, loops or rolling disks: add them with "
                             "System.add_contact, add_loop or add_rolling")
        return self.constraint_rows

    def _row_sizes(self, params) -> np.ndarray:
        """The size of each row of J_c (with J̇_c u) at three random states (`random_states`: unit
        quaternions), per parameter values; rows of size 0 (the z row of a loop in a plane mechanism;
        round-off below 1e-12 of the largest row or of 1; the normal row of a disk its tree keeps on the
        ground, `grounded`) no motion can violate."""
        self._function("J_c", lambda: self.eom.kinematics.constraint_jacobian()[0])
        key = tuple(np.ravel(self._p(params, "J_c")))
        if key not in self._row_size:
            q, u, _ = random_states(self.eom.system, 3, np.random.default_rng(0))
            rows = [np.abs(self.contact_jacobian(q[k], params)).max(axis=1)
                    + np.abs(self.contact_jacobian_dot_u(q[k], u[k], params)) for k in range(3)]
            grounded = {d.row_names[2] for d in self.eom.kinematics.grounded_disks()}
            size = np.where([r in grounded for r in self.constraint_rows], 0.0, np.max(rows, axis=0))
            self._row_size[key] = np.where(size > 1e-12 * max(1.0, size.max()), size, 0.0)  # round-off: 0
        return self._row_size[key]

    def _held(self, q, params) -> tuple[np.ndarray, np.ndarray, list[str]]:
        """(mask, J, names) of the rows of J_c some motion can violate at q: they carry the forces; the
        others carry none. A row that vanishes only at q (below 1e-12 of its size, a singular configuration
        of the constraint) is warned of; a rolling disk lying (nearly) flat (`refuse_flat`) and a row that
        is not finite refused."""
        names, size, J = self._contacts(), self._row_sizes(params), self.contact_jacobian(q, params)
        if self.eom.system.rolling:
            self._function("tilt", lambda: tilts(self.eom.kinematics))
            refuse_flat(self.eom.system.rolling, self.call("tilt", q, params=params))
        broken = [n for n, row in zip(names, J) if not np.all(np.isfinite(row))]
        if broken:
            raise ModelError(f"constraint rows {broken} are not finite at this state (a rolling disk whose "
                             "axle is normal to the ground, lying flat, has no contact point)")
        held = (size > 0) & (np.abs(J).max(axis=1) > 1e-12 * size)
        lost = [n for n, s, h in zip(names, size, held) if s > 0 and not h]
        if lost:
            warnings.warn(f"constraint rows {lost} cannot be violated by any motion at this state (a singular "
                          "configuration): no force along them", stacklevel=3)
        return held, J[held], [n for n, h in zip(names, held) if h]

    def constrained_dynamics(self, q, u, tau_a=None, params=None,
                             baumgarte: tuple[float, float] | None = None) -> tuple[np.ndarray, np.ndarray]:
        """(u̇, F_c) with every contact, loop and rolling disk held: F_c = −(J M⁻¹ Jᵀ)⁻¹ (J M⁻¹ h + c),
        the constraint forces on the system, stacked like J_c's rows (0 on rows no motion can violate).
        c = J̇ u holds J u̇ + J̇ u = 0; with baumgarte = (α, β), c = J̇ u + 2 α J u + β² r holds
        J u̇ + J̇ u = −2 α J u − β² r (r: the closure residual on its rows, `closure_index`; 0 on the rows
        of contacts and no-slip), which drives a drift of r and J u back to zero (critically damped at
        α = β)."""
        active, J, names = self._held(q, params)
        F = np.zeros(len(active))
        if not active.any():
            return self.forward_dynamics(q, u, tau_a, params), F
        bias = self.contact_jacobian_dot_u(q, u, params)
        if baumgarte is not None:
            alpha, beta = baumgarte
            bias[active] += 2 * alpha * (J @ np.asarray(u, float))  # the rows that carry forces
            if self.closure_rows:
                bias[self.closure_index] += beta ** 2 * self.closure_residual(q, params)
        u_dot, F_active = contact_dynamics(self.M(q, params), self._h(q, u, tau_a, params), J, bias[active],
                                           names)
        F[active] = F_active
        return u_dot, F

    def constraint_forces(self, q, u, tau_a=None, params=None) -> dict[str, np.ndarray]:
        """F_c by constraint name (a contact's frame, a loop's or a rolling disk's name): a loop's force
        acts on frame_a's body, its opposite on frame_b's; a disk's rows are along ground x, y and z."""
        F, system, out = self.constrained_dynamics(q, u, tau_a, params)[1], self.eom.system, {}
        for c in (*system.contacts, *system.loops, *system.rolling):
            out[c.name], F = F[:len(c.row_names)], F[len(c.row_names):]
        return out

    def contact_forces(self, q, u, tau_a=None, params=None) -> np.ndarray:
        """F_c, stacked like J_c's rows (world-aligned axes)."""
        return self.constrained_dynamics(q, u, tau_a, params)[1]

    def support_projector(self, q, params=None) -> np.ndarray:
        """N_c = 1 − M⁻¹ J_cᵀ (J_c M⁻¹ J_cᵀ)⁻¹ J_c (J_c N_c = 0, N_c² = N_c)."""
        active, J, names = self._held(q, params)
        return support_projector(self.M(q, params), J, names) if active.any() else np.eye(self.nv)

    def support_consistent_residual(self, q, u, ud, tau_a=None, params=None) -> np.ndarray:
        """N_cᵀ (M u̇ + b + g − Sᵀ τ − τ_loads): zero along any motion the contacts allow."""
        N = self.support_projector(q, params)
        return N.T @ (self.M(q, params) @ np.asarray(ud, float) - self._h(q, u, tau_a, params))


def equations(eom, entry: str, *others: type) -> None:
    """Refuse, naming `entry`, anything but an `EquationsOfMotion` (or one of `others`)."""
    if not isinstance(eom, (EquationsOfMotion, *others)):
        kinds = " or ".join(t.__name__ for t in (EquationsOfMotion, *others))
        raise ModelError(f"{entry}: expected {kinds}, got {type(eom).__name__} (derive the equations "
                         "first: eg.derive(system))")


def codegen(eom, backend: str = "numpy", params: Mapping | None = None):
    """Numeric functions of an `EquationsOfMotion` (or of `KaneEquations`): backend "numpy", or "c"
    (compiled with the machine's C compiler; same functions, per call and batched). With `params`
    ({name: value}, every parameter but the motor currents) the values are bound once and the calls
    take no params."""
    equations(eom, "codegen", KaneEquations)
    if backend not in BACKENDS:
        raise ModelError(f"unknown backend {backend!r}; available: {list(BACKENDS)}")
    kane = isinstance(eom, KaneEquations)
    if backend == "c":
        from .c_backend import CompiledEoM

        f = CompiledKane(eom) if kane else CompiledEoM(eom)
    else:
        f = NumericKane(eom) if kane else NumericEoM(eom)
    return f if params is None else bind(f, params)


from .module import module_source, write_module  # noqa: E402  (module builds on NumericEoM)
from .c_backend import write_c  # noqa: E402
from .kane import CompiledKane, NumericKane  # noqa: E402,F401
