"""Simulated rack cutting: the gear outline as the blank minus every position of the cutter teeth.

The generating rack (see :mod:`assur.gears.teeth` for its geometry and the rolling path) is placed at the path's
states s_j; in each state every cutter tooth within its engagement window (the states at which one of its flanks
touches its envelope: foot point between the cutter tip and root lines) is a trapezoid in the gear's body frame.
Each flank edge of a trapezoid carries, as an extra vertex, the exact envelope point of that state (the foot of the
perpendicular from the instantaneous centre, :mod:`assur.gears.teeth`), so the boundary of the cut passes through
the exact envelope points; between two states it follows the two flank lines to their intersection (a deviation of
the order Δ²/(8ρ): Δ the spacing of envelope points, ρ the flank's radius of curvature; below 0.01 µm at the default
256 states per pitch for module-2 teeth). The polygon booleans (union of the cutter positions, blank minus union)
are those of shapely (GEOS), so the outline is a simple polygon whatever the curve does: the teeth cannot fold,
jump or overlap as ray-sampled outlines can on concave stretches.
"""
from __future__ import annotations

import math

import numpy as np

from ..errors import GearError
from .raster import TWO_PI


#: precision grid of the polygon booleans' fallback, in modules (2 nm for module 2 mm)
GRID = 1e-6
#: the cut outline is simplified (Douglas–Peucker, topology kept) within this, in modules (40 nm for module 2 mm):
#: it drops the intersection points of consecutive flank lines that lie within it of the exact envelope chords
SIMPLIFY = 2e-5
#: scallops (intersections of two positions of the cutter between exact points) shallower than this are dropped,
#: in modules (10 µm for module 2 mm; the scallops of a sharp tip corner are ~0.4 of its step, a few µm)
ZIGZAG = 5e-3
#: segments per quarter circle of the tip-radius buffer: a chord of the arcs is within ρ·(1 − cos(π/128)) = 0.03 %
#: of ρ (0.23 µm for ρ = 0.76 mm); the fillet's boundary is made of far shorter arcs between consecutive states,
#: whose ends are exact points of the offset curve
BUFFER_SEGMENTS = 32


def _shapely():
    try:
        import shapely
    except ImportError as exc:  # pragma: no cover - a core dependency
        raise ImportError("the tooth outlines need shapely: pip install shapely") from exc
    return shapely


def cut_polygon(P, T, N, s, inside, centres, rack, tip_xy) -> np.ndarray:
    """The cut gear as a closed counter-clockwise polygon (M, 2), m.

    P, T, N: (Z, K, 2) pitch point, unit tangent and outward normal of the K path states around each of the Z
    cutter teeth; s (Z, K) their arc lengths; ``inside`` (Z, K) the states within each tooth's engagement window;
    centres (Z,) the cutter teeth's rack abscissae; ``rack`` the cutter's geometry for this gear
    (:class:`assur.gears.teeth.Rack`: flank half-width at the pitch curve, tip and top lines, tip radius);
    tip_xy (Q, 2) the blank (the pitch curve offset by the gear's addendum), counter-clockwise. Raises GearError
    (with the body angle) when the cut is not one simple polygon.

    A rack tooth with tip radius ρ > 0 is the union of the trapezoid with its tip corners cut off along the chords
    of the corner arcs and the two discs of radius ρ centred on the arcs' centres; its sweep is the sweep of the
    cut trapezoid (with the exact envelope points as above) and the paths of the two centres buffered by ρ (discs
    swept along them): the root fillets are the offsets by ρ of the centres' trochoids, tangent to the root and to
    the flanks, with no ridge between rack states."""
    shapely = _shapely()
    module = rack.module
    sa, ca = math.sin(rack.alpha), math.cos(rack.alpha)
    ta = sa / ca
    rho = rack.tip_radius
    w0 = rack.half_width
    v_tip = rack.v_tip
    top = rack.v_top
    land = w0 + v_tip * ta - rho * (1 - sa) / ca     # half the straight tip land (between the rounded corners)
    v_tan = v_tip + rho * (1 - sa)                   # where the straight flank starts (tangent to the corner arc)
    uc = centres[:, None]
    rounded = rho > 0
    corners_uv = [(uc - land, v_tip), "root", (uc + land, v_tip)]
    if rounded:
        corners_uv.append((uc + land + rho * ca, v_tan))
    corners_uv += [None, (uc + w0 + top * ta, top), (uc - w0 - top * ta, top), None]
    if rounded:
        corners_uv.append((uc - land - rho * ca, v_tan))
    flank_index = [k for k, c in enumerate(corners_uv) if c is None]
    pts = []
    for k, c in enumerate(corners_uv):
        if isinstance(c, str):   # the envelope point of the tip land (the root curve): u = s, else its midpoint
            u = np.where(np.abs(s - uc) < land, s, uc)
            v = np.full(s.shape, v_tip)
        elif c is None:       # the envelope (foot) point of the flank just passed
            side = 1.0 if k == flank_index[0] else -1.0
            a_u = uc + side * w0
            v = side * (s - a_u) * sa * ca
            v = np.where((v > v_tan) & (v < top), v, 0.5 * (top + v_tan))     # off the flank: its midpoint instead
            u = a_u + side * v * ta
        else:
            u, v = c
            u = np.broadcast_to(u, s.shape)
            v = np.full(s.shape, v)
        pts.append(P + (u - s)[..., None] * T + v[..., None] * N)
    quads = np.stack(pts, axis=-2)                               # (Z, K, 7 or 9, 2)
    blank = shapely.Polygon(tip_xy)
    if not blank.is_valid:
        blank = shapely.make_valid(blank)
    discs = [[] for _ in range(quads.shape[0])]
    if rounded:    # the rounded corners: the paths of the arcs' centres, buffered by ρ (discs swept along them)
        for side in (-1.0, 1.0):
            c = P + (uc + side * land - s)[..., None] * T + (v_tip + rho) * N
            for z in range(quads.shape[0]):
                path = c[z][inside[z]]
                if path.shape[0] >= 2:
                    discs[z].append(shapely.buffer(shapely.LineString(path), rho, quad_segs=BUFFER_SEGMENTS))
    try:       # one union per cutter tooth (its space), then of the spaces: far faster than one big union
        spaces = [shapely.union_all(list(shapely.polygons(quads[z][inside[z]])) + discs[z])
                  for z in range(quads.shape[0])]
        gear = blank.difference(shapely.union_all(spaces))
    except shapely.errors.GEOSException:          # pragma: no cover - robustness fallback: snap to a fine grid
        grid = GRID * module
        cut = shapely.union_all(list(shapely.polygons(quads[inside])) + sum(discs, []), grid_size=grid)
        gear = shapely.difference(blank, cut, grid_size=grid)
    xy = _single_outline(gear, module)
    if rho == 0:
        xy = _drop_scallops(xy, quads[inside][:, [0, 2]].reshape(-1, 2), ZIGZAG * module)
    gear = shapely.simplify(shapely.Polygon(xy), SIMPLIFY * module, preserve_topology=True)
    return _single_outline(gear, module)


