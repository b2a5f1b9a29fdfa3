"""PMKS+ share links and ``.pmks`` files (https://app.pmksplus.com): reading both the production and the current
encoding, writing the production one (:mod:`.pmks_codec` has the text layer).

The previous (2023) encoding ``?j=…&l=…&f=…&s=…`` is read too (:func:`decode_2023`).

**Joints** are ``FLAGS id,name,x,y,angle[,carrier,slotA,slotB[,driveSpeed[,…]]]`` with the flags (prismatic,
input, grounded, welded, show curve, sealed); coordinates in the drawing's length unit, the angle (a slider's
slide direction) in radians. **Links** are ``ROOT TYPE id,name,mass,inertia,xCoM,yCoM,color,joint,…,,subset,…``:
``R`` a rigid link through its joints, ``P`` a slider block ("piston") between a pin and its prismatic joint; a
root link with subset links is one welded body. The settings give the length unit (inch, cm, m), the input's
direction (clockwise flag) and speed (rpm).

Mapping to assur: a grounded joint is a frame point; the grounded input joint is a crank's pivot, its link the
crank; a grounded prismatic joint is a slot of the frame along its angle through its position, ridden by the pin
its block carries (the block's own joint, drawn on the pin, is that pin); a floating slot (``carrier, slotA,
slotB``) is a slot of the carrier link along slotA → slotB. Welded joints join their links into one. Masses,
forces and display settings are not read (a warning names them).

Not representable (a located error): a driven slider (a prismatic input), more than one input.
"""
from __future__ import annotations

import math
import warnings

from ..errors import SpecError
from ..io import units as U
from ..model.mechanism import FRAME, Mechanism
from .common import assembled, drivers, frame_slots, one_driver, refuse_extras
from .draft import Crank, Draft, InteropWarning, Slot
from .pmks_codec import (Tokens, checksum, from_decimal, from_int, pack_flags, to_decimal, to_int, unpack_flags,
                         unwrap)

LENGTH_UNITS = ("in", "cm", "m")        # PMKS+ LengthUnit: INCH, CM, METER
ANGLE_UNITS = ("deg", "rad")            # AngleUnit: DEGREE, RADIAN
APP = "https://app.pmksplus.com/"
FORMAT_NAME = "a PMKS+ link"
LINK_FLAGS = set("YAMGNamg01234567")
ROOT_FLAGS = set("YAMG0123")


def _joint(text: str, k: int) -> dict:
    where = f"joints[{k}]"
    t = Tokens(text)
    flags = unpack_flags(t.char(), 6, where)
    jid = t.token()
    if not jid:
        raise SpecError([(where, "a joint without an id")])
    j = {"id": jid, "name": t.token() or jid, "prismatic": flags[0], "input": flags[1], "grounded": flags[2],
         "welded": flags[3], "where": where}
    j["x"] = to_decimal(t.token(), f"{where}.x")
    j["y"] = to_decimal(t.token(), f"{where}.y")
    j["angle"] = to_decimal(t.token(), f"{where}.angle")
    j["carrier"], j["slot_a"], j["slot_b"] = t.token(), t.token(), t.token()
    j["speed"] = to_decimal(t.token(), f"{where}.driveSpeed")
    return j


def _link(text: str, k: int) -> dict:
    where = f"links[{k}]"
    t = Tokens(text)
    root, kind = t.char(), t.char()
    if root not in LINK_FLAGS or kind not in "RP":
        raise SpecError([(where, f"unknown link record {text[:2]!r} (a PMKS+ link starts Y/N/A/M/G… then R or P)")])
    lid = t.token()
    name = t.token() or lid
    for _ in range(4):   # mass, inertia, centre of mass
        t.token()
    t.token()           # colour
    joints = []
    while not t.empty():
        j = t.token()
        if j == "":
            break
        joints.append(j)
    subset = []
    while not t.empty():
        s = t.token()
        if s:
            subset.append(s)
    return {"id": lid, "name": name, "root": root in ROOT_FLAGS, "piston": kind == "P", "joints": joints,
            "subset": subset, "where": where}


