"""The sections of a mechanism file (``format = "assur/1"``), one reader each: ``[points]``, ``[links]``,
``[[prismatic]]``, ``[actuators]``, ``[[drivers]]``, ``[branches]``, ``[joints]``, ``[gait]``.

Each reader takes the parsed document, the :class:`~assur.io.problems.Problems` of the file (it adds every problem
it finds there, with its location, and goes on) and what it depends on (the point names, the links …), and returns
what read (numbers in SI). :func:`assur.io.mechanism_file.from_dict` calls them in turn and raises the problems at
the end; the other sections have their own modules (dynamics_file, gear_pairs, cam_pairs, make_file, motor_file).
"""
from __future__ import annotations

import math
import re

from ..errors import SpecError
from ..model.mechanism import (FRAME, Actuator, BranchHint, Gait, Joint, LinearDriver, Link, Placement, Prismatic,
                               RotaryDriver, TimeTable, Units)
from ..tolerances import DEFAULT as TOL
from . import units as U
from .dynamics_file import MASS_KEYS, read_gait_load

_NAME = re.compile(r"^[A-Za-z_][A-Za-z0-9_']*$")
_JOINT_KINDS = {"revolute", "spherical", "cylindrical", "universal", "prismatic"}

#: every number of a mechanism file (a coordinate, length, angle …, in file units) is below this in magnitude
MAX_MAGNITUDE = 1e9

def _name(x):
    """A name field as found, or the text of any other value (a list, a table, a number): never a name, so the
    usual 'unknown …' check reports it, and never unhashable."""
    return x if x is None or isinstance(x, str) else repr(x)


def _num(x) -> bool:
    """A usable number: finite and below MAX_MAGNITUDE in magnitude (1e308° or 1e300 mm is a typo)."""
    return isinstance(x, (int, float)) and not isinstance(x, bool) and math.isfinite(x) and abs(x) < MAX_MAGNITUDE


def _branch_hint(P, path, pn, spec, point_names, slides) -> BranchHint | None:
    """One ``[branches]`` entry: ``{side, of}`` (the side of a directed line), ``{slide, on}`` (an RPR group's
    slider hinge ahead of or behind its guide's hinge along the slide ``on``), or both; None after a problem."""
    if pn not in point_names:
        P.add(path, f"unknown point {pn!r} {_known(point_names)}")
        return None
    sided = isinstance(spec, dict) and ("side" in spec or "of" in spec)
    slid = isinstance(spec, dict) and ("slide" in spec or "on" in spec)
    extra = sorted(set(spec) - {"side", "of", "slide", "on"}) if isinstance(spec, dict) else []
    if not (sided or slid) or extra:
        P.add(path, "must be {side = 'left'|'right', of = [P, Q]} (the side of the directed line P → Q) or "
                    "{slide = 'ahead'|'behind', on = SLIDE} (an RPR group's slider hinge along its slide)")
        return None
    side = of = slide = on = None
    if sided:
        if spec.get("side") not in ("left", "right") or not isinstance(spec.get("of"), list) or len(spec["of"]) != 2:
            P.add(path, "must be {side = 'left'|'right', of = [P, Q]} (the side of the directed line P → Q)")
            return None
        bad = [q for q in spec["of"] if _name(q) not in point_names]
        if bad:
            P.add(f"{path}.of", f"unknown point {bad[0]!r} {_known(point_names)}")
            return None
        side, of = spec["side"], tuple(spec["of"])
    if slid:
        if spec.get("slide") not in ("ahead", "behind"):
            P.add(f"{path}.slide", f"must be 'ahead' or 'behind' (the point along the slide's direction from the "
                                   f"guide's hinge): {spec.get('slide')!r}")
            return None
        if spec.get("on") not in slides:
            P.add(f"{path}.on", f"must name the prismatic pair or actuator the point slides on: {spec.get('on')!r} "
                                f"{_known(sorted(slides))}")
            return None
        slide, on = spec["slide"], spec["on"]
    return BranchHint(pn, side, of, slide, on)


def _known(names) -> str:
    names = list(names)
    shown = ", ".join(sorted(names)[:12]) + (", …" if len(names) > 12 else "")
    return f"(known: {shown})" if names else "(none defined)"

