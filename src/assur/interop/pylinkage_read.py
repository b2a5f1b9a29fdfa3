"""Reading pylinkage mechanisms (https://github.com/HugoFara/pylinkage): its JSON serialisations and live objects.

- **Mechanism JSON** (pylinkage ≥ 0.8, ``pylinkage.mechanism.mechanism_to_json``): ``joints`` (``ground``,
  ``revolute``, ``prismatic``, ``tracker``) with positions, ``links`` (``ground``, ``driver``, ``arc_driver``,
  ``link``) listing joint ids. The positions are the assembled initial position; link lengths are their
  distances, as pylinkage caches them.
- **Legacy linkage JSON** (pylinkage < 1.0, ``Linkage.to_dict``): ``joints`` of type ``Static``, ``Crank``,
  ``Fixed``, ``Revolute`` (``Pivot``), ``Prismatic`` (``Linear``) with their dimensions; ``x``, ``y`` are only
  the initial guess, so the joints are assembled here the way pylinkage does it: the intersection nearest the
  guess.
- **Hypergraph JSON** (``{"graph": graph_to_dict(...), "dimensions": Dimensions.to_dict()}``): converted by
  pylinkage's own ``to_mechanism`` (pylinkage must be installed) and read as Mechanism JSON.
- Live objects: a ``pylinkage.mechanism.Mechanism`` (through ``mechanism_to_dict``) and a
  ``pylinkage.simulation.Linkage``, read component by component (Ground, Crank, ArcCrank, RRRDyad, RRPDyad,
  FixedDyad, PointTracker) from their dimensions; a component's current position is only the hint of its
  assembly, as in pylinkage (its own ``to_hypergraph`` conversion keeps unassembled positions as dimensions).

pylinkage has no units and no time: lengths are read in ``units`` (default m) and an ``angular_velocity`` (rad per
simulation step) as rad/s. A mechanism exported by assur carries its units in an ``assur`` block, read back here.
"""
from __future__ import annotations

import math

from ..errors import SpecError, require
from ..io.units import LENGTH
from .draft import Crank, Draft, Slot, count_limit, finite

MODERN_JOINTS = ("ground", "revolute", "prismatic", "tracker")
MODERN_LINKS = ("ground", "driver", "arc_driver", "link")
LEGACY_JOINTS = ("Static", "Crank", "Fixed", "Revolute", "Pivot", "Prismatic", "Linear")
SOURCE = "pylinkage mechanism"


def kind_of(data) -> str | None:
    """'modern', 'legacy' or 'hypergraph' for a dict that is one of pylinkage's serialisations, else None."""
    if not isinstance(data, dict):
        return None
    joints = data.get("joints")
    if isinstance(joints, list) and joints and all(isinstance(j, dict) for j in joints):
        types = {j.get("type") for j in joints}
        if types & set(LEGACY_JOINTS) and "links" not in data:
            return "legacy"
        if isinstance(data.get("links"), list) and all("id" in j for j in joints):
            return "modern"
    if isinstance(data.get("graph"), dict) and isinstance(data.get("dimensions"), dict):
        return "hypergraph"
    return None


def _units(data, units: str | None) -> str:
    meta = data.get("assur") if isinstance(data.get("assur"), dict) else {}
    unit = units or (meta.get("units") or {}).get("length") or "m"
    if unit not in LENGTH:
        raise SpecError([("assur.units.length", f"must be one of {', '.join(LENGTH)}: {unit!r}")])
    return unit


def _xy(value, where: str) -> tuple[float, float]:
    if not (isinstance(value, (list, tuple)) and len(value) == 2):
        raise SpecError([(where, f"must be [x, y]: {value!r}")])
    return finite(value[0], f"{where}[0]"), finite(value[1], f"{where}[1]")