def decode_2023(text: str) -> dict:
    """The records of a link in the previous encoding (2023): ``?j=JOINTS&l=LINKS&f=FORCES&s=SETTINGS``, one record
    a line; a joint ``id,x,y,link|link,R|P,ground t|f,angle (rad) or Null,input t|f``, a link ``id,R|P,mass,inertia,
    xCoM,yCoM,joint|joint,…``, the settings ``rpm,clockwise,gravity,unit``."""
    from urllib.parse import unquote
    query = unquote(text.strip().split("?", 1)[-1])
    parts = {}
    for key, nxt in (("j=", "&l="), ("&l=", "&f="), ("&f=", "&s="), ("&s=", None)):
        i = query.find(key)
        if i < 0:
            raise SpecError([("", f"the PMKS+ link lacks its {key.strip('&=')} section (truncated?)")])
        j = query.find(nxt, i) if nxt else len(query)
        parts[key.strip("&=")] = query[i + len(key): j if j >= 0 else len(query)]
    joints, links = [], []
    for k, line in enumerate(x for x in parts["j"].split("\n") if x.strip()):
        f = line.split(",")
        where = f"joints[{k}]"
        if len(f) < 8 or f[4] not in ("R", "P"):
            raise SpecError([(where, f"must be id,x,y,links,R|P,ground,angle,input: {line[:60]!r}")])
        joints.append({"id": f[0], "name": f[0], "prismatic": f[4] == "P", "input": f[7] == "t", "grounded": f[5] == "t",
                       "welded": False, "where": where, "x": _float(f[1], f"{where}.x"), "y": _float(f[2], f"{where}.y"),
                       "angle": 0.0 if f[6] in ("Null", "") else _float(f[6], f"{where}.angle"), "carrier": "",
                       "slot_a": "", "slot_b": "", "speed": 0.0})
    for k, line in enumerate(x for x in parts["l"].split("\n") if x.strip()):
        f = line.split(",")
        where = f"links[{k}]"
        if len(f) < 7 or f[1] not in ("R", "P"):
            raise SpecError([(where, f"must be id,R|P,mass,inertia,xCoM,yCoM,joints,…: {line[:60]!r}")])
        links.append({"id": f[0], "name": f[0], "root": True, "piston": f[1] == "P", "joints": f[6].split("|"),
                      "subset": [], "where": where})
    settings = parts["s"].split(",")
    rpm = _float(settings[0], "settings.speed") if settings and settings[0] else 0.0
    unit = {"in": "in", "inch": "in", "m": "m", "cm": "cm", "mm": "mm"}.get(settings[3] if len(settings) > 3 else "cm",
                                                                           "cm")
    return {"cw": len(settings) < 2 or settings[1] != "false", "scale": 1.0, "rpm": rpm, "length": unit,
            "angle": "deg", "joints": joints, "links": links,
            "forces": sum(1 for x in parts["f"].split("\n") if x.strip())}


def _float(text: str, where: str) -> float:
    try:
        v = float(text)
    except ValueError:
        raise SpecError([(where, f"must be a number: {text!r}")]) from None
    if not math.isfinite(v) or abs(v) >= 1e9:
        raise SpecError([(where, f"must be a finite number below 1e9: {text!r}")])
    return v


def decode(text: str) -> dict:
    """The records of a link or ``.pmks`` body: settings, joints, links, the number of forces (the 2023 encoding
    ``?j=…&l=…`` too)."""
    from urllib.parse import unquote
    if len(text) > 1024 * 1024:
        raise SpecError([("", "a PMKS+ link longer than 1048576 characters is not read")])
    if unquote(text.strip().split("?", 1)[-1]).startswith("j="):
        return decode_2023(text)
    body = unwrap(text)
    t = Tokens(body)
    sections = [t.token(".") for _ in range(4)]
    if not sections[0] or not sections[2]:
        raise SpecError([("", "the PMKS+ link's settings are missing (truncated?)")])
    bools = unpack_flags(sections[0], 9, "settings")
    decimals = sections[1].split(",")
    ints = [to_int(x, "settings.ints") if x else 0 for x in sections[2].split(",")]
    enums = sections[3]
    joints, links, forces = [], [], 0
    while not t.empty() and t.peek() != ".":
        joints.append(_joint(t.token("."), len(joints)))
    if t.empty():
        raise SpecError([("links", "the PMKS+ link ends before its links (truncated?)")])
    t.char()
    while not t.empty() and t.peek() != ".":
        links.append(_link(t.token("."), len(links)))
    if t.empty():
        raise SpecError([("forces", "the PMKS+ link ends before its forces (truncated?)")])
    t.char()
    while not t.empty() and t.peek() != ".":
        t.token(".")
        forces += 1
    if len(joints) > 2000 or len(links) > 2000:
        raise SpecError([("", "a PMKS+ link with more than 2000 joints or links is not read")])
    unit = int(enums[0]) if enums[:1].isdigit() and int(enums[0]) < 3 else 1
    angle = int(enums[1]) if enums[1:2].isdigit() and int(enums[1]) < 2 else 0
    return {"cw": bools[0], "scale": to_decimal(decimals[0], "settings.scale") if decimals else 1.0,
            "rpm": ints[0] if ints else 0, "length": LENGTH_UNITS[unit], "angle": ANGLE_UNITS[angle],
            "joints": joints, "links": links, "forces": forces}


