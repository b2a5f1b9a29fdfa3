"""From the conflicts to the layer program, and from its layout to the stack: every part's layer and height, the
washers and spacer sleeves on the pins, the base plate (and a top plate when a frame end uses it) on standoffs,
and the motor mount.

Heights (m; z up, the base plate's top face at z = 0, plate thickness t, washer gap g, base thickness t_b):
layer k spans [g + k·(t + g), g + k·(t + g) + t]; the base [−t_b, 0]; the top plate sits one gap above the last
layer. A pin runs from the bottom of the lowest part it holds to the top of the highest; between two consecutive
parts it holds it carries a washer (adjacent layers) or a spacer sleeve (layers between), both of the washer's
outer diameter, which is the reach the conflict check kept clear.
"""
from __future__ import annotations

import numpy as np

from .layers import PinNeed, Program
from .settings import NEMA17, STEEL_DENSITY
from .shapes import Part, Shape2D, rectangle


def _groups(design) -> list[list[str]]:
    """The layered parts grouped by the pairs that share a layer by design (union-find)."""
    names = [p.name for p in design.stack]
    parent = {n: n for n in names}

    def root(n):
        while parent[n] != n:
            parent[n] = parent[parent[n]]
            n = parent[n]
        return n
    for a, b in design.same_layer:
        parent[root(a)] = root(b)
    out: dict[str, list[str]] = {}
    for n in names:
        out.setdefault(root(n), []).append(n)
    return list(out.values())


def program_of(design, conflicts) -> Program:
    """The layer program of ``design`` (:class:`~assur.parts.footprints.Design`) and its ``conflicts``."""
    groups = _groups(design)
    gid = {n: g for g, members in enumerate(groups) for n in members}
    edges = set()
    for a, b in conflicts.edges("parts"):
        g, h = gid[a], gid[b]
        edges.add((min(g, h), max(g, h)))
    sides = [f"frame end of {spec.part.name}" for spec in design.pins if spec.frame] + [p.name for p in design.sided]
    side_of_block = {p.name: sides.index(p.name) for p in design.sided}
    blocked: dict[str, set] = {}
    for a, b in conflicts.edges("pins"):
        blocked.setdefault(a, set()).add(gid[b])
    pins = []
    for spec in design.pins:
        ends = [side_of_block[n] for n in spec.through if n in side_of_block]
        if spec.frame:
            ends.append(sides.index(f"frame end of {spec.part.name}"))
        pins.append(PinNeed(spec.part.name, sorted({gid[n] for n in spec.through if n in gid}), ends,
                            sorted(blocked.get(spec.part.name, ()))))
    index = {p.name: j for j, p in enumerate(pins)}
    pin_edges = [(index[a], index[b]) for a, b in conflicts.edges("pin_pairs")]
    return Program(groups, edges, pins, pin_edges, sides)


def layer_z(settings, k: int) -> tuple[float, float]:
    """(z_min, z_max) of layer k (m)."""
    z0 = settings.washer + k * settings.pitch
    return z0, z0 + settings.thickness


def swept_box(frames, design) -> np.ndarray:
    """(2, 2) [[x_min, y_min], [x_max, y_max]] of everything that moves in the layers over the whole run, and of
    the frame ends (m, sketch frame)."""
    lo, hi = np.full(2, np.inf), np.full(2, -np.inf)
    for p in design.stack + [spec.part for spec in design.pins]:
        ring = np.asarray(p.region().exterior.coords)
        world = frames.to_world(p.body, ring)
        lo = np.minimum(lo, world.reshape(-1, 2).min(axis=0))
        hi = np.maximum(hi, world.reshape(-1, 2).max(axis=0))
    for _, x0, y0, x1, y1, w in design.frame_slots:
        for x, y in ((x0, y0), (x1, y1)):
            lo = np.minimum(lo, [x - w, y - w])
            hi = np.maximum(hi, [x + w, y + w])
    return np.array([lo, hi])


