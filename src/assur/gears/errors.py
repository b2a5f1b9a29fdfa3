"""Errors of the gear package (:class:`GearError`, defined in :mod:`assur.errors`), and the helper that names
offending angle ranges in messages."""
from __future__ import annotations

import math

import numpy as np

from ..errors import GearError
from ..kernels.runs import runs


def angle_ranges(angles, bad, *, max_ranges: int = 4) -> str:
    """The runs of ``bad`` samples as text ``"[a°, b°], [c°, d°]"``.

    angles: (N,) increasing sample angles (rad); bad: (N,) bool. At most ``max_ranges`` runs are listed."""
    angles = np.asarray(angles, dtype=float)
    found = runs(bad)
    parts = [f"[{math.degrees(angles[s]):.1f}°, {math.degrees(angles[e]):.1f}°]" for s, e in found[:max_ranges]]
    if len(found) > max_ranges:
        parts.append(f"and {len(found) - max_ranges} more")
    return ", ".join(parts)


__all__ = ["GearError", "angle_ranges"]