def read(text: str, units: str | None = None) -> Draft:
    """A Draft of a PMKS+ link or ``.pmks`` body (``units`` is ignored: the link names its own)."""
    rec = decode(text)
    d = Draft("PMKS+ link", length_unit=rec["length"], angle_unit=rec["angle"])
    joints = {j["id"]: j for j in rec["joints"]}
    if len(joints) != len(rec["joints"]):
        raise SpecError([("joints", "a joint id is used twice")])
    links = {lk["id"]: lk for lk in rec["links"]}
    for lk in rec["links"]:
        for i, jid in enumerate(lk["joints"]):
            if jid not in joints:
                raise SpecError([(f"{lk['where']}.joints[{i}]", f"unknown joint {jid!r}")])
        for sid in lk["subset"]:
            if sid not in links:
                raise SpecError([(lk["where"], f"unknown subset link {sid!r}")])
    # the pins of slider blocks: a block's prismatic joint drawn on its pin is that pin
    alias = {}
    for lk in rec["links"]:
        if lk["piston"]:
            pris = [j for j in lk["joints"] if joints[j]["prismatic"]]
            pins = [j for j in lk["joints"] if not joints[j]["prismatic"]]
            if len(pris) == 1 and len(pins) == 1:
                alias[pris[0]] = pins[0]
    bodies = _bodies(rec, joints, links, alias)
    for jid, j in joints.items():
        if jid in alias:
            continue
        d.point(jid, j["x"], j["y"], j["where"], label=j["name"] if j["name"] != jid else None)
        if j["grounded"] and not j["prismatic"]:
            d.fix(jid)
    for lid, pts in bodies.items():
        d.link(lid, pts, links[lid]["where"] if lid in links else lid,
               label=links[lid]["name"] if lid in links and links[lid]["name"] != lid else None)
    for jid, j in joints.items():
        if not j["prismatic"]:
            continue
        pin = alias.get(jid, jid)
        if j["input"]:
            raise SpecError([(j["where"], f"a driven slider (joint {jid!r}) is not representable: assur drives cranks "
                                          "and linear actuators")])
        if j["carrier"]:
            a, b = joints.get(j["slot_a"]), joints.get(j["slot_b"])
            if a is None or b is None or j["carrier"] not in links:
                raise SpecError([(j["where"], "its floating slot names a link or joints the link does not hold")])
            guide = next((lid for lid, pts in bodies.items() if j["slot_a"] in pts and j["slot_b"] in pts), None)
            d.slots.append(Slot(angle=math.atan2(b["y"] - a["y"], b["x"] - a["x"]), at=(j["x"], j["y"]), point=pin,
                                guide=guide, name=f"{jid}_slot"))
        elif j["grounded"] and j["welded"]:   # the block welded to its link: the link translates on the guide
            owners = [lid for lid, pts in d.links.items() if pin in pts]
            if len(owners) != 1:
                raise SpecError([(j["where"], f"a welded slider (joint {jid!r}) must carry exactly one link")])
            pts = d.links[owners[0]]
            pts.insert(0, pts.pop(pts.index(pin)))
            d.slots.append(Slot(angle=j["angle"], at=(j["x"], j["y"]), link=owners[0], name=f"{jid}_slot"))
        elif j["grounded"]:
            d.slots.append(Slot(angle=j["angle"], at=(j["x"], j["y"]), point=pin, name=f"{jid}_slot"))
        else:
            raise SpecError([(j["where"], f"prismatic joint {jid!r} is neither grounded nor in a floating slot")])
    inputs = [j for j in joints.values() if j["input"]]
    if len(inputs) > 1:
        raise SpecError([("joints", f"{len(inputs)} input joints: assur imports one PMKS+ input")])
    if inputs:
        _crank(d, rec, inputs[0], bodies)
    if rec["forces"]:
        d.warn(f"{rec['forces']} force(s) and the links' masses are not read")
    return d


def _bodies(rec, joints, links, alias) -> dict:
    """The rigid bodies: root real links (with their subsets' joints), merged across welded joints."""
    parent: dict = {}

    def find(x):
        while parent.setdefault(x, x) != x:
            x = parent[x]
        return x
    members = {}
    for lk in rec["links"]:
        if not lk["root"] or lk["piston"]:
            continue
        pts = list(lk["joints"])
        for sid in lk["subset"]:
            pts += [p for p in links[sid]["joints"] if p not in pts]
        members[lk["id"]] = [alias.get(p, p) for p in pts]
        find(lk["id"])
    for jid, j in joints.items():
        if j["welded"]:
            owners = [lid for lid, pts in members.items() if jid in pts]
            for o in owners[1:]:
                parent[find(o)] = find(owners[0])
    out: dict = {}
    for lid, pts in members.items():
        root = find(lid)
        out.setdefault(root, [])
        out[root] += [p for p in pts if p not in out[root]]
    return out


