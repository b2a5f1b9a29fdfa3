"""Checks of a closed tooth outline as it is written (DXF/SVG/CSV): what a printer or a CAM program needs.

:func:`outline_defects` lists located findings (body angle in degrees, lengths in mm):

- **not simple**: the polygon crosses or touches itself (GEOS validity, via shapely), or has fewer than 3 points;
- **spacing**: consecutive points farther apart than ``max_step`` (default module/8);
- **sliver / needle**: material that an opening with a disc of radius ε = module/20 removes, in pieces of area above
  4ε² (a spike or a thin sliver of material: it would print as a whisker or not at all);
- **notch**: a gap that a closing with the same disc fills, in pieces of area above 4ε² (a needle-like cut into the
  material; fillets and the corners of a rack-cut tooth lose or gain less than ε² each);
- **teeth**: with the pitch curve given, the outline must cross it in exactly ``teeth`` pieces of material (the
  teeth), each as thick along the pitch curve as designed within 10 % (a rack that overcuts a concave stretch thins
  or removes neighbouring teeth).

An empty list means the outline is clean.
"""
from __future__ import annotations

import math

import numpy as np

#: opening/closing disc radius, in modules
SLIVER_RADIUS = 0.05
#: a tooth whose thickness on the pitch curve differs from the design by more than this fraction is reported
THICKNESS_TOLERANCE = 0.10


def _deg(x, y):
    return f"{math.degrees(math.atan2(y, x)) % 360:.2f}°"


def _pieces(geom, min_area):
    parts = getattr(geom, "geoms", [geom])
    return [g for g in parts if not g.is_empty and g.area > min_area]


def pitch_ring_angles(teeth: int) -> np.ndarray:
    """(K,) the body angles (rad) at which the tooth checks of :func:`outline_defects` sample the pitch curve."""
    return np.linspace(0.0, 2 * math.pi, 8 * 1024 * max(1, teeth // 32), endpoint=False)


def outline_defects(xy, module: float, *, teeth: int | None = None, name: str = "outline",
                    max_step: float | None = None, thickness: float | None = None, pitch_radius=None,
                    max_listed: int = 6) -> list[str]:
    """Located defects of the closed polygon xy (M, 2) (m, body frame, centre at the origin); see the module
    docstring. pitch_radius: the pitch curve r(ψ) (vectorised callable, or its radii (K,) at the angles
    :func:`pitch_ring_angles` (teeth)) for the tooth checks, with ``teeth`` and the designed tooth ``thickness`` on
    it (m)."""
    import shapely
    from shapely.validation import explain_validity
    xy = np.asarray(xy, dtype=float)
    if xy.ndim != 2 or xy.shape[0] < 3 or xy.shape[1] != 2 or not np.all(np.isfinite(xy)):
        return [f"{name}: not a finite closed polygon of at least 3 points (shape {xy.shape})"]
    out = []
    max_step = module / 8 if max_step is None else max_step
    step = np.hypot(*(np.roll(xy, -1, axis=0) - xy).T)
    far = np.flatnonzero(step > max_step * (1 + 1e-9))
    if far.size:
        i = far[np.argmax(step[far])]
        out.append(f"{name}: {far.size} pair(s) of consecutive points farther apart than {max_step * 1e3:.4g} mm "
                   f"(largest {step[i] * 1e3:.4g} mm at body angle {_deg(*xy[i])})")
    poly = shapely.Polygon(xy)
    if not poly.is_valid:
        why = explain_validity(poly)
        where = ""
        if "[" in why:
            try:
                x, y = (float(v) for v in why.split("[", 1)[1].rstrip("]").split()[:2])
                where = f" at body angle {_deg(x, y)} (radius {math.hypot(x, y) * 1e3:.3f} mm)"
            except ValueError:
                pass
        out.append(f"{name}: not a simple polygon ({why.split('[')[0].strip()}{where})")
        return out
    eps = SLIVER_RADIUS * module
    min_area = 4 * eps * eps
    coarse = poly.simplify(0.01 * module, preserve_topology=True)    # 20 µm for m = 2 mm: < ε, and fast buffers
    opened = coarse.buffer(-eps, quad_segs=4).buffer(eps, quad_segs=4)
    closed = coarse.buffer(eps, quad_segs=4).buffer(-eps, quad_segs=4)
    for kind, geom in (("sliver or needle of material", coarse.difference(opened)),
                       ("needle-like notch", closed.difference(coarse))):
        bad = _pieces(geom, min_area)
        if bad:
            where = ", ".join(_deg(p.representative_point().x, p.representative_point().y) for p in bad[:max_listed])
            more = f" and {len(bad) - max_listed} more" if len(bad) > max_listed else ""
            out.append(f"{name}: {len(bad)} {kind} thinner than {2 * eps * 1e3:.3g} mm at body angle {where}{more}")
    if pitch_radius is not None and teeth is not None:
        a = pitch_ring_angles(teeth)
        r = np.asarray(pitch_radius(a) if callable(pitch_radius) else pitch_radius, dtype=float)
        ring = shapely.LinearRing(np.column_stack([r * np.cos(a), r * np.sin(a)]))
        on = shapely.line_merge(poly.intersection(ring))
        pieces = [g for g in getattr(on, "geoms", [on]) if g.geom_type == "LineString" and g.length > 0]
        if len(pieces) != teeth:
            out.append(f"{name}: {len(pieces)} teeth cross the pitch curve, designed {teeth}")
        if thickness is not None and pieces:
            thick = np.array([g.length for g in pieces])
            off = np.flatnonzero(np.abs(thick / thickness - 1) > THICKNESS_TOLERANCE)
            if off.size:
                where = ", ".join(f"{_deg(*np.asarray(pieces[i].interpolate(0.5, normalized=True).coords[0]))} "
                                  f"({thick[i] * 1e3:.3f} mm)" for i in off[:max_listed])
                more = f" and {off.size - max_listed} more" if off.size > max_listed else ""
                out.append(f"{name}: {off.size} teeth thinner or thicker on the pitch curve than the designed "
                           f"{thickness * 1e3:.3f} mm ±{THICKNESS_TOLERANCE:.0%}: at body angle {where}{more}")
    return out


__all__ = ["outline_defects", "pitch_ring_angles", "SLIVER_RADIUS", "THICKNESS_TOLERANCE"]