def read_modern(data: dict, units: str | None = None) -> Draft:
    """A Draft of a Mechanism JSON dict (see the module docstring)."""
    meta = data.get("assur") if isinstance(data.get("assur"), dict) else {}
    d = Draft(SOURCE, length_unit=_units(data, units), angle_unit="deg", name=str(data.get("name") or ""),
              description=str(meta.get("description") or ""))
    joints, links = data.get("joints"), data.get("links")
    if not isinstance(joints, list) or not isinstance(links, list):
        raise SpecError([("joints", "a pylinkage mechanism needs the lists 'joints' and 'links'")])
    count_limit(joints, "joints", "joints")
    count_limit(links, "links", "links")
    kinds, trackers, slots = {}, [], []
    for i, j in enumerate(joints):
        where = f"joints[{i}]"
        if not isinstance(j, dict) or not isinstance(j.get("id"), str) or not j["id"]:
            raise SpecError([(where, "must be a table with a string 'id'")])
        kind = j.get("type", "revolute")
        if kind not in MODERN_JOINTS:
            raise SpecError([(f"{where}.type", f"unknown joint kind {kind!r} (pylinkage's: {', '.join(MODERN_JOINTS)})")])
        kinds[j["id"]] = kind
        if kind == "tracker":
            trackers.append((i, j))
            continue
        d.point(j["id"], *_xy(j.get("position"), f"{where}.position"), where, label=j.get("name"))
        if kind == "ground":
            d.fix(j["id"])
        elif kind == "prismatic":
            slots.append((i, j))
    drivers = []
    for i, lk in enumerate(links):
        where = f"links[{i}]"
        if not isinstance(lk, dict) or not isinstance(lk.get("id"), str) or not isinstance(lk.get("joints"), list):
            raise SpecError([(where, "must be a table with a string 'id' and a list 'joints'")])
        kind = lk.get("type", "link")
        if kind not in MODERN_LINKS:
            raise SpecError([(f"{where}.type", f"unknown link kind {kind!r} (pylinkage's: {', '.join(MODERN_LINKS)})")])
        ids = [x for x in lk["joints"] if kinds.get(x) != "tracker"]
        for k, x in enumerate(lk["joints"]):
            if x not in kinds:
                raise SpecError([(f"{where}.joints[{k}]", f"unknown joint {x!r}")])
        if kind == "ground":
            for x in ids:
                d.fix(x)
            continue
        d.link(lk["id"], ids, f"{where}.joints", label=lk.get("name") if lk.get("name") != lk["id"] else None)
        if kind in ("driver", "arc_driver"):
            drivers.append((i, lk, kind))
    for i, lk, kind in drivers:
        _driver(d, i, lk, kind, meta)
    for i, j in slots:
        where = f"joints[{i}]"
        ax, ay = _xy(j.get("axis", [1.0, 0.0]), f"{where}.axis")
        if math.hypot(ax, ay) == 0:
            raise SpecError([(f"{where}.axis", "must be a non-zero direction")])
        at = _xy(j.get("line_point", [0.0, 0.0]), f"{where}.line_point")
        angle = math.atan2(ay, ax)
        px, py = d.points[j["id"]]
        off = math.cos(angle) * (py - at[1]) - math.sin(angle) * (px - at[0])
        if abs(off) > 1e-9 * max(1.0, abs(px), abs(py)):
            d.warn(f"prismatic joint {j['id']!r} is drawn {abs(off):.6g} off its slide line: its links keep the drawn "
                   "lengths and the joint moves onto the line, as in pylinkage")
        d.slots.append(Slot(angle=angle, at=at, point=j["id"], name=f"{j['id']}_slide"))
    for i, j in trackers:
        _tracker(d, i, j, kinds)
    return d


def _driver(d: Draft, i: int, lk: dict, kind: str, meta: dict) -> None:
    where = f"links[{i}]"
    motor = lk.get("motor_joint")
    pts = d.links[lk["id"]]
    if motor not in pts or motor not in d.ground:
        raise SpecError([(f"{where}.motor_joint", f"a driver turns about a ground joint of its link: {motor!r}")])
    others = [p for p in pts if p != motor]
    if not others:
        raise SpecError([(where, "a driver link needs a joint besides its motor joint")])
    omega = finite(lk.get("angular_velocity", math.tau / 360), f"{where}.angular_velocity")
    names = meta.get("drivers") if isinstance(meta.get("drivers"), dict) else {}
    d.cranks.append(Crank(lk["id"], motor, others[0], omega,
                          name=names.get(lk["id"]) if isinstance(names.get(lk["id"]), str) else lk["id"]))
    if kind == "arc_driver":
        d.warn(f"arc_driver {lk['id']!r} oscillates between {lk.get('arc_start', 0.0)!r} and {lk.get('arc_end')!r} rad; "
               "assur reads it as a crank: give that range with --range")
    init = lk.get("initial_angle")
    if isinstance(init, (int, float)) and not isinstance(init, bool) and math.isfinite(init):
        (mx, my), (ox, oy) = d.points[motor], d.points[others[0]]
        drawn = math.atan2(oy - my, ox - mx)
        if abs(math.remainder(init - drawn, math.tau)) > 1e-9:
            d.warn(f"driver {lk['id']!r}: initial_angle {init!r} rad differs from its drawn joints ({drawn!r} rad); "
                   "the drawing is the sketch (assur's input is the absolute crank angle)")


