"""The designer's document: an ``assur/1`` mechanism file as a table (file units), and the edits a page sends.

A document is the dict of :func:`assur.io.mechanism_writer.as_dict` plus an optional ``style.designer`` table of
the editor's locks (``[style]`` is free for tools, so the file stays an ``assur/1`` file). Edits arrive in SI (m,
rad, rad/s, m/s) and are written into the document in the file's units; every edit returns a new document and
never changes its argument. A refused edit raises :class:`EditRefused` with the reason and the place.
"""
from __future__ import annotations

import copy
import math

from ..errors import AssurError
from ..io import units as U

#: the version of the share fragment ``#m=<version>.<payload>`` this designer writes and reads
SHARE_VERSION = 1


class EditRefused(AssurError):
    """An edit the designer refuses; ``where`` names the point, link or group concerned."""

    def __init__(self, message: str, where: str = ""):
        super().__init__(message)
        self.where = where


# ---------------------------------------------------------------------------------------------------------------
# Reading the document

def length_factor(doc: dict) -> float:
    """Metres per file length unit."""
    return U.LENGTH[doc.get("units", {}).get("length", "m")]


def angle_factor(doc: dict) -> float:
    """Radians per file angle unit."""
    return U.ANGLE[doc.get("units", {}).get("angle", "deg")]


def link_points(entry) -> list:
    """The points of a ``[links]`` entry (a list, or a table with ``points``)."""
    return list(entry.get("points", [])) if isinstance(entry, dict) else list(entry)


def _set_link_points(links: dict, name: str, points: list) -> None:
    if isinstance(links[name], dict):
        links[name]["points"] = points
    else:
        links[name] = points


def locks(doc: dict) -> tuple[list, list]:
    """(locked points, locked links) of the document's ``style.designer`` table."""
    t = doc.get("style", {}).get("designer", {})
    return list(t.get("locked_points", [])), list(t.get("locked_links", []))


def _set_locks(doc: dict, points: list, links: list) -> None:
    t = doc.setdefault("style", {}).setdefault("designer", {})
    t["locked_points"], t["locked_links"] = points, links


def _fresh(existing, stem: str) -> str:
    k = 1
    while f"{stem}{k}" in existing:
        k += 1
    return f"{stem}{k}"


def _xy(v, what: str) -> tuple[float, float]:
    try:
        x, y = (float(c) for c in v)
    except (TypeError, ValueError):
        raise EditRefused(f"{what} must be two numbers [x, y] (m): {v!r}", what) from None
    if not (math.isfinite(x) and math.isfinite(y)) or max(abs(x), abs(y)) >= 1e6:
        raise EditRefused(f"{what} must be finite and within 1000 km of the origin: {v!r}", what)
    return x, y


def _quantity(value, kind: str, what: str, doc: dict) -> float:
    """An edit's number in SI: a JSON number (m, rad, rad/s or m/s as the protocol says) or a string with a unit
    as the file format reads it (``"60 rpm"``, ``"30 deg"``, ``"12 mm"``); refused, naming ``what``, otherwise."""
    from ..errors import SpecError
    if isinstance(value, bool) or not isinstance(value, (int, float, str)):
        raise EditRefused(f"{what} must be a number (SI) or a string with a unit such as "
                          f"'{_EXAMPLES[kind]}': {value!r}", what)
    if isinstance(value, str):
        units = _units(doc)
        try:
            v = U.parse_speed(value, kind, units) if kind in ("rotary", "linear") else \
                U.parse_quantity(value, kind, units)
        except SpecError as exc:
            raise EditRefused(f"{what} {exc}", what) from None
    else:
        v = float(value)
    if not math.isfinite(v) or abs(v) >= 1e9:
        raise EditRefused(f"{what} must be finite and below 1e9 (SI): {value!r}", what)
    return v


_EXAMPLES = {"length": "12 mm", "angle": "30 deg", "rotary": "60 rpm", "linear": "0.1 m/s"}


def _units(doc: dict):
    """The document's units (its defaults where the table is missing or broken)."""
    from ..model.mechanism import Units
    t = doc.get("units", {})
    t = {k: v for k, v in t.items() if k in ("length", "angle") and v in (U.LENGTH if k == "length" else U.ANGLE)} \
        if isinstance(t, dict) else {}
    return Units(**t)


def _name_or_none(value, what: str) -> str | None:
    """An optional name of an edit: None or a string (the file reader judges the spelling)."""
    if value is not None and not isinstance(value, str):
        raise EditRefused(f"{what} must be a name (a string): {value!r}", what)
    return value


def _flag(value, what: str) -> bool:
    """A JSON true or false (never a string or a number taken as one)."""
    if not isinstance(value, bool):
        raise EditRefused(f"{what} must be true or false: {value!r}", what)
    return value


