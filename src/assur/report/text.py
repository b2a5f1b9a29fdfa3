"""Text for people, shared by the terminal and the HTML pages: numbers, angles, speeds, the structure,
parameters and drivers of a mechanism, and the rows and lines of an analysis summary
(:meth:`assur.analysis.study.Study.as_dict`). Lengths are shown in the file's unit where a factor is given,
speeds and accelerations in SI, angles in degrees.
"""
from __future__ import annotations

import math

from ..io.units import ANGLE, LENGTH, param_unit
from ..structure.assur import GroupKind, roman
from ..tolerances import DEFAULT as TOL

MM = 1e3


def shown_value(v, scale=None):
    """``v`` with rounding noise removed: 0 when |v| is at most :attr:`~assur.tolerances.Tolerances.rounding_noise`
    times ``scale`` (the magnitude of the quantity in the mechanism: its length scale, the largest speed …, in
    the unit of ``v``); ``v`` unchanged without a scale. The one rule by which every page and terminal line
    prints noise as 0."""
    if v is None or scale is None:
        return v
    v = float(v)
    return 0.0 if math.isfinite(v) and abs(v) <= TOL.rounding_noise * abs(float(scale)) else v


def format_number(v, digits: int = 6, scale=None) -> str:
    """A number for people: ``digits`` significant digits, '—' for a missing or non-finite value, 0 for
    rounding noise relative to ``scale`` (:func:`shown_value`)."""
    if v is None:
        return "—"
    v = float(shown_value(v, scale))
    if not math.isfinite(v):
        return "—"
    if v == 0:
        return "0"
    return f"{v:.{digits}g}"


def length_display(units, system: str = "file") -> tuple[float, str]:
    """(factor, unit) in which lengths are shown: a value in metres divided by the factor is in the unit.
    ``system`` 'file' (the default): the file's length unit, so a mm file shows mm, mm/s and mm/s²;
    'si': metres."""
    if system == "si":
        return 1.0, "m"
    return LENGTH[units.length], units.length


def deg_text(v, digits: int = 2) -> str:
    """An angle (rad) in degrees with ``digits`` decimals, '—' for a missing or non-finite value."""
    return "—" if v is None or not math.isfinite(float(v)) else f"{math.degrees(float(v)):.{digits}f}°"


def mm_text(v, digits: int = 4) -> str:
    """A length (m) in millimetres with ``digits`` decimals, '—' for a missing value."""
    return "—" if v is None else f"{v * MM:.{digits}f} mm"


def phases_text(phases) -> str:
    """Crank phases (rad) in whole degrees: '0°, 120°, 240°'."""
    return ", ".join(f"{math.degrees(p):.0f}°" for p in phases)


def dyad_kind_number(kind: str) -> int | None:
    """The textbook kind number (1–5) of a dyad's kind ('RRR' → 1, …), None for other groups."""
    try:
        return GroupKind(kind).dyad_kind_number
    except ValueError:
        return None


def group_text(g: dict) -> str:
    """One Assur group of a structure summary, for the terminal."""
    kind = g["kind"]
    num = dyad_kind_number(kind)
    kind_text = f"{kind} ({num}{ {1: 'st', 2: 'nd', 3: 'rd'}.get(num, 'th') } kind)" if num else kind
    return (f"class {roman(g['class'])}, order {g['order']}, {kind_text}: bodies {', '.join(g['bodies'])}; "
            f"attached to {', '.join(g['attaches_to'])}")


def speed_text(kind: str, speed: float, units) -> str:
    """A driver's speed (SI) in rpm or the file's length unit per second, with the SI value."""
    if kind == "rotary":
        return f"{format_number(speed * 60 / (2 * math.pi), 5)} rpm ({format_number(speed, 5)} rad/s)"
    return f"{format_number(speed / LENGTH[units.length], 5)} {units.length}/s ({format_number(speed, 5)} m/s)"


