"""The function catalogue: every function a model offers, named once, which every target prints."""
from .catalogue import FORMS, Catalogue, Family, Function
from .equations import QUANTITIES, catalogue, expect_equations
from .kane import kane_catalogue
from .outputs import DERIVATIVES, forward_dynamics, forward_key
from .parameters import assumptions, sorted_parameters

__all__ = ["DERIVATIVES", "FORMS", "QUANTITIES", "Catalogue", "Family", "Function", "assumptions", "catalogue",
           "expect_equations", "forward_dynamics", "forward_key", "kane_catalogue", "sorted_parameters"]
