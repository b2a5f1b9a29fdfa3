"""four-bar-rs designs (https://github.com/KmolYuan/four-bar-rs): its RON files of a planar four-bar.

A ``FourBar`` (and a motion ``MFourBar``) is ``(p1x, p1y, a, l1, l2, l3, l4, l5, g, stat[, e])``: the driver pivot
P1, the ground link's angle ``a`` and length ``l1`` (to the follower pivot P2), the driver ``l2`` (P1–P3), the
coupler ``l3`` (P3–P4), the follower ``l4`` (P2–P4), and the coupler point P5 at ``l5`` from P3 and ``g`` from
P3 → P4. Its input angle b is measured from the ground link (the crank points along a + b). ``stat`` is the circuit
(``c1``: P4 on the left of P3 → P2, ``c2``: on the right) and, for an open curve, the branch of the input's range.

Mapping: points P1…P5, links ``crank`` [P1, P3], ``coupler`` [P3, P4, P5], ``follower`` [P2, P4], the crank's
zero the ground link's angle (so assur's input is four-bar-rs's b), the sketch at b = 0 or, when b = 0 cannot
be assembled, at the middle of the input's range. A spherical four-bar (``SFourBar``: ``ox, oy, oz, r, …``) is
refused: its coupler point is a point of a coupler turning about the sphere's centre, which assur's spatial
solver (R–S–S dyads, a coupler that spins idly) does not hold. four-bar-rs has no units and no speed.
"""
from __future__ import annotations

import json
import math
import re

from ..errors import SpecError
from ..io import units as U
from ..model.mechanism import FRAME, Mechanism
from .common import assembled, drivers, frame_slots, one_driver, refuse_extras
from .draft import Crank, Draft, finite

FIELDS = ("p1x", "p1y", "a", "l1", "l2", "l3", "l4", "l5", "g", "stat")
SPHERICAL = ("ox", "oy", "oz", "r", "p1i", "p1j")
STATS = ("c1b1", "c1b2", "c2b1", "c2b2")
FORMAT_NAME = "a four-bar-rs RON file"
_META = re.compile(r"//\s*assur:\s*(\{.*\})\s*$", re.M)
_TOKEN = re.compile(r"\s*(?:(?P<num>[-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?)|(?P<name>[A-Za-z_][A-Za-z0-9_]*)"
                    r"|(?P<punct>[(),:]))")


def parse_ron(text: str) -> tuple[dict, dict]:
    """The fields of a flat RON struct ``[Name](field: value, …)`` (numbers and identifiers), and the ``// assur:``
    metadata comment if any. SpecError (with the field) for anything else."""
    meta = {}
    m = _META.search(text)
    if m:
        try:
            meta = json.loads(m.group(1))
        except ValueError:
            meta = {}
    text = re.sub(r"/\*.*?\*/", " ", text, flags=re.S)
    text = re.sub(r"//[^\n]*", " ", text).strip()
    pos, toks = 0, []
    while pos < len(text):
        t = _TOKEN.match(text, pos)
        if not t or t.end() == pos:
            raise SpecError([("", f"not a four-bar-rs RON struct: unexpected {text[pos:pos + 20]!r}")])
        toks.append((t.lastgroup, t.group(t.lastgroup)))
        pos = t.end()
        if len(toks) > 200:
            raise SpecError([("", "not a four-bar-rs RON struct: too many fields")])
    if toks and toks[0][0] == "name":
        toks = toks[1:]
    if not toks or toks[0] != ("punct", "(") or toks[-1] != ("punct", ")"):
        raise SpecError([("", "not a four-bar-rs RON struct: expected (field: value, …)")])
    fields, i = {}, 1
    while i < len(toks) - 1:
        if toks[i][0] != "name" or toks[i + 1] != ("punct", ":") or i + 2 >= len(toks) - 1:
            raise SpecError([("", f"not a four-bar-rs RON struct near {toks[i][1]!r}")])
        key, (kind, value) = toks[i][1], toks[i + 2]
        if kind == "punct":
            raise SpecError([(key, "a nested value is not a four-bar-rs field")])
        if key in fields:
            raise SpecError([(key, "is given twice")])
        fields[key] = float(value) if kind == "num" else value
        i += 3
        if toks[i] == ("punct", ","):
            i += 1
    return fields, meta


