"""Numeric functions from the equations of motion."""
from __future__ import annotations

import re
from collections.abc import Mapping

import numpy as np
import sympy as sp

from ..eom import EquationsOfMotion
from ..errors import ModelError
from .numpy_backend import FunctionWriter, compile_function

BACKENDS = ("numpy",)


class NumericEoM:
    """Numeric M(q), b(q, u), g(q), tau(q, u), T(q, u), U(q) and forward dynamics of one
    `EquationsOfMotion`. Symbolic parameters (see `params`) are given as a mapping from the
    symbol or its name to a value in each call."""

    def __init__(self, eom: EquationsOfMotion) -> None:
        self.eom = eom
        self.nq = len(eom.q)
        self.params = sorted(eom.system.parameters, key=str)
        inputs = {"q": list(eom.q), "u": list(eom.u), "p": self.params}
        self._writer = writer = FunctionWriter(eom.subexpressions, inputs)
        self.sources: dict[str, str] = {}
        self._functions = {}
        tau = sp.zeros(self.nq, 1)
        for name in eom.load_names:
            tau += eom.compact[f"tau:{name}"]
        for name, expr in [("M", eom.compact["M"]), ("b", eom.compact["b"]), ("g", eom.compact["g"]),
                           ("tau", tau), ("T", eom.compact["T"]), ("U", eom.compact["U"])]:
            self.sources[name] = writer.source(name, expr)
            self._functions[name] = compile_function(self.sources[name], name)

    def _p(self, params: Mapping | None, key: str) -> np.ndarray:
        """The parameter vector; only the parameters that function `key` uses must be given."""
        by_name = {str(k): v for k, v in dict(params or {}).items()}
        used = {int(k) for k in re.findall(r"\b_p(\d+) =", self.sources[key])}
        missing = [str(s) for k, s in enumerate(self.params) if k in used and str(s) not in by_name]
        if missing:
            raise ModelError(f"values missing for the parameters {missing}")
        return np.array([float(by_name.get(str(s), np.nan)) for s in self.params])

    def _state(self, x, name: str) -> np.ndarray:
        x = np.asarray(x, dtype=float)
        if x.shape != (self.nq,):
            raise ValueError(f"{name}: expected shape ({self.nq},), got {x.shape}")
        if not np.all(np.isfinite(x)):
            raise ValueError(f"{name}: contains NaN or infinite values")
        return x

    def _call(self, name: str, q, u=None, params=None):
        u = np.zeros(self.nq) if u is None else self._state(u, "u")
        return self._functions[name](self._state(q, "q"), u, self._p(params, name))

    def M(self, q, params=None) -> np.ndarray:
        return self._call("M", q, None, params)

    def b(self, q, u, params=None) -> np.ndarray:
        return self._call("b", q, u, params)[:, 0]

    def g(self, q, params=None) -> np.ndarray:
        return self._call("g", q, None, params)[:, 0]

    def tau(self, q, u, params=None) -> np.ndarray:
        """Generalized forces of all loads."""
        return self._call("tau", q, u, params)[:, 0]

    def T(self, q, u, params=None) -> float:
        return float(self._call("T", q, u, params))

    def U(self, q, params=None) -> float:
        return float(self._call("U", q, None, params))

    def _lazy(self, key: str, build):
        """A function generated on first request (a frame's Jacobian, one load's τ)."""
        if key not in self._functions:
            self.sources[key] = self._writer.source("f", build())
            self._functions[key] = compile_function(self.sources[key], "f")
        return self._functions[key]

    def jacobian(self, frame: str, q, params=None) -> np.ndarray:
        """6 × n Jacobian [J_P; J_R] of a frame or body origin, world-aligned axes."""
        f = self._lazy(key := f"J:{frame}", lambda: self.eom.kinematics.jacobian(frame))
        return f(self._state(q, "q"), np.zeros(self.nq), self._p(params, key))

    def jacobian_dot_u(self, frame: str, q, u, params=None) -> np.ndarray:
        """J̇ u (6-vector, [linear; angular]) of a frame or body origin."""
        f = self._lazy(key := f"Jdot_u:{frame}", lambda: self.eom.kinematics.jacobian_dot_u(frame))
        return f(self._state(q, "q"), self._state(u, "u"), self._p(params, key))[:, 0]

    def tau_of(self, load: str, q, u, params=None) -> np.ndarray:
        """Generalized force of one load, by name."""
        if load not in self.eom.load_names:
            raise ModelError(f"unknown load {load!r}; loads are {self.eom.load_names}")
        f = self._lazy(key := f"tau:{load}", lambda: self.eom.compact[f"tau:{load}"])
        return f(self._state(q, "q"), self._state(u, "u"), self._p(params, key))[:, 0]

    def forward_dynamics(self, q, u, tau_a=None, params=None) -> np.ndarray:
        """u̇ = M⁻¹ (τ + Sᵀ τ_a − b − g), solved numerically."""
        rhs = self.tau(q, u, params) - self.b(q, u, params) - self.g(q, params)
        if tau_a is not None:
            rhs += np.asarray(sp.matrix2numpy(self.eom.S.T, dtype=float) @ np.asarray(tau_a, float))
        return np.linalg.solve(self.M(q, params), rhs)


def codegen(eom: EquationsOfMotion, backend: str = "numpy") -> NumericEoM:
    """Numeric functions of `eom` (backend "numpy")."""
    if backend not in BACKENDS:
        raise ModelError(f"unknown backend {backend!r}; available: {list(BACKENDS)}")
    return NumericEoM(eom)
