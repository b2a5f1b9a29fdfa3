"""Writing mechanism files (TOML, ``format = "assur/1"``): numbers back in the file's units, each with the
fewest digits that load back to exactly the same SI value. With ``clean=True`` (the designs ``assur synth -o``
writes) rounding noise — a length below 1e-9 of the sketch's size, an angle below 1e-9 rad — is written as 0.
"""
from __future__ import annotations

import math

from ..model.mechanism import Mechanism
from ..tolerances import DEFAULT as TOL
from . import units as U
from .cam_pairs import law_table
from .motor_file import motor_table
from .output import atomic_file
from .toml_writer import dumps as write_toml


def _out(si: float, factor: float = 1.0, scale: float | None = None) -> float | int:
    """``si / factor`` in file units with the fewest digits that load back to exactly ``si``; 0 for rounding
    noise, |si| at most :attr:`~assur.tolerances.Tolerances.rounding_noise` times ``scale`` (SI)."""
    if scale is not None and abs(si) <= TOL.rounding_noise * abs(scale):
        return 0
    x = si / factor
    y = x
    for digits in range(1, 18):
        y = float(f"{x:.{digits}g}")
        if y * factor == si:
            break
    else:
        y = x
    return int(y) if y.is_integer() and abs(y) < 2**53 else y


def _length_scale(m: Mechanism) -> float:
    """The size of the sketch's bounding box (m), the scale of the rounding noise of its lengths."""
    coords = [xy for _, xy in m.points]
    if not coords:
        return 1.0
    span = max(max(c[i] for c in coords) - min(c[i] for c in coords) for i in range(len(coords[0])))
    return span if span > 0 else max(1.0, max(abs(v) for c in coords for v in c))


