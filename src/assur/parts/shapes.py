"""Flat shapes of parts in their body's frame: the exact recipe a solid is built from, and the region a conflict
check moves (a polygon that contains the exact shape, so a distance measured on it never exceeds the true one).

A :class:`Shape2D` is the union of convex hulls of circles (a bar is the hull of two bosses, a ternary plate of
three) and of polygons (a gear's teeth, a block), minus round holes and straight slots. Lengths in m.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

#: sides of the polygon that stands for a circle in the conflict regions (circumscribed: it contains the circle)
CIRCLE_SIDES = 48


def circle_polygon(x: float, y: float, r: float, sides: int = CIRCLE_SIDES) -> np.ndarray:
    """(sides, 2) a regular polygon circumscribed about the circle (x, y, r), counter-clockwise."""
    R = r / math.cos(math.pi / sides)
    a = np.linspace(0.0, 2.0 * math.pi, sides, endpoint=False)
    return np.stack([x + R * np.cos(a), y + R * np.sin(a)], axis=-1)


def rectangle(centre, direction, length: float, width: float) -> np.ndarray:
    """(4, 2) the rectangle of ``length`` along the unit ``direction`` and ``width`` across it, centred at
    ``centre``, counter-clockwise."""
    c = np.asarray(centre, dtype=float)
    u = np.asarray(direction, dtype=float)
    u = u / np.hypot(*u)
    v = np.array([-u[1], u[0]])
    h, w = 0.5 * length, 0.5 * width
    return np.array([c - h * u - w * v, c + h * u - w * v, c + h * u + w * v, c - h * u + w * v])


@dataclass(frozen=True, eq=False)
class Shape2D:
    """The flat shape of a part in its body's frame (m).

    ``hulls``: each a tuple of circles (x, y, r) whose convex hull is filled (one circle: a disc, two: a bar);
    ``polygons``: (k, 2) filled simple polygons; ``holes``: round holes (x, y, diameter); ``slots``: straight
    slots cut through (x0, y0, x1, y1, width) with round ends; ``flats``: D-bores for a motor's D-shaft (x, y,
    diameter, the flat's distance from the centre; the flat parallel to the body's x axis, on its +y side);
    ``trim``: the same D cut off the filled area (a D-shaft itself). The part is the union of the hulls and
    polygons, trimmed, minus the holes, slots and D-bores."""
    hulls: tuple = ()
    polygons: tuple = ()
    holes: tuple = ()
    slots: tuple = ()
    flats: tuple = ()
    trim: tuple = ()

    def bores(self) -> tuple:
        """(x, y, diameter) of every round hole and D-bore."""
        return self.holes + tuple(f[:3] for f in self.flats)

    def region(self):
        """The shapely polygon of the filled area without its holes and slots, conservatively: circles as
        circumscribed polygons (the region contains the exact shape)."""
        import shapely
        pieces = [shapely.MultiPoint(np.vstack([circle_polygon(*c) for c in hull])).convex_hull
                  for hull in self.hulls]
        pieces += [shapely.Polygon(p) for p in self.polygons]
        out = shapely.union_all(pieces)
        if out.geom_type != "Polygon":        # pieces that do not touch: the hull keeps one part one region
            out = out.convex_hull
        return shapely.Polygon(out.exterior)

    def outline(self) -> np.ndarray:
        """(k, 2) the exterior of :meth:`region`, counter-clockwise, first point not repeated."""
        import shapely
        ring = shapely.Polygon(self.region()).exterior
        if not ring.is_ccw:
            ring = shapely.LinearRing(list(ring.coords)[::-1])
        return np.asarray(ring.coords)[:-1]

    def bounding_circle(self) -> tuple[np.ndarray, float]:
        """(centre (2,), radius): a circle about the region's bounding-box centre containing the region."""
        xy = self.outline()
        c = 0.5 * (xy.min(axis=0) + xy.max(axis=0))
        return c, float(np.max(np.hypot(*(xy - c).T)))


def disc(x: float, y: float, r: float, hole: float | None = None) -> Shape2D:
    """A disc of radius ``r`` at (x, y), with a central hole of diameter ``hole`` (a washer) or none (a pin)."""
    return Shape2D(hulls=(((x, y, r),),), holes=(() if hole is None else ((x, y, hole),)))


def file_name(text: str) -> str:
    """A part name that is also a file name and a STEP label: letters, digits and '_' only."""
    return text.replace("'", "_prime").replace(".", "_")


@dataclass(eq=False)
class Part:
    """One part: ``shape`` drawn in the frame of body ``body`` (``body_name``).

    ``kind``: plate, gear, block, cylinder, rod (take a layer); pin (a dowel or the motor shaft: ``joint`` and
    ``holds`` the body names it joins, the one it moves with first; ``reach`` the radius of what it carries
    through a layer it crosses);
    washer; base, top, standoff, motor_mount (frame parts). ``partner``: the part it touches by design (a gear's
    mate, a block's guide). ``layer`` and ``z`` ([z_min, z_max], m) are set by the stack."""
    name: str
    kind: str
    body: int
    body_name: str
    shape: Shape2D
    thickness: float
    joint: str | None = None
    holds: tuple = ()
    reach: float = 0.0
    partner: str | None = None
    material: str = ""
    density: float = 0.0
    layer: object = None
    z: tuple | None = None
    note: str = ""
    #: a gear's conflict region is its outline simplified within this and grown by it (m; 0: the exact region)
    region_tolerance: float = 0.0

    def region(self):
        """The conflict region of the part in its body's frame: a shapely polygon that contains the part (a pin's
        is the disc of its ``reach``: what it carries through the layers it crosses)."""
        import shapely
        if self.kind == "pin":
            (x, y, _), = self.shape.hulls[0]
            return Shape2D(hulls=(((x, y, self.reach),),)).region()
        out = self.shape.region()
        if self.region_tolerance > 0:
            out = shapely.Polygon(out.simplify(self.region_tolerance).buffer(self.region_tolerance).exterior)
        return out


__all__ = ["CIRCLE_SIDES", "Part", "Shape2D", "circle_polygon", "disc", "file_name", "rectangle"]
