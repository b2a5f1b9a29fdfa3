"""L1: the frozen description of a mechanism (names, connectivity, sketch, dimensions, drivers)."""
from .gearing import GearLaw, GearPair
from .making import MakeSpec
from .mechanism import (Actuator, BranchHint, Gait, Joint, LinearDriver, Link, Mechanism, Placement,
                        Prismatic, RotaryDriver, Units)

__all__ = ["Actuator", "BranchHint", "Gait", "GearLaw", "GearPair", "Joint", "LinearDriver", "Link", "MakeSpec", "Mechanism", "Placement",
           "Prismatic", "RotaryDriver", "Units"]
