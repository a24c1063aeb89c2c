"""eomgen: symbolic equations of motion of multibody systems, M(q) u̇ + b(q, u) + g(q) = τ + Sᵀ τ_a,
derived by several methods and turned into verified numeric code."""
__version__ = "0.1.0"

from .codegen import codegen, write_c, write_module
from .eom import EquationsOfMotion
from .errors import ModelError
from .kinematics import Kinematics
from .methods import derive
from .methods.kane import KaneEquations, kane
from .model.dh import DHLink, from_dh
from .model import Fixed, FlexibleLink, FreeFlyer, Placement, Prismatic, Revolute, System, from_urdf, robots
from .progress import quiet
from .simplification import simplified
from .worked import Solution, Step, solution
from .state import integrate, random_states
from .tradeoff import tradeoff
from .verify import verify

__all__ = ["EquationsOfMotion", "KaneEquations", "Fixed", "FlexibleLink", "FreeFlyer", "Kinematics",
           "ModelError", "Placement", "Prismatic", "Revolute", "Solution", "Step", "System", "codegen", "derive",
           "from_urdf", "integrate", "kane", "quiet", "random_states", "robots", "simplified", "solution",
           "tradeoff", "verify", "write_c", "write_module"]