def _need(edit: dict, key: str):
    if key not in edit:
        raise EditRefused(f"edit '{edit.get('kind')}' needs '{key}'", key)
    return edit[key]


def _point(doc: dict, name) -> str:
    if not isinstance(name, str) or name not in doc.get("points", {}):
        raise EditRefused(f"no point named {name!r}", str(name))
    return name


def _link(doc: dict, name) -> str:
    if not isinstance(name, str) or name not in doc.get("links", {}):
        raise EditRefused(f"no link named {name!r}", str(name))
    return name


# ---------------------------------------------------------------------------------------------------------------
# Moving a point of the sketch

def _dist(a, b) -> float:
    return math.hypot(b[0] - a[0], b[1] - a[1])


def _constrained(doc: dict, name: str, to: tuple[float, float], fL: float) -> tuple[float, float]:
    """``to`` (m) moved onto the circle that keeps a locked link's length, if one holds the point."""
    locked_points, locked_links = locks(doc)
    if name in locked_points:
        raise EditRefused(f"point {name} is locked; unlock it to move it", name)
    pts = doc["points"]
    holders = []
    for ln in locked_links:
        first_two = link_points(doc["links"].get(ln, []))[:2]
        if name in first_two and len(first_two) == 2:
            other = first_two[1] if first_two[0] == name else first_two[0]
            holders.append((ln, other))
    if len(holders) > 1:
        raise EditRefused(f"point {name} is held by the locked lengths of {holders[0][0]} and {holders[1][0]}; "
                          f"unlock one to move it", name)
    if not holders:
        return to
    ln, other = holders[0]
    c = [v * fL for v in pts[other]]
    r = _dist(c, [v * fL for v in pts[name]])
    d = _dist(c, to)
    if d == 0.0:
        return tuple(v * fL for v in pts[name])
    return c[0] + (to[0] - c[0]) * r / d, c[1] + (to[1] - c[1]) * r / d


def _placement(pts: dict, point: str, origin: str, toward: str, fA: float) -> tuple[float, float]:
    """(distance, angle in file units) of ``point`` from ``origin``, the angle from the direction to ``toward``."""
    p, o, t = pts[point], pts[origin], pts[toward]
    ang = math.atan2(p[1] - o[1], p[0] - o[0]) - math.atan2(t[1] - o[1], t[0] - o[0])
    ang = (ang + math.pi) % (2 * math.pi) - math.pi
    return _dist(o, p), ang / fA


def _refresh_dimensions(doc: dict, moved: set) -> None:
    """Rewrite the explicit lengths and placements that involve a moved point from the sketch."""
    pts, fA = doc["points"], angle_factor(doc)
    for entry in doc.get("links", {}).values():
        if not isinstance(entry, dict):
            continue
        first_two = entry.get("points", [])[:2]
        if "length" in entry and len(first_two) == 2 and moved & set(first_two):
            entry["length"] = _dist(pts[first_two[0]], pts[first_two[1]])
        for p, pl in entry.get("place", {}).items():
            if isinstance(pl, dict) and moved & {p, pl.get("from"), pl.get("toward")}:
                pl["distance"], pl["angle"] = _placement(pts, p, pl["from"], pl["toward"], fA)


def move_point(doc: dict, name: str, to) -> dict:
    name = _point(doc, name)
    to = _xy(to, f"the new position of {name}")
    new = copy.deepcopy(doc)
    fL = length_factor(new)
    x, y = _constrained(new, name, to, fL)
    new["points"][name] = [x / fL, y / fL]
    _refresh_dimensions(new, {name})
    return new


# ---------------------------------------------------------------------------------------------------------------
# Adding and deleting elements

def add_point(doc: dict, at, link: str = "frame", name: str | None = None) -> dict:
    new = copy.deepcopy(doc)
    x, y = _xy(at, "the new point")
    name = _name_or_none(name, "name") or _fresh(new.get("points", {}), "P")
    if name in new.get("points", {}):
        raise EditRefused(f"a point named {name} exists already", name)
    fL = length_factor(new)
    new.setdefault("points", {})[name] = [x / fL, y / fL]
    links = new.setdefault("links", {})
    if link == "frame" and "frame" not in links:
        links["frame"] = []
    _link(new, link)
    _set_link_points(links, link, link_points(links[link]) + [name])
    return new


