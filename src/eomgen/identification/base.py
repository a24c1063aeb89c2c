"""Base parameters: the independent combinations of the parameters π that the torques determine.

Y(q, u, u̇), stacked over K states (rows: K·nv), has rank b < p: some columns are combinations of
others. QR with column pivoting of the column-normalised stack, Y D⁻¹ P = Q [[R₁₁, R₁₂], [0, R₂₂]],
puts b independent columns first (|R₁₁| diagonal above the tolerance) and gives the dependent ones as
Y₂ = Y₁ D₁⁻¹ R₁₁⁻¹ R₁₂ D₂, so that

    Y π = Y₁ π₁ + Y₂ π₂ = Y_b β,    Y_b = Y P_b (the independent columns),    β = π₁ + K_d π₂.

The rank tolerance is LAPACK's rule for a numerical rank, τ = max(K·nv, p) · ε · |R₁₁|₁ (ε the
double precision, |R₁₁|₁ the largest diagonal entry of R, the columns normalised to unit length so
that the parameters' units do not matter). Before that, a column whose norm is at most τ/|R₁₁|₁ times
the largest column norm is taken as zero: a parameter that does not act, its column rounding errors
(normalised, they would look independent). `tolerance` sets the relative τ/|R₁₁|₁ instead."""
from __future__ import annotations

import warnings
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
import scipy.linalg

from ..errors import ModelError
from .data import Regressor, checked_names, stack

DROPPED = 1e-10  # coefficients of the combinations' text below this magnitude are left out
GAP = 1e-9  # an independent column's relative |R_kk| below this: warned, the rank may be rounding errors


@dataclass(frozen=True)
class BaseParameters:
    """The base parameters β = map · π of the parameters `parameters`."""

    names: tuple[str, ...]  # β's names: each its independent column's parameter
    parameters: tuple[str, ...]  # π's names, all p of them
    columns: tuple[int, ...]  # the independent columns of Y, β's order: Y_b = Y[..., columns]
    map: np.ndarray  # (b, p): β = map · π
    tolerance: float  # the relative rank tolerance used on |diag R| / |R₁₁|
    diagonal: np.ndarray  # |diag R| / |R₁₁| of the pivoted QR, all min(rows, p) of it (the rank gap)

    @property
    def rank(self) -> int:
        return len(self.columns)

    def regressor(self, Y: np.ndarray) -> np.ndarray:
        """Y_b: the independent columns of Y (..., nv, p)."""
        return np.asarray(Y)[..., list(self.columns)]

    def of(self, pi) -> np.ndarray:
        """β = map · π."""
        pi = np.asarray(pi, dtype=float)
        if pi.shape != (len(self.parameters),):
            raise ModelError(f"argument 'pi' must have {len(self.parameters)} entries, got shape {pi.shape}")
        return self.map @ pi

    def combinations(self, digits: int = 6) -> list[str]:
        """Each β as text, e.g. "I_zz_2 + 0.18 m_3 - 0.4 mc_x_3" (coefficients rounded to `digits`
        significant digits, those below 1e-10 left out)."""
        return [_text(row, self.parameters, digits) for row in self.map]

    def __str__(self) -> str:
        return "\n".join(f"{n} := {c}" for n, c in zip(self.names, self.combinations()))


def base_parameters(regressor: Regressor, names: Sequence[str], q, u, ud,
                    tolerance: float | None = None) -> BaseParameters:
    """The base parameters of `regressor` (Y(q, u, u̇) → (nv, p), columns `names`) from the states
    (q, u, u̇) (random states, K·nv well above p: a few times p rows), see the module's text."""
    names = checked_names(names)
    Y = stack(regressor, names, q, u, ud)
    W = Y.reshape(-1, len(names))
    if W.shape[0] < W.shape[1]:
        raise ModelError(f"base_parameters: {len(Y)} states give {W.shape[0]} rows for {W.shape[1]} "
                         "parameters; give more states (rows: a few times the parameters)")
    return _base(W, names, tolerance)


def _base(W: np.ndarray, names: tuple[str, ...], tolerance: float | None) -> BaseParameters:
    """The pivoted QR split of the stacked regressor W (rows × p)."""
    p = W.shape[1]
    tol = max(W.shape) * np.finfo(float).eps if tolerance is None else float(tolerance)
    if not 0 < tol < 1:
        raise ModelError(f"base_parameters: argument 'tolerance' must be in (0, 1), got {tolerance!r}")
    scale = np.linalg.norm(W, axis=0)
    if scale.max() == 0:
        raise ModelError("base_parameters: the regressor is zero at every state given")
    zero = scale <= tol * scale.max()  # a parameter that never acts (its column rounding errors at most)
    W, scale[zero] = np.where(zero, 0.0, W), 1.0
    _, R, pivots = scipy.linalg.qr(W / scale, mode="economic", pivoting=True)
    diagonal = np.abs(np.diag(R)) / abs(R[0, 0])
    b = int(np.sum(diagonal > tol))
    if diagonal[b - 1] < GAP:
        warnings.warn(f"base_parameters: no clear rank gap: the smallest independent column's |R_kk| is "
                      f"{diagonal[b - 1]:.1e} of |R_11| (rounding errors may count as rank); see "
                      "BaseParameters.diagonal and set `tolerance`", stacklevel=3)
    independent, dependent = pivots[:b], pivots[b:]
    K = scipy.linalg.solve_triangular(R[:b, :b], R[:b, b:])  # scaled: Y₂ D₂⁻¹ = Y₁ D₁⁻¹ K
    full = np.zeros((b, p))
    full[np.arange(b), independent] = 1.0
    full[:, dependent] = K * scale[dependent] / scale[independent, None]
    order = np.argsort(independent)  # β in the parameters' own order
    return BaseParameters(names=tuple(names[i] for i in independent[order]), parameters=names,
                          columns=tuple(int(i) for i in independent[order]), map=full[order],
                          tolerance=tol, diagonal=diagonal)


def _text(row: np.ndarray, names: tuple[str, ...], digits: int) -> str:
    terms = []
    for c, name in zip(row, names):
        if abs(c) < DROPPED:
            continue
        value = f"{abs(c):.{digits}g}"
        term = name if value == "1" else f"{value} {name}"
        terms.append(("- " if c < 0 else "+ ") + term)
    if not terms:
        return "0"
    text = " ".join(terms)
    return text[2:] if text.startswith("+ ") else "-" + text[2:]