def _tracker(d: Draft, i: int, j: dict, kinds: dict) -> None:
    """A tracker: a point at a fixed distance and angle from the line of two joints, put on the link that joins
    them (or the ground)."""
    where = f"joints[{i}]"
    r1, r2 = j.get("ref_joint1_id"), j.get("ref_joint2_id")
    if not r1 and not r2:   # a free tracker stays where it is drawn: an anchor on the ground
        d.point(j["id"], *_xy(j.get("position"), f"{where}.position"), where, label=j.get("name"))
        d.fix(j["id"])
        return
    for key, r in (("ref_joint1_id", r1), ("ref_joint2_id", r2)):
        if r not in d.points:
            raise SpecError([(f"{where}.{key}", f"unknown joint {r!r}")])
    dist = finite(j.get("distance", 0.0), f"{where}.distance")
    ang = finite(j.get("angle", 0.0), f"{where}.angle")
    (x1, y1), (x2, y2) = d.points[r1], d.points[r2]
    base = math.atan2(y2 - y1, x2 - x1)
    d.point(j["id"], x1 + dist * math.cos(base + ang), y1 + dist * math.sin(base + ang), where, label=j.get("name"))
    if r1 in d.ground and r2 in d.ground:
        d.fix(j["id"])
        return
    for lid, pts in d.links.items():
        if r1 in pts and r2 in pts:
            pts.append(j["id"])
            return
    raise SpecError([(where, f"tracker {j['id']!r} follows {r1!r} and {r2!r}, which no link of the mechanism joins "
                             "rigidly: assur places a point on a rigid link only")])


