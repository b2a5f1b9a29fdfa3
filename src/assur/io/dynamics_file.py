"""The force analysis' part of a mechanism file: masses, loads, friction, gravity and the gait's foot load.

Read by :mod:`assur.io.mechanism_file`: ``mass``, ``inertia`` and ``com`` of ``[links.NAME]``, of a pin-in-slot
``[[prismatic]]`` (its block) and of an actuator's ``cylinder`` and ``rod`` sub-tables; ``[dynamics]`` (gravity,
friction), ``[[loads]]`` and ``[gait] weight, friction``. Numbers are converted to SI (kg, kg·m², m, N, N·m) and
every problem is added to the reader's :class:`~assur.io.problems.Problems` with its location.
"""
from __future__ import annotations

import math

from ..errors import SpecError
from ..model.dynamics import Dynamics, Friction, Load, LoadLaw, MassProperties
from . import units as U

#: the keys of a body's mass properties in its table
MASS_KEYS = ("mass", "inertia", "com")
_DYNAMICS_KEYS = ("gravity", "joint_friction_radius", "slide_friction", "joints", "slides")
_LOAD_KEYS = ("point", "link", "force", "torque", "opposes", "law")
_MAX = 1e9


def _number(x) -> bool:
    return isinstance(x, (int, float)) and not isinstance(x, bool) and math.isfinite(x) and abs(x) < _MAX


def _names(names) -> str:
    names = sorted(names)
    return ", ".join(names[:12]) + (", …" if len(names) > 12 else "") if names else "none"


def _quantity(P, path, value, kind, units=None, nonnegative=False):
    """``value`` in SI (:func:`assur.io.units.parse_quantity`), or None after adding the problem."""
    try:
        v = U.parse_quantity(value, kind, units)
    except SpecError as exc:
        P.add(path, str(exc))
        return None
    if nonnegative and v < 0:
        P.add(path, f"must not be negative: {value!r}")
        return None
    return v


def _coefficient(P, path, value):
    """A friction coefficient: a number >= 0, or None after adding the problem."""
    if not _number(value) or value < 0:
        P.add(path, f"must be a non-negative number (a friction coefficient): {value!r}")
        return None
    return float(value)


def _mass(spec, path, P, com):
    """The MassProperties of a body's table (``com`` already read), or None when it gives none."""
    if not any(k in spec for k in MASS_KEYS):
        return None
    mass = _quantity(P, f"{path}.mass", spec["mass"], "mass", nonnegative=True) if "mass" in spec else 0.0
    inertia = _quantity(P, f"{path}.inertia", spec["inertia"], "inertia", nonnegative=True) \
        if "inertia" in spec else None
    return MassProperties(mass or 0.0, inertia, com)


def _link_com(v, lname, plist, path, P, factor, dimension):
    """A link's ``com``: "mid" (binary links), one of its points, or sketch coordinates (file length unit)."""
    if v is None:
        return None
    if v == "mid":
        if len(plist) != 2:
            P.add(path, f"'mid' needs a binary link; '{lname}' has {len(plist)} points")
        return "mid"
    if isinstance(v, str):
        if v not in plist:
            P.add(path, f"is not a point of link '{lname}' (its points: {', '.join(map(str, plist))}): {v!r}")
        return v
    if isinstance(v, list) and len(v) == dimension and all(_number(c) for c in v):
        return tuple(float(c) * factor for c in v)
    xyz = ", ".join("xyz"[:dimension])
    P.add(path, f"must be 'mid', a point of the link or [{xyz}] (sketch coordinates, file length unit): {v!r}")
    return None


def _vector(v, path, P, dimension, kind):
    """A force (or gravity, kind None) vector of ``dimension`` components in SI, or None after the problem."""
    if not isinstance(v, list) or len(v) != dimension:
        P.add(path, f"must be [{', '.join('xyz'[:dimension])}]: {v!r}")
        return None
    if kind is None:
        if not all(_number(c) for c in v):
            P.add(path, f"must be [{', '.join('xyz'[:dimension])}] numbers (m/s²): {v!r}")
            return None
        g = math.hypot(*(float(c) for c in v))
        if g > U.MAX_GRAVITY:
            P.add(path, f"|g| = {g:.4g} m/s² is beyond any machine's ground (at most {U.MAX_GRAVITY:g} m/s², about "
                        f"100 g; the Earth's is 9.81): {v!r}")
            return None
        return tuple(float(c) for c in v)
    out = [_quantity(P, f"{path}[{j}]", c, kind) for j, c in enumerate(v)]
    return None if any(c is None for c in out) else tuple(out)