def read(text: str, units: str | None = None) -> Draft:
    """A Draft of a four-bar-rs RON four-bar (see the module docstring)."""
    f, meta = parse_ron(text)
    if all(k in f for k in ("ox", "oy", "oz")) or "p1i" in f:
        raise SpecError([("", "a spherical four-bar (four-bar-rs SFourBar) is not representable in assur: its "
                              "coupler turns about the sphere's centre, and assur's spatial solver holds R–S–S dyads "
                              "whose coupler spins idly, so the coupler point has no place")])
    missing = [k for k in FIELDS if k not in f]
    if missing:
        raise SpecError([(missing[0], f"is missing (a four-bar-rs FourBar has {', '.join(FIELDS)})")])
    unknown = [k for k in f if k not in FIELDS + ("e",)]
    if unknown:
        raise SpecError([(unknown[0], f"unknown field (a four-bar-rs FourBar has {', '.join(FIELDS)})")])
    v = {k: finite(f[k], k) for k in FIELDS if k != "stat"}
    stat = str(f["stat"]).lower()
    if stat not in STATS:
        raise SpecError([("stat", f"must be one of {', '.join(STATS)}: {f['stat']!r}")])
    for k in ("l1", "l2", "l3", "l4"):
        if v[k] <= 0:
            raise SpecError([(k, f"a link length must be positive: {v[k]!r}")])
    unit = units or meta.get("units") or "m"
    if unit not in U.LENGTH:
        raise SpecError([("units", f"must be one of {', '.join(U.LENGTH)}: {unit!r}")])
    names = meta.get("points") if isinstance(meta.get("points"), list) and len(meta.get("points")) == 5 else None
    links = meta.get("links") if isinstance(meta.get("links"), list) and len(meta.get("links")) == 3 else None
    d = Draft("four-bar-rs four-bar", length_unit=unit, angle_unit="deg", name=str(meta.get("name", "")),
              description=str(meta.get("description", "")))
    p = positions(v, stat, _sketch_input(v, stat))
    if p is None:
        raise SpecError([("", "the four-bar cannot be assembled (its loop does not close at any input)")])
    ids = names or ["P1", "P2", "P3", "P4", "P5"]
    for pid, xy in zip(ids, p):
        d.point(pid, *xy, pid)
    d.fix(ids[0])
    d.fix(ids[1])
    crank, coupler, follower = links or ("crank", "coupler", "follower")
    d.link(crank, [ids[0], ids[2]], "l2")
    d.link(coupler, [ids[2], ids[3], ids[4]] if v["l5"] else [ids[2], ids[3]], "l3")
    d.link(follower, [ids[1], ids[3]], "l4")
    speed = meta.get("speed") if isinstance(meta.get("speed"), (int, float)) else None
    d.cranks.append(Crank(crank, ids[0], ids[2], speed, name=str(meta.get("driver") or "input"), zero=v["a"]))
    if "e" in f:
        d.warn(f"e = {f['e']!r} (the motion four-bar's coupler angle) is not represented: the positions are")
    if stat.endswith("b2"):
        d.warn(f"stat = {stat}: the branch b2 selects a part of an open curve's input range; assur runs the whole "
               "assembly (give the range with --range)")
    return d


def positions(v: dict, stat: str, b: float):
    """P1…P5 at input ``b`` as four-bar-rs places them (None where the loop does not close)."""
    p1 = (v["p1x"], v["p1y"])
    p2 = (p1[0] + v["l1"] * math.cos(v["a"]), p1[1] + v["l1"] * math.sin(v["a"]))
    p3 = (p1[0] + v["l2"] * math.cos(v["a"] + b), p1[1] + v["l2"] * math.sin(v["a"] + b))
    dx, dy = p2[0] - p3[0], p2[1] - p3[1]
    r = math.hypot(dx, dy)
    l3, l4 = v["l3"], v["l4"]
    if r > l3 + l4 or r < abs(l3 - l4) or r == 0:
        return None
    c = (l3 * l3 - l4 * l4 + r * r) / (2 * r)
    s = math.sqrt(max(l3 * l3 - c * c, 0.0)) * (1 if stat.startswith("c1") else -1)
    ux, uy = dx / r, dy / r
    p4 = (p3[0] + c * ux - s * uy, p3[1] + c * uy + s * ux)
    th = math.atan2(p4[1] - p3[1], p4[0] - p3[0]) + v["g"]
    p5 = (p3[0] + v["l5"] * math.cos(th), p3[1] + v["l5"] * math.sin(th))
    return [p1, p2, p3, p4, p5]


