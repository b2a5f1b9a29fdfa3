"""Local coordinates of every body's points and every slide line, from the parameters.

The plan's ``geometry_program`` says, per body, how its points' local coordinates follow from the
design parameters: frame points are parameters; a link's first point is its origin, its second lies
on its local x axis at ``length``, further points at (distance, angle) from an origin toward a
second point; a block, cylinder or rod has its one point at its origin.
"""
from __future__ import annotations

import numpy as np


def geometry(plan, params: np.ndarray):
    """Local coordinates of every body's points and every slide line, from ``params (..., n_params)``.

    Returns ``(w, lines)``: ``w[(body, point)]`` complex arrays of shape ``params.shape[:-1]`` and
    ``lines[i] = (q, u, ref, u_slider)``: the line point and unit direction in the guide's frame,
    the slider's reference point and the line direction in the slider's frame. A non-physical
    design (a link length ≤ 0, a negative placement distance) gives NaN coordinates, so every sample
    of it is unbuildable: never a mirrored answer.
    """
    p = params
    shape = p.shape[:-1]
    zero = np.zeros(shape, dtype=complex)
    w: dict[tuple[int, str], np.ndarray] = {}
    for bi, rec in enumerate(plan.geometry_program):
        if rec[0] == "frame":
            for name, ix, iy in rec[1]:
                w[(bi, name)] = p[..., ix] + 1j * p[..., iy]
        elif rec[0] == "point":
            w[(bi, rec[1])] = zero
        else:
            _, p0, p1, il, placed = rec
            w[(bi, p0)] = zero
            length = p[..., il]
            w[(bi, p1)] = np.where(length > 0, length, np.nan) + 0j
            for name, org, tow, idist, iang in placed:
                a, b = w[(bi, org)], w[(bi, tow)]
                d = b - a
                n = np.abs(d)
                dist = p[..., idist]
                dist = np.where(dist >= 0, dist, np.nan)
                w[(bi, name)] = a + dist * np.exp(1j * p[..., iang]) * (d / np.where(n > 0, n, 1.0))
    lines = []
    for rec in plan.lines:
        kind, name, gb, slider, through, ia, io, ref, u_slider = rec
        if kind == "actuator":
            lines.append((zero, 1 + 0j, zero, 1 + 0j))
            continue
        u = np.exp(1j * p[..., ia])
        q = w[(gb, through)] + 1j * u * p[..., io]
        lines.append((q, u, w[(slider, ref)], u_slider))
    return w, lines