def driver_lines(m) -> list[str]:
    """One line per driver of the mechanism ``m``: what it drives, its zero, sense and speed."""
    out = []
    for d in m.drivers:
        if d.kind == "rotary":
            zero = d.zero / ANGLE[m.units.angle]
            out.append(f"{d.name}: rotary, link {d.link} about {d.pivot} (arm {d.arm}), zero = {format_number(zero)}"
                       f"{'°' if m.units.angle == 'deg' else 'rad'}, {'ccw' if d.sense > 0 else 'cw'}, "
                       f"speed {speed_text('rotary', d.speed, m.units)}")
        else:
            ac = next((a for a in m.actuators if a.name == d.actuator), None)
            between = f" between {ac.between[0]} and {ac.between[1]}" if ac else ""
            out.append(f"{d.name}: linear, actuator {d.actuator}{between}, speed "
                       f"{speed_text('linear', d.speed, m.units)}")
    return out


def parameter_rows(plan) -> list[tuple[str, str, str, str, str]]:
    """(name, value in the file's unit, that unit, SI value, SI unit) per parameter of ``plan``."""
    u = plan.mechanism.units
    rows = []
    for name, v in zip(plan.param_names, plan.defaults):
        f, unit = param_unit(plan.param_kind_of(name), u)
        si = "m" if unit == u.length else ("rad" if unit else "")
        scale = plan.length_scale if si == "m" else (math.pi if si == "rad" else None)   # noise shows as 0
        rows.append((name, format_number(v * f, 8, None if scale is None else scale * f), unit,
                     format_number(v, 8, scale), si))
    return rows


def parameter_lines(plan) -> list[str]:
    """``assur info``'s parameter table (in the file's units) and driver lines, planar or spatial."""
    rows = parameter_rows(plan)
    w = max(len(r[0]) for r in rows)
    out = [f"parameters ({len(rows)}, in the file's units):"]
    out += [f"  {name:<{w}} = {value}" + (f" {unit}" if unit else "") for name, value, unit, _, _ in rows]
    return out + ["drivers:"] + ["  " + line for line in driver_lines(plan.mechanism)]


def branch_lines(plan) -> list[str]:
    """The R–S–S dyads of a spatial plan with their assembly branches."""
    out = []
    for st in plan.rss_steps():
        D, A, B = st.pivot, st.start, st.joint
        out.append(f"{B}: R–S–S dyad (rocker {plan.body_names[st.body]} about {D}, coupler "
                   f"{plan.body_names[st.coupler]} from {A}), branch s = sign det[{A} − {D}, e, {B} − {D}] = "
                   f"{st.branch:+d}")
    return out


def joints_line(m, axes: bool = True) -> str:
    """The joints of a spatial mechanism on one line (with their revolute axes when ``axes``); '' without
    joints."""
    parts = []
    for j in {j.point: j for j in m.joints}.values():
        ax = "" if not axes or j.axis is None else f" axis [{', '.join(format_number(c, 6, 1.0) for c in j.axis)}]"
        parts.append(f"{j.point} {j.kind}{ax}")
    return "joints: " + ", ".join(parts) if parts else ""


def spatial_plan_lines(plan) -> list[str]:
    """``assur info``'s spatial part: joints with their axes, the solve plan and the dyads' branches."""
    joints = joints_line(plan.mechanism)
    out = [joints] if joints else []
    out.append("solve plan: crank, then "
               + (", ".join(f"R–S–S dyad → {s.key_point}" for s in plan.rss_steps()) or "—"))
    return out + ["  " + line for line in branch_lines(plan)]


def validation_line(path, m, plan=None, structure=None) -> str:
    """``assur validate``'s verdict on the file ``path``: its mechanism ``m`` compiled into ``plan``, or for a
    spatial structural description (no revolute axes) its ``structure`` (:func:`assur.structure.assur.analyse`)."""
    if plan is None:
        return (f"{path}: ok (spatial, W = {structure.mobility} by {structure.formula_name}; a structural "
                f"description: without revolute axes it is not solved)")
    s = plan.structure
    if m.dimension == 3:
        idle = f", {s.idle} idle" if s.idle else ""
        return (f"{path}: ok (spatial, W = {s.mobility}{idle} by {s.formula_name}; "
                f"{', '.join('R–S–S → ' + st.key_point for st in plan.rss_steps())})")
    return f"{path}: ok (W = {s.mobility}, {s.structural_formula})"