def read_points(data, P, dimension: int, L: float):
    """``[points]``: the (name, SI coordinates) pairs that read, and the set of every name listed."""
    pdata = data.get("points")
    points: list[tuple[str, tuple[float, ...]]] = []
    if not isinstance(pdata, dict) or not pdata:
        P.add("points", "must be a non-empty table of name = [x, y]")
        pdata = {}
    for name, xy in pdata.items():
        if not isinstance(name, str) or not _NAME.match(name):
            P.add(f"points.{name}", "a point name must start with a letter or '_' and hold only letters, digits, _ or '")
        if (not isinstance(xy, list) or len(xy) != dimension or not all(_num(c) for c in xy)):
            P.add(f"points.{name}", f"must be [{', '.join('xyz'[:dimension])}] numbers: {xy!r}")
            continue
        points.append((name, tuple(float(c) * L for c in xy)))
    return points, set(pdata)


def read_links(data, P, point_names, L: float, A: float):
    """``[links]``: the links that read, and the table as written ({} after a problem)."""
    ldata = data.get("links")
    links: list[Link] = []
    if not isinstance(ldata, dict) or not ldata:
        P.add("links", "must be a table of links, including 'frame'")
        ldata = {}
    elif FRAME not in ldata:
        P.add("links", f"must include the ground link '{FRAME}' (links: {', '.join(ldata)})")
    for lname, spec in ldata.items():
        link = _read_link(P, lname, spec, point_names, L, A)
        if link is not None:
            links.append(link)
    return links, ldata


def _read_link(P, lname, spec, point_names, L: float, A: float) -> Link | None:
    """One link: a list of point names, or a table with ``points``, ``length``, ``place`` (and masses, read by
    :mod:`.dynamics_file`); None when its point list has a problem."""
    path = f"links.{lname}"
    if not isinstance(lname, str) or not _NAME.match(lname):
        P.add(path, "a link name must start with a letter or '_' and hold only letters, digits, _ or '")
    length = None
    place: list[tuple[str, Placement]] = []
    if isinstance(spec, list):
        plist = spec
        ppath = path
    elif isinstance(spec, dict):
        P.unknown_keys(spec, ("length", "place", "points") + MASS_KEYS, path)
        plist = spec.get("points")
        ppath = f"{path}.points"
        if not isinstance(plist, list):
            P.add(ppath, "must be a list of point names")
            return None
    else:
        P.add(path, "must be a list of point names or a table with 'points'")
        return None
    ok = True
    for i, pn in enumerate(plist):
        if not isinstance(pn, str) or pn not in point_names:
            P.add(f"{ppath}[{i}]", f"unknown point {pn!r} {_known(point_names)}")
            ok = False
    if len(set(map(str, plist))) != len(plist):
        P.add(ppath, f"lists a point twice: {plist!r}")
        ok = False
    if not plist:
        P.add(ppath, "a link needs at least one point")
        ok = False
    if not ok:             # names that are not strings go no further (nothing below could use them)
        plist = [pn for pn in plist if isinstance(pn, str)]
    if isinstance(spec, dict):
        if "length" in spec:
            if lname == FRAME:
                P.add(f"{path}.length", "the frame's points are fixed at their coordinates; it takes no length")
            elif not _num(spec["length"]) or spec["length"] <= 0:
                P.add(f"{path}.length", f"must be a positive number below 1e9: {spec['length']!r}")
            elif len(plist) < 2:
                P.add(f"{path}.length", "needs at least two points")
            else:
                length = float(spec["length"]) * L
        place = _read_placements(P, path, lname, spec.get("place", {}), plist, L, A)
    return Link(lname, tuple(plist), length, tuple(place)) if ok else None


