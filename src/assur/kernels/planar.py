"""Closed-form planar kernels on complex arrays or jets (batch axes first, points as complex numbers).

Every kernel returns ``(result, valid)``: samples that cannot be assembled are NaN with
``valid`` False, never finite garbage. Branch signs are explicit (+1/−1) and never chosen by
proximity to a previous sample. The kernels with a radicand take ``margins``: a list to which they
append their normalised radicand plus the tolerance (≥ 0 assembled, < 0 how far past the toggle), or
None; with margins a sample past a toggle continues at the toggle instead of NaN (:func:`_tolerant_radicand`),
its ``valid`` False all the same. The compiled kernels trace these functions (:mod:`assur.kernels.trace`):
element-wise code only.

Conventions (z = x + i·y):
- ``circle_circle``: branch +1 puts the point to the left of the directed line c1 → c2.
- ``circle_line``: branch +1 takes the intersection farther along the line's direction u.
- ``rotation_from_slide``: branch +1 puts the slider ahead of its guide along the guide line.
"""
from __future__ import annotations

import numpy as np

from .jet import Jet, abs2, cross, dot, sqrt, value


def _tolerant_radicand(rad, scale2, tol: float, margins=None):
    """Clamp tiny negative radicands (tangency within round-off) to 0; flag the rest invalid (NaN).
    Works on jets and on plain arrays alike. ``margins``: a list that gets ``rad/scale2 + tol``, or None;
    with margins, a radicand past the toggle is clamped to 0 too (not NaN): the group continues at its
    toggle, so the groups it feeds measure their own margins and a chain's summed shortfall is continuous
    (``valid`` still says the sample does not assemble)."""
    v = value(rad)
    valid = v >= -tol * scale2
    if margins is not None:
        margins.append(v / scale2 + tol)
        clamped = np.maximum(v, 0.0)
    else:
        clamped = np.where(valid, np.maximum(v, 0.0), np.nan)
    return (Jet(clamped, rad.d, rad.dd) if isinstance(rad, Jet) else clamped), valid


def circle_circle(c1, r1, c2, r2, branch, tol: float = 1e-12, margins=None):
    """Intersection of circle (c1, r1) and circle (c2, r2). Shapes broadcast; returns (z, valid)."""
    D = c2 - c1
    d2 = abs2(D)
    inv = 1.0 / d2                     # one reciprocal for both terms
    a = (d2 + r1 * r1 - r2 * r2) * inv * 0.5
    h2 = r1 * r1 * inv - a * a
    h2, valid = _tolerant_radicand(h2, 1.0, tol, margins)
    h = sqrt(h2) * branch
    z = c1 + D * (a + h * 1j)
    return z, valid & (value(d2) > 0)


def circle_line(c, r, q, u, branch, tol: float = 1e-12, margins=None):
    """Intersection of circle (c, r) with the line q + t·u (|u| = 1). Returns (z, valid)."""
    w = q - c
    proj = dot(u, w)
    rad = proj * proj - abs2(w) + r * r
    scale2 = value(r) * value(r) + 1e-300
    rad, valid = _tolerant_radicand(rad, scale2, tol, margins)
    t = sqrt(rad) * branch - proj
    return q + u * t, valid


def line_line(q1, u1, q2, u2, tol: float = 1e-12):
    """Intersection of lines q1 + t·u1 and q2 + s·u2 (unit directions). Returns (z, valid)."""
    den = cross(u2, u1)
    valid = np.abs(value(den)) > tol
    safe = Jet(np.where(valid, den.v, np.nan), den.d, den.dd) if isinstance(den, Jet) else np.where(valid, den, np.nan)
    t = cross(u2, q2 - q1) / safe
    return q1 + u1 * t, valid


def rotation_from_slide(D, c_par, c_perp, branch, tol: float = 1e-12, margins=None):
    """Orientation e (|e| = 1) of a guide body for an RPR group.

    Solves ``D = e·u·((c_par + t) + i·c_perp)`` for the unit complex ``e·u`` (u is the guide line's
    local direction, folded into the caller), given the known vector ``D`` between the group's
    two outer revolutes and the constant offsets of the slide. Returns ``(e_u, valid)``.
    """
    DD = abs2(D)
    rad = DD - c_perp * c_perp
    rad, valid = _tolerant_radicand(rad, value(DD) + 1e-300, tol, margins)
    s = sqrt(rad) * branch
    return D / (s + c_perp * 1j), valid
