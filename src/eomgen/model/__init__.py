"""What the system is: bodies, joints, frames, loads. Building a model computes nothing."""
from .dh import DHLink, from_dh
from .joints import Fixed, FlexibleLink, FreeFlyer, Joint, Placement, Prismatic, Revolute
from .loads import Actuator, Damper, Force, Point, Spring, Torque
from .system import Body, Frame, System
from . import robots
from .urdf import from_pinocchio, from_urdf, pinocchio_configuration

__all__ = ["Actuator", "Body", "Damper", "Fixed", "FlexibleLink", "Force", "FreeFlyer", "Frame", "Joint", "Placement", "Point",
           "Prismatic", "Revolute", "Spring", "System", "Torque", "from_pinocchio", "from_urdf",
           "pinocchio_configuration"]
