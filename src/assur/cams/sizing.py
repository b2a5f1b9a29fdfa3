"""Cam size: the smallest base circle that keeps the pressure angle and the radius of curvature within limits.

The pressure angle falls as the cam grows, and a roller's pitch curve flattens; :func:`base_circle` finds the
smallest base radius whose cam meets every limit given (bisection on the radius: each trial cam is checked over a
whole turn by :meth:`~assur.cams.geometry.CamGeometry.summary`). For an in-line translating roller or knife follower
the pressure-angle bound has the closed form R_p ≥ max over the turn of (s′/tan α_max − s) (tan α = s′/(R_p + s));
:func:`prime_radius_inline` gives it (the check of the search in the tests).
"""
from __future__ import annotations

import math

import numpy as np

from ..errors import SpecError
from ..model.camming import TWO_PI, CamLaw
from .followers import oscillating, translating


def prime_radius_inline(law: CamLaw, max_pressure_angle: float, samples: int = 1 << 16) -> float:
    """The smallest prime radius of an in-line translating roller (or knife) follower with |α| ≤ ``max_pressure_angle``
    over the turn: max (|s′|/tan α_max − s), on a fine grid refined by a bounded search."""
    from scipy.optimize import minimize_scalar
    phi = np.linspace(0.0, TWO_PI, samples, endpoint=False)
    t = math.tan(max_pressure_angle)

    def need(x):
        s, s1, _, _ = law.evaluate(np.atleast_1d(x))
        return np.abs(s1) / t - s

    g = need(phi)
    i = int(np.argmax(g))
    h = TWO_PI / samples
    best = minimize_scalar(lambda x: -need(x)[0], bounds=(phi[i] - h, phi[i] + h), method="bounded",
                           options={"xatol": 1e-14})
    return float(max(g[i], -best.fun))


def base_circle(law: CamLaw, *, motion: str = "translating", contact: str = "roller", roller_radius: float = 0.0,
                offset: float = 0.0, pivot_distance: float | None = None, arm_length: float | None = None,
                max_pressure_angle: float | None = math.radians(30.0), min_curvature: float | None = None,
                rotation: int = 1, samples: int = 2880, rtol: float = 1e-10) -> float:
    """The smallest base radius (m) of a cam for ``law`` whose follower (as :func:`~assur.cams.followers.translating`
    or :func:`~assur.cams.followers.oscillating` build it) meets: |α| ≤ ``max_pressure_angle`` over the turn (knife and
    roller; None: no bound), no undercut, and every convex radius of curvature of the profile ≥ ``min_curvature``
    (default: > 0 for a flat face, none otherwise). SpecError when no radius up to 1000 times the stroke does."""
    stroke = max(law.stroke, 1e-12)
    if motion == "oscillating" and (pivot_distance is None or arm_length is None):
        raise SpecError([("pivot_distance", "an oscillating follower needs pivot_distance and arm_length")])
    scale = stroke if motion == "translating" else stroke * (arm_length or 1.0)

    def build(rb):
        if motion == "translating":
            return translating(law, rb, offset=offset, contact=contact, roller_radius=roller_radius, rotation=rotation)
        return oscillating(law, rb, pivot_distance=pivot_distance, arm_length=arm_length, contact=contact,
                           roller_radius=roller_radius, rotation=rotation)

    def ok(rb) -> bool:
        try:
            s = build(rb).summary(samples)
        except SpecError:
            return False
        if s["undercut"]:
            return False
        if max_pressure_angle is not None and contact != "flat" and s["pressure_angle_max"] > max_pressure_angle:
            return False
        if min_curvature is not None and (s["min_profile_radius"] is None or s["min_profile_radius"] < min_curvature):
            return False
        return True

    lo = max(abs(offset) - roller_radius, 0.0) + 1e-9 * scale
    hi = max(lo, scale)
    while not ok(hi):
        hi *= 2.0
        if hi > 1000.0 * scale + lo:
            raise SpecError([("base_circle", "no base radius up to 1000 times the stroke meets the limits")])
    if ok(lo):
        return lo
    while hi - lo > rtol * hi:
        mid = 0.5 * (lo + hi)
        lo, hi = (lo, mid) if ok(mid) else (mid, hi)
    return hi
