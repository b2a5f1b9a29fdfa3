"""Figures of mechanisms (matplotlib, imported lazily; the "Agg" backend)."""
from __future__ import annotations

from .figures import (Sweep, animation, draw_mechanism, frame_guides, mechanism_figure, sample, save_animation,
                      sweep_inputs, timeline_figure, tracked_point)

__all__ = ["Sweep", "animation", "draw_mechanism", "frame_guides", "mechanism_figure", "sample", "save_animation",
           "sweep_inputs", "timeline_figure", "tracked_point"]