def as_dict(m: Mechanism, clean: bool = False) -> dict:
    """The mechanism as a document dict (file units), ready for the TOML writer; ``clean``: rounding noise of
    lengths and angles as 0 (else every value loads back exactly)."""
    L, A = U.LENGTH[m.units.length], U.ANGLE[m.units.angle]
    sL = _length_scale(m) if clean else None

    def ln(v):   # a length
        return _out(v, L, sL)

    def an(v):   # an angle
        return _out(v, A, math.pi if clean else None)

    def unit(v):   # a component of a direction: exact (a file's axis angles load to these components)
        return _out(v)
    d: dict = {"format": m.format}
    if m.name:
        d["name"] = m.name
    if m.description:
        d["description"] = m.description
    if m.dimension != 2:
        d["dimension"] = m.dimension
    d["units"] = {"length": m.units.length, "angle": m.units.angle}
    d["points"] = {n: [ln(c) for c in xy] for n, xy in m.points}
    links = {}
    for lk in m.links:
        if lk.length is None and not lk.place:
            links[lk.name] = list(lk.points)
        else:
            t: dict = {"points": list(lk.points)}
            if lk.length is not None:
                t["length"] = ln(lk.length)
            if lk.place:
                t["place"] = {pn: {"from": p.origin, "toward": p.toward, "distance": ln(p.distance),
                                   "angle": an(p.angle)} for pn, p in lk.place}
            links[lk.name] = t
    d["links"] = links
    masses = dict(m.dynamics.bodies) if m.dynamics is not None else {}
    for name, mp in masses.items():
        if name in links:
            if isinstance(links[name], list):
                links[name] = {"points": links[name]}
            links[name] |= _mass_table(mp, ln)
    # TOML writes plain values before tables: once a link is a table, the later ones are tables too (their order
    # is the bodies' numbering)
    tabled = False
    for name, v in links.items():
        tabled = tabled or isinstance(v, dict)
        if tabled and isinstance(v, list):
            links[name] = {"points": v}
    if m.prismatic:
        out = []
        for pr in m.prismatic:
            t = {"name": pr.name, "guide": pr.guide, "through": pr.through, "angle": an(pr.angle)}
            if pr.offset:
                t["offset"] = ln(pr.offset)
            if pr.point is not None:
                t["point"] = pr.point
            else:
                t["link"] = pr.link
            if f"{pr.name}.block" in masses:
                t |= _mass_table(masses[f"{pr.name}.block"], ln)
            out.append(t)
        d["prismatic"] = out
    if m.actuators:
        d["actuators"] = {a.name: {"between": list(a.between)} | {part: _mass_table(masses[f"{a.name}.{part}"], ln)
                                                                  for part in ("cylinder", "rod")
                                                                  if f"{a.name}.{part}" in masses}
                          for a in m.actuators}
    if m.drivers:
        out = []
        for dr in m.drivers:
            if dr.kind == "rotary":
                out.append({"name": dr.name, "kind": "rotary", "link": dr.link, "pivot": dr.pivot, "arm": dr.arm,
                            "zero": an(dr.zero), "sense": "cw" if dr.sense < 0 else "ccw",
                            "speed": U.format_speed(dr.speed, "rotary", m.units)})
            else:
                t = {"name": dr.name, "kind": "linear", "actuator": dr.actuator,
                     "speed": U.format_speed(dr.speed, "linear", m.units)}
                if dr.range is not None:
                    t["range"] = [ln(v) for v in dr.range]
                if dr.law is not None:
                    t["law"] = {"time": [_out(v) for v in dr.law.times], "length": [ln(v) for v in dr.law.values],
                                "interpolation": dr.law.interpolation}
                out.append(t)
        d["drivers"] = out
    if m.gears:
        d["gears"] = [_gear_table(gp, an) for gp in m.gears]
    if m.cams:
        d["cams"] = [_cam_table(cp, ln, an) for cp in m.cams]
    if m.branches:
        d["branches"] = {b.point: ({"side": b.side, "of": list(b.of)} if b.side is not None else {})
                         | ({"slide": b.slide, "on": b.on} if b.slide is not None else {}) for b in m.branches}
    if m.joints:
        with_axes = any(j.axis is not None for j in m.joints)   # then all as tables: the writer keeps their order
        d["joints"] = {j.point: ({"kind": j.kind} | ({} if j.axis is None else {"axis": [unit(c) for c in j.axis]})
                                 if with_axes else j.kind) for j in m.joints}
    if m.gait is not None:
        g = {"foot": m.gait.foot, "ground": [unit(c) for c in m.gait.ground]}
        if m.gait.up is not None:
            g["up"] = [unit(c) for c in m.gait.up]
        g["phases"] = [an(p) for p in m.gait.phases]
        if m.gait.weight is not None:
            g["weight"] = _out(m.gait.weight)
        if m.gait.friction is not None:
            g["friction"] = _out(m.gait.friction)
        d["gait"] = g
    if m.dynamics is not None:
        _write_dynamics(d, m, ln)
    if m.motor is not None:
        d["motor"] = motor_table(m.motor, m, _out)
    if m.make is not None:
        from .make_file import make_table
        d["make"] = make_table(m.make, lambda v: _out(v, L), _out)
    return d


def _gear_table(gp, an) -> dict:
    """A ``[[gears]]`` entry: the law as it was given (a ratio, an expression, a design file) or as its table."""
    law = gp.law
    if gp.design is not None:
        value = gp.design
    elif law.kind == "ratio":
        value = _out(law.ratio)
    elif law.expression is not None:
        value = law.expression
    else:
        value = {"phi": [an(v) for v in law.phi], "theta": [an(v) for v in law.theta]}
    t = {"name": gp.name, "a": gp.a, "b": gp.b, "law": value}
    if law.kind != "ratio" and gp.design is None and law.driving_turns != 1:
        t["driving_turns"] = law.driving_turns
    t |= {"mesh": gp.mesh, "phase": an(gp.phase), "pressure_angle": an(gp.pressure_angle)}
    return t