# -- legacy joints (pylinkage < 1.0) --------------------------------------------------------------------------
def read_legacy(data: dict, units: str | None = None) -> Draft:
    """A Draft of a legacy ``Linkage.to_dict`` document: each joint assembled from its dimensions, the
    intersection nearest its ``x``, ``y`` (as pylinkage builds it)."""
    d = Draft("pylinkage linkage (legacy joints)", length_unit=_units(data, units), name=str(data.get("name") or ""))
    joints = data["joints"]
    count_limit(joints, "joints", "joints")
    ids: dict = {}
    inline = 0

    def ref(value, where):
        nonlocal inline
        if value is None:
            return None
        if isinstance(value, dict) and value.get("inline"):
            inline += 1
            pid = str(value.get("name") or f"static{inline}")
            if pid not in d.points:
                d.point(pid, finite(value.get("x", 0), f"{where}.x"), finite(value.get("y", 0), f"{where}.y"), where)
                d.fix(pid)
            return pid
        name = value.get("ref") if isinstance(value, dict) else value
        if name not in ids:
            raise SpecError([(where, f"refers to {name!r}, not a joint defined before it")])
        return ids[name]

    for i, j in enumerate(joints):
        where = f"joints[{i}]"
        if not isinstance(j, dict):
            raise SpecError([(where, "must be a table")])
        kind, name = j.get("type"), j.get("name") or f"joint{i}"
        if kind not in LEGACY_JOINTS:
            raise SpecError([(f"{where}.type", f"unknown joint kind {kind!r} (pylinkage's: {', '.join(LEGACY_JOINTS)})")])
        if name in ids:
            raise SpecError([(f"{where}.name", f"the name {name!r} is used twice")])
        hint = (finite(j.get("x") or 0.0, f"{where}.x"), finite(j.get("y") or 0.0, f"{where}.y"))
        a0, a1 = ref(j.get("joint0"), f"{where}.joint0"), ref(j.get("joint1"), f"{where}.joint1")
        if kind == "Static":
            d.point(name, *hint, where)
            d.fix(name)
        elif kind == "Crank":
            _need(a0, where, "joint0")
            r = finite(j.get("distance"), f"{where}.distance", "the crank radius")
            (x0, y0) = d.points[a0]
            th = math.atan2(hint[1] - y0, hint[0] - x0)
            d.point(name, x0 + r * math.cos(th), y0 + r * math.sin(th), where)
            d.link(f"{name}_crank", [a0, name], where)
            if a0 not in d.ground:
                raise SpecError([(f"{where}.joint0", f"a crank turns about a Static joint: {a0!r}")])
            omega = finite(j.get("angle") or 0.0, f"{where}.angle")
            d.cranks.append(Crank(f"{name}_crank", a0, name, omega or None, name=name))
        elif kind == "Fixed":
            _need(a0, where, "joint0")
            _need(a1, where, "joint1")
            r = finite(j.get("distance"), f"{where}.distance")
            ang = finite(j.get("angle"), f"{where}.angle")
            (x0, y0), (x1, y1) = d.points[a0], d.points[a1]
            base = math.atan2(y1 - y0, x1 - x0)
            d.point(name, x0 + r * math.cos(base + ang), y0 + r * math.sin(base + ang), where)
            _rigid(d, name, a0, a1)
        elif kind in ("Revolute", "Pivot"):
            _need(a0, where, "joint0")
            _need(a1, where, "joint1")
            r0 = finite(j.get("distance0"), f"{where}.distance0")
            r1 = finite(j.get("distance1"), f"{where}.distance1")
            d.point(name, *_circles(d.points[a0], r0, d.points[a1], r1, hint, where), where)
            d.link(f"{a0}_{name}", [a0, name], where)
            d.link(f"{a1}_{name}", [a1, name], where)
        else:   # Prismatic / Linear: circle about joint0 ∩ the line joint1 → joint2
            _need(a0, where, "joint0")
            _need(a1, where, "joint1")
            a2 = ref(j.get("joint2"), f"{where}.joint2")
            _need(a2, where, "joint2")
            r = finite(j.get("revolute_radius"), f"{where}.revolute_radius")
            p1, p2 = d.points[a1], d.points[a2]
            d.point(name, *_circle_line(d.points[a0], r, p1, p2, hint, where), where)
            d.link(f"{a0}_{name}", [a0, name], where)
            guide = None
            if not (a1 in d.ground and a2 in d.ground):
                guide = next((lid for lid, pts in d.links.items() if a1 in pts and a2 in pts), None)
                if guide is None:
                    raise SpecError([(where, f"the slide line {a1!r} → {a2!r} is on no one link")])
            d.slots.append(Slot(angle=math.atan2(p2[1] - p1[1], p2[0] - p1[0]), at=p1, point=name, guide=guide,
                                name=f"{name}_slide"))
        ids[name] = name
    return d


def _need(value, where, key):
    if value is None:
        raise SpecError([(f"{where}.{key}", "is missing")])


def _rigid(d: Draft, name: str, a0: str, a1: str) -> None:
    """Put the point ``name`` on the body of its two references (the ground, or a link holding both, else a new
    ternary link joining them)."""
    if a0 in d.ground and a1 in d.ground:
        d.fix(name)
        return
    for pts in d.links.values():
        if a0 in pts and a1 in pts:
            pts.append(name)
            return
    d.link(f"{a0}_{a1}_{name}", [a0, a1, name], f"joint {name}")


def _circles(c0, r0, c1, r1, hint, where):
    """The intersection of two circles nearest ``hint`` (SpecError when they do not meet)."""
    dx, dy = c1[0] - c0[0], c1[1] - c0[1]
    dd = math.hypot(dx, dy)
    if dd == 0 or dd > r0 + r1 or dd < abs(r0 - r1):
        raise SpecError([(where, "cannot be assembled: its two circles do not meet")])
    a = (r0 * r0 - r1 * r1 + dd * dd) / (2 * dd)
    h = math.sqrt(max(r0 * r0 - a * a, 0.0))
    mx, my = c0[0] + a * dx / dd, c0[1] + a * dy / dd
    cands = [(mx - h * dy / dd, my + h * dx / dd), (mx + h * dy / dd, my - h * dx / dd)]
    return min(cands, key=lambda p: math.dist(p, hint))


