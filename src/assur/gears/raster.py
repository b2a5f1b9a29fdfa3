"""Polar rasterisation of polylines for the tooth outlines: per ray, the nearest crossing of any polyline.

Rays are uniform in angle about the gear centre (:func:`rasterise_min`); along each polyline segment the distance
is interpolated linearly in (angle, distance).
Also the periodic interpolation of values sampled on uniform angles, and angle wrapping.
"""
from __future__ import annotations

import math

import numpy as np

from ..tolerances import DEFAULT as TOL

TWO_PI = 2.0 * math.pi


def periodic_interp(a, values):
    """Linear interpolation of values sampled at 2π·i/M (i = 0..M−1) at angles a (...), periodic."""
    m = values.shape[0]
    x = np.mod(a, TWO_PI) * (m / TWO_PI)
    i0 = np.floor(x).astype(np.intp)
    f = x - i0
    i0 %= m
    return values[i0] * (1.0 - f) + values[(i0 + 1) % m] * f


def wrap_angle(a):
    """Angles a (...) wrapped into [−π, π), rad."""
    return (a + math.pi) % TWO_PI - math.pi


def _values_on_rays(g0, g1, a0, a1, d0, d1, spacing):
    """Per segment i (ends at angles a0[i], a1[i] with values d0[i], d1[i]) and each ray g0[i] ≤ g ≤ g1[i] at
    angle g·spacing: the value on that ray, linear in angle along the segment. spacing: a number or (S,) per
    segment. Returns (segment (P,), ray (P,), value (P,)), or None when no segment covers a ray."""
    n = np.maximum(g1 - g0 + 1, 0)
    if n.sum() == 0:
        return None
    seg = np.repeat(np.arange(n.size), n)
    first = np.concatenate([[0], np.cumsum(n)[:-1]])
    g = g0[seg] + (np.arange(seg.size) - first[seg])
    span = a1[seg] - a0[seg]
    with np.errstate(invalid="ignore", divide="ignore"):
        f = np.where(np.abs(span) > 0, (g * (spacing if np.ndim(spacing) == 0 else spacing[seg]) - a0[seg]) / span,
                     0.0)
    return seg, g, d0[seg] + np.clip(f, 0.0, 1.0) * (d1[seg] - d0[seg])


def rasterise_min(out, xy, valid):
    """Lower ``out`` (M,) (radius per uniform ray) by every segment of polylines ``xy`` (..., K, 2) between
    consecutive valid points (valid (..., K)). Linear interpolation in (ψ, ρ) along each segment."""
    m = out.shape[0]
    dpsi = TWO_PI / m
    a = xy[..., :-1, :].reshape(-1, 2)
    b = xy[..., 1:, :].reshape(-1, 2)
    ok = (valid[..., :-1] & valid[..., 1:]).reshape(-1)
    a, b = a[ok], b[ok]
    psi_a = np.arctan2(a[:, 1], a[:, 0])
    psi_b = psi_a + wrap_angle(np.arctan2(b[:, 1], b[:, 0]) - psi_a)
    rho_a = np.hypot(a[:, 0], a[:, 1])
    rho_b = np.hypot(b[:, 0], b[:, 1])
    lo = np.minimum(psi_a, psi_b)
    hi = np.maximum(psi_a, psi_b)
    g0 = np.ceil(lo / dpsi - TOL.ray_end).astype(np.int64)      # rays on a segment's end belong to both neighbours
    g1 = np.floor(hi / dpsi + TOL.ray_end).astype(np.int64)
    found = _values_on_rays(g0, g1, psi_a, psi_b, rho_a, rho_b, dpsi)
    if found is not None:
        _, g, rho = found
        np.minimum.at(out, np.mod(g, m), rho)


__all__ = ["TWO_PI", "periodic_interp", "rasterise_min", "wrap_angle"]