def _cam_table(cp, ln, an) -> dict:
    """A ``[[cams]]`` entry (lifts in the file's length unit, or its angle unit for an oscillating follower)."""
    t = {"name": cp.name, "cam": cp.cam, "follower": cp.follower, "point": cp.point, "contact": cp.contact}
    if cp.contact == "roller":
        t["roller_radius"] = ln(cp.roller_radius)
    if cp.contact == "flat" and cp.face_angle:
        t["face_angle"] = an(cp.face_angle)
    if not cp.law.profile:
        t |= {"phase": an(cp.phase), "rotation": "ccw" if cp.rotation > 0 else "cw"}
    t["pressure_limit"] = an(cp.pressure_limit)
    t["law"] = law_table(cp.law, an, an if cp.motion == "oscillating" else ln, ln)
    return t


def _mass_table(mp, ln) -> dict:
    """A body's mass properties as its table's keys: kg, kg·m² and the com in the file's length unit."""
    t: dict = {"mass": _out(mp.mass)}
    if mp.inertia is not None:
        t["inertia"] = _out(mp.inertia)
    if isinstance(mp.com, tuple):
        t["com"] = [ln(c) for c in mp.com]
    elif isinstance(mp.com, (int, float)):
        t["com"] = ln(mp.com)
    elif mp.com is not None:
        t["com"] = mp.com
    return t


def _write_dynamics(d: dict, m: Mechanism, ln) -> None:
    """``[dynamics]`` (gravity, friction) and ``[[loads]]`` (N, N·m; a law's input in the first driver's unit)."""
    dyn, fr = m.dynamics, m.dynamics.friction
    t: dict = {"gravity": [_out(g) for g in dyn.gravity]}
    if fr.joint_radius:
        t["joint_friction_radius"] = ln(fr.joint_radius)
    if fr.slide:
        t["slide_friction"] = _out(fr.slide)
    if fr.joints:
        t["joints"] = {p: ln(r) for p, r in fr.joints}
    if fr.slides:
        t["slides"] = {n: _out(mu) for n, mu in fr.slides}
    d["dynamics"] = t
    if not dyn.loads:
        return
    factor = 1.0
    if m.drivers:
        factor = U.ANGLE[m.units.angle] if m.drivers[0].kind == "rotary" else U.LENGTH[m.units.length]
    out = []
    for ld in dyn.loads:
        t = {k: v for k, v in (("point", ld.point), ("link", ld.link)) if v is not None}
        if ld.force is not None:
            t["force"] = [_out(c) for c in ld.force]
        if ld.torque is not None:
            t["torque"] = _out(ld.torque)
        if ld.opposes is not None:
            t["opposes"] = ld.opposes
        if ld.law is not None:
            law: dict = {"input": [_out(v, factor) for v in ld.law.inputs]}
            if len(ld.law.values[0]) == 1:   # (n, 1) torques; forces have 2 or 3 components
                law["torque"] = [_out(r[0]) for r in ld.law.values]
            else:
                law["force"] = [[_out(c) for c in r] for r in ld.law.values]
            t["law"] = law
        out.append(t)
    d["loads"] = out


def dumps(m: Mechanism, clean: bool = False) -> str:
    """The mechanism as TOML text (``clean``: rounding noise as 0, see :func:`as_dict`)."""
    from ..model.mechanism import require_mechanism
    return write_toml(as_dict(require_mechanism(m), clean))


def dump(m: Mechanism, path=None, clean: bool = False) -> str:
    """The mechanism as TOML text; written to ``path`` (atomically) when given."""
    text = dumps(m, clean)
    if path is not None:
        with atomic_file(path) as tmp:
            tmp.write_text(text, encoding="utf-8")
    return text


__all__ = ["as_dict", "dump", "dumps", "to_dict"]


#: the former name of :func:`as_dict` (the pair of ``mechanism_file.from_dict``)
to_dict = as_dict
