"""Dynamic identification from measured motion: τ = Y(q, u, u̇) π, π the inertial parameters (ten per
body in Pinocchio's order, then armature and friction), Y a regressor callable with one name per column.

- `base_parameters`: the identifiable combinations β (pivoted QR on random states);
- `identify`: weighted least squares for β with its standard deviations and condition number;
- `identify_consistent`: π with every body's pseudo-inertia ⪰ 0 (cvxpy, the extra `identification`);
- `excite`: a Fourier excitation trajectory within joint limits, optimised for cond(Y_b);
- `group`: the base parameters as sympy expressions in the user's symbols, from the tree's structure;
- `numeric_regressor`: an eomgen model's regressor as numbers (each function above takes a System, its
  EquationsOfMotion or `eg.regressor(...)` where it takes a regressor callable)."""
from .base import BaseParameters, base_parameters
from .consistent import ConsistentIdentification, identify_consistent
from .excitation import Excitation, condition, excite
from .fourier import Fourier, random_fourier
from .grouping import Grouping, group
from .least_squares import Identification, identify
from .model import ModelRegressor, numeric_regressor
from .pseudo_inertia import pseudo_inertia, smallest_eigenvalues

__all__ = ["base_parameters", "BaseParameters", "condition", "ConsistentIdentification", "Excitation",
           "excite", "Fourier", "group", "Grouping", "Identification", "identify",
           "identify_consistent", "ModelRegressor", "numeric_regressor", "pseudo_inertia",
           "random_fourier", "smallest_eigenvalues"]