def info_head_lines(m, title: str, path, s: dict) -> list[str]:
    """The head of ``assur info``: name, units and mobility of the mechanism ``m`` (structure summary ``s``)."""
    u = m.units
    pairs = ", ".join(f"{k} = {v}" for k, v in s["pairs"].items())
    out = [f"{title}  [{path}]",
           f"units: length {u.length}, angle {u.angle}" + (", spatial (dimension = 3)" if m.dimension == 3 else ""),
           f"mobility ({s['formula']}): {s['mobility_formula']}"]
    if s.get("idle_freedoms"):
        out.append(f"  of which idle: {s['idle_freedoms']} (a link between two spherical joints spins about its "
                   f"axis); W without idle freedoms = {s['mobility_without_idle']}")
    out.append(f"  moving links n = {s['moving_links']}; pairs {pairs}; drivers: {len(m.drivers)}"
               + (f" ({', '.join(s['drivers'])})" if s["drivers"] else ""))
    return out


def point_lines(m) -> list[str]:
    """The sketch points of a spatial mechanism in the file's length unit."""
    u = m.units
    w = max(len(n) for n in m.point_names)
    scale = max((abs(c) for _, xyz in m.points for c in xyz), default=1.0) / LENGTH[u.length]
    return ["points:"] + [f"  {name:<{w}} = [{', '.join(format_number(c / LENGTH[u.length], 6, scale) for c in xyz)}] "
                          f"{u.length}" for name, xyz in m.points]


def structural_description_lines(m) -> list[str]:
    """``assur info`` on a spatial structural description (no revolute axes): joints, drivers, a note."""
    joints = joints_line(m, axes=False)
    out = [joints] if joints else []
    if m.drivers:
        out += ["drivers:"] + ["  " + line for line in driver_lines(m)]
    return out + ["note: a structural description (no revolute axes): its mobility is computed, it is not solved"]


def group_lines(s: dict, undetermined=()) -> list[str]:
    """The Assur groups and structural formula of a structure summary ``s``, and the points the drivers leave
    undetermined."""
    out = []
    if s["groups"]:
        out.append("Assur groups:")
        out += [f"  {i}. {group_text(g)}" for i, g in enumerate(s["groups"], 1)]
    if s["structural_formula"]:
        out.append(f"structural formula: {s['structural_formula']}")
        out.append(f"                    {s['structural_formula_numbered']}")
    if undetermined:
        out.append(f"not determined by the drivers: {', '.join(undetermined)}")
    return out


def gait_lines(m) -> list[str]:
    """The ``[gait]`` table of the mechanism ``m`` on one line ([] without one)."""
    g = m.gait
    if g is None:
        return []
    return [f"gait: foot {g.foot}, ground [{', '.join(format_number(c) for c in g.ground)}], up "
            f"[{', '.join(format_number(c) for c in g.up_vector)}], phases "
            f"{', '.join(format_number(math.degrees(p), 5) + '°' for p in g.phases)}"]


def gait_rows(g: dict, length_factor: float = 1.0, length_unit: str = "m") -> list[tuple[str, str, str]]:
    """The gait metrics of an ``analyze`` summary as (quantity, value, unit) rows; lengths, speeds and
    accelerations are shown divided by ``length_factor`` (in ``length_unit``, ``length_unit``/s, /s²;
    :func:`length_display`), rounding noise as 0. Shared by the CLI and the report."""
    n = format_number
    Lf, Lu = length_factor, length_unit
    vscale = max((abs(g[k][s]) for k in ("support_speed", "support_vx") for s in ("max", "min")
                  if g[k][s] is not None), default=None)
    ascale = max((abs(v) for v in (g["support_ax"]["min"], g["support_ax"]["max"]) if v is not None), default=None)
    rows = [
        ("support definition", g["support"], ""),
        ("contact arc", f"{math.degrees(g['contact_start']) % 360:.2f} … {math.degrees(g['contact_end']) % 360:.2f}", "°"),
        ("step length", n(g["step_length"] / length_factor, 5), length_unit),
        ("lift (path height)", n(g["lift"] / length_factor, 5), length_unit),
        ("sag (support height variation)", n(g["sag"] / length_factor, 5), length_unit),
        ("clearance (swing above the support)",
         n(g.get("clearance", g["lift"] - g["sag"]) / length_factor, 5), length_unit),
        ("duty factor", f"{g['duty_factor']:.4f}", ""),
        ("contact ratio (support / transfer)", n(g["contact_ratio"], 5), ""),
    ]
    for key, label in (("support_speed", "support speed |v|"), ("support_vx", "support speed |vx|")):
        for stat in ("max", "min", "mean", "midrange"):
            v = g[key][stat]
            rows.append((f"{label} {stat}", n(None if v is None else v / Lf, 5, vscale and vscale / Lf), f"{Lu}/s"))
    for fraction, v in (g.get("vx_spread") or {}).items():
        rows.append((f"support |vx| spread, central {float(fraction):.0%} of the stride", n(v, 5), ""))
    for stat in ("min", "max"):
        v = g["support_ax"][stat]
        rows.append((f"support acceleration ax {stat}", n(None if v is None else v / Lf, 5, ascale and ascale / Lf),
                     f"{Lu}/s²"))
    rows.append(("input speed ω (the driver's)", n(g["omega"], 5), "rad/s"))
    return rows


