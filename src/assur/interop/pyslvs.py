"""Pyslvs mechanisms (https://github.com/KmolYuan/Pyslvs-UI): the PMKS-style expression and the YAML project.

The expression lists joints in order (Pyslvs calls them P0, P1, …)::

    M[J[R, color[Green], P[0.0, 0.0], L[ground, L1]], J[RP, A[30.0], P[51.38, -12.63], L[ground, L2]], …]

``R`` is a revolute joining the links it lists (``ground`` is the frame); ``RP`` a pin in a slot of its first
link, at the slot's angle ``A`` (degrees, in the drawing); ``P`` a prismatic pair: its other link slides along
the first without turning. The YAML project (``mechanism: …``, ``input: [[base, drive], …]``) adds the inputs: the
link shared by the joints ``base`` and ``drive`` turns about ``base``. Pyslvs has no units and no speeds.

Mapping: Pn → point ``Pn``; an ``RP`` joint → ``[[prismatic]] point`` on its first link (the frame or a moving
guide); a ``P`` joint → ``[[prismatic]] link`` (its link's first point is the joint). Not representable (a
located error): an input about a moving joint or on a slider (``base = drive``), a ``P`` joint carrying more
than one sliding link.
"""
from __future__ import annotations

import math
import re

from ..errors import SpecError
from ..io import units as U
from ..model.mechanism import FRAME, Mechanism
from .common import assembled, drivers, refuse_extras
from .draft import Crank, Draft, Slot, count_limit, finite

GROUND = "ground"
FORMAT_NAME = "a Pyslvs project"
_TOKEN = re.compile(r"\s*(?:(?P<open>M\[|J\[|P\[|L\[|A\[|color\[)|(?P<close>\])|(?P<punct>[(),])"
                    r"|(?P<num>[-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?)|(?P<name>[A-Za-z_][A-Za-z0-9_-]*))")


def _tokens(text: str) -> list:
    text = re.sub(r"#\[.*?#\][^\n]*", " ", text, flags=re.S)
    text = re.sub(r"#[^\n]*", " ", text)
    out, pos = [], 0
    while pos < len(text):
        if text[pos:].strip() == "":
            break
        m = _TOKEN.match(text, pos)
        if not m or m.end() == pos:
            raise SpecError([(f"mechanism[{pos}]", f"not a Pyslvs expression: unexpected {text[pos:pos + 20]!r}")])
        out.append((m.lastgroup, m.group(m.lastgroup).strip()))
        pos = m.end()
    return out


def parse_expression(text: str) -> list[dict]:
    """The joints of an expression: ``{"type", "angle", "x", "y", "links"}`` each, in order."""
    toks = _tokens(text)
    count_limit(toks, "mechanism", "tokens")
    i = 0

    def take(kind, value=None):
        nonlocal i
        if i >= len(toks) or toks[i][0] != kind or (value is not None and toks[i][1] != value):
            got = toks[i][1] if i < len(toks) else "the end"
            raise SpecError([(f"mechanism (token {i})", f"expected {value or kind}, found {got!r}")])
        i += 1
        return toks[i - 1][1]

    def maybe(kind, value=None):
        return i < len(toks) and toks[i][0] == kind and (value is None or toks[i][1] == value)
    take("open", "M[")
    joints = []
    while not maybe("close"):
        where = f"mechanism.P{len(joints)}"
        take("open", "J[")
        jtype = take("name")
        if jtype not in ("R", "P", "RP"):
            raise SpecError([(where, f"unknown joint type {jtype!r} (Pyslvs's: R, P, RP)")])
        angle = 0.0
        take("punct", ",")
        if maybe("open", "A["):
            take("open", "A[")
            angle = float(take("num"))
            take("close")
            take("punct", ",")
        if maybe("open", "color["):
            take("open", "color[")
            while not maybe("close"):
                i += 1
                if i >= len(toks):
                    take("close")
            take("close")
            take("punct", ",")
        take("open", "P[")
        x = float(take("num"))
        take("punct", ",")
        y = float(take("num"))
        take("close")
        take("punct", ",")
        take("open", "L[")
        links = []
        while not maybe("close"):
            links.append(take("name"))
            if maybe("punct", ","):
                take("punct", ",")
        take("close")
        take("close")
        joints.append({"type": jtype, "angle": angle, "x": finite(x, f"{where}.x"), "y": finite(y, f"{where}.y"),
                       "links": links, "where": where})
        if maybe("punct", ","):
            take("punct", ",")
    take("close")
    if i != len(toks):
        raise SpecError([("mechanism", f"text after the expression: {toks[i][1]!r}")])
    return joints