def _drop_scallops(xy, exact, tol):
    """Drop the vertices of xy between two positions of the cutter's tip corners (``exact``: the points of its
    trochoids) that lie within ``tol`` of the chord of those two: the scallops between consecutive positions of a
    sharp tip corner (intersections of two cutter positions, not envelope points)."""
    z = xy[:, 0] + 1j * xy[:, 1]
    is_exact = np.isin(z, exact[:, 0] + 1j * exact[:, 1])
    prev, nxt = np.roll(xy, 1, axis=0), np.roll(xy, -1, axis=0)
    chord = nxt - prev
    L = np.hypot(chord[:, 0], chord[:, 1])
    dev = np.abs(chord[:, 0] * (xy[:, 1] - prev[:, 1]) - chord[:, 1] * (xy[:, 0] - prev[:, 0])) / np.maximum(L, 1e-300)
    drop = ~is_exact & (dev < tol) & np.roll(is_exact, 1) & np.roll(is_exact, -1)
    return xy[~drop]


def _single_outline(geom, module) -> np.ndarray:
    shapely = _shapely()
    if geom.geom_type == "MultiPolygon":
        parts = sorted(geom.geoms, key=lambda g: g.area, reverse=True)
        main = parts[0]
        loose = [p for p in parts[1:] if p.area > (0.01 * module) ** 2]
        if loose:
            c = loose[0].representative_point()
            raise GearError(f"the cut leaves {len(loose)} loose piece(s) of material besides the gear (the first at "
                            f"body angle {math.degrees(math.atan2(c.y, c.x)) % 360:.2f}°): the rack cannot cut this "
                            f"pitch curve with module {module * 1e3:.4g} mm")
        geom = main
    if geom.geom_type != "Polygon" or geom.is_empty:
        raise GearError(f"the rack cut leaves no gear ({geom.geom_type}); the module {module * 1e3:.4g} mm is too "
                        f"large for the pitch curve")
    if len(geom.interiors):
        c = shapely.Polygon(geom.interiors[0]).representative_point()
        raise GearError(f"the rack cut leaves a hole in the gear at body angle "
                        f"{math.degrees(math.atan2(c.y, c.x)) % 360:.2f}°")
    geom = shapely.orient_polygons(geom) if hasattr(shapely, "orient_polygons") else shapely.geometry.polygon.orient(geom)
    xy = np.asarray(geom.exterior.coords)[:-1]
    # drop coincident consecutive vertices (GEOS keeps repeated points of the input rings)
    d = np.hypot(*(np.roll(xy, -1, axis=0) - xy).T)
    xy = xy[d > 1e-12 * module]
    if _signed_area(xy) < 0:
        xy = xy[::-1]
    # start at the vertex nearest body angle 0 (a deterministic start)
    a = np.mod(np.arctan2(xy[:, 1], xy[:, 0]), TWO_PI)
    return np.roll(xy, -int(np.argmin(a)), axis=0)


def _signed_area(xy):
    x, y = xy[:, 0], xy[:, 1]
    return 0.5 * float(np.sum(x * np.roll(y, -1) - np.roll(x, -1) * y))


def densify(xy, max_step: float) -> np.ndarray:
    """The closed polygon xy (M, 2) with every edge longer than ``max_step`` split into equal parts."""
    nxt = np.roll(xy, -1, axis=0)
    seg = np.hypot(*(nxt - xy).T)
    n = np.maximum(1, np.ceil(seg / max_step).astype(np.intp))
    if n.max() == 1:
        return xy
    owner = np.repeat(np.arange(xy.shape[0]), n)
    f = (np.arange(owner.size) - np.repeat(np.cumsum(n) - n, n)) / n[owner]
    return xy[owner] + f[:, None] * (nxt[owner] - xy[owner])


__all__ = ["cut_polygon", "densify"]
