"""One cam pair's checks as a JSON-ready dict (SI): what ``assur cam`` prints and the report shows."""
from __future__ import annotations

import numpy as np

from ..errors import SpecError


def cam_summary(plan, geometry) -> dict:
    """The JSON-ready checks of one cam pair (SI)."""
    from ..cams.laws import continuity, peaks
    from ..cams.sizing import base_circle
    g = geometry
    speed = abs(float(plan.speeds[0])) if plan.n_inputs else None
    s = g.summary()
    c = continuity(g.law)
    out = {"name": g.name, "follower": {"motion": g.motion, "contact": g.contact, "roller_radius": g.roller_radius},
           "law": {"kind": g.law.kind, "continuous": {"s": c.smooth >= 0, "v": c.smooth >= 1, "a": c.smooth >= 2,
                                                       "j": c.smooth >= 3},
                   "fundamental_law": c.ok, "findings": c.findings(),
                   "peaks_per_rad": {k: v for k, v in peaks(g.law).items() if not k.endswith("_at")}}}
    if speed:
        out["law"]["peaks_at_speed"] = {k: v for k, v in peaks(g.law, speed=speed).items() if not k.endswith("_at")}
    out["profile"] = s
    try:
        if g.motion == "translating":
            d = g.direction
            offset = float(np.imag(np.conj(d) * (g.trace - g.pivot)))
            rb = base_circle(g.law, contact=g.contact, roller_radius=g.roller_radius, offset=offset,
                             max_pressure_angle=None if g.contact == "flat" else g.pressure_limit,
                             min_curvature=1e-9 if g.contact == "flat" else None, samples=1440, rtol=1e-6)
        else:
            rb = base_circle(g.law, motion="oscillating", contact=g.contact, roller_radius=g.roller_radius,
                             pivot_distance=abs(g.follower_pivot - g.pivot), arm_length=abs(g.trace - g.follower_pivot),
                             max_pressure_angle=None if g.contact == "flat" else g.pressure_limit,
                             min_curvature=1e-9 if g.contact == "flat" else None, samples=1440, rtol=1e-6)
        out["smallest_base_radius"] = rb
    except SpecError as exc:
        out["smallest_base_radius"] = None
        out["sizing_note"] = str(exc)
    return out
