"""Mechanism files (TOML, ``format = "assur/1"``): load with full validation, dump, round-trip.

Every problem in a file is collected and raised at once as one :class:`~assur.errors.SpecError`
whose lines name the location, e.g. ``links.coupler[2]: unknown point 'Q' (known: A, B, O1)``.
Numbers are converted to SI at load (``[units]``) and back to the file's units at dump.
"""
from __future__ import annotations

import math
import re
import warnings

from ..errors import SketchWarning, SpecError
from ..model.mechanism import (FRAME, Actuator, BranchHint, Gait, Joint, LinearDriver, Link, Mechanism,
                               Placement, Prismatic, RotaryDriver, TimeTable, Units)
from ..tolerances import DEFAULT as TOL
from . import units as U
from .dynamics_file import MASS_KEYS, read_dynamics, read_gait_load
from .mechanism_writer import as_dict, dump, dumps, to_dict
from .cam_pairs import read_cam_pairs
from .gear_pairs import read_gear_pairs
from .motor_file import read_motor
from .make_file import read_make
from .problems import Problems
from .toml_reader import parse_toml, read_text, read_toml

FORMAT = "assur/1"
_NAME = re.compile(r"^[A-Za-z_][A-Za-z0-9_']*$")
_TOP = {"format", "name", "description", "units", "points", "links", "prismatic", "actuators", "drivers",
        "branches", "joints", "gait", "style", "dimension", "dynamics", "loads", "gears", "cams", "motor", "make"}
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
        bad = [q for q in spec["of"] if q not in point_names]
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


def load(path) -> Mechanism:
    """Read a mechanism file. Raises SpecError (every problem, with its location)."""
    return loads(read_text(path), source=str(path))


def loads(text: str, source: str | None = None) -> Mechanism:
    """Read a mechanism from TOML text (``source`` names it in messages). Raises SpecError."""
    return from_dict(parse_toml(text, source), source)


