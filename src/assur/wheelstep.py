"""Deprecated: the wheel-step mover of paper 001 is :mod:`assur.gears.wheelstep`.

Kept for one release so that ``from assur.wheelstep import Shoe`` keeps working; importing it warns with a
``DeprecationWarning`` naming the new place.
"""
import warnings

from .gears.wheelstep import STEP_HALF_ANGLE, DisplacementBudget, Shoe, bar_length_for

warnings.warn("assur.wheelstep is deprecated: import from assur.gears.wheelstep (Shoe, DisplacementBudget, "
              "bar_length_for, STEP_HALF_ANGLE)", DeprecationWarning, stacklevel=2)

__all__ = ["STEP_HALF_ANGLE", "DisplacementBudget", "Shoe", "bar_length_for"]
