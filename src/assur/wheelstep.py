"""The wheel-step mover of paper 001: :mod:`assur.gears.wheelstep` (re-exported here)."""
from .gears.wheelstep import STEP_HALF_ANGLE, DisplacementBudget, Shoe, bar_length_for

__all__ = ["STEP_HALF_ANGLE", "DisplacementBudget", "Shoe", "bar_length_for"]