def read_bodies(data, P, units, dimension, length_factor):
    """(body name, MassProperties) of every body whose table gives mass properties, in file order: links,
    slider blocks, actuators' cylinders and rods."""
    bodies = []
    ldata = data.get("links")
    for lname, spec in (ldata.items() if isinstance(ldata, dict) else ()):
        if not isinstance(spec, dict):
            continue
        plist = spec.get("points") if isinstance(spec.get("points"), list) else []
        com = _link_com(spec.get("com"), lname, plist, f"links.{lname}.com", P, length_factor, dimension)
        mp = _mass(spec, f"links.{lname}", P, com)
        if mp is not None:
            bodies.append((lname, mp))
    prdata = data.get("prismatic")
    for i, spec in enumerate(prdata if isinstance(prdata, list) else ()):
        path = f"prismatic[{i}]"
        if not isinstance(spec, dict) or not any(k in spec for k in MASS_KEYS):
            continue
        if spec.get("link") is not None:
            for k in MASS_KEYS:
                if k in spec:
                    P.add(f"{path}.{k}", f"the link '{spec['link']}' translates on the guide: give its {k} "
                                         f"in [links.{spec['link']}]")
            continue
        if "com" in spec:
            P.add(f"{path}.com", f"a slider block's centre of mass is its point {spec.get('point')!r}; "
                                 "it takes no com")
        mp = _mass(spec, path, P, None)
        bodies.append((f"{spec.get('name', f'slide{i + 1}')}.block", mp))
    adata = data.get("actuators")
    for name, spec in (adata.items() if isinstance(adata, dict) else ()):
        if not isinstance(spec, dict):
            continue
        for part in ("cylinder", "rod"):
            if part not in spec:
                continue
            sub, path = spec[part], f"actuators.{name}.{part}"
            if not isinstance(sub, dict):
                P.add(path, f"must be a table {{mass, inertia, com}}: {sub!r}")
                continue
            P.unknown_keys(sub, MASS_KEYS, path)
            com = _quantity(P, f"{path}.com", sub["com"], "length", units) if "com" in sub else None
            mp = _mass(sub, path, P, com)
            if mp is not None:
                bodies.append((f"{name}.{part}", mp))
    return bodies


def _law(v, path, P, dimension, input_factor):
    """A load's ``law = {input = [...], force = [[x, y], ...]}`` (or ``torque = [...]``): (LoadLaw, kind)."""
    if not isinstance(v, dict):
        P.add(path, f"must be a table {{input = [...], force = [[x, y], ...]}} or {{input = [...], torque = [...]}}: "
                    f"{v!r}")
        return None, None
    P.unknown_keys(v, ("input", "force", "torque"), path)
    kinds = [k for k in ("force", "torque") if k in v]
    if len(kinds) != 1:
        P.add(path, "needs exactly one of force = [[x, y], …] or torque = […]")
        return None, None
    kind = kinds[0]
    inp, vals = v.get("input"), v[kind]
    ok = True
    if input_factor is None:
        P.add(f"{path}.input", "needs a driver: the input is the first driver's (crank angle or actuator length)")
        ok = False
    if not (isinstance(inp, list) and len(inp) >= 2 and all(_number(c) for c in inp)):
        P.add(f"{path}.input", f"must be a list of at least 2 inputs of the first driver: {inp!r}")
        return None, kind
    bad = [i for i, (a, b) in enumerate(zip(inp, inp[1:])) if b <= a]
    if bad:
        P.add(f"{path}.input[{bad[0] + 1}]", f"inputs must increase strictly: {inp[bad[0]]!r} then {inp[bad[0] + 1]!r}")
        ok = False
    if not isinstance(vals, list) or len(vals) != len(inp):
        n = len(vals) if isinstance(vals, list) else vals
        P.add(f"{path}.{kind}", f"needs one value per input: {n!r} for {len(inp)} inputs")
        return None, kind
    if kind == "force":
        rows = [_vector(r, f"{path}.force[{j}]", P, dimension, "force") for j, r in enumerate(vals)]
    else:
        rows = [_quantity(P, f"{path}.torque[{j}]", r, "torque") for j, r in enumerate(vals)]
        rows = [None if r is None else (r,) for r in rows]
    if not ok or any(r is None for r in rows):
        return None, kind
    return LoadLaw(tuple(float(c) * input_factor for c in inp), tuple(rows)), kind


