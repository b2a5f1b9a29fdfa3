"""The parts of a planar mechanism, drawn flat in their bodies' frames, before they get their layers.

- every moving link becomes a plate: the convex hull of its joint bosses (a slender bar for a binary link), with
  a hole at each joint; a link that carries a gear of a ``[[gears]]`` pair gets the gear plate
  (:mod:`assur.parts.gearplates`) and a plate only when it also joins other links;
- a pin-in-slot (``[[prismatic]] point``) becomes a block on the pin, riding in a slot of its guide: a slot in the
  base or top plate for a frame guide, a slot housing added to the guide's plate for a moving guide;
- an actuator becomes a cylinder plate with a slot and a rod plate carrying two guide pins in that slot;
- every joint gets a pin through the parts it holds (the driver's pivot: the motor shaft).

:class:`Design` holds them: the parts that take a layer (``stack``), the blocks that ride in the base or top plate
(``sided``), the pins, the pairs that share a layer by design and the frame pins whose side is free.
"""
from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from ..errors import SpecError
from ..model.mechanism import FRAME
from .motion import joints
from .shapes import Part, Shape2D, file_name, rectangle


@dataclass(eq=False)
class PinSpec:
    """A pin at ``joint``: its part, the parts it goes through (``through``: stack parts and sided blocks by name)
    and whether the frame holds it (``frame``: its other end sits in the base or the top plate)."""
    part: Part
    through: list
    frame: bool = False
    driver: bool = False


@dataclass(eq=False)
class Design:
    """The parts before layering. ``stack``: parts that take a layer; ``sided``: blocks riding in a slot of the
    base or top plate; ``pins``; ``same_layer``: (a, b) part names that share a layer (a gear pair, a block in a
    moving guide); ``frame_slots``: (block name, x0, y0, x1, y1, width) slots of frame guides (sketch frame);
    ``driver``: (joint, body) of the turning crank's pivot, or None."""
    stack: list = field(default_factory=list)
    sided: list = field(default_factory=list)
    pins: list = field(default_factory=list)
    same_layer: list = field(default_factory=list)
    frame_slots: list = field(default_factory=list)
    driver: tuple | None = None

    def part(self, name: str) -> Part:
        for p in self.stack + self.sided + [pin.part for pin in self.pins]:
            if p.name == name:
                return p
        raise KeyError(name)


def _turning_driver(mechanism, plan):
    """The rotary driver whose input turns over the run (speed ≠ 0), or None."""
    for k, d in enumerate(mechanism.drivers):
        if d.kind == "rotary" and plan.speeds[k] != 0:
            return d
    return None