def read(text: str, units: str | None = None) -> Draft:
    """A Draft of a Pyslvs YAML project or a bare expression (see the module docstring)."""
    data = _project(text)
    meta = data.get("assur") if isinstance(data.get("assur"), dict) else {}
    expr = data.get("mechanism")
    if not isinstance(expr, str):
        raise SpecError([("mechanism", "a Pyslvs project needs the expression 'mechanism: M[…]'")])
    joints = parse_expression(expr)
    unit = units or meta.get("units") or "m"
    if unit not in U.LENGTH:
        raise SpecError([("assur.units", f"must be one of {', '.join(U.LENGTH)}: {unit!r}")])
    d = Draft("Pyslvs mechanism", length_unit=unit, angle_unit="deg", name=str(meta.get("name", "")),
              description=str(meta.get("description", "")))
    names = meta.get("points") if isinstance(meta.get("points"), list) and len(meta["points"]) == len(joints) else None
    ids = [str(n) for n in names] if names else [f"P{k}" for k in range(len(joints))]
    members: dict = {}
    for pid, j in zip(ids, joints):
        d.point(pid, j["x"], j["y"], j["where"])
        if j["type"] == "R":
            on = j["links"]
        else:
            if len(j["links"]) < 2:
                raise SpecError([(j["where"], f"a {j['type']} joint needs its slot link and a sliding link")])
            on = j["links"][1:]
            if j["type"] == "P" and len(on) != 1:
                raise SpecError([(j["where"], "a P joint carrying more than one sliding link is not representable")])
        for ln in on:
            if ln == GROUND:
                d.fix(pid)
            else:
                members.setdefault(ln, [])
                # a P joint's point first: the translating link's line passes through its first point
                members[ln].insert(0 if j["type"] == "P" else len(members[ln]), pid)
    for pid, j in zip(ids, joints):   # a slot link carries the slot: give it a second point when it has none
        slot = j["links"][0] if j["type"] != "R" else GROUND
        if slot != GROUND and len(members.get(slot, [])) < 2:
            # the slot's node on its link, one link length along the slot from the pin (Pyslvs keeps it there)
            other = members.get(slot, [])
            reach = math.dist(d.points[other[0]], (j["x"], j["y"])) if other else 1.0
            a = math.radians(j["angle"])
            d.point(f"{pid}_slot", j["x"] + reach * math.cos(a), j["y"] + reach * math.sin(a), j["where"])
            members.setdefault(slot, []).append(f"{pid}_slot")
    order = meta.get("links") if isinstance(meta.get("links"), list) else []
    for ln in sorted(members, key=lambda n: order.index(n) if n in order else len(order)):
        d.link(ln, members[ln], f"links.{ln}")
    for pid, j in zip(ids, joints):
        if j["type"] == "R":
            continue
        slot = j["links"][0]
        guide = None if slot == GROUND else slot
        if guide is not None and guide not in d.links:
            raise SpecError([(j["where"], f"the slot link {slot!r} holds no other joint")])
        kw = {"point": pid} if j["type"] == "RP" else {"link": j["links"][1]}
        d.slots.append(Slot(angle=math.radians(j["angle"]), at=(j["x"], j["y"]), guide=guide, name=f"{pid}_slot", **kw))
    _inputs(d, data, joints, ids, meta)
    return d


def _project(text: str) -> dict:
    """The project dict of a YAML project, or ``{"mechanism": text}`` for a bare expression."""
    if text.lstrip().startswith("M["):
        return {"mechanism": text}
    import yaml
    try:
        data = yaml.safe_load(text)
    except yaml.YAMLError as exc:
        raise SpecError([("", f"not a Pyslvs YAML project: {exc}")]) from None
    if not isinstance(data, dict):
        raise SpecError([("", "not a Pyslvs YAML project (a table with 'mechanism')")])
    return data


