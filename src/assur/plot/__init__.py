"""Figures and animations of mechanisms (matplotlib, imported lazily; the "Agg" backend).

draw.py draws a planar mechanism on axes; figures.py the figures of a solved run (:class:`Sweep`);
quick.py the one-line ``mechanism(plan)``; animation.py the animations and their files; spatial.py the 3D
views; gears.py and actuators.py the figures of gear pairs and of linear actuators.
"""
from __future__ import annotations

from ..analysis.sampling import sweep_inputs, tracked_point
from .animation import animation, save_animation
from .draw import draw_mechanism, frame_guides
from .figures import Sweep, mechanism_figure, sample, timeline_figure
from .quick import mechanism

__all__ = ["Sweep", "animation", "draw_mechanism", "frame_guides", "mechanism", "mechanism_figure", "sample",
           "save_animation", "sweep_inputs", "timeline_figure", "tracked_point"]