def read_loads(data, P, dimension, point_names, body_points, input_factor, place=None):
    """The ``[[loads]]``. ``body_points``: body name → its points (links, blocks, cylinders, rods); ``place(point)``
    the body a force at a point without ``link`` acts on (ValueError where that is ambiguous: the rule of
    :func:`assur.model.dynamics.load_body`)."""
    ldata = P.section(data, "loads", "must be an array of tables [[loads]]", list)
    loads = []
    for i, spec in enumerate(ldata):
        path = f"loads[{i}]"
        if not isinstance(spec, dict):
            P.add(path, "must be a table")
            continue
        P.unknown_keys(spec, _LOAD_KEYS, path)
        point, link = (x if x is None or isinstance(x, str) else repr(x) for x in (spec.get("point"), spec.get("link")))
        if point is not None and point not in point_names:
            P.add(f"{path}.point", f"unknown point {point!r} (known: {_names(point_names)})")
        if link is not None and link not in body_points:
            P.add(f"{path}.link", f"unknown link {link!r} (known: {_names(body_points)})")
        elif point in point_names and link is not None and point not in body_points[link]:
            P.add(f"{path}.point", f"is not a point of '{link}' (its points: {', '.join(body_points[link])}): {point!r}")
        given = [k for k in ("force", "torque", "law") if k in spec]
        if not given:
            P.add(path, "a load on nothing: give force = [x, y] (at a point), torque (on a link) or law")
            continue
        if len(given) > 1:
            P.add(path, f"takes one of force, torque or law (a force or torque that varies): got {', '.join(given)}")
            continue
        force = torque = law = None
        if "force" in spec:
            kind, force = "force", _vector(spec["force"], f"{path}.force", P, dimension, "force")
        elif "torque" in spec:
            kind, torque = "torque", _quantity(P, f"{path}.torque", spec["torque"], "torque")
        else:
            law, kind = _law(spec["law"], f"{path}.law", P, dimension, input_factor)
        if kind == "force" and point is None:
            P.add(f"{path}.point", "a force needs the point it acts at")
        elif kind == "force" and link is None and point in point_names and place is not None:
            try:
                place(point)
            except ValueError as exc:
                P.add(f"{path}.link", str(exc))
        if kind == "torque" and link is None:
            P.add(f"{path}.link", "a torque needs the link it acts on")
        opposes = spec.get("opposes")
        if opposes is not None and opposes != "velocity":
            P.add(f"{path}.opposes", f"must be 'velocity': {opposes!r}")
        elif opposes is not None and kind != "force":
            P.add(f"{path}.opposes", "opposes the velocity of a point: it needs a force")
        loads.append(Load(point, link, force, torque, opposes, law))
    return loads


def read_friction(dyn, P, units, point_names, pair_names):
    """The friction keys of ``[dynamics]``."""
    radius = _quantity(P, "dynamics.joint_friction_radius", dyn["joint_friction_radius"], "length", units,
                       nonnegative=True) if "joint_friction_radius" in dyn else 0.0
    slide = _coefficient(P, "dynamics.slide_friction", dyn["slide_friction"]) if "slide_friction" in dyn else 0.0
    joints, slides = [], []
    for key, known, what, out in (("joints", point_names, "point", joints), ("slides", pair_names, "pair", slides)):
        table = dyn.get(key, {})
        if not isinstance(table, dict):
            P.add(f"dynamics.{key}", f"must be a table of {what} = value")
            continue
        for name, v in table.items():
            path = f"dynamics.{key}.{name}"
            if name not in known:
                kinds = "point" if key == "joints" else "prismatic pair or actuator"
                P.add(path, f"unknown {kinds} {name!r} (known: {_names(known)})")
                continue
            x = _quantity(P, path, v, "length", units, nonnegative=True) if key == "joints" \
                else _coefficient(P, path, v)
            if x is not None:
                out.append((name, x))
    return Friction(radius or 0.0, slide or 0.0, tuple(joints), tuple(slides))


def read_dynamics(data, P, *, units, dimension, length_factor, point_names, links, prismatic, actuators,
                  drivers):
    """The mechanism's :class:`Dynamics`, or None when the file gives no ``[dynamics]``, no mass and no load.

    ``links``, ``prismatic``, ``actuators``, ``drivers``: the elements read so far (their names and points);
    the input of a load's law is in the file's unit of the first driver (angle or length)."""
    bodies = read_bodies(data, P, units, dimension, length_factor)
    body_points = {lk.name: tuple(lk.points) for lk in links}
    body_points |= {f"{pr.name}.block": (pr.point,) for pr in prismatic if pr.point is not None}
    for ac in actuators:
        body_points[f"{ac.name}.cylinder"] = (ac.between[0],)
        body_points[f"{ac.name}.rod"] = (ac.between[1],)
    input_factor = None
    if drivers:
        input_factor = U.ANGLE[units.angle] if drivers[0].kind == "rotary" else U.LENGTH[units.length]
    from ..model.dynamics import load_body
    from ..model.mechanism import bodies_at

    def place(point):
        return load_body(point, None, *bodies_at(point, links, prismatic, actuators))
    loads = read_loads(data, P, dimension, point_names, body_points, input_factor, place)
    dyn = P.section(data, "dynamics", "must be a table [dynamics]")
    if "dynamics" not in data and not bodies and not loads:
        return None
    P.unknown_keys(dyn, _DYNAMICS_KEYS, "dynamics")
    gravity = (0.0,) * dimension
    if "gravity" in dyn:
        gravity = _vector(dyn["gravity"], "dynamics.gravity", P, dimension, None) or gravity
    pair_names = {pr.name for pr in prismatic} | {ac.name for ac in actuators}
    friction = read_friction(dyn, P, units, point_names, pair_names)
    return Dynamics(gravity, tuple(bodies), tuple(loads), friction)


def read_gait_load(gdata, P):
    """``[gait] weight`` (N, >= 0) and ``friction`` (μ >= 0): (weight, friction), each None when not given."""
    weight = _quantity(P, "gait.weight", gdata["weight"], "force", nonnegative=True) if "weight" in gdata else None
    friction = _coefficient(P, "gait.friction", gdata["friction"]) if "friction" in gdata else None
    return weight, friction


__all__ = ["MASS_KEYS", "read_bodies", "read_dynamics", "read_friction", "read_gait_load", "read_loads"]