def _circle_line(c, r, p1, p2, hint, where):
    """The intersection of a circle and the line p1 → p2 nearest ``hint``."""
    ux, uy = p2[0] - p1[0], p2[1] - p1[1]
    n = math.hypot(ux, uy)
    if n == 0:
        raise SpecError([(where, "the slide line's two joints coincide")])
    ux, uy = ux / n, uy / n
    t0 = (c[0] - p1[0]) * ux + (c[1] - p1[1]) * uy
    fx, fy = p1[0] + t0 * ux, p1[1] + t0 * uy
    h2 = r * r - ((c[0] - fx) ** 2 + (c[1] - fy) ** 2)
    if h2 < 0:
        raise SpecError([(where, "cannot be assembled: the circle does not reach the slide line")])
    h = math.sqrt(h2)
    return min([(fx + h * ux, fy + h * uy), (fx - h * ux, fy - h * uy)], key=lambda p: math.dist(p, hint))


# -- through pylinkage itself -----------------------------------------------------------------------------------
def _pylinkage():
    from ..kernels.numba_target import configure
    configure()                 # before pylinkage imports numba and fixes its target (kernels/numba_target.py)
    return require("pylinkage", "reading a pylinkage object or hypergraph", "pip install 'assur[pylinkage]'")


def read_hypergraph(data: dict, units: str | None = None) -> Draft:
    """A Draft of ``{"graph": …, "dimensions": …}`` through pylinkage's own ``to_mechanism``."""
    _pylinkage()
    from pylinkage.dimensions import Dimensions
    from pylinkage.hypergraph.mechanism_conversion import to_mechanism
    from pylinkage.hypergraph.serialization import graph_from_dict
    from pylinkage.mechanism import mechanism_to_dict
    try:
        mech = to_mechanism(graph_from_dict(data["graph"]), Dimensions.from_dict(data["dimensions"]))
    except (KeyError, TypeError, ValueError, AttributeError) as exc:
        raise SpecError([("graph", f"pylinkage cannot read this hypergraph: {exc}")]) from None
    return read_modern(mechanism_to_dict(mech) | {"assur": data.get("assur", {})}, units)


def is_live(obj) -> bool:
    """Whether ``obj`` is a pylinkage Linkage or Mechanism object."""
    return type(obj).__module__.startswith("pylinkage.") and (hasattr(obj, "components") or hasattr(obj, "links"))


def read_live(obj, units: str | None = None) -> Draft:
    """A Draft of a live ``pylinkage.mechanism.Mechanism`` (through its dict) or ``pylinkage.simulation.Linkage``
    (its components, each assembled from its dimensions the way pylinkage builds it: the intersection nearest the
    component's current position)."""
    _pylinkage()
    from pylinkage.mechanism import Mechanism, mechanism_to_dict
    if isinstance(obj, Mechanism):
        return read_modern(mechanism_to_dict(obj), units)
    return read_components(obj, units)


def read_components(linkage, units: str | None = None) -> Draft:
    """A Draft of a ``pylinkage.simulation.Linkage``: Ground, Crank, ArcCrank, RRRDyad, RRPDyad, FixedDyad and
    PointTracker components (others are refused by name)."""
    d = Draft("pylinkage linkage", length_unit=units or "m", name=str(getattr(linkage, "name", "") or ""))
    comps = list(linkage.components)
    count_limit(comps, "components", "components")
    ids, owner = {}, {}
    for k, c in enumerate(comps):
        name = str(c.name) if getattr(c, "name", None) else f"component{k}"
        if name in ids.values():
            raise SpecError([(f"components[{k}]", f"the name {name!r} is used twice")])
        ids[id(c)] = name
        out = getattr(c, "output", None)
        if out is not None:
            owner[id(out)] = c

    def pid(anchor):
        return ids.get(id(owner.get(id(anchor), anchor)))
    pending = list(enumerate(comps))
    while pending:
        rest = []
        for k, c in pending:
            if not _component(d, k, c, ids[id(c)], pid):
                rest.append((k, c))
        if len(rest) == len(pending):
            k, c = rest[0]
            raise SpecError([(f"components[{k}]", f"{type(c).__name__} {ids[id(c)]!r} hangs on components that "
                                                 "never get placed")])
        pending = rest
    return d