def build(mechanism, plan, frames, settings) -> Design:
    """The parts of ``mechanism`` in their bodies' frames (``frames``: :class:`~assur.parts.motion.BodyFrames`
    over the run) with the sizes of ``settings``. SpecError for what cannot be made (a link sliding on a guide,
    an actuator whose stroke is longer than its closed length)."""
    from .gearplates import gear_parts
    s = settings
    hinged = joints(mechanism, plan)
    pos = np.asarray(frames.sketch_state.pos).reshape(plan.n_points, 2)
    names = plan.body_names
    index = {n: b for b, n in enumerate(names)}
    design = Design()
    for k, pr in enumerate(mechanism.prismatic):
        if pr.link is not None:
            raise SpecError([(f"prismatic[{k}].link", "assur make builds pins in slots (point = ...); a link "
                                                      "sliding on a guide is not made yet")])
    driver = _turning_driver(mechanism, plan)
    gears = gear_parts(mechanism, plan, frames, s)          # {link: Part}, pairs
    design.same_layer.extend(gears.pairs)
    hole = s.pin + s.hole_allowance
    shaft_hole = s.shaft + s.hole_allowance

    def local(b, point):
        return frames.to_local(b, pos[plan.point_index(point)])

    def hole_of(point, b):
        x, y = local(b, point)
        return (float(x), float(y), hole)

    def bores(points, b):
        """(holes, D-bores) of body b at ``points``: the turning crank's pivot is a D-bore for the motor's
        shaft (the crank turns with it), every other joint a round hole for its pin."""
        holes, flats = [], []
        for p in points:
            x, y = local(b, p)
            if driver is not None and p == driver.pivot and names[b] == driver.link:
                flats.append((float(x), float(y), shaft_hole, s.shaft_flat_distance + 0.5 * s.hole_allowance))
            else:
                holes.append((float(x), float(y), hole))
        return tuple(holes), tuple(flats)

    plate_of: dict[int, Part] = {}
    # -- link plates and gear plates ------------------------------------------------------------------------
    for lk in mechanism.links:
        if lk.name == FRAME or lk.name not in index:
            continue
        b = index[lk.name]
        pts = [local(b, p) for p in lk.points]
        joints_here = [p for p in lk.points if p in hinged]
        gear = gears.parts.get(lk.name)
        if gear is not None:
            holes, flats = bores([p for p in joints_here if p == gears.pivot[lk.name]], b)
            gear.shape = Shape2D(gear.shape.hulls, gear.shape.polygons, holes, flats=flats)
            design.stack.append(gear)
            if all(p == gears.pivot[lk.name] for p in joints_here):
                continue                                        # the gear is the whole link
        # the boss about the motor shaft keeps the wall a pin's boss has
        shaft_boss = max(s.boss, 0.5 * s.shaft + s.boss - 0.5 * s.pin)
        radii = [shaft_boss if driver is not None and p == driver.pivot and lk.name == driver.link else s.boss
                 for p in lk.points]
        hulls = (tuple((float(x), float(y), r) for (x, y), r in zip(pts, radii)),)
        holes, flats = bores(joints_here, b)
        shape = Shape2D(hulls=hulls, holes=holes, flats=flats)
        part = Part(file_name(f"plate_{lk.name}"), "plate", b, lk.name, shape, s.thickness,
                    material=s.material, density=s.density)
        plate_of[b] = part
        design.stack.append(part)
    # -- pins in slots: blocks and guides --------------------------------------------------------------------
    _slides(mechanism, plan, frames, s, design, plate_of, local, hole_of)
    # -- actuators -------------------------------------------------------------------------------------------
    _actuators(mechanism, plan, frames, s, design, local, hole_of)
    # -- pins at the joints ----------------------------------------------------------------------------------
    by_body: dict[int, list] = {}
    for p in design.stack + design.sided:
        by_body.setdefault(p.body, []).append(p)
    for point, bodies in hinged.items():
        through = []
        for b in bodies:
            if b == 0:
                continue
            for p in by_body.get(b, ()):
                lx, ly = local(b, point)
                if any(abs(hx - lx) < 1e-12 + 1e-9 * s.width and abs(hy - ly) < 1e-12 + 1e-9 * s.width
                       for hx, hy, _ in p.shape.bores()):
                    through.append(p.name)
        carrier = next(b for b in bodies if b != 0)
        is_driver = driver is not None and point == driver.pivot and index.get(driver.link) in bodies
        d = s.shaft if is_driver else s.pin
        x, y = local(carrier, point)
        trim = ((float(x), float(y), d + s.shaft_allowance, s.shaft_flat_distance + 0.5 * s.shaft_allowance),) \
            if is_driver else ()
        pin = Part(file_name(f"{'shaft' if is_driver else 'pin'}_{point}"), "pin", carrier, names[carrier],
                   Shape2D(hulls=(((float(x), float(y), 0.5 * (d + s.shaft_allowance)),),), trim=trim), 0.0,
                   joint=point, holds=tuple(names[b] for b in (carrier,) + tuple(b for b in bodies if b != carrier)),
                   reach=s.sleeve, material="steel")
        if is_driver:
            pin.note = f"motor shaft ⌀{d * 1e3:g} mm"
            design.driver = (point, carrier)
        design.pins.append(PinSpec(pin, through, frame=0 in bodies, driver=is_driver))
    return design


def _travel(frames, guide: int, point_xy_world) -> np.ndarray:
    """(n, 2) the world positions ``point_xy_world (n, 2)`` of the run in body ``guide``'s frame."""
    c, s_ = np.cos(frames.angle[:, guide]), np.sin(frames.angle[:, guide])
    d = point_xy_world - frames.origin[:, guide]
    return np.stack([c * d[:, 0] + s_ * d[:, 1], -s_ * d[:, 0] + c * d[:, 1]], axis=-1)


