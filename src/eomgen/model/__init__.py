"""What the system is: bodies, joints, frames, loads. Building a model computes nothing."""
from .dh import DHLink, from_dh
from .flexible_link import FlexibleLink
from .free_flyer import FreeFlyer
from .joints import Fixed, Joint, Placement, Prismatic, Revolute
from .multi_axis import Cylindrical, Helical, Planar, Translation, Universal
from .spherical import Spherical
from .loads import Actuator, Damper, Force, Point, Spring, Torque
from .system import Body, Frame, System
from . import robots
from .urdf import from_pinocchio, from_urdf, pinocchio_configuration
from .mjcf import from_mjcf

__all__ = ["Actuator", "Body", "Cylindrical", "DHLink", "Damper", "Fixed", "FlexibleLink", "Force", "FreeFlyer", "Frame",
           "Helical", "Joint", "Placement", "Planar", "Point", "Prismatic", "Revolute", "Spherical", "Spring",
           "System", "Torque", "Translation", "Universal", "from_dh", "from_mjcf", "from_pinocchio", "from_urdf",
           "pinocchio_configuration"]