def _height(v: dict, b: float) -> float:
    """How far P4 stands off the line P3 → P2 at input ``b`` (0 where the loop folds flat, -1 where it is open)."""
    p1 = (v["p1x"], v["p1y"])
    p2 = (p1[0] + v["l1"] * math.cos(v["a"]), p1[1] + v["l1"] * math.sin(v["a"]))
    p3 = (p1[0] + v["l2"] * math.cos(v["a"] + b), p1[1] + v["l2"] * math.sin(v["a"] + b))
    r = math.dist(p2, p3)
    if r == 0 or r > v["l3"] + v["l4"] or r < abs(v["l3"] - v["l4"]):
        return -1.0
    c = (v["l3"] ** 2 - v["l4"] ** 2 + r * r) / (2 * r)
    return math.sqrt(max(v["l3"] ** 2 - c * c, 0.0))


def _sketch_input(v: dict, stat: str) -> float:
    """b = 0 when the loop closes there well clear of a fold, else the input where P4 stands farthest off the line
    P3 → P2 (a scan of one turn): a sketch that tells the assembly."""
    clear = 0.05 * min(v["l3"], v["l4"])
    if _height(v, 0.0) >= clear:
        return 0.0
    best = max(range(720), key=lambda k: _height(v, k * math.tau / 720))
    return best * math.tau / 720


# -- writing ----------------------------------------------------------------------------------------------------
def to_ron(m: Mechanism) -> str:
    """The RON text of a four-bar (frame of two points, a crank, a coupler with at most one more point, a
    follower); SpecError for any other mechanism."""
    refuse_extras(m, FORMAT_NAME)
    one_driver(m, FORMAT_NAME)
    xy = assembled(m)
    dr = drivers(m, xy)[0]
    frame_slots(m, xy, FORMAT_NAME)
    if m.prismatic:
        raise SpecError([("prismatic", f"{FORMAT_NAME} holds a four-bar of revolutes only")])
    frame = m.link(FRAME).points
    moving = [lk for lk in m.links if lk.name != FRAME]
    if len(frame) != 2 or len(moving) != 3 or dr.pivot not in frame:
        raise SpecError([("links", f"{FORMAT_NAME} holds a four-bar: a frame of two pivots and three moving links")])
    p1, p2 = dr.pivot, next(p for p in frame if p != dr.pivot)
    p3 = dr.arm
    crank = m.link(dr.link)
    follower = next((lk for lk in moving if p2 in lk.points), None)
    coupler = next((lk for lk in moving if lk is not crank and lk is not follower), None)
    if (follower is None or coupler is None or len(crank.points) != 2 or len(follower.points) != 2
            or p3 not in coupler.points or len(coupler.points) > 3):
        raise SpecError([("links", f"{FORMAT_NAME} holds a four-bar whose coupler carries at most one more point")])
    p4 = next(p for p in follower.points if p != p2)
    if p4 not in coupler.points:
        raise SpecError([("links", "the coupler does not join the crank and the follower")])
    extra = [p for p in coupler.points if p not in (p3, p4)]

    def dist(a, b):
        return math.dist(xy[a], xy[b])

    def ang(a, b):
        return math.atan2(xy[b][1] - xy[a][1], xy[b][0] - xy[a][0])
    a = ang(p1, p2)
    l5, g = (dist(p3, extra[0]), math.remainder(ang(p3, extra[0]) - ang(p3, p4), math.tau)) if extra else (0.0, 0.0)
    (x3, y3), (x2, y2), (x4, y4) = xy[p3], xy[p2], xy[p4]
    circuit = "c1" if (x2 - x3) * (y4 - y3) - (y2 - y3) * (x4 - x3) > 0 else "c2"
    p5 = extra[0] if extra else f"{coupler.name}_point"
    meta = {"points": [p1, p2, p3, p4, p5], "links": [crank.name, coupler.name, follower.name], "driver": dr.name,
            "units": m.units.length, "name": m.name, "speed": dr.omega}
    values = {"p1x": xy[p1][0], "p1y": xy[p1][1], "a": a, "l1": dist(p1, p2), "l2": dist(p1, p3), "l3": dist(p3, p4),
              "l4": dist(p2, p4), "l5": l5, "g": g}
    lines = [f"// assur: {json.dumps(meta, ensure_ascii=False)}", "("]
    lines += [f"    {k}: {float(x)!r}," for k, x in values.items()]
    lines += [f"    stat: {circuit}b1,", ")"]
    return "\n".join(lines) + "\n"


def write(m: Mechanism, path) -> str | None:
    """Write the four-bar-rs RON file of ``m`` to ``path`` (atomically)."""
    from ..io.output import atomic_file
    text = to_ron(m)
    with atomic_file(path) as tmp:
        tmp.write_text(text, encoding="utf-8")
    return None


__all__ = ["FORMAT_NAME", "parse_ron", "positions", "read", "to_ron", "write"]