def _read_placements(P, path: str, lname, pl, plist: list, L: float, A: float) -> list[tuple[str, Placement]]:
    """A link's ``place`` table: point = {from, toward, distance, angle}, each relative to points placed
    before it (the link's first two points, then the earlier entries)."""
    place: list[tuple[str, Placement]] = []
    if not isinstance(pl, dict):
        P.add(f"{path}.place", "must be a table of point = {from, toward, distance, angle}")
        pl = {}
    placed = set(plist[:2])
    for pn, pspec in pl.items():
        qpath = f"{path}.place.{pn}"
        if pn not in plist:
            P.add(qpath, f"is not a point of link '{lname}' (its points: {', '.join(map(str, plist))})")
            continue
        if pn in plist[:2]:
            P.add(qpath, "the first two points of a link define its frame; place further points only")
            continue
        if not isinstance(pspec, dict):
            P.add(qpath, "must be a table {from, toward, distance, angle}")
            continue
        bad = P.unknown_keys(pspec, ("angle", "distance", "from", "toward"), qpath)
        for k in ("from", "toward"):
            ref = _name(pspec.get(k, plist[0] if k == "from" else plist[1] if len(plist) > 1 else None))
            if ref not in placed:
                P.add(f"{qpath}.{k}", f"must be a point of '{lname}' placed before {pn!r}: {ref!r}")
                bad = True
        dist, ang = pspec.get("distance"), pspec.get("angle", 0.0)
        if not _num(dist) or dist < 0:
            P.add(f"{qpath}.distance", f"must be a non-negative number: {dist!r}")
            bad = True
        if not _num(ang):
            P.add(f"{qpath}.angle", f"must be a number below 1e9 in magnitude: {ang!r}")
            bad = True
        if not bad:
            org = pspec.get("from", plist[0])
            tow = pspec.get("toward", plist[1])
            if org == tow:
                P.add(qpath, f"'from' and 'toward' must differ: {org!r}")
            else:
                place.append((pn, Placement(org, tow, float(dist) * L, float(ang) * A)))
        placed.add(pn)
    return place


def read_prismatic(data, P, point_names, link_names, link_points, L: float, A: float) -> list[Prismatic]:
    """``[[prismatic]]``: slides of a point in a slot (``point``) or of a link on its guide (``link``)."""
    prismatic: list[Prismatic] = []
    prdata = P.section(data, "prismatic", "must be an array of tables [[prismatic]]", list)
    seen_names: set[str] = set()
    for i, spec in enumerate(prdata):
        path = f"prismatic[{i}]"
        if not isinstance(spec, dict):
            P.add(path, "must be a table")
            continue
        P.unknown_keys(spec, ("angle", "guide", "link", "name", "offset", "point", "through") + MASS_KEYS, path)
        name = spec.get("name", f"slide{i + 1}")
        if not isinstance(name, str) or not _NAME.match(name) or name in seen_names:
            P.add(f"{path}.name", f"must be a unique name: {name!r}")
        seen_names.add(str(name))
        guide = _name(spec.get("guide", FRAME))
        if guide not in link_names:
            P.add(f"{path}.guide", f"unknown link {guide!r} {_known(link_names)}")
        through = _name(spec.get("through"))
        if guide in link_points and through not in link_points[guide]:
            P.add(f"{path}.through", f"must be a point of the guide link '{guide}': {through!r}")
        ang, off = spec.get("angle", 0.0), spec.get("offset", 0.0)
        if not _num(ang):
            P.add(f"{path}.angle", f"must be a number below 1e9 in magnitude: {ang!r}")
        if not _num(off):
            P.add(f"{path}.offset", f"must be a number below 1e9 in magnitude: {off!r}")
        point, link = _name(spec.get("point")), _name(spec.get("link"))
        if (point is None) == (link is None):
            P.add(path, "needs exactly one of 'point' (a pin in a slot) or 'link' (a link translating on the guide)")
        if point is not None and point not in point_names:
            P.add(f"{path}.point", f"unknown point {point!r} {_known(point_names)}")
        if point is not None and guide in link_points and point in link_points[guide]:
            P.add(f"{path}.point", f"is a point of its own guide '{guide}'")
        if link is not None and (link not in link_names or link == FRAME or link == guide):
            P.add(f"{path}.link", f"must be a moving link other than the guide {_known(link_names - {FRAME})}: {link!r}")
        if _num(ang) and _num(off):
            prismatic.append(Prismatic(str(name), guide, through, float(ang) * A, float(off) * L, point, link))
    return prismatic


