"""Writing mechanism files (TOML, ``format = "assur/1"``): numbers back in the file's units, each with the
fewest digits that load back to exactly the same SI value.
"""
from __future__ import annotations

from ..model.mechanism import Mechanism
from . import units as U
from .output import atomic_file
from .toml_writer import dumps as write_toml


def _out(si: float, factor: float = 1.0) -> float | int:
    """``si / factor`` in file units with the fewest digits that load back to exactly ``si``."""
    x = si / factor
    for digits in (15, 16, 17):
        y = float(f"{x:.{digits}g}")
        if y * factor == si or y == x and digits == 17:
            break
    return int(y) if y.is_integer() and abs(y) < 2**53 else y


def as_dict(m: Mechanism) -> dict:
    """The mechanism as a document dict (file units), ready for the TOML writer."""
    L, A = U.LENGTH[m.units.length], U.ANGLE[m.units.angle]
    d: dict = {"format": m.format}
    if m.name:
        d["name"] = m.name
    if m.description:
        d["description"] = m.description
    if m.dimension != 2:
        d["dimension"] = m.dimension
    d["units"] = {"length": m.units.length, "angle": m.units.angle}
    d["points"] = {n: [_out(c, L) for c in xy] for n, xy in m.points}
    links = {}
    for lk in m.links:
        if lk.length is None and not lk.place:
            links[lk.name] = list(lk.points)
        else:
            t: dict = {"points": list(lk.points)}
            if lk.length is not None:
                t["length"] = _out(lk.length, L)
            if lk.place:
                t["place"] = {pn: {"from": p.origin, "toward": p.toward, "distance": _out(p.distance, L),
                                   "angle": _out(p.angle, A)} for pn, p in lk.place}
            links[lk.name] = t
    d["links"] = links
    if m.prismatic:
        out = []
        for pr in m.prismatic:
            t = {"name": pr.name, "guide": pr.guide, "through": pr.through, "angle": _out(pr.angle, A)}
            if pr.offset:
                t["offset"] = _out(pr.offset, L)
            if pr.point is not None:
                t["point"] = pr.point
            else:
                t["link"] = pr.link
            out.append(t)
        d["prismatic"] = out
    if m.actuators:
        d["actuators"] = {a.name: {"between": list(a.between)} for a in m.actuators}
    if m.drivers:
        out = []
        for dr in m.drivers:
            if dr.kind == "rotary":
                out.append({"name": dr.name, "kind": "rotary", "link": dr.link, "pivot": dr.pivot, "arm": dr.arm,
                            "zero": _out(dr.zero, A), "sense": "cw" if dr.sense < 0 else "ccw",
                            "speed": U.format_speed(dr.speed, "rotary", m.units)})
            else:
                t = {"name": dr.name, "kind": "linear", "actuator": dr.actuator,
                     "speed": U.format_speed(dr.speed, "linear", m.units)}
                if dr.range is not None:
                    t["range"] = [_out(v, L) for v in dr.range]
                if dr.law is not None:
                    t["law"] = {"time": [_out(v) for v in dr.law.times], "length": [_out(v, L) for v in dr.law.values],
                                "interpolation": dr.law.interpolation}
                out.append(t)
        d["drivers"] = out
    if m.branches:
        d["branches"] = {b.point: {"side": b.side, "of": list(b.of)} for b in m.branches}
    if m.joints:
        with_axes = any(j.axis is not None for j in m.joints)   # then all as tables: the writer keeps their order
        d["joints"] = {j.point: ({"kind": j.kind} | ({} if j.axis is None else {"axis": [_out(c) for c in j.axis]})
                                 if with_axes else j.kind) for j in m.joints}
    if m.gait is not None:
        g = {"foot": m.gait.foot, "ground": [_out(c) for c in m.gait.ground]}
        if m.gait.up is not None:
            g["up"] = [_out(c) for c in m.gait.up]
        g["phases"] = [_out(p, A) for p in m.gait.phases]
        d["gait"] = g
    return d


def dumps(m: Mechanism) -> str:
    """The mechanism as TOML text."""
    return write_toml(as_dict(m))


def dump(m: Mechanism, path=None) -> str:
    """The mechanism as TOML text; written to ``path`` (atomically) when given."""
    text = dumps(m)
    if path is not None:
        with atomic_file(path) as tmp:
            tmp.write_text(text, encoding="utf-8")
    return text


__all__ = ["as_dict", "dump", "dumps", "to_dict"]


#: the former name of :func:`as_dict` (the pair of ``mechanism_file.from_dict``)
to_dict = as_dict
