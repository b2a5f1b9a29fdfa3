"""A cam's profile as DXF or SVG in mm (the cam plate's outline of :mod:`assur.cams.outline` through
:mod:`assur.io.cad`)."""
from __future__ import annotations

from pathlib import Path

import numpy as np

from ..cams.outline import MM, outline
from ..errors import SpecError


def write_profile(path, geometry, *, bore: float | None = None, samples: int = 1440) -> Path:
    """The cam's profile (and its pitch curve as a reference) as DXF or SVG (by the extension) in mm; ``bore`` the
    shaft's diameter (m)."""
    from .cad import Shape, write_dxf, write_svg
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
