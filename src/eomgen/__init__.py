"""eomgen: symbolic equations of motion of multibody systems, M(q) u̇ + b(q, u) + g(q) = τ + Sᵀ τ_a,
derived by several methods and turned into verified numeric code."""
from .version import __version__  # noqa: F401  (re-exported)
from . import deprecated  # noqa: F401  (old module names, for one release)

from .check_answer import check_answer
from .codegen import codegen, write_c, write_module  # the package first: eg.codegen is the function
from .numeric import assemble, project, reduce
from .eom import EquationsOfMotion
from .errors import ModelError
from .kinematics import Kinematics
from .linearization import Linearization, linearize
from .methods import derive
from .methods.kane import KaneEquations, kane
from .model import (Cylindrical, DHLink, Fixed, FlexibleLink, FreeFlyer, Helical, Placement, Planar, Prismatic,
                    Revolute, Spherical, System, Translation, Universal, from_dh, from_mjcf, from_urdf,
                    robots)
from .progress import quiet
from .regressor import Regressor, regressor
from .simplification import simplified
from .worked import Solution, Step, solution
from .state import difference, integrate, random_states
from .symbols import t
from .simulate import simulate
from .sweep import sweep
from . import identification
from .identification import base_parameters, excite, identify, identify_consistent
from .plotting import plot
from .animation import animate
from .view import View, view
from .tradeoff import tradeoff
from .verify import verify

__all__ = ["EquationsOfMotion", "KaneEquations", "Cylindrical", "DHLink", "Fixed", "FlexibleLink", "FreeFlyer", "Helical",
           "Kinematics", "Linearization", "ModelError", "Placement", "Planar", "Prismatic",
           "Regressor", "Revolute",
           "Solution", "Spherical", "Step",
           "System", "Translation", "Universal", "assemble", "check_answer", "codegen",
           "derive", "from_dh", "from_mjcf",
           "from_urdf", "integrate", "kane", "linearize", "project", "quiet", "random_states", "reduce",
           "regressor", "base_parameters", "identify", "identify_consistent", "excite", "identification",
           "robots",
           "difference", "simplified", "simulate", "sweep", "plot", "animate", "solution",
           "t", "tradeoff", "verify", "view", "View", "write_c", "write_module"]
