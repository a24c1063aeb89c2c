"""Numeric functions from the equations of motion."""
from __future__ import annotations

import re
from collections.abc import Callable, Mapping
from dataclasses import dataclass

import numpy as np
import sympy as sp

from ..eom import EquationsOfMotion
from ..errors import ModelError
from .numpy_backend import FunctionWriter, compile_function
from .runtime import runtime_namespace

_call = runtime_namespace()["_call"]

BACKENDS = ("numpy",)


@dataclass
class Generated:
    """One generated function: its source, output shape and operation count."""

    source: str
    shape: tuple
    ops: int
    function: Callable

    def __post_init__(self) -> None:
        self.params_used = {int(k) for k in re.findall(r"\b_p(\d+) =", self.source)}


class NumericEoM:
    """Numeric M(q), b(q, u), g(q), tau(q, u), T(q, u), U(q), frame Jacobians, forward dynamics and
    (free cut) joint reactions of one `EquationsOfMotion`.

    q and u are arrays of shape (n,), or (N, n) for N states at once (evaluated without a Python
    loop). Symbolic parameters (see `params`) are given as a mapping from the symbol or its name to a
    value in each call; a function asks only for the ones it uses."""

    def __init__(self, eom: EquationsOfMotion) -> None:
        self.eom = eom
        self.nq, self.nv = len(eom.q), len(eom.u)
        self.params = sorted(eom.system.parameters, key=str)
        self._writer = FunctionWriter(eom.subexpressions, {"q": list(eom.q), "u": list(eom.u),
                                                           "ud": list(eom.system.ud), "p": self.params})
        self.functions: dict[str, Generated] = {}
        for name in ("M", "b", "g", "tau", "T", "U"):
            self._function(name, lambda name=name: eom.tau_compact if name == "tau" else eom.compact[name],
                           symmetric=name == "M")

    @property
    def sources(self) -> dict[str, str]:
        return {k: f.source for k, f in self.functions.items()}

    @property
    def ops(self) -> dict[str, int]:
        """Floating-point operations of each generated function (after sharing the intermediates)."""
        return {k: f.ops for k, f in self.functions.items()}

    def _function(self, key: str, build: Callable[[], sp.Basic], symmetric: bool = False) -> Generated:
        """The generated function `key`, written on first request."""
        if key not in self.functions:
            source, shape, ops = self._writer.source("f", build(), symmetric)
            self.functions[key] = Generated(source, shape, ops, compile_function(source, key))
        return self.functions[key]

    def _p(self, params: Mapping | None, key: str) -> list[float]:
        """The parameter vector; only the parameters that function `key` uses must be given."""
        if not self.params:
            return []
        by_name = {str(k): v for k, v in dict(params or {}).items()}
        used = self.functions[key].params_used
        missing = [str(s) for k, s in enumerate(self.params) if k in used and str(s) not in by_name]
        if missing:
            raise ModelError(f"values missing for the parameters {missing}")
        return [float(by_name.get(str(s), np.nan)) for s in self.params]

    def call(self, key: str, q, u=None, ud=None, params=None) -> np.ndarray:
        """Evaluate generated function `key` at q, u, u̇ (one state, or N states along axis 0)."""
        f = self.functions[key]
        return _call(f.function, f.shape, self.nq, self.nv, q, u, ud, self._p(params, key))

    def M(self, q, params=None) -> np.ndarray:
        return self.call("M", q, params=params)

    def b(self, q, u, params=None) -> np.ndarray:
        return self.call("b", q, u, params=params)[..., 0]

    def g(self, q, params=None) -> np.ndarray:
        return self.call("g", q, params=params)[..., 0]

    def tau(self, q, u, params=None) -> np.ndarray:
        """Generalized forces of all loads."""
        return self.call("tau", q, u, params=params)[..., 0]

    def T(self, q, u, params=None):
        return self.call("T", q, u, params=params)[..., 0, 0]

    def U(self, q, params=None):
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
            raise ModelError(f"unknown load {load!r}; loads are {self.eom.load_names}")
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
        out = {}
        for joint in self._free_cut("reactions", None):
            self._function(key := f"R:{joint}", lambda: self._free_cut("reactions", joint))
            W = self.call(key, q, u, ud, params)[..., 0]
            out[joint] = (W[..., :3], W[..., 3:])
        return out

    def _free_cut(self, key: str, joint: str | None):
        results = self.eom._free_cut_result(key)
        if joint is not None and joint not in results:
            raise ModelError(f"unknown joint {joint!r}; joints are {sorted(results)}")
        return results[joint] if joint is not None else results

    def forward_dynamics(self, q, u, tau_a=None, params=None) -> np.ndarray:
        """u̇ = M⁻¹ (τ + Sᵀ τ_a − b − g), solved numerically."""
        rhs = self.tau(q, u, params) - self.b(q, u, params) - self.g(q, params)
        if tau_a is not None:
            S = np.array(self.eom.S.tolist(), dtype=float).reshape(-1, self.nv)
            rhs = rhs + np.asarray(tau_a, float) @ S
        return np.linalg.solve(self.M(q, params), rhs[..., None])[..., 0]


def codegen(eom: EquationsOfMotion, backend: str = "numpy") -> NumericEoM:
    """Numeric functions of `eom` (backend "numpy")."""
    if backend not in BACKENDS:
        raise ModelError(f"unknown backend {backend!r}; available: {list(BACKENDS)}")
    return NumericEoM(eom)


from .module import module_source, write_module  # noqa: E402  (module builds on NumericEoM)