def _crank(d: Draft, rec: dict, j: dict, bodies: dict) -> None:
    owners = [lid for lid, pts in bodies.items() if j["id"] in pts]
    if not j["grounded"] or len(owners) != 1:
        raise SpecError([(j["where"], "the input joint must be a grounded pin of exactly one link")])
    arm = next(p for p in bodies[owners[0]] if p != j["id"])
    rpm = abs(j["speed"]) if j["speed"] else rec["rpm"]
    ccw = j["speed"] > 0 if j["speed"] else not rec["cw"]
    omega = rpm * U.ANGULAR_SPEED["rpm"] * (1 if ccw else -1)
    d.cranks.append(Crank(owners[0], j["id"], arm, omega if rpm else None, name=f"{owners[0]}_input"))


# -- writing ----------------------------------------------------------------------------------------------------
def _unit(m: Mechanism) -> tuple[int, float]:
    """(PMKS+ length unit index, factor file unit → that unit)."""
    L = U.LENGTH[m.units.length]
    if m.units.length in ("in", "ft"):
        return 0, L / U.LENGTH["in"]
    return 1, L / U.LENGTH["cm"]   # every metric unit: thousandths of a cm (10 µm) are the link's finest metric step


def encode(m: Mechanism) -> str:
    """The body of the PMKS+ production encoding of ``m`` (coordinates in thousandths of its length unit)."""
    refuse_extras(m, FORMAT_NAME)
    one_driver(m, FORMAT_NAME)
    xy = assembled(m)
    crank = drivers(m, xy)[0]
    slots = {s.point: s for s in frame_slots(m, xy, FORMAT_NAME)}
    unit, f = _unit(m)
    frame = set(m.link(FRAME).points)
    for name in m.point_names:
        if "," in name or "." in name:
            raise SpecError([(f"points.{name}", "a PMKS+ id cannot hold ',' or '.'")])
    rpm = abs(crank.omega) / U.ANGULAR_SPEED["rpm"]
    if abs(rpm - round(rpm)) > 1e-9:
        warnings.warn(f"PMKS+ takes a whole number of rpm: the crank's {rpm:.6g} rpm is written as {round(rpm)}",
                      InteropWarning, stacklevel=2)
    span = max(max(abs(x), abs(y)) for x, y in xy.values()) * f or 1.0
    joints, links = [], []
    for name in m.point_names:
        x, y = xy[name]
        flags = [False, name == crank.pivot, name in frame, False, name not in frame, False]
        joints.append(f"{pack_flags(flags[:5])}{name},{name},{from_decimal(x * f)},{from_decimal(y * f)},0")
        if name in slots:
            s = slots[name]
            joints.append(f"{pack_flags([True, False, True, False, False])}{name}_slide,{name}_slide,"
                          f"{from_decimal(x * f)},{from_decimal(y * f)},{from_decimal(s.angle)}")
    for lk in m.links:
        if lk.name == FRAME:
            continue
        cx = sum(xy[p][0] for p in lk.points) / len(lk.points) * f
        cy = sum(xy[p][1] for p in lk.points) / len(lk.points) * f
        links.append(f"YR{lk.name},{lk.name},{from_decimal(1)},{from_decimal(1)},{from_decimal(cx)},"
                     f"{from_decimal(cy)},303e9f,{''.join(p + ',' for p in lk.points)},")
    for name, s in slots.items():
        links.append(f"YP{name}_block,{name}_block,{from_decimal(1)},0,0,0,,{name},{name}_slide,,")
    bools = pack_flags([crank.omega < 0, False, True, True, True, True, False, False])
    body = (f"{bools}.{from_decimal(round(span / 5, 3) or 0.001)}.{from_int(round(rpm))},0."
            f"{unit}{0 if m.units.angle == 'deg' else 1}{0 if unit == 0 else 1}{0 if unit == 0 else 1 + (unit == 2)}."
            + "".join(j + "." for j in joints) + "." + "".join(lk + "." for lk in links) + "." + "." + "N")
    return body + checksum(body)


def share_link(m: Mechanism) -> str:
    """The PMKS+ link that opens ``m`` in the browser app."""
    return APP + "?" + encode(m)


def write(m: Mechanism, path) -> str:
    """Write the ``.pmks`` file of ``m`` (its encoded body) to ``path``; returns the share link to print."""
    from ..io.output import atomic_file
    body = encode(m)
    with atomic_file(path) as tmp:
        tmp.write_text(body + "\n", encoding="utf-8")
    return f"PMKS+ link: {APP}?{body}"


__all__ = ["FORMAT_NAME", "decode", "encode", "read", "share_link", "write"]
