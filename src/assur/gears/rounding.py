"""Rounding the corners of a transmission law's pitch curves before a rack cuts them (paper 001's law has a
kink at each step end; a rack cannot follow a corner of the pitch curve)."""
from __future__ import annotations

import math

import numpy as np

from ..errors import GearError
from .law import law_from_ratio
from .pitch import curvature_report, find_corners, pitch_pair
from .raster import TWO_PI, wrap_angle


def _bump(d):
    """1 for d ≤ 2, 0 for d ≥ 4, C¹ smoothstep between."""
    x = np.clip((d - 2.0) / 2.0, 0.0, 1.0)
    return 1.0 - x * x * (3.0 - 2.0 * x)


def rounded_pair(pair, module: float, pressure_angle: float = math.radians(20.0), *, width: float | None = None,
                 samples: int = 4096, widths=None):
    """The pair with the corners of its pitch curves rounded, for a rack that cannot cut a corner.

    The speed ratio k(φ) has a kink at each corner. Near each corner (driving angle φ_c) k is replaced by its
    periodic Gaussian smoothing of standard deviation ``width`` (rad of φ), blended back to the exact k between
    2 and 4 widths from the corner; the result is scaled so that ∫k over a driving turn stays 2π/n (the curves
    close). ``width=None``: the smallest of ``widths`` (default 0.01 … 0.6 rad, geometric) for which both pitch
    curves have no corner and no stretch with radius of curvature below m/sin²α
    (:func:`assur.gears.pitch.curvature_report`). Returns (pair, width) — (pair, 0.0) when there is no corner.
    Raises GearError when no width in the range suffices."""
    from scipy.interpolate import CubicSpline
    n = int(pair.driving_turns)
    corners = find_corners(pair.driving)
    if not corners and not find_corners(pair.driven):
        return pair, 0.0
    phi_c = np.mod(-np.array([c.angle for c in corners]), TWO_PI)
    u = np.arange(samples) * (TWO_PI / samples)
    k = np.asarray(pair.ratio(u), dtype=float)
    dist = np.min(np.abs(wrap_angle(u[:, None] - phi_c[None, :])), axis=1) if phi_c.size else np.full(u.shape, np.inf)
    freq = np.fft.rfftfreq(samples, d=TWO_PI / samples) * TWO_PI       # angular frequency per rad

    def build(w):
        smooth = np.fft.irfft(np.fft.rfft(k) * np.exp(-0.5 * (freq * w) ** 2), n=samples)
        ks = k + _bump(dist / w) * (smooth - k)
        ks *= (TWO_PI / n) / (ks.mean() * TWO_PI)
        spline = CubicSpline(np.append(u, TWO_PI), np.append(ks, ks[0]), bc_type="periodic")
        law = law_from_ratio(lambda x: spline(np.mod(x, TWO_PI)), driving_turns=n, samples=samples)
        return pitch_pair(law, pair.centre_distance, samples=max(2048, samples // 2))

    def fine(p):
        for curve in (p.driving, p.driven):
            rep = curvature_report(curve, module=module, pressure_angle=pressure_angle)
            if rep.corners or rep.undercut_ranges:
                return False
        return True

    if width is not None:
        return build(float(width)), float(width)
    for w in (widths if widths is not None else np.geomspace(0.01, 0.6, 16)):
        p = build(float(w))
        if fine(p):
            return p, float(w)
    raise GearError(f"the pitch-curve corners cannot be rounded for module {1e3 * module:g} mm: even a rounding "
                    f"width of {math.degrees(float(w)):.1f}° of the driving angle leaves a radius of curvature "
                    f"below m/sin²α = {1e3 * module / math.sin(pressure_angle) ** 2:.3f} mm")


__all__ = ["rounded_pair"]