def _without_point_refs(new: dict, name: str) -> None:
    links = new.get("links", {})
    for ln in list(links):
        pts = [p for p in link_points(links[ln]) if p != name]
        if ln != "frame" and len(pts) < 2:
            _drop_link_refs(new, ln)
            continue
        _set_link_points(links, ln, pts)
        entry = links[ln]
        if isinstance(entry, dict):
            place = entry.get("place", {})
            for p in [p for p, pl in place.items() if name in (p, pl.get("from"), pl.get("toward"))]:
                del place[p]
    new["prismatic"] = [s for s in new.get("prismatic", []) if name not in (s.get("point"), s.get("through"))]
    acts = new.get("actuators", {})
    gone = [a for a, t in acts.items() if name in t.get("between", [])]
    for a in gone:
        del acts[a]
    new["drivers"] = [d for d in new.get("drivers", [])
                      if name not in (d.get("pivot"), d.get("arm")) and d.get("actuator") not in gone]
    br = new.get("branches", {})
    for p in [p for p, h in br.items() if p == name or name in h.get("of", [])]:
        del br[p]
    if new.get("gait", {}).get("foot") == name:
        del new["gait"]
    lp, ll = locks(new)
    if name in lp:
        _set_locks(new, [p for p in lp if p != name], ll)


def _drop_link_refs(new: dict, ln: str) -> None:
    new["links"].pop(ln, None)
    new["drivers"] = [d for d in new.get("drivers", []) if d.get("link") != ln]
    new["prismatic"] = [s for s in new.get("prismatic", []) if ln not in (s.get("guide"), s.get("link"))]
    lp, ll = locks(new)
    if ln in ll:
        _set_locks(new, lp, [x for x in ll if x != ln])


def _tidy(new: dict) -> dict:
    """Drop empty optional tables, a ``[motor]`` whose driver is gone, the ``slide`` hints of slides that are gone
    and points no element uses any more."""
    motor = new.get("motor")
    if isinstance(motor, dict):
        names = [d.get("name") for d in new.get("drivers", [])]
        if not names or motor.get("driver", names[0]) not in names:
            del new["motor"]
    slides = {s.get("name") for s in new.get("prismatic", [])} | set(new.get("actuators", {}))
    for point, hint in list(new.get("branches", {}).items()):      # a slide hint on a slide that is gone
        if isinstance(hint, dict) and "on" in hint and hint["on"] not in slides:
            hint.pop("slide", None), hint.pop("on")
            if not hint:
                del new["branches"][point]
    for key in ("prismatic", "drivers", "branches", "actuators"):
        if key in new and not new[key]:
            del new[key]
    used = {p for e in new.get("links", {}).values() for p in link_points(e)}
    used |= {p for t in new.get("actuators", {}).values() for p in t.get("between", [])}
    for p in [p for p in new.get("points", {}) if p not in used]:
        del new["points"][p]
    return new


def delete_point(doc: dict, name: str) -> dict:
    name = _point(doc, name)
    new = copy.deepcopy(doc)
    del new["points"][name]
    _without_point_refs(new, name)
    return _tidy(new)


def add_link(doc: dict, points, new_points=None, name: str | None = None) -> dict:
    new = copy.deepcopy(doc)
    fL = length_factor(new)
    if new_points is not None and not isinstance(new_points, dict):
        raise EditRefused(f"new_points must be a table of name = [x, y] (m): {new_points!r}", "new_points")
    for p, xy in (new_points or {}).items():
        if p in new.get("points", {}):
            raise EditRefused(f"a point named {p} exists already", p)
        x, y = _xy(xy, f"the new point {p}")
        new.setdefault("points", {})[p] = [x / fL, y / fL]
    if not isinstance(points, list) or not all(isinstance(p, str) for p in points):
        raise EditRefused(f"points must be a list of point names: {points!r}", "points")
    if len(points) < 2 or len(set(points)) != len(points):
        raise EditRefused(f"a link needs two or more different points: {points}", "points")
    for p in points:
        _point(new, p)
    name = _name_or_none(name, "name") or _fresh(new.get("links", {}), "link")
    if name in new.get("links", {}):
        raise EditRefused(f"a link named {name} exists already", name)
    new.setdefault("links", {})[name] = points
    return new


def delete_link(doc: dict, name: str) -> dict:
    name = _link(doc, name)
    if name == "frame":
        raise EditRefused("the frame cannot be deleted; delete its points instead", name)
    new = copy.deepcopy(doc)
    _drop_link_refs(new, name)
    return _tidy(new)


def add_slider(doc: dict, point: str, through: str | None = None, angle: float = 0.0, offset: float = 0.0,
               guide: str = "frame", name: str | None = None) -> dict:
    point = _point(doc, point)
    guide = _link(doc, guide)
    through = _point(doc, through) if through is not None else link_points(doc["links"][guide])[0]
    angle = _quantity(angle, "angle", "angle", doc)
    offset = _quantity(offset, "length", "offset", doc)
    new = copy.deepcopy(doc)
    name = _name_or_none(name, "name") or _fresh({s.get("name") for s in new.get("prismatic", [])}, "slot")
    new.setdefault("prismatic", []).append({"name": name, "guide": guide, "through": through,
                                            "angle": angle / angle_factor(new),
                                            "offset": offset / length_factor(new), "point": point})
    return new