def read_actuators(data, P, point_names) -> list[Actuator]:
    """``[actuators]``: name = {between = [A, B]} (a linear actuator between two points)."""
    actuators: list[Actuator] = []
    adata = P.section(data, "actuators", "must be a table of name = {between = [A, B]}")
    for name, spec in adata.items():
        path = f"actuators.{name}"
        if not isinstance(spec, dict) or not isinstance(spec.get("between"), list) or len(spec["between"]) != 2:
            P.add(path, "must be a table with between = [A, B]")
            continue
        P.unknown_keys(spec, ("between", "cylinder", "rod"), path)
        a, b = (_name(x) for x in spec["between"])
        for j, pn in enumerate((a, b)):
            if pn not in point_names:
                P.add(f"{path}.between[{j}]", f"unknown point {pn!r} {_known(point_names)}")
        if a == b:
            P.add(f"{path}.between", f"needs two different points: {a!r}")
        actuators.append(Actuator(name, (a, b)))
    return actuators


def read_drivers(data, P, units: Units, ldata, link_names, link_points, actuator_names) -> list:
    """``[[drivers]]``: rotary (a crank about a frame pivot) or linear (an actuator's length) inputs."""
    L, A = U.LENGTH[units.length], U.ANGLE[units.angle]
    drivers = []
    ddata = P.section(data, "drivers", "must be an array of tables [[drivers]]", list)
    seen_names: set[str] = set()
    for i, spec in enumerate(ddata):
        path = f"drivers[{i}]"
        if not isinstance(spec, dict):
            P.add(path, "must be a table")
            continue
        kind = spec.get("kind", "rotary")
        name = spec.get("name", f"input{i + 1}")
        if not isinstance(name, str) or not _NAME.match(name) or name in seen_names:
            P.add(f"{path}.name", f"must be a unique name: {name!r}")
        seen_names.add(str(name))
        try:
            speed = U.parse_speed(spec.get("speed", 1.0 if kind == "rotary" else 0.0), kind, units) \
                if kind in ("rotary", "linear") else 0.0
        except SpecError as exc:
            P.add(f"{path}.speed", str(exc))
            speed = 0.0
        if kind == "rotary":
            drivers.append(_read_rotary_driver(P, path, spec, str(name), speed, A, ldata, link_names, link_points))
        elif kind == "linear":
            P.unknown_keys(spec, ("actuator", "kind", "law", "name", "range", "speed"), path)
            act = _name(spec.get("actuator"))
            if act not in actuator_names:
                P.add(f"{path}.actuator", f"unknown actuator {act!r} {_known(actuator_names)}")
            drivers.append(LinearDriver(str(name), act, speed, _stroke_range(spec.get("range"), L, f"{path}.range", P),
                                        _time_table(spec.get("law"), L, f"{path}.law", P)))
        else:
            P.add(f"{path}.kind", f"must be 'rotary' or 'linear': {kind!r}")
    return drivers


def _read_rotary_driver(P, path: str, spec: dict, name: str, speed: float, A: float, ldata, link_names,
                        link_points) -> RotaryDriver:
    """One rotary driver: ``link`` turning about the frame point ``pivot``, its angle measured to ``arm``."""
    P.unknown_keys(spec, ("arm", "kind", "link", "name", "pivot", "sense", "speed", "zero"), path)
    link = _name(spec.get("link"))
    if link not in link_names or link == FRAME:
        P.add(f"{path}.link", f"must be a moving link {_known(link_names - {FRAME})}: {link!r}")
    pivot, arm = _name(spec.get("pivot")), _name(spec.get("arm"))
    pts = link_points.get(link, set())
    if link in link_points and pivot not in pts:
        P.add(f"{path}.pivot", f"must be a point of link '{link}': {pivot!r}")
    elif FRAME in link_points and pivot not in link_points[FRAME]:
        P.add(f"{path}.pivot", f"must be a point of the frame (a crank turns about a fixed pivot): {pivot!r}")
    if arm is None and link in link_points:
        others = [p for p in ldata_points(ldata, link) if p != pivot]
        arm = others[0] if others else None
    if link in link_points and (arm not in pts or arm == pivot):
        P.add(f"{path}.arm", f"must be a point of link '{link}' other than the pivot: {arm!r}")
    zero = spec.get("zero", 0.0)
    if not _num(zero):
        P.add(f"{path}.zero", f"must be a number below 1e9 in magnitude: {zero!r}")
        zero = 0.0
    sense = spec.get("sense", "ccw")
    if sense not in ("ccw", "cw"):
        P.add(f"{path}.sense", f"must be 'ccw' or 'cw': {sense!r}")
    return RotaryDriver(name, link, pivot, arm, float(zero) * A, -1 if sense == "cw" else 1, speed)


