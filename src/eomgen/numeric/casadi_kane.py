"""Kane's equations in CasADi: the pieces of `kane_catalogue` as `casadi.Function`s on SX
(`f.casadi[key]`, `casadi_functions.CasadiPrinted`); with numbers they return arrays, on which the NumPy
algorithms of `numeric.kane` compute mass_matrix, forcing, the speeds, rhs and energy."""
from __future__ import annotations

from .casadi_functions import CasadiPrinted
from .kane import NumericKane


class CasadiKane(CasadiPrinted, NumericKane):
    """`NumericKane` whose pieces are CasADi functions of (q, u, ud = w, p)."""
