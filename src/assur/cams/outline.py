"""The cam plate: its outline polygon (mm, the cam's frame) and its DXF and SVG drawings.

The outline is the profile (:meth:`~assur.cams.geometry.CamGeometry.profile`) as a closed counter-clockwise polygon
in millimetres, in the cam's frame: the origin at the cam's pivot (the shaft's centre, where the bore goes) and the
x axis along the cam link's pivot → arm direction as drawn in the sketch, so that the link's other holes keep their
local coordinates. A cam whose profile is undercut (a roller larger than the pitch curve's convex radius, a flat face
on a profile that is not convex) has no such outline: :class:`~assur.errors.SpecError` says why. ``assur make``
(:mod:`assur.parts`) takes :func:`plate_outline` for a cam link's plate; :func:`assur.io.cam_profile.write_profile`
writes the outline as DXF or SVG.
"""
from __future__ import annotations

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
