"""Writing pylinkage's Mechanism JSON (``pylinkage.mechanism.mechanism_from_json`` reads it and simulates it).

Joints are named as assur's points: frame points are ``ground`` joints, a pin in a slot of the frame a
``prismatic`` joint (its ``axis`` and a ``line_point`` of the slot), every other point a ``revolute`` joint, at the
mechanism's assembled position in its file length unit. The frame is the ``ground`` link, each crank a ``driver``
link turning about its pivot at its speed (rad/s read as pylinkage's rad per step) from its drawn angle, every other
link a ``link``. An ``assur`` block (ignored by pylinkage) keeps the units, the description and the drivers' names
so that reading the file back gives the same description.

Not representable (a located error): a crank link with more than two points (pylinkage turns a two-joint driver),
slots in moving links and translating links, actuators and linear drivers, gear pairs, spatial mechanisms.
"""
from __future__ import annotations

import json
import math

from ..errors import SpecError
from ..model.mechanism import FRAME, Mechanism
from .common import assembled, drivers, frame_slots, refuse_extras

FORMAT_NAME = "pylinkage's Mechanism JSON"


def to_dict(m: Mechanism) -> dict:
    """The pylinkage Mechanism dict of ``m`` (see the module docstring); SpecError for what it cannot hold."""
    refuse_extras(m, FORMAT_NAME)
    xy = assembled(m)
    cranks = drivers(m, xy)
    slots = {s.point: s for s in frame_slots(m, xy, FORMAT_NAME)}
    frame = set(m.link(FRAME).points)
    joints = []
    for name, _ in m.points:
        j = {"id": name, "type": "ground" if name in frame else "revolute", "position": list(xy[name])}
        if name in slots:
            s = slots[name]
            j |= {"type": "prismatic", "axis": [math.cos(s.angle), math.sin(s.angle)], "line_point": list(s.at),
                  "slide_distance": 0.0}
        joints.append(j)
    by_link = {c.link: c for c in cranks}
    links = [{"id": FRAME, "type": "ground", "joints": list(m.link(FRAME).points)}]
    for lk in m.links:
        if lk.name == FRAME:
            continue
        t = {"id": lk.name, "type": "link", "joints": list(lk.points)}
        c = by_link.get(lk.name)
        if c is not None:
            if len(lk.points) != 2:
                raise SpecError([(f"links.{lk.name}", "pylinkage's driver link turns two joints only: this crank "
                                                      f"carries {len(lk.points)} points")])
            t |= {"type": "driver", "joints": [c.pivot, c.arm], "angular_velocity": c.omega,
                  "initial_angle": c.angle, "motor_joint": c.pivot}
        links.append(t)
    return {"name": m.name, "joints": joints, "links": links, "ground": FRAME,
            "assur": {"format": m.format, "units": {"length": m.units.length}, "description": m.description,
                      "drivers": {c.link: c.name for c in cranks}}}


def write(m: Mechanism, path) -> str | None:
    """Write the pylinkage JSON of ``m`` to ``path`` (atomically)."""
    from ..io.output import atomic_file
    text = json.dumps(to_dict(m), indent=2, ensure_ascii=False, allow_nan=False) + "\n"
    with atomic_file(path) as tmp:
        tmp.write_text(text, encoding="utf-8")
    return None


__all__ = ["FORMAT_NAME", "to_dict", "write"]
