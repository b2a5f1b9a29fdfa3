"""The closed-form placement of a path-synthesis design (:mod:`assur.synthesis.placement`): one function that the
numpy route calls on arrays and the compiled kernels' helper (:func:`assur.kernels.reductions.similarity_fit`) compiles
for scalars. numpy only, so it imports without numba."""
from __future__ import annotations

import numpy as np


def similarity(qx, qy, tx, ty, A, C, D, lim, rotate):
    """The best placement from the centred sums (:mod:`assur.synthesis.placement`): the centroids (qx, qy), (tx, ty) of the
    assembled targets, A, C, D, the limits ``lim`` (6 values or rows: s interval, x bounds, y bounds), ``rotate``
    (1.0: turn, 0.0: keep the angle). Returns (s, φ, dx, dy). Elementwise arithmetic only (no branch), so the same
    lines serve arrays (the numpy route) and scalars (compiled into the kernels' helper,
    :func:`assur.kernels.reductions.similarity_fit`). Where no positive size improves on none (A = 0: fewer than two
    assembled targets; or, without the turn, D ≤ 0: the shape fits best mirrored, and the fit would shrink it to a
    point), the size stays as proposed (s = 1, clipped)."""
    phi = np.arctan2(C, D) * rotate
    along = rotate * np.hypot(C, D) + (1.0 - rotate) * D
    fits = (A > 0.0) * (along > 0.0) * 1.0
    s = fits * along / (A + (1.0 - fits)) + (1.0 - fits)
    s = np.minimum(np.maximum(s, lim[0]), lim[1])
    cphi, sphi = np.cos(phi), np.sin(phi)
    dx = np.minimum(np.maximum(tx - s * (cphi * qx - sphi * qy), lim[2]), lim[3])
    dy = np.minimum(np.maximum(ty - s * (sphi * qx + cphi * qy), lim[4]), lim[5])
    return s, phi, dx, dy


__all__ = ["similarity"]