def _inputs(d: Draft, data: dict, joints: list, ids: list, meta: dict) -> None:
    pairs = data.get("input")
    speeds = meta.get("speeds") if isinstance(meta.get("speeds"), list) else []
    dnames = meta.get("drivers") if isinstance(meta.get("drivers"), list) else []
    if pairs is None:
        base = next((k for k, j in enumerate(joints) if j["type"] == "R" and GROUND in j["links"]
                     and any(ln != GROUND and sum(ln in o["links"] for o in joints) >= 2 for ln in j["links"])), None)
        if base is None:
            return
        link = next(ln for ln in joints[base]["links"] if ln != GROUND)
        drive = next(k for k, o in enumerate(joints) if k != base and link in o["links"])
        pairs = [[base, drive]]
        d.warn(f"no input pair given: {ids[base]} → {ids[drive]} is taken as the crank (Pyslvs's examples start there)")
    if not isinstance(pairs, list):
        raise SpecError([("input", "must be a list of [base, drive] joint numbers")])
    for k, pair in enumerate(pairs):
        where = f"input[{k}]"
        if not (isinstance(pair, (list, tuple)) and len(pair) == 2 and all(isinstance(x, int) for x in pair)
                and all(0 <= x < len(joints) for x in pair)):
            raise SpecError([(where, f"must be [base, drive], two joint numbers below {len(joints)}: {pair!r}")])
        b, dv = pair
        if b == dv:
            raise SpecError([(where, f"a slider input (P{b}) is not representable: assur drives cranks")])
        if ids[b] not in d.ground:
            raise SpecError([(where, f"the input turns about {ids[b]}, a moving joint: assur's cranks turn about the "
                                     "frame")])
        shared = [ln for ln in joints[b]["links"] if ln != GROUND and ln in joints[dv]["links"]]
        if not shared:
            raise SpecError([(where, f"{ids[b]} and {ids[dv]} share no moving link")])
        speed = speeds[k] if k < len(speeds) and isinstance(speeds[k], (int, float)) else None
        name = dnames[k] if k < len(dnames) and isinstance(dnames[k], str) else None
        d.cranks.append(Crank(shared[0], ids[b], ids[dv], speed, name=name))
    if pairs and not speeds:
        d.warn("Pyslvs has no input speeds: assur's default speed (1 rad/s) is used")


# -- writing ----------------------------------------------------------------------------------------------------
def _num(v: float) -> str:
    return repr(float(v))


def to_project(m: Mechanism) -> dict:
    """The Pyslvs YAML project of ``m`` (expression, links, inputs; an ``assur`` block with the names, units and
    speeds, which Pyslvs ignores)."""
    refuse_extras(m, FORMAT_NAME)
    xy = assembled(m)
    cranks = drivers(m, xy)
    for lk in m.links:
        if lk.name == GROUND or not re.fullmatch(r"[A-Za-z_][A-Za-z0-9_]*", lk.name):
            raise SpecError([(f"links.{lk.name}", "a Pyslvs link name holds letters, digits and _ only (and is not "
                                                  "'ground')")])
    frame = set(m.link(FRAME).points)
    on = {n: [] for n in m.point_names}
    for lk in m.links:
        for p in lk.points:
            on[p].append(GROUND if lk.name == FRAME else lk.name)
    kinds = {n: ("R", 0.0, on[n]) for n in m.point_names}
    A = 180.0 / math.pi
    for i, pr in enumerate(m.prismatic):
        guide = GROUND if pr.guide == FRAME else pr.guide
        base = 0.0
        if pr.guide != FRAME:
            g = m.link(pr.guide).points
            base = math.atan2(xy[g[1]][1] - xy[g[0]][1], xy[g[1]][0] - xy[g[0]][0])
        ang = (pr.angle + base) * A
        if pr.point is not None:
            kinds[pr.point] = ("RP", ang, [guide] + [x for x in on[pr.point] if x != guide])
        else:
            first = m.link(pr.link).points[0]
            if on[first] != [pr.link]:
                raise SpecError([(f"prismatic[{i}]", f"the first point of '{pr.link}' is a joint of other links too: "
                                                     "a Pyslvs P joint belongs to its sliding link only")])
            kinds[first] = ("P", ang, [guide, pr.link])
    joints = []
    for n in m.point_names:
        t, ang, links = kinds[n]
        head = "R" if t == "R" else f"{t}, A[{_num(ang)}]"
        joints.append(f"J[{head}, color[Green], P[{_num(xy[n][0])}, {_num(xy[n][1])}], L[{', '.join(links)}]]")
    index = {n: k for k, n in enumerate(m.point_names)}
    del frame
    return {"mechanism": "M[" + ", ".join(joints) + "]",
            "links": {GROUND: "White", **{lk.name: "Blue" for lk in m.links if lk.name != FRAME}},
            "input": [[index[c.pivot], index[c.arm]] for c in cranks],
            "assur": {"format": m.format, "name": m.name, "description": m.description, "units": m.units.length,
                      "points": list(m.point_names), "links": [lk.name for lk in m.links if lk.name != FRAME],
                      "speeds": [c.omega for c in cranks], "drivers": [c.name for c in cranks]}}


def write(m: Mechanism, path) -> str | None:
    """Write the Pyslvs YAML project of ``m`` to ``path`` (atomically)."""
    import yaml

    from ..io.output import atomic_file
    text = yaml.safe_dump(to_project(m), sort_keys=False, allow_unicode=True, width=2 ** 20)
    with atomic_file(path) as tmp:
        tmp.write_text(text, encoding="utf-8")
    return None


__all__ = ["FORMAT_NAME", "parse_expression", "read", "to_project", "write"]
