"""Gear plates of a mechanism's ``[[gears]]`` pairs: the tooth outlines ``assur gears`` cuts for the pair's design
file (the rack-cutter envelope of :func:`assur.gears.teeth.cut_pair`, with the design's teeth, module, backlash and
tip rounding, from the same cache), placed on the two links at the sketch pose.

The design's frame has the driving gear about O1 = (0, 0) turning counter-clockwise by φ and the driven gear about
O2 = (L, 0) turning clockwise by θ(φ) (:mod:`assur.gears.pitch`); the mechanism's pair ``(a, b)`` has the law's
driving angle ``phase`` at the sketch. So at the sketch the driving outline is turned by α + phase about a's pivot
and the driven one by α − θ(phase) about b's pivot, α the direction from a's pivot to b's.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from ..errors import SpecError
from ..model.gearing import gear_ends
from .shapes import Part, Shape2D, file_name

#: rack states per tooth pitch of the envelope cut (the value ``assur gears`` uses, so both share the cache)
STATES_PER_TOOTH = 64
#: the outline a solid is built from keeps the vertices needed to stay within this of the cut outline (m): 20 µm,
#: a tenth of a typical backlash, and about a thousand edges per gear (a B-rep of the full cut outline is slow)
OUTLINE_TOLERANCE = 2e-5
#: the conflict region of a gear: its outline simplified within this fraction of the module, then grown by it
REGION_TOLERANCE = 0.25


@dataclass(eq=False)
class GearParts:
    """``parts``: {link name: its gear Part}; ``pivot``: {link name: the pivot point}; ``pairs``: (driving part,
    driven part) names that mesh (one layer)."""
    parts: dict = field(default_factory=dict)
    pivot: dict = field(default_factory=dict)
    pairs: list = field(default_factory=list)


def _rotate(xy, angle, centre):
    c, s = math.cos(angle), math.sin(angle)
    return np.stack([centre[0] + c * xy[:, 0] - s * xy[:, 1], centre[1] + s * xy[:, 0] + c * xy[:, 1]], axis=-1)


def cut_outlines(design):
    """(driving (k, 2), driven (k, 2), module) the design's envelope tooth outlines in each gear's frame (m)."""
    from ..gears.teeth import cut_pair
    pair = design.pair()
    gt = cut_pair(pair, module=design.module if design.method == "envelope" else None, teeth=design.driving_teeth,
                  pressure_angle=design.pressure_angle, addendum=design.addendum, clearance=design.clearance,
                  backlash=design.backlash, tip_radius=design.tip_radius, profile_shift=design.profile_shift,
                  print_clearance=design.print_clearance, states_per_tooth=STATES_PER_TOOTH)
    return gt.driving.xy, gt.driven.xy, gt.tooth.module


def _thin(xy, tol):
    """The outline with the vertices Douglas–Peucker keeps within ``tol`` (m), counter-clockwise."""
    import shapely
    poly = shapely.Polygon(xy).simplify(tol, preserve_topology=True)
    ring = poly.exterior
    if not ring.is_ccw:
        ring = shapely.LinearRing(list(ring.coords)[::-1])
    return np.asarray(ring.coords)[:-1]


def gear_parts(mechanism, plan, frames, settings) -> GearParts:
    """The gear plates of every ``[[gears]]`` pair in their links' frames. SpecError (at ``gears[i]``) for a pair
    without a design file, an internal pair, or a design whose centre distance or law is not the mechanism's."""
    from ..io.gear_file import load_design
    out = GearParts()
    if not mechanism.gears:
        return out
    pos = np.asarray(frames.sketch_state.pos).reshape(plan.n_points, 2)
    index = {n: b for b, n in enumerate(plan.body_names)}
    for i, gp in enumerate(mechanism.gears):
        where = f"gears[{i}]"
        if gp.design is None:
            raise SpecError([(f"{where}.law", "assur make cuts gear plates from a gear design file "
                                              "(law = \"design.toml\", format assur-gears/1); this pair has none")])
        if gp.mesh != "external":
            raise SpecError([(f"{where}.mesh", "assur make cuts external gear pairs only")])
        design = load_design(gp.design)
        (pa, _), (pb, _) = gear_ends(mechanism, gp)
        oa, ob = pos[plan.point_index(pa)], pos[plan.point_index(pb)]
        d = float(np.hypot(*(ob - oa)))
        if abs(d - design.centre_distance) > 1e-6 * max(d, 1e-3):
            raise SpecError([(where, f"the design's centre distance {design.centre_distance * 1e3:.4f} mm is not "
                                     f"the pivots' {pa}–{pb} distance {d * 1e3:.4f} mm")])
        law = design.pair().law
        phi = np.linspace(0.0, 2.0 * math.pi, 64, endpoint=False)
        off = np.max(np.abs(np.asarray(law(phi)) - gp.law.evaluate(phi)[0]))
        if off > 1e-6:
            raise SpecError([(where, f"the design file's law differs from the pair's by {math.degrees(off):.3g}°")])
        xa, xb, module = cut_outlines(design)
        alpha = math.atan2(ob[1] - oa[1], ob[0] - oa[0])
        theta0 = float(np.asarray(law(np.asarray(gp.phase))))
        placed = {gp.a: (_rotate(xa, alpha + gp.phase, oa), pa), gp.b: (_rotate(xb, alpha - theta0, ob), pb)}
        names = []
        for link, (world, pivot) in placed.items():
            if link in out.parts:
                raise SpecError([(where, f"the link {link!r} already carries a gear: assur make cuts one gear "
                                         "per link")])
            b = index[link]
            local = frames.to_local(b, _thin(world, OUTLINE_TOLERANCE))
            part = Part(file_name(f"gear_{link}"), "gear", b, link, Shape2D(polygons=(local,)), settings.thickness,
                        material=settings.material, density=settings.density,
                        note=f"{design.driving_teeth if link == gp.a else design.driven_teeth} teeth, module "
                             f"{module * 1e3:.4g} mm ({gp.name})", region_tolerance=REGION_TOLERANCE * module)
            out.parts[link], out.pivot[link] = part, pivot
            names.append(part.name)
        out.parts[gp.a].partner, out.parts[gp.b].partner = names[1], names[0]
        out.pairs.append((names[0], names[1]))
    return out


__all__ = ["GearParts", "cut_outlines", "gear_parts"]