def delete_slider(doc: dict, name: str) -> dict:
    if not isinstance(name, str) or name not in {s.get("name") for s in doc.get("prismatic", [])}:
        raise EditRefused(f"no slider named {name!r}", str(name))
    new = copy.deepcopy(doc)
    new["prismatic"] = [s for s in new["prismatic"] if s.get("name") != name]
    return _tidy(new)


def _speed_text(doc: dict, kind: str, speed) -> str:
    """A driver speed (rad/s or m/s, or a string with a unit as the file format reads it: "60 rpm") as the file
    writer spells it (:func:`assur.io.units.format_speed`)."""
    if kind not in ("rotary", "linear"):
        raise EditRefused(f"the driver's kind must be 'rotary' or 'linear': {kind!r}", "kind")
    return U.format_speed(_quantity(speed, kind, "speed", doc), kind, _units(doc))


def add_driver(doc: dict, link: str, pivot: str, arm: str, speed: float = 1.0, name: str | None = None) -> dict:
    link, pivot, arm = _link(doc, link), _point(doc, pivot), _point(doc, arm)
    speed = _speed_text(doc, "rotary", speed)
    new = copy.deepcopy(doc)
    name = _name_or_none(name, "name") or _fresh({d.get("name") for d in new.get("drivers", [])}, "driver")
    new.setdefault("drivers", []).append({"name": name, "kind": "rotary", "link": link, "pivot": pivot,
                                          "arm": arm, "zero": 0, "sense": "ccw", "speed": speed})
    return new


def _driver(doc: dict, name: str) -> int:
    for k, d in enumerate(doc.get("drivers", [])):
        if d.get("name") == name:
            return k
    raise EditRefused(f"no driver named {name!r}", str(name))


def delete_driver(doc: dict, name: str) -> dict:
    k = _driver(doc, name)
    new = copy.deepcopy(doc)
    del new["drivers"][k]
    return _tidy(new)


def set_speed(doc: dict, driver: str, speed: float) -> dict:
    k = _driver(doc, driver)
    text = _speed_text(doc, doc["drivers"][k].get("kind", "rotary"), speed)
    new = copy.deepcopy(doc)
    new["drivers"][k]["speed"] = text
    return new


def _lock(doc: dict, which: int, name: str, locked: bool) -> dict:
    """``doc`` with ``name`` added to (or removed from) the locked points (``which`` 0) or links (1)."""
    locked = _flag(locked, "locked")
    new = copy.deepcopy(doc)
    lists = list(locks(new))
    lists[which] = sorted(set(lists[which]) | {name}) if locked else [x for x in lists[which] if x != name]
    _set_locks(new, *lists)
    return new


def lock_point(doc: dict, point: str, locked: bool = True) -> dict:
    """Lock (or unlock) a point: a drag does not move it."""
    return _lock(doc, 0, _point(doc, point), locked)


def lock_link(doc: dict, link: str, locked: bool = True) -> dict:
    """Lock (or unlock) a link's length: its first two points keep their distance in a drag."""
    return _lock(doc, 1, _link(doc, link), locked)


#: the edits the page may send (``flip`` needs the compiled plan and lives in :mod:`.session`)
EDITS = {
    "move_point": lambda d, e: move_point(d, _need(e, "point"), _need(e, "to")),
    "add_point": lambda d, e: add_point(d, _need(e, "at"), e.get("link", "frame"), e.get("name")),
    "delete_point": lambda d, e: delete_point(d, _need(e, "point")),
    "add_link": lambda d, e: add_link(d, _need(e, "points"), e.get("new_points"), e.get("name")),
    "delete_link": lambda d, e: delete_link(d, _need(e, "link")),
    "add_slider": lambda d, e: add_slider(d, _need(e, "point"), e.get("through"), e.get("angle", 0.0),
                                          e.get("offset", 0.0), e.get("guide", "frame"), e.get("name")),
    "delete_slider": lambda d, e: delete_slider(d, _need(e, "name")),
    "add_driver": lambda d, e: add_driver(d, _need(e, "link"), _need(e, "pivot"), _need(e, "arm"),
                                          e.get("speed", 1.0), e.get("name")),
    "delete_driver": lambda d, e: delete_driver(d, _need(e, "name")),
    "set_speed": lambda d, e: set_speed(d, _need(e, "driver"), _need(e, "speed")),
    "lock_point": lambda d, e: lock_point(d, _need(e, "point"), e.get("locked", True)),
    "lock_link": lambda d, e: lock_link(d, _need(e, "link"), e.get("locked", True)),
}