def assemble(design, program: Program, layout, frames, settings, *, motor: bool = True) -> list[Part]:
    """Every part with its ``layer`` and ``z`` set: the layered parts, the sided blocks, the pins with their
    washers and sleeves, the base plate, the top plate and its standoffs when used, and the motor mount."""
    s = settings
    L = layout.layers
    gid = {n: g for g, members in enumerate(program.groups) for n in members}
    out: list[Part] = []
    for p in design.stack:
        k = int(layout.layer[gid[p.name]])
        p.layer, p.z = k, layer_z(s, k)
        out.append(p)
    top_used = bool(np.any(layout.side))
    base_z = (-s.base_thickness, 0.0)
    top_z = (s.washer + L * s.pitch, s.washer + L * s.pitch + s.base_thickness)
    for p in design.sided:
        up = bool(layout.side[program.sides.index(p.name)])
        p.layer, p.z = (L, top_z) if up else (-1, base_z)
        out.append(p)
    base_holes, top_holes = [], []
    driver_side = None
    for spec, need in zip(design.pins, program.pins):
        pin = spec.part
        levels = [int(layout.layer[g]) for g in need.groups] + [L if layout.side[f] else -1 for f in need.ends]
        z_of = {k: (layer_z(s, k) if 0 <= k < L else base_z if k < 0 else top_z) for k in levels}
        lo, hi = min(levels), max(levels)
        pin.layer, pin.z = [lo, hi], (z_of[lo][0], z_of[hi][1])
        pin.thickness = pin.z[1] - pin.z[0]
        pin.density = STEEL_DENSITY
        out.append(pin)
        (x, y, _), = pin.shape.hulls[0]
        if spec.frame:
            frame_end = need.ends[-1]
            world = frames.at_sketch(pin.body, np.array([[x, y]]))[0]
            diameter = s.shaft + s.hole_allowance if spec.driver else s.pin + s.hole_allowance
            (top_holes if layout.side[frame_end] else base_holes).append((float(world[0]), float(world[1]),
                                                                          diameter, spec.driver))
            if spec.driver:
                driver_side = "top" if layout.side[frame_end] else "base"
        used = sorted(set(levels))
        for i, (k1, k2) in enumerate(zip(used, used[1:])):
            z0, z1 = z_of[k1][1], z_of[k2][0]
            sleeve = k2 > k1 + 1
            w = Part(f"{'sleeve' if sleeve else 'washer'}_{pin.name.split('_', 1)[1]}_{i + 1}", "washer", pin.body,
                     pin.body_name, Shape2D(hulls=(((x, y, 0.5 * s.washer_od),),),
                                            holes=((x, y, (s.shaft if spec.driver else s.pin) + s.hole_allowance),)),
                     z1 - z0, joint=pin.joint, holds=pin.holds, material=s.material if sleeve else "steel",
                     density=s.density if sleeve else STEEL_DENSITY,
                     note="spacer sleeve" if sleeve else "DIN 125-A washer")
            w.layer, w.z = [k1, k2], (z0, z1)
            out.append(w)
    box = swept_box(frames, design)
    out += _frame_plates(design, layout, program, s, box, base_holes, top_holes, top_used, base_z, top_z, L,
                         driver_side if motor else None)
    return out


def _motor_holes(x, y):
    """The NEMA 17 pilot and the four bolt holes about the shaft at (x, y): (x, y, diameter) each."""
    h = 0.5 * NEMA17["bolts"]
    return [(x, y, NEMA17["pilot"] + 0.0004)] + [(x + sx * h, y + sy * h, NEMA17["bolt_hole"])
                                                  for sx in (-1, 1) for sy in (-1, 1)]


def _frame_plates(design, layout, program, s, box, base_holes, top_holes, top_used, base_z, top_z, L,
                  driver_side):
    """The base plate, the top plate with four standoffs (when a frame end uses it) and the motor mount."""
    r_post = s.boss
    inset = r_post + s.clearance
    lo, hi = box[0] - inset, box[1] + inset                 # the standoffs' centres
    margin = r_post + s.clearance
    plate = rectangle(0.5 * (lo + hi), (1.0, 0.0), hi[0] - lo[0] + 2 * margin, hi[1] - lo[1] + 2 * margin)
    out = []
    posts = [(lo[0], lo[1]), (hi[0], lo[1]), (hi[0], hi[1]), (lo[0], hi[1])] if top_used else []
    screw = s.pin + s.hole_allowance                         # a screw (or threaded rod) of the pin's size
    post_holes = [(x, y, screw) for x, y in posts]
    for name, holes, z, level, used in (("base", base_holes, base_z, -1, True), ("top", top_holes, top_z, L,
                                                                                  top_used)):
        if not used:
            continue
        hole_list = [(x, y, d) for x, y, d, drv in holes if not drv]
        for x, y, d, drv in holes:
            if drv:              # the motor's pilot and bolt pattern (the shaft passes through the pilot)
                hole_list += _motor_holes(x, y)
        slots = tuple((x0, y0, x1, y1, w) for blk, x0, y0, x1, y1, w in design.frame_slots
                      if bool(layout.side[program.sides.index(blk)]) == (name == "top"))
        part = Part(name, name, 0, "frame", Shape2D(polygons=(plate,), holes=tuple(hole_list) + tuple(post_holes),
                                                    slots=slots), s.base_thickness, material=s.material,
                    density=s.density, note="frame plate")
        part.layer, part.z = level, z
        out.append(part)
    for i, (x, y) in enumerate(posts):
        post = Part(f"standoff_{i + 1}", "standoff", 0, "frame", Shape2D(hulls=(((x, y, r_post),),),
                                                                          holes=((x, y, screw),)),
                    top_z[0], material=s.material, density=s.density, note="standoff between base and top plate")
        post.layer, post.z = [-1, L], (0.0, top_z[0])
        out.append(post)
    if driver_side is not None:
        x, y, _, _ = next(h for h in (base_holes if driver_side == "base" else top_holes) if h[3])
        flange = NEMA17["flange"]
        mount = Part("motor_mount", "motor_mount", 0, "frame",
                     Shape2D(polygons=(rectangle((x, y), (1.0, 0.0), flange, flange),), holes=tuple(_motor_holes(x, y))),
                     s.thickness, material=s.material, density=s.density,
                     note="NEMA 17 flange: bolts to the plate with four M3 screws")
        if driver_side == "base":
            mount.layer, mount.z = -2, (base_z[0] - s.thickness, base_z[0])
        else:
            mount.layer, mount.z = L + 1, (top_z[1], top_z[1] + s.thickness)
        out.append(mount)
    return out


__all__ = ["assemble", "layer_z", "program_of", "swept_box"]
