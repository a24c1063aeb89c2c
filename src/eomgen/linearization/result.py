"""The result of `eg.linearize`: A, B, the names of the states and inputs and the operating point."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import sympy as sp

from ..errors import ModelError


@dataclass(frozen=True)
class Linearization:
    """ẋ ≈ xdot0 + A (x − x0) + B (r − r0) about an operating point: `states` name the entries of x (the
    independent coordinates, `delta_<speed>` for a tangent coordinate of a quaternion or planar joint,
    then the independent speeds, then the motor currents), `inputs` those of r. NumPy arrays, or sympy
    matrices when symbolic. xdot0 = 0 at an equilibrium; a steady motion (u0 ≠ 0) has the coordinates'
    rates in it."""

    A: np.ndarray | sp.Matrix
    B: np.ndarray | sp.Matrix
    states: tuple[str, ...]
    inputs: tuple[str, ...]
    x0: np.ndarray | sp.Matrix
    r0: np.ndarray | sp.Matrix
    xdot0: np.ndarray | sp.Matrix

    def index(self, names) -> list[int]:
        """The positions of states in x, by name."""
        names = [names] if isinstance(names, str) else list(names)
        unknown = [x for x in names if x not in self.states]
        if unknown:
            raise ModelError(f"Linearization: unknown states {unknown}; the states are {list(self.states)}")
        return [self.states.index(x) for x in names]

    def select(self, states, inputs=None) -> Linearization:
        """The rows and columns of some states (and of some inputs; default all): the linearization of a
        subsystem, exact when the other states do not drive these (A block triangular)."""
        i = self.index(states)
        inputs = self.inputs if inputs is None else [inputs] if isinstance(inputs, str) else list(inputs)
        unknown = [x for x in inputs if x not in self.inputs]
        if unknown:
            raise ModelError(f"Linearization: unknown inputs {unknown}; the inputs are {list(self.inputs)}")
        k = [self.inputs.index(x) for x in inputs]
        if isinstance(self.A, sp.MatrixBase):
            part = lambda X, r, c=(0,): X.extract(r, list(c))  # noqa: E731
        else:
            part = lambda X, r, c=None: X[np.ix_(r, c)] if c is not None else X[r]  # noqa: E731
        return Linearization(
            part(self.A, i, i),
            part(self.B, i, k),
            tuple(self.states[j] for j in i),
            tuple(inputs),
            part(self.x0, i),
            part(self.r0, k),
            part(self.xdot0, i),
        )

    def eigenvalues(self) -> np.ndarray:
        """The eigenvalues of A, sorted (numpy.sort_complex); numbers only."""
        try:
            A = np.array(self.A.tolist() if isinstance(self.A, sp.MatrixBase) else self.A, dtype=float)
        except TypeError:
            raise ModelError(
                "Linearization: A has symbols: substitute numbers for its eigenvalues"
            ) from None
        return np.sort_complex(np.linalg.eigvals(A))