#: the envelope's quantities: (label, SI → shown factor kind, unit); kind "L" = the file's length unit
_ROD_QUANTITIES = (("extension", "length change L − L₀", "L", None), ("rate", "rate dL/dt", "v", None),
                   ("accel", "acceleration d²L/dt²", "a", None), ("angle", "rotation from the start", "deg", "°"),
                   ("omega", "angular velocity ω", "1", "rad/s"), ("alpha", "angular acceleration ε", "1", "rad/s²"))


def actuator_rows(act: dict, length_factor: float = 1.0, length_unit: str = "m") -> dict:
    """The ``actuators`` entry of an ``analyze`` summary for people, shared by the CLI and the report.

    Returns ``{"stroke": [text lines], "extremes": [(rod, quantity, min, max, interior extrema, unit)],
    "pairs": [(quantity, value, note)], "lever": [(quantity, value, unit)]}``; lengths divided by
    ``length_factor`` (in ``length_unit``; rates in ``length_unit``/s and /s²), angles in degrees, angular rates
    in rad/s."""
    n = format_number
    st = act["stroke"]
    Lf = length_factor

    def where(e):
        if e is None:
            return "—"
        t = "" if st["analogues"] else f"t = {n(e['t'], 4)} s, "
        return f"{t}{st['actuator']} = {n(e['q'] / Lf, 5)} {length_unit}"

    lines = [f"stroke: {st['driver']} drives {st['actuator']} from {n(st['start'] / Lf, 6)} to {n(st['stop'] / Lf, 6)} "
             f"{length_unit} ({st['law']}" + ("" if st["analogues"] else
                                               f", t = {n(st['t_start'], 5)} … {n(st['t_end'], 5)} s") + ")"]
    if act["unbuildable_ranges"]:
        bad = ", ".join(f"{n(r['start'] / Lf, 6)} … {n(r['end'] / Lf, 6)} {length_unit}" for r in act["unbuildable_ranges"])
        lines.append(f"buildability: cannot be assembled for {st['actuator']} = {bad} "
                     f"({act['unbuildable']} of {st['samples']} samples; the guide or a joint is out of reach there)")
    else:
        lines.append(f"buildability: the whole stroke can be assembled (0 of {st['samples']} samples unbuildable)")
    factors = {"L": (1.0 / Lf, length_unit), "v": (1.0 / Lf, f"{length_unit}/s"), "a": (1.0 / Lf, f"{length_unit}/s²"),
               "deg": (180.0 / math.pi, "°"),
               "1": (1.0, None)}
    extremes = []
    for rod, info in act["rods"].items():
        q = info["quantities"]
        for key, label, kind, unit in _ROD_QUANTITIES:
            if key not in q:
                continue
            f, u = factors[kind]
            u = unit if u is None else u
            e = q[key]
            big = max(abs(e["min"]["value"]), abs(e["max"]["value"]))
            chop = lambda v: 0.0 if abs(v) <= max(TOL.rounding_noise * big, TOL.shown_zero) else v  # noqa: E731 - noise shows as 0
            fmt = lambda x: f"{n(chop(x['value']) * f, 6)} ({where(x)})"  # noqa: E731
            inner = "; ".join(fmt(x) for x in e["interior"]) or "none"
            extremes.append((rod + (" (the driver)" if info["driven"] else ""), label, fmt(e["min"]), fmt(e["max"]), inner, u))
    pairs = []
    for p in act["rod_pairs"]:
        k, a = p.get("K_omega"), p.get("areal_ratio")
        head = f"{p['driven']} / {p['driving']}"
        if k:
            inner = "; ".join(f"{n(x['value'], 6)} at {where(x)}" for x in k["interior"]) or "none"
            pairs.append((f"K_ω = ω({p['driven']}) / ω({p['driving']})",
                          f"{n(k['min']['value'], 6)} … {n(k['max']['value'], 6)}", f"interior extrema: {inner}"))
        if a:
            pairs.append((f"areal-velocity ratio {head}",
                          n(a["min"]["value"], 10) if a["constant"] else f"{n(a['min']['value'], 6)} … {n(a['max']['value'], 6)}",
                          "constant along the stroke" if a["constant"] else "varies"))
        pf = p.get("past_foot_from")
        pairs.append((f"{p['driven']} lengthens (past the foot of its pivot)",
                      "never along the stroke" if pf is None else f"from {st['actuator']} = {n(pf / Lf, 7)} {length_unit}", ""))
    lever = []
    g = act.get("lever")
    if g:
        d = lambda x: n(math.degrees(x) if abs(x) > TOL.shown_zero else 0.0, 7)  # noqa: E731
        lever = [("a = |O A|", n(g["a"] / Lf, 7), length_unit), ("α", d(g["alpha"]), "°"), ("β", d(g["beta"]), "°"),
                 ("γ", d(g["gamma"]), "°"), ("b1 (driven rod at the start)", n(g["b1"] / Lf, 7), length_unit),
                 ("l1 (driving rod at the start)", n(g["l1"] / Lf, 7), length_unit),
                 ("h_O, h_A (distances of O, A from the guide)", f"{n(g['h_O'] / Lf, 7)}, {n(g['h_A'] / Lf, 7)}", length_unit),
                 ("S_BOB1 / S_BAB1 = h_O / h_A", n(g["area_ratio"], 10), ""),
                 ("s1* (B at the foot of O)", n(g["foot_stroke"] / Lf, 7), length_unit),
                 ("s2 max = b1 − h_O", n(g["s2_max"] / Lf if g["s2_max"] is not None else None, 7), length_unit),
                 ("limits s1 → ∞: ψ, φ, K_ω", f"{d(g['limits']['psi'])}°, {d(g['limits']['phi'])}°, "
                                              f"{n(g['limits']['K_omega'], 7)}", "")]
        if g["mirrored"]:
            lever.append(("frame", "mirrored (B0 below O → A): ψ and φ are clockwise in the file's frame", ""))
    elif act.get("lever_note"):
        lever = [("lever manipulator", act["lever_note"], "")]
    return {"stroke": lines, "extremes": extremes, "pairs": pairs, "lever": lever}


