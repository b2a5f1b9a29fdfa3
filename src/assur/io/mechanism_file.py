"""Mechanism files (TOML, ``format = "assur/1"``): load with full validation, dump, round-trip.

Every problem in a file is collected and raised at once as one :class:`~assur.errors.SpecError`
whose lines name the location, e.g. ``links.coupler[2]: unknown point 'Q' (known: A, B, O1)``.
Numbers are converted to SI at load (``[units]``) and back to the file's units at dump.
Each section has its reader in :mod:`assur.io.mechanism_sections`; :func:`from_dict` calls them in turn.
"""
from __future__ import annotations

import math
import warnings

from ..errors import SketchWarning
from ..model.mechanism import FRAME, Mechanism, Units
from ..tolerances import DEFAULT as TOL
from . import units as U
from .cam_pairs import read_cam_pairs
from .dynamics_file import read_dynamics
from .gear_pairs import read_gear_pairs
from .make_file import read_make
from .mechanism_sections import (MAX_MAGNITUDE, ldata_points, read_actuators, read_branches, read_drivers, read_gait,
                                 read_joints, read_links, read_points, read_prismatic)
from .mechanism_writer import as_dict, dump, dumps, to_dict
from .motor_file import read_motor
from .problems import Problems
from .toml_reader import parse_toml, read_text, read_toml

FORMAT = "assur/1"
_TOP = {"format", "name", "description", "units", "points", "links", "prismatic", "actuators", "drivers",
        "branches", "joints", "gait", "style", "dimension", "dynamics", "loads", "gears", "cams", "motor", "make"}


def load(path) -> Mechanism:
    """Read a mechanism file. Raises SpecError (every problem, with its location)."""
    return loads(read_text(path), source=str(path))


def loads(text: str, source: str | None = None) -> Mechanism:
    """Read a mechanism from TOML text (``source`` names it in messages). Raises SpecError."""
    return from_dict(parse_toml(text, source), source)


def from_dict(data: dict, source: str | None = None) -> Mechanism:
    """A Mechanism from a parsed document. Raises SpecError listing every problem with its location.

    Each section has its reader below, called in the file's order of dependence (points before links, links
    before pairs and drivers …); every reader adds its problems to one list, raised at the end."""
    P = Problems()
    P.unknown_keys(data, sorted(_TOP))
    dimension = _read_format(data, P)
    ulen, uang = U.parse_units(data, P, "m")
    units = Units(ulen, uang)
    L, A = U.LENGTH[ulen], U.ANGLE[uang]
    points, point_names = read_points(data, P, dimension, L)
    links, ldata = read_links(data, P, point_names, L, A)
    link_names = {lk.name for lk in links} | set(ldata)
    link_points = {lk.name: set(lk.points) for lk in links}
    prismatic = read_prismatic(data, P, point_names, link_names, link_points, L, A)
    actuators = read_actuators(data, P, point_names)
    drivers = read_drivers(data, P, units, ldata, link_names, link_points, {a.name for a in actuators})
    branches = read_branches(data, P, point_names, {pr.name for pr in prismatic} | {a.name for a in actuators})
    joints = read_joints(data, P, point_names, dimension, A)
    gait = read_gait(data, P, point_names, A)
    link_point_lists = {lk.name: lk.points for lk in links}
    frame_points = set(next((lk.points for lk in links if lk.name == FRAME), ()))
    gears = read_gear_pairs(data, P, angle_factor=A, link_points=link_point_lists, frame_points=frame_points,
                            source=source)
    if gears and dimension == 3:
        P.add("gears", "gear pairs need a planar mechanism (dimension = 2)")
    cams = read_cam_pairs(data, P, length_factor=L, angle_factor=A, link_points=link_point_lists,
                          frame_points=frame_points, prismatic=prismatic, drivers=drivers, points=dict(points))
    if cams and dimension == 3:
        P.add("cams", "cam pairs need a planar mechanism (dimension = 2)")
    dynamics = read_dynamics(data, P, units=units, dimension=dimension, length_factor=L, point_names=point_names,
                             links=links, prismatic=prismatic, actuators=actuators, drivers=drivers)
    make = read_make(data, P, units=units)
    if make is not None and dimension == 3:
        P.add("make", "assur make builds planar mechanisms (dimension = 2)")
    motor = read_motor(data["motor"], P, units, drivers) if "motor" in data else None
    _check_every_point_is_on_something(P, ldata, points, prismatic, actuators)
    name = _read_text(data, P, "name")
    desc = _read_text(data, P, "description")
    P.raise_if_any(source)
    m = Mechanism(name=name, points=tuple(points), links=tuple(links), prismatic=tuple(prismatic),
                  actuators=tuple(actuators), drivers=tuple(drivers), branches=tuple(branches),
                  joints=tuple(joints), gait=gait, dynamics=dynamics, gears=gears, cams=cams, description=desc,
                  units=units, dimension=dimension, motor=motor, make=make)
    _warn_lengths_off_the_sketch(m, L, source)
    return m


def _read_format(data, P) -> int:
    """``format`` (must be assur/1) and ``dimension`` (2 or 3; 2 after a problem)."""
    fmt = data.get("format")
    if fmt != FORMAT:
        P.add("format", f"must be '{FORMAT}': {fmt!r}")
    dimension = data.get("dimension", 2)
    if dimension not in (2, 3):
        P.add("dimension", f"must be 2 or 3: {dimension!r}")
        dimension = 2
    return dimension


def _read_text(data, P, key: str) -> str:
    """A free-text field (``name``, ``description``); '' when absent or after a problem."""
    text = data.get(key, "")
    if not isinstance(text, str):
        P.add(key, f"must be a string: {text!r}")
        text = ""
    return text

def _check_every_point_is_on_something(P, ldata, points, prismatic, actuators) -> None:
    """Every point must be on a link (as listed, even by a link with other problems), a slider or an actuator."""
    on_something = set()
    for spec in ldata.values():
        plist = spec if isinstance(spec, list) else (spec.get("points") if isinstance(spec, dict) else None)
        if isinstance(plist, list):
            on_something |= {p for p in plist if isinstance(p, str)}
    for pr in prismatic:
        if pr.point:
            on_something.add(pr.point)
    for ac in actuators:
        on_something |= set(ac.between)
    for name, _ in points:
        if name not in on_something:
            P.add(f"points.{name}", "is not on any link, slider or actuator")

def _warn_lengths_off_the_sketch(m: Mechanism, factor: float, source) -> None:
    """A SketchWarning for every ``length`` that differs from the sketch by more than
    ``tolerances.sketch_length_mismatch`` (the length is used; the sketch only chooses the assembly)."""
    for lk in m.links:
        if lk.length is None or len(lk.points) < 2:
            continue
        drawn = math.dist(m.sketch(lk.points[0]), m.sketch(lk.points[1]))
        if abs(drawn - lk.length) > TOL.sketch_length_mismatch * lk.length:
            unit = m.units.length
            warnings.warn(f"{source + ': ' if source else ''}links.{lk.name}.length: {lk.length / factor:.6g} {unit} "
                          f"is used, but the sketch draws {lk.points[0]}–{lk.points[1]} {drawn / factor:.6g} {unit} "
                          "long (the sketch only chooses the assembly branch)", SketchWarning, stacklevel=4)


__all__ = ["FORMAT", "MAX_MAGNITUDE", "as_dict", "dump", "dumps", "from_dict", "ldata_points", "load", "loads",
           "read_text", "read_toml", "to_dict"]