def _slides(mechanism, plan, frames, s, design, plate_of, local, hole_of):
    """Blocks of the pins in slots, and the slots: in the base/top plate (frame guides) or added to the guide's
    plate (moving guides)."""
    from ..engine.planar.geometry import geometry
    names = plan.body_names
    index = {n: b for b, n in enumerate(names)}
    _, lines = geometry(plan, frames.params)
    length, width = 2.0 * s.width, s.width
    for k, pr in enumerate(mechanism.prismatic):
        bname = f"{pr.name}.block"
        if pr.point is None or bname not in index:
            continue
        blk, guide = index[bname], index[pr.guide]
        line = next(i for i, rec in enumerate(plan.lines) if rec[0] == "prismatic" and rec[1] == pr.name)
        _, u_guide, _, u_block = lines[line]
        ub = np.array([float(np.real(u_block)), float(np.imag(u_block))])
        ug = np.array([float(np.real(u_guide)), float(np.imag(u_guide))])
        shape = Shape2D(polygons=(rectangle((0.0, 0.0), ub, length, width),), holes=(hole_of(pr.point, blk),))
        block = Part(file_name(f"block_{pr.name}"), "block", blk, bname, shape, s.thickness,
                     material=s.material, density=s.density)
        # the block centre's travel along the line, in the guide's frame
        world = frames.origin[:, blk]
        travel = _travel(frames, guide, world) if guide != 0 else world
        along = travel @ ug
        a0, a1 = float(along.min()), float(along.max())
        base = travel[int(np.argmin(along))] - a0 * ug
        ends = base + np.outer([a0 - 0.5 * length, a1 + 0.5 * length], ug)
        # a slot with round ends about these centres holds the block's whole travel with its sliding fit
        slot = (float(ends[0, 0]), float(ends[0, 1]), float(ends[1, 0]), float(ends[1, 1]), width + s.slide_fit)
        if guide == 0:
            block.thickness = s.base_thickness
            design.sided.append(block)
            design.frame_slots.append((block.name,) + slot)
            continue
        host = plate_of.get(guide)
        if host is None:
            raise SpecError([(f"prismatic[{k}].guide", f"the guide {pr.guide!r} has no plate to hold the slot")])
        x0, y0, x1, y1, w = slot
        wall = s.boss
        host.shape = Shape2D(host.shape.hulls + (((x0, y0, 0.5 * w + wall), (x1, y1, 0.5 * w + wall)),),
                             host.shape.polygons, host.shape.holes, host.shape.slots + (slot,), host.shape.flats)
        block.partner, host.partner = host.name, block.name
        design.stack.append(block)
        design.same_layer.append((block.name, host.name))


def _actuators(mechanism, plan, frames, s, design, local, hole_of):
    """Each actuator: a cylinder plate from its first hinge with a slot along the axis, and a rod plate from its
    second hinge carrying two guide pins that ride in the slot (a prismatic pair made of pins in a slot)."""
    names = plan.body_names
    index = {n: b for b, n in enumerate(names)}
    pos = frames
    for ac in mechanism.actuators:
        cyl, rod = index.get(f"{ac.name}.cylinder"), index.get(f"{ac.name}.rod")
        if cyl is None or rod is None:
            continue
        gap = pos.origin[:, rod] - pos.origin[:, cyl]
        stroke = np.hypot(gap[:, 0], gap[:, 1])
        lmin, lmax = float(stroke.min()), float(stroke.max())
        margin, spacing = s.width, 1.5 * s.width
        p1 = lmin - margin                      # the guide pins' distances back from the rod's hinge
        p2 = p1 - spacing
        if p2 < 2.0 * s.boss:
            raise SpecError([(f"actuators.{ac.name}", f"its shortest length {lmin * 1e3:.1f} mm leaves no room for "
                                                      f"a rod with two guide pins ({(margin + spacing + s.width) * 1e3:.1f}"
                                                      " mm at least)")])
        x_lo, x_hi = lmin - p1, lmax - p2       # the guide pins' travel in the cylinder's frame
        slot = (x_lo - 0.5 * s.pin, 0.0, x_hi + 0.5 * s.pin, 0.0, s.pin + s.slide_fit)
        cyl_shape = Shape2D(hulls=(((0.0, 0.0, s.boss), (x_hi + 0.5 * s.pin + s.boss, 0.0, s.boss)),),
                            holes=(hole_of(ac.between[0], cyl),), slots=(slot,))
        rod_shape = Shape2D(hulls=(((0.0, 0.0, s.boss), (-p1, 0.0, s.boss)),),
                            holes=(hole_of(ac.between[1], rod), (-p1, 0.0, s.pin + s.hole_allowance),
                                   (-p2, 0.0, s.pin + s.hole_allowance)))
        cpart = Part(file_name(f"cylinder_{ac.name}"), "cylinder", cyl, names[cyl], cyl_shape, s.thickness,
                     material=s.material, density=s.density)
        rpart = Part(file_name(f"rod_{ac.name}"), "rod", rod, names[rod], rod_shape, s.thickness,
                     material=s.material, density=s.density)
        design.stack += [cpart, rpart]
        for j, p in enumerate((p1, p2)):
            pin = Part(file_name(f"guidepin_{ac.name}_{j + 1}"), "pin", rod, names[rod],
                       Shape2D(hulls=(((-p, 0.0, 0.5 * (s.pin + s.shaft_allowance)),),)), 0.0,
                       joint=ac.name, holds=(names[rod], names[cyl]), reach=s.sleeve, material="steel",
                       note=f"guide pin of {ac.name} in the cylinder's slot")
            design.pins.append(PinSpec(pin, [cpart.name, rpart.name]))


__all__ = ["Design", "PinSpec", "build"]