def on_arc(theta, start):
    """An angle ``theta`` (rad) written on the arc that begins at ``start``: start + ((θ − start) mod 2π) within
    rounding, so that a swing's range and its extremes use one convention on a page; ``theta`` when either is
    missing."""
    if theta is None or start is None or not (math.isfinite(theta) and math.isfinite(start)):
        return theta
    d = (theta - start) % (2 * math.pi)
    return start + (0.0 if d > 2 * math.pi - 1e-9 else d)


def mesh_text(s: dict, label: str) -> str:
    """One line on a gear pair's mesh check (a mesh summary of :mod:`assur.gears.mesh`, SI)."""
    fine = s.get("fine_scan")
    if fine and fine["interference_driving_ranges"]:
        verdict = (f"INTERFERES near the step boundaries at driving angle φ ∈ {fine['interference_driving_ranges']} "
                   f"(fine scan; max penetration {mm_text(fine['max_penetration'], 3)})")
    elif s["interference"]:
        verdict = (f"INTERFERES at driving angle φ ∈ {s['interference_driving_ranges']} (max penetration "
                   f"{mm_text(s['max_penetration'], 3)})")
    else:
        verdict = "runs without interference"
    bl = (f"; backlash {s['backlash_min'] * MM:.3f}…{s['backlash_max'] * MM:.3f} mm"
          if s["backlash_min"] is not None else "")
    ratio = (f"; transmitted ratio {s['actual_ratio_min']:.4f}…{s['actual_ratio_max']:.4f} "
             f"(law {s['law_ratio_min']:.4f}…{s['law_ratio_max']:.4f}, largest deviation "
             f"{100 * s['max_ratio_deviation']:.2f} %)" if s["max_ratio_deviation"] is not None else "")
    return f"mesh check ({label}, {s['positions']} positions): {verdict}{bl}{ratio}"