def read_branches(data, P, point_names, slides) -> list[BranchHint]:
    """``[branches]``: point = {side, of} or {slide, on}, the assembly branch of each group named."""
    branches = []
    bdata = P.section(data, "branches", "must be a table of point = {side, of} (or {slide, on})")
    for pn, spec in bdata.items():
        hint = _branch_hint(P, f"branches.{pn}", pn, spec, point_names, slides)
        if hint is not None:
            branches.append(hint)
    return branches


def read_joints(data, P, point_names, dimension: int, A: float) -> list[Joint]:
    """``[joints]`` (spatial descriptions): point = kind, or {kind, axis}."""
    joints = []
    jdata = P.section(data, "joints", "must be a table of point = kind")
    for pn, kind in jdata.items():
        axis = None
        if isinstance(kind, dict):   # {kind = "revolute", axis = [x, y, z] | {gamma1, gamma2}}
            spec, kind = kind, kind.get("kind")
            P.unknown_keys(spec, ("axis", "kind"), f"joints.{pn}")
            axis = _joint_axis(spec.get("axis"), A, f"joints.{pn}.axis", P)
        if pn not in point_names:
            P.add(f"joints.{pn}", f"unknown point {pn!r} {_known(point_names)}")
        elif not isinstance(kind, str) or kind not in _JOINT_KINDS:
            hint = (f" (an axis goes in a table: {pn} = {{kind = \"revolute\", axis = [x, y, z]}})"
                    if isinstance(kind, list) else "")
            P.add(f"joints.{pn}", f"must be one of {', '.join(sorted(_JOINT_KINDS))}{hint}: {kind!r}")
        else:
            joints.append(Joint(pn, kind, axis))
    if joints and dimension == 2 and any(j.kind != "revolute" for j in joints):
        P.add("joints", "spherical, cylindrical and universal joints need dimension = 3")
    return joints


def read_gait(data, P, point_names, A: float) -> Gait | None:
    """``[gait]``: the foot, the ground and up directions, the legs' phases and the load (weight, friction)."""
    gdata = data.get("gait")
    if gdata is None:
        return None
    if not isinstance(gdata, dict):
        P.add("gait", "must be a table with 'foot'")
        return None
    P.unknown_keys(gdata, ("foot", "ground", "phases", "up", "weight", "friction"), "gait")
    foot = gdata.get("foot")
    if _name(foot) not in point_names:
        P.add("gait.foot", f"unknown point {foot!r} {_known(point_names)}")
    vecs = {k: _unit_vector_2d(gdata.get(k), f"gait.{k}", P) for k in ("ground", "up")}
    phases = gdata.get("phases", [0.0])
    if not isinstance(phases, list) or not phases or not all(_num(c) for c in phases):
        P.add("gait.phases", f"must be a non-empty list of crank phase offsets: {phases!r}")
        phases = [0.0]
    if vecs["ground"] and vecs["up"] and abs(vecs["ground"][0] * vecs["up"][0]
                                             + vecs["ground"][1] * vecs["up"][1]) > TOL.perpendicular:
        P.add("gait.up", "must be perpendicular to gait.ground")
    return Gait(str(foot), vecs["ground"] or (1.0, 0.0), vecs["up"], tuple(float(c) * A for c in phases),
                *read_gait_load(gdata, P))


def _unit_vector_2d(v, path: str, P) -> tuple[float, float] | None:
    """A direction [x, y] made unit (kept exactly when already unit, e.g. written by dump); None when absent or
    after a problem."""
    if v is None:
        return None
    if not isinstance(v, list) or len(v) != 2 or not all(_num(c) for c in v) or math.hypot(*v) == 0:
        P.add(path, f"must be a non-zero vector [x, y]: {v!r}")
        return None
    n = math.hypot(*v)
    if abs(n - 1.0) < TOL.unit_norm:
        n = 1.0
    return (float(v[0]) / n, float(v[1]) / n)

