"""The cam plate: its outline polygon (mm, the cam's frame) and its DXF and SVG drawings.

The outline is the profile (:meth:`~assur.cams.geometry.CamGeometry.profile`) as a closed counter-clockwise polygon
in millimetres, in the cam's frame: the origin at the cam's pivot (the shaft's centre, where the bore goes) and the
x axis along the cam link's pivot → arm direction as drawn in the sketch, so that the link's other holes keep their
local coordinates. A cam whose profile is undercut (a roller larger than the pitch curve's convex radius, a flat face
on a profile that is not convex) has no such outline: :class:`~assur.errors.SpecError` says why. ``assur make``
(:mod:`assur.parts`) takes :func:`plate_outline` for a cam link's plate.
"""
from __future__ import annotations

from pathlib import Path

import numpy as np

from ..errors import SpecError

MM = 1e3


def outline(geometry, samples: int = 1440) -> np.ndarray:
    """(samples, 2) the cam's outline in mm, counter-clockwise, in the cam's frame (first point not repeated)."""
    s = geometry.summary(samples)
    if s["undercut"]:
        raise SpecError([("cam", f"the profile of cam {geometry.name or ''} is undercut (a cusp or a loop): no plate; "
                                 f"enlarge the base circle or use a roller below {1e3 * (s['roller_radius_limit'] or 0):.4g}"
                                 " mm")])
    z = geometry.profile(samples)[::-1] * MM                 # the follower meets it clockwise: reverse
    xy = np.column_stack([z.real, z.imag])
    from shapely.geometry import Polygon
    poly = Polygon(xy)
    if not poly.is_valid or not poly.contains(Polygon([(0, 0), (1e-6, 0), (0, 1e-6)]).centroid):
        raise SpecError([("cam", f"the profile of cam {geometry.name or ''} is not a simple outline round its pivot")])
    return xy


def plate_outline(plan, cam=0, params=None, samples: int = 1440) -> np.ndarray:
    """The outline (mm, cam frame, counter-clockwise) of the mechanism's cam pair ``cam`` (a name or an index) at
    ``params`` (default the plan's): what ``assur make`` cuts for the cam link."""
    from .followers import from_plan
    return outline(from_plan(plan, cam, params), samples)


def write_profile(path, geometry, *, bore: float | None = None, samples: int = 1440) -> Path:
    """The cam's profile (and its pitch curve as a reference) as DXF or SVG (by the extension) in mm; ``bore`` the
    shaft's diameter (m)."""
    from ..io.cad import Shape, write_dxf, write_svg
    path = Path(path)
    xy = outline(geometry, samples) / MM
    pitch = geometry.pitch_curve(samples)
    refs = () if geometry.contact == "flat" else (np.column_stack([pitch.real, pitch.imag]),)
    s = geometry.summary(samples)
    meta = {"cam": geometry.name, "follower": f"{geometry.motion} {geometry.contact}",
            "base_radius_mm": round(s["base_radius"] * MM, 6), "prime_radius_mm": round(s["prime_radius"] * MM, 6),
            "roller_radius_mm": round(geometry.roller_radius * MM, 6),
            "pressure_angle_max_deg": round(float(np.degrees(s["pressure_angle_max"])), 4), "points": len(xy)}
    shape = Shape(geometry.name or "cam", xy, (0.0, 0.0), refs, bore)
    ext = path.suffix.lower()
    if ext == ".dxf":
        return write_dxf(path, [shape], metadata=meta)
    if ext == ".svg":
        return write_svg(path, [shape], metadata=meta)
    raise SpecError([("output", f"a cam profile is written as .dxf or .svg: {path.name!r}")])
