"""Kinetostatics: reactions, driving torques and forces, power, by Assur groups, batched like the kinematics.

``assur.forces(plan, params, inputs, …)`` (:mod:`.api`) returns a :class:`~.result.Forces`; the sign
convention is in :mod:`.result`, the group-by-group closed forms in :mod:`.groups`.
"""
from .api import forces
from .result import Forces

__all__ = ["forces", "Forces"]