def _component(d: Draft, k: int, c, name: str, pid) -> bool:
    """Add one component when its anchors are placed; False to try again later."""
    kind = type(c).__name__
    where = f"components[{k}] ({kind} {name!r})"
    here = (c.x, c.y) if c.x is not None and c.y is not None else None
    if kind == "Ground":
        d.point(name, finite(c.x, f"{where}.x"), finite(c.y, f"{where}.y"), where)
        d.fix(name)
        return True
    anchors = [getattr(c, a) for a in ("anchor", "anchor1", "anchor2", "revolute_anchor", "line_anchor1",
                                       "line_anchor2") if getattr(c, a, None) is not None]
    refs = [pid(a) for a in anchors]
    if kind not in ("Crank", "ArcCrank", "RRRDyad", "RRPDyad", "FixedDyad", "PointTracker"):
        raise SpecError([(where, f"a {kind} is not representable in assur (it reads Ground, Crank, ArcCrank, "
                                 "RRRDyad, RRPDyad, FixedDyad and PointTracker)")])
    if any(r is None or r not in d.points for r in refs):
        return False
    if kind in ("Crank", "ArcCrank"):
        a = refs[0]
        if a not in d.ground:
            raise SpecError([(where, f"a crank turns about a Ground: {a!r}")])
        ax, ay = d.points[a]
        r = finite(c.radius, f"{where}.radius")
        th = math.atan2(here[1] - ay, here[0] - ax) if here else finite(c.initial_angle or 0.0, where)
        d.point(name, ax + r * math.cos(th), ay + r * math.sin(th), where)
        d.link(f"{name}_crank", [a, name], where)
        omega = finite(c.angular_velocity, f"{where}.angular_velocity")
        d.cranks.append(Crank(f"{name}_crank", a, name, omega, name=name))
        if kind == "ArcCrank":
            d.warn(f"ArcCrank {name!r} oscillates between {c.arc_start!r} and {c.arc_end!r} rad; assur reads it as a "
                   "crank: give that range with --range")
    elif kind == "RRRDyad":
        a0, a1 = refs
        hint = here or d.points[a0]
        xy = _circles(d.points[a0], finite(c.distance1, where), d.points[a1], finite(c.distance2, where), hint, where)
        d.point(name, *xy, where)
        d.link(f"{a0}_{name}", [a0, name], where)
        d.link(f"{a1}_{name}", [a1, name], where)
    elif kind == "RRPDyad":
        a0, l1, l2 = refs
        p1, p2 = d.points[l1], d.points[l2]
        d.point(name, *_circle_line(d.points[a0], finite(c.distance, where), p1, p2, here or d.points[a0], where),
                where)
        d.link(f"{a0}_{name}", [a0, name], where)
        guide = None
        if not (l1 in d.ground and l2 in d.ground):
            guide = next((lid for lid, pts in d.links.items() if l1 in pts and l2 in pts), None)
            if guide is None:
                raise SpecError([(where, f"the slide line {l1!r} → {l2!r} is on no one link")])
        d.slots.append(Slot(angle=math.atan2(p2[1] - p1[1], p2[0] - p1[0]), at=p1, point=name, guide=guide,
                            name=f"{name}_slide"))
    else:   # FixedDyad, PointTracker: polar from anchor1 along anchor1 → anchor2
        a0, a1 = refs
        (x0, y0), (x1, y1) = d.points[a0], d.points[a1]
        base = math.atan2(y1 - y0, x1 - x0) + finite(c.angle, f"{where}.angle")
        r = finite(c.distance, f"{where}.distance")
        d.point(name, x0 + r * math.cos(base), y0 + r * math.sin(base), where)
        _rigid(d, name, a0, a1)
    return True


__all__ = ["is_live", "kind_of", "read_components", "read_hypergraph", "read_legacy", "read_live", "read_modern"]