def _joint_axis(v, angle_factor, path, P):
    """A joint axis: a non-zero vector [x, y, z], or {gamma1, gamma2} (file angle units), the axis
    e_Z2 = (sin γ1 cos γ2, −sin γ2, cos γ1 cos γ2) of paper 003 eq. (8); a unit tuple or None."""
    if v is None:
        return None
    if isinstance(v, dict):
        bad = [k for k in v if k not in ("gamma1", "gamma2")]
        if bad or not all(_num(v.get(k, 0.0)) for k in ("gamma1", "gamma2")):
            P.add(path, f"must be [x, y, z] or {{gamma1, gamma2}} (angles): {v!r}")
            return None
        g1, g2 = (float(v.get(k, 0.0)) * angle_factor for k in ("gamma1", "gamma2"))
        return (math.sin(g1) * math.cos(g2), -math.sin(g2), math.cos(g1) * math.cos(g2))
    if not isinstance(v, list) or len(v) != 3 or not all(_num(c) for c in v) or math.hypot(*v) == 0:
        P.add(path, f"must be a non-zero vector [x, y, z] or {{gamma1, gamma2}}: {v!r}")
        return None
    n = math.hypot(*v)
    if abs(n - 1.0) < TOL.unit_norm:
        n = 1.0
    return tuple(float(c) / n for c in v)


def _stroke_range(v, length_factor, path, P):
    """A linear driver's ``range = [START, STOP]`` (file length unit, both positive, different) in m."""
    if v is None:
        return None
    if not (isinstance(v, list) and len(v) == 2 and all(_num(c) and c > 0 for c in v) and v[0] != v[1]):
        P.add(path, f"must be [START, STOP], two different positive actuator lengths: {v!r}")
        return None
    return (float(v[0]) * length_factor, float(v[1]) * length_factor)


def _time_table(v, length_factor, path, P):
    """A linear driver's ``law = {time = [...], length = [...], interpolation = "cubic" | "pchip"}``."""
    if v is None:
        return None
    if not isinstance(v, dict):
        P.add(path, f"must be a table {{time = [...], length = [...]}}: {v!r}")
        return None
    bad = [k for k in v if k not in ("time", "length", "interpolation")]
    if bad:
        P.add(f"{path}.{bad[0]}", "unknown key (allowed: interpolation, length, time)")
    t, q = v.get("time"), v.get("length")
    ok = True
    if not (isinstance(t, list) and len(t) >= 2 and all(_num(c) for c in t)):
        P.add(f"{path}.time", f"must be a list of at least 2 times (s): {t!r}")
        ok = False
    elif any(b <= a for a, b in zip(t, t[1:])):
        i = next(i for i, (a, b) in enumerate(zip(t, t[1:])) if b <= a)
        P.add(f"{path}.time[{i + 1}]", f"times must increase strictly: {t[i]!r} then {t[i + 1]!r}")
        ok = False
    if not (isinstance(q, list) and all(_num(c) and c > 0 for c in q)):
        P.add(f"{path}.length", f"must be a list of positive actuator lengths: {q!r}")
        ok = False
    elif isinstance(t, list) and len(q) != len(t):
        P.add(f"{path}.length", f"needs one length per time: {len(q)} lengths for {len(t)} times")
        ok = False
    kind = v.get("interpolation", "cubic")
    if kind not in ("cubic", "pchip"):
        P.add(f"{path}.interpolation", f"must be 'cubic' or 'pchip': {kind!r}")
        ok = False
    if not ok:
        return None
    return TimeTable(tuple(float(c) for c in t), tuple(float(c) * length_factor for c in q), kind)


def ldata_points(ldata, link) -> list:
    """The point names listed by link ``link`` of a document's ``links`` table (as written)."""
    spec = ldata.get(link)
    return spec if isinstance(spec, list) else (spec or {}).get("points", [])



__all__ = ["MAX_MAGNITUDE", "ldata_points", "read_actuators", "read_branches", "read_drivers", "read_gait",
           "read_joints", "read_links", "read_points", "read_prismatic"]
