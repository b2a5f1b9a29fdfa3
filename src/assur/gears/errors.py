"""Errors of the gear package, and the helper that names offending angle ranges in messages."""
from __future__ import annotations

import math

import numpy as np

from ..errors import AssurError


class GearError(AssurError, ValueError):
    """A transmission law, centre distance or tooth layout cannot make a working gear pair.

    The message names the quantity and the offending angle range, e.g.
    ``pitch radius of the driven gear ≤ 0 for φ ∈ [212.0°, 236.5°]``."""


def angle_ranges(angles, bad, *, max_ranges: int = 4) -> str:
    """The runs of ``bad`` samples as text ``"[a°, b°], [c°, d°]"``.

    angles: (N,) increasing sample angles (rad); bad: (N,) bool. At most ``max_ranges`` runs are listed."""
    angles = np.asarray(angles, dtype=float)
    bad = np.asarray(bad, dtype=bool)
    idx = np.flatnonzero(bad)
    if idx.size == 0:
        return ""
    breaks = np.flatnonzero(np.diff(idx) > 1)
    starts = np.concatenate([[idx[0]], idx[breaks + 1]])
    ends = np.concatenate([idx[breaks], [idx[-1]]])
    parts = [f"[{math.degrees(angles[s]):.1f}°, {math.degrees(angles[e]):.1f}°]"
             for s, e in zip(starts[:max_ranges], ends[:max_ranges])]
    if len(starts) > max_ranges:
        parts.append(f"and {len(starts) - max_ranges} more")
    return ", ".join(parts)
