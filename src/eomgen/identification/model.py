"""The regressor of an eomgen model as numbers: `eg.regressor`'s columns of the generated
`f.regressor(q, u, u̇)` (every backend prints it), with its names, the model's π and random states, so
that the identification functions take a `System`, its `EquationsOfMotion` or an `eg.regressor(...)`
where they take a regressor callable."""
from __future__ import annotations

from collections.abc import Mapping, Sequence

import numpy as np
import sympy as sp

from ..eom import EquationsOfMotion
from ..errors import ModelError
from ..model import System
from ..numeric.codegen import codegen
from ..regressor import FRICTION, Regressor, links, regressor
from ..state import random_states
from .data import checked_names


class ModelRegressor:
    """Y(q, u, u̇) → (nv, p) or (N, nv, p) of a `Regressor`'s columns, from generated code (`backend`,
    `params` bound: {name: value} for every symbol of the model)."""

    def __init__(self, symbolic: Regressor, params: Mapping | None = None, backend: str = "numpy") -> None:
        self.symbolic, self.names = symbolic, symbolic.names
        self.system = symbolic.equations.system
        self.values = {s: params[s.name] for s in self.system.parameters if params and s.name in params}
        unbound = sorted(str(s) for s in self.system.parameters if s not in self.values)
        if unbound:
            raise ModelError(f"the regressor's model has symbols without values: {unbound}; give them: "
                             "identification.numeric_regressor(model, params={name: value, ...})")
        self.functions = codegen(symbolic.equations, backend=backend, params=params or None)
        self.columns = list(symbolic.columns)

    def __call__(self, q, u, ud) -> np.ndarray:
        return np.asarray(self.functions.regressor(q, u, ud))[..., self.columns]

    @property
    def pi(self) -> np.ndarray:
        """The model's π in numbers (friction 0: the model has none)."""
        return np.array([float(sp.sympify(x).xreplace(self.values)) for x in self.symbolic.pi], float)

    @property
    def bodies(self) -> int:
        """The links, ten parameters each, first in π."""
        return len(links(self.system))

    @property
    def nonnegative(self) -> list[str]:
        """The armatures and the viscous and Coulomb friction coefficients."""
        kinds = ("Ia", FRICTION["viscous"], FRICTION["coulomb"])
        return [n for n in self.names if n.split("_")[0] in kinds]

    def states(self, n: int, seed: int = 0) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """n random states (q, u, u̇) of the model (`eg.random_states`)."""
        return random_states(self.system, n, np.random.default_rng(seed))


def numeric_regressor(model, params: Mapping | None = None, backend: str = "numpy") -> ModelRegressor:
    """The numeric regressor of a System or EquationsOfMotion (all columns of `eg.regressor`'s defaults)
    or of an `eg.regressor(...)`."""
    if isinstance(model, (System, EquationsOfMotion)):
        model = regressor(model)
    if not isinstance(model, Regressor):
        raise ModelError(f"numeric_regressor: expected a System, EquationsOfMotion or eg.regressor(...), got "
                         f"{type(model).__name__}")
    return ModelRegressor(model, params, backend)


def resolve(regressor_, names: Sequence[str] | None) -> tuple:
    """(the regressor callable, its names): a model becomes its `ModelRegressor`; names default to the
    regressor's own (`.names`)."""
    if isinstance(regressor_, (System, EquationsOfMotion, Regressor)):
        regressor_ = numeric_regressor(regressor_)
    if not callable(regressor_):
        raise ModelError("argument 'regressor' must be a System, EquationsOfMotion, eg.regressor(...) or a "
                         f"callable Y(q, u, ud), got {type(regressor_).__name__}")
    names = getattr(regressor_, "names", None) if names is None else names
    if names is None:
        raise ModelError("argument 'names' is needed with a regressor callable: one name per column")
    return regressor_, checked_names(names)
