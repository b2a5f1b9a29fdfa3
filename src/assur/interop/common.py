"""What the exporters share: a mechanism's assembled position in its file units, its cranks and slots as the peers
see them, and the checks that refuse what a format cannot hold (one located SpecError, never a silent drop).
"""
from __future__ import annotations

import math
import warnings
from dataclasses import dataclass

import numpy as np

from ..errors import SpecError
from ..io import units as U
from ..model.mechanism import FRAME, Mechanism
from .draft import InteropWarning


@dataclass(frozen=True)
class Driven:
    """A crank as a peer sees it: ``link`` turning about the frame point ``pivot``; ``arm`` the point it carries;
    ``angle`` the absolute direction pivot → arm in the assembled sketch (rad); ``omega`` the signed angular speed
    (rad/s, counter-clockwise positive); ``name`` the driver's."""
    name: str
    link: str
    pivot: str
    arm: str
    angle: float
    omega: float


@dataclass(frozen=True)
class FrameSlot:
    """A pin ``point`` in a slot of the frame: the line through ``at`` (file length unit) with direction ``angle``
    (rad)."""
    name: str
    point: str
    at: tuple[float, float]
    angle: float


def assembled(m: Mechanism) -> dict[str, tuple[float, float]]:
    """Every point's position (file length unit) in the mechanism's own assembly at its sketch input: the sketch
    where the file gives dimensions that differ from it."""
    from ..engine import compile as compile_, solve
    if m.dimension != 2:
        raise SpecError([("dimension", "a spatial mechanism (dimension = 3) cannot be exported to a planar tool")])
    plan = compile_(m)
    st = solve(plan, inputs=plan.sketch_inputs, order=0, on_unbuildable="nan")
    pos = np.asarray(st.pos).reshape(-1, plan.n_points, 2)[0]
    if not np.all(np.isfinite(pos)):
        raise SpecError([("points", "the mechanism cannot be assembled at its sketch input")])
    L = U.LENGTH[m.units.length]
    names = set(m.point_names)
    return {n: (float(pos[i, 0]) / L, float(pos[i, 1]) / L) for i, n in enumerate(plan.point_names) if n in names}


def drivers(m: Mechanism, xy: dict) -> list[Driven]:
    """The rotary drivers as :class:`Driven` (SpecError for a linear one)."""
    out = []
    for i, dr in enumerate(m.drivers):
        if dr.kind != "rotary":
            raise SpecError([(f"drivers[{i}]", f"a linear driver ('{dr.name}', an actuator's length) is not "
                                              "representable here: only cranks are")])
        (px, py), (ax, ay) = xy[dr.pivot], xy[dr.arm]
        out.append(Driven(dr.name, dr.link, dr.pivot, dr.arm, math.atan2(ay - py, ax - px), dr.sense * dr.speed))
    return out


def frame_slots(m: Mechanism, xy: dict, fmt: str) -> list[FrameSlot]:
    """The pins in slots of the frame (SpecError, located, for any other prismatic pair)."""
    out = []
    L = U.LENGTH[m.units.length]
    for i, pr in enumerate(m.prismatic):
        if pr.guide != FRAME or pr.point is None:
            what = f"link '{pr.link}' translating on '{pr.guide}'" if pr.link else f"a slot in the moving link '{pr.guide}'"
            raise SpecError([(f"prismatic[{i}]", f"{what} is not representable in {fmt}: only pins in slots of the "
                                                "frame are")])
        tx, ty = xy[pr.through]
        at = (tx - pr.offset / L * math.sin(pr.angle), ty + pr.offset / L * math.cos(pr.angle))
        out.append(FrameSlot(pr.name, pr.point, at, pr.angle))
    return out


def refuse_extras(m: Mechanism, fmt: str, *, actuators: bool = True) -> None:
    """SpecError for what no exporter here writes (gear and cam pairs, actuators); an InteropWarning for what is
    left out (masses, loads, the gait)."""
    if m.gears:
        raise SpecError([("gears", f"gear pairs are not representable in {fmt}")])
    if m.cams:
        raise SpecError([("cams", f"cam pairs are not representable in {fmt}")])
    if actuators and m.actuators:
        raise SpecError([(f"actuators.{m.actuators[0].name}", f"linear actuators are not representable in {fmt}")])
    dropped = [what for what, present in (("masses, loads and friction ([dynamics])", m.dynamics is not None),
                                          ("the gait of a walking leg ([gait])", m.gait is not None)) if present]
    if dropped:
        warnings.warn(f"{fmt} cannot hold {' nor '.join(dropped)}: left out of the export", InteropWarning,
                      stacklevel=3)


def one_driver(m: Mechanism, fmt: str) -> None:
    """SpecError unless the mechanism has exactly one driver (a format with one input)."""
    if len(m.drivers) != 1:
        raise SpecError([("drivers", f"{fmt} drives a mechanism by one input: this one has {len(m.drivers)}")])


__all__ = ["Driven", "FrameSlot", "assembled", "drivers", "frame_slots", "one_driver", "refuse_extras"]