def from_dict(data: dict, source: str | None = None) -> Mechanism:
    """A Mechanism from a parsed document. Raises SpecError listing every problem with its location."""
    P = Problems()
    P.unknown_keys(data, sorted(_TOP))
    fmt = data.get("format")
    if fmt != FORMAT:
        P.add("format", f"must be '{FORMAT}': {fmt!r}")
    dimension = data.get("dimension", 2)
    if dimension not in (2, 3):
        P.add("dimension", f"must be 2 or 3: {dimension!r}")
        dimension = 2

    ulen, uang = U.parse_units(data, P, "m")
    units = Units(ulen, uang)
    L, A = U.LENGTH[ulen], U.ANGLE[uang]

    # points
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
    point_names = set(pdata)

    # links
    ldata = data.get("links")
    links: list[Link] = []
    if not isinstance(ldata, dict) or not ldata:
        P.add("links", "must be a table of links, including 'frame'")
        ldata = {}
    elif FRAME not in ldata:
        P.add("links", f"must include the ground link '{FRAME}' (links: {', '.join(ldata)})")
    for lname, spec in ldata.items():
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
                continue
        else:
            P.add(path, "must be a list of point names or a table with 'points'")
            continue
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
            pl = spec.get("place", {})
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
        if ok:
            links.append(Link(lname, tuple(plist), length, tuple(place)))
    link_names = {lk.name for lk in links} | set(ldata)
    link_points = {lk.name: set(lk.points) for lk in links}

    # prismatic pairs
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

    # actuators
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
    actuator_names = {a.name for a in actuators}

    # drivers
    drivers = []
    ddata = P.section(data, "drivers", "must be an array of tables [[drivers]]", list)
    seen_names = set()
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
            drivers.append(RotaryDriver(str(name), link, pivot, arm, float(zero) * A,
                                        -1 if sense == "cw" else 1, speed))
        elif kind == "linear":
            P.unknown_keys(spec, ("actuator", "kind", "law", "name", "range", "speed"), path)
            act = _name(spec.get("actuator"))
            if act not in actuator_names:
                P.add(f"{path}.actuator", f"unknown actuator {act!r} {_known(actuator_names)}")
            drivers.append(LinearDriver(str(name), act, speed, _stroke_range(spec.get("range"), L, f"{path}.range", P),
                                        _time_table(spec.get("law"), L, f"{path}.law", P)))
        else:
            P.add(f"{path}.kind", f"must be 'rotary' or 'linear': {kind!r}")

    # branches
    branches = []
    bdata = P.section(data, "branches", "must be a table of point = {side, of} (or {slide, on})")
    slides = {pr.name for pr in prismatic} | {a.name for a in actuators}
    for pn, spec in bdata.items():
        hint = _branch_hint(P, f"branches.{pn}", pn, spec, point_names, slides)
        if hint is not None:
            branches.append(hint)

    # joints (spatial descriptions)
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

    # gait
    gait = None
    gdata = data.get("gait")
    if gdata is not None:
        if not isinstance(gdata, dict):
            P.add("gait", "must be a table with 'foot'")
        else:
            P.unknown_keys(gdata, ("foot", "ground", "phases", "up", "weight", "friction"), "gait")
            foot = gdata.get("foot")
            if foot not in point_names:
                P.add("gait.foot", f"unknown point {foot!r} {_known(point_names)}")
            vecs = {}
            for k in ("ground", "up"):
                v = gdata.get(k)
                if v is None:
                    vecs[k] = None
                elif not isinstance(v, list) or len(v) != 2 or not all(_num(c) for c in v) or math.hypot(*v) == 0:
                    P.add(f"gait.{k}", f"must be a non-zero vector [x, y]: {v!r}")
                    vecs[k] = None
                else:
                    n = math.hypot(*v)
                    if abs(n - 1.0) < TOL.unit_norm:   # already a unit vector (e.g. written by dump): keep it exactly
                        n = 1.0
                    vecs[k] = (float(v[0]) / n, float(v[1]) / n)
            phases = gdata.get("phases", [0.0])
            if not isinstance(phases, list) or not phases or not all(_num(c) for c in phases):
                P.add("gait.phases", f"must be a non-empty list of crank phase offsets: {phases!r}")
                phases = [0.0]
            if vecs["ground"] and vecs["up"] and abs(vecs["ground"][0] * vecs["up"][0]
                                                     + vecs["ground"][1] * vecs["up"][1]) > TOL.perpendicular:
                P.add("gait.up", "must be perpendicular to gait.ground")
            gait = Gait(str(foot), vecs["ground"] or (1.0, 0.0), vecs["up"], tuple(float(c) * A for c in phases),
                        *read_gait_load(gdata, P))

    gears = read_gear_pairs(data, P, angle_factor=A, link_points={lk.name: lk.points for lk in links},
                            frame_points=set(next((lk.points for lk in links if lk.name == FRAME), ())),
                            source=source)
    if gears and dimension == 3:
        P.add("gears", "gear pairs need a planar mechanism (dimension = 2)")
    cams = read_cam_pairs(data, P, length_factor=L, angle_factor=A, link_points={lk.name: lk.points for lk in links},
                          frame_points=set(next((lk.points for lk in links if lk.name == FRAME), ())),
                          prismatic=prismatic, drivers=drivers, points=dict(points))
    if cams and dimension == 3:
        P.add("cams", "cam pairs need a planar mechanism (dimension = 2)")
    dynamics = read_dynamics(data, P, units=units, dimension=dimension, length_factor=L, point_names=point_names,
                             links=links, prismatic=prismatic, actuators=actuators, drivers=drivers)
    make = read_make(data, P, units=units)
    if make is not None and dimension == 3:
        P.add("make", "assur make builds planar mechanisms (dimension = 2)")

    motor = read_motor(data["motor"], P, units, drivers) if "motor" in data else None

    # every point must be on something (as listed, even by a link with other problems)
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

    name = data.get("name", "")
    if not isinstance(name, str):
        P.add("name", f"must be a string: {name!r}")
        name = ""
    desc = data.get("description", "")
    if not isinstance(desc, str):
        P.add("description", f"must be a string: {desc!r}")
        desc = ""
    P.raise_if_any(source)
    m = Mechanism(name=name, points=tuple(points), links=tuple(links), prismatic=tuple(prismatic),
                  actuators=tuple(actuators), drivers=tuple(drivers), branches=tuple(branches),
                  joints=tuple(joints), gait=gait, dynamics=dynamics, gears=gears, cams=cams, description=desc,
                  units=units, dimension=dimension, motor=motor, make=make)
    _warn_lengths_off_the_sketch(m, L, source)
    return m


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


__all__ = ["FORMAT", "as_dict", "dump", "dumps", "from_dict", "ldata_points", "load", "loads", "read_text", "read_toml",
           "to_dict"]
