"""Base parameters: the independent combinations of the parameters π that the torques determine.

Y(q, u, u̇), stacked over K states (rows: K·nv), has rank b < p: some columns are combinations of
others. QR with column pivoting of the column-normalised stack, Y D⁻¹ P = Q [[R₁₁, R₁₂], [0, R₂₂]],
puts b independent columns first (|R₁₁| diagonal above the tolerance) and gives the dependent ones as
Y₂ = Y₁ D₁⁻¹ R₁₁⁻¹ R₁₂ D₂, so that

    Y π = Y₁ π₁ + Y₂ π₂ = Y_b β,    Y_b = Y P_b (the independent columns),    β = π₁ + K_d π₂.

The rank tolerance is relative, τ = 10⁻⁹ |R₁₁|₁ (|R₁₁|₁ the largest diagonal entry of R, the columns
normalised to unit length so that the parameters' units do not matter): a column independent of the
others by less than that is taken as dependent. LAPACK's rule for a numerical rank, max(K·nv, p) · ε,
would count the rounding of a file's numbers as rank (URDF angles are rounded to about 10⁻¹², which
makes a nominally parallel axis independent by that much). Before the split, a column whose norm is at
most τ/|R₁₁|₁ times the largest column norm is taken as zero: a parameter that does not act, its column
rounding errors (normalised, they would look independent). `tolerance` sets the relative τ/|R₁₁|₁
instead. A gap of less than GAP between the smallest kept |R_kk| and the largest dropped one (or τ) is
warned: the rank is then unclear."""
from __future__ import annotations

import warnings
from collections.abc import Sequence
from dataclasses import dataclass, replace

import numpy as np

from ..errors import ModelError
from .data import stack
from .grouping import Grouping, group
from .model import ModelRegressor, resolve

DROPPED = 1e-10  # coefficients of the combinations' text below this magnitude are left out
TOLERANCE = 1e-9  # the default relative rank tolerance
GAP = 1e3  # the smallest kept |R_kk| over the largest dropped one (or the tolerance) below this: warned


@dataclass(frozen=True)
class BaseParameters:
    """The base parameters β = map · π of the parameters `parameters`."""

    names: tuple[str, ...]  # β's names: each its independent column's parameter
    parameters: tuple[str, ...]  # π's names, all p of them
    columns: tuple[int, ...]  # the independent columns of Y, β's order: Y_b = Y[..., columns]
    map: np.ndarray  # (b, p): β = map · π
    tolerance: float  # the relative rank tolerance used on |diag R| / |R₁₁|
    diagonal: np.ndarray  # |diag R| / |R₁₁| of the pivoted QR, all min(rows, p) of it (the rank gap)
    grouping: Grouping | None = None  # a model's base parameters in its symbols (`base_parameters`)
    note: str = ""  # why `grouping` is None for a model

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


def base_parameters(regressor, q=None, u=None, ud=None, *, names: Sequence[str] | None = None,
                    tolerance: float | None = None, states: int | None = None,
                    seed: int = 0) -> BaseParameters:
    """The base parameters of `regressor` (a System, EquationsOfMotion, `eg.regressor(...)`, or a
    callable Y(q, u, u̇) → (nv, p) with column `names`) from the states (q, u, u̇) (K·nv well above p: a
    few times p rows; a model's own random states by default, `states` of them, `seed`), see the module's
    text. For a model, `grouping` holds the base parameters in the model's symbols where its structure
    gives them all (`identification.grouping`), else None and `note` says why."""
    regressor, names = resolve(regressor, names)
    if q is None and isinstance(regressor, ModelRegressor):
        q, u, ud = regressor.states(states or max(50, -(-4 * len(names) // len(regressor.system.u))), seed)
    Y = stack(regressor, names, q, u, ud)
    W = Y.reshape(-1, len(names))
    if W.shape[0] < W.shape[1]:
        raise ModelError(f"base_parameters: {len(Y)} states give {W.shape[0]} rows for {W.shape[1]} "
                         "parameters; give more states (rows: a few times the parameters)")
    base = _base(W, names, tolerance)
    if isinstance(regressor, ModelRegressor):
        base = replace(base, **structural(regressor, W, base))
    return base


def structural(regressor: ModelRegressor, W: np.ndarray, base: BaseParameters) -> dict:
    """{grouping, note}: the structural grouping restricted to the columns that act (as `_base` finds
    them), when it has the numerical rank and Y = Y_R K holds on W."""
    G = group(regressor.symbolic)
    K = np.array(G.K.xreplace(regressor.values).tolist(), dtype=float)
    scale = np.linalg.norm(W, axis=0)
    if np.abs(W - W[:, G.columns] @ K).max() > 1e-9 * max(1.0, np.abs(W).max()):
        return {"grouping": None, "note": "the structural rules do not hold for this model"}
    acting = scale[G.columns] > base.tolerance * scale.max()
    G = G.restrict(acting)
    if len(G.names) != base.rank or np.linalg.matrix_rank(W[:, G.columns]) != base.rank:
        return {"grouping": None, "note": f"the structure leaves {len(G.names)} parameters for a rank of "
                                          f"{base.rank}: dependencies beyond the grouping rules"}
    return {"grouping": G, "note": ""}


def _base(W: np.ndarray, names: tuple[str, ...], tolerance: float | None) -> BaseParameters:
    """The pivoted QR split of the stacked regressor W (rows × p)."""
    p = W.shape[1]
    tol = TOLERANCE if tolerance is None else float(tolerance)
    if not 0 < tol < 1:
        raise ModelError(f"base_parameters: argument 'tolerance' must be in (0, 1), got {tolerance!r}")
    scale = np.linalg.norm(W, axis=0)
    if scale.max() == 0:
        raise ModelError("base_parameters: the regressor is zero at every state given")
    zero = scale <= tol * scale.max()  # a parameter that never acts (its column rounding errors at most)
    W, scale[zero] = np.where(zero, 0.0, W), 1.0
    import scipy.linalg

    _, R, pivots = scipy.linalg.qr(W / scale, mode="economic", pivoting=True)
    diagonal = np.abs(np.diag(R)) / abs(R[0, 0])
    b = int(np.sum(diagonal > tol))
    dropped = diagonal[b] if b < len(diagonal) else 0.0
    if diagonal[b - 1] < GAP * max(dropped, tol):
        warnings.warn(f"base_parameters: no clear rank gap: the smallest independent column's |R_kk| is "
                      f"{diagonal[b - 1]:.1e} of |R_11|, the largest dependent one's {dropped:.1e} (the "
                      f"tolerance {tol:.0e}); see BaseParameters.diagonal and set `tolerance`", stacklevel=3)
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
