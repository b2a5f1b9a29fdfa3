"""One summary of a mechanism: structure, buildability, transmission, dead centres and gait.

This is what ``assur analyze --json`` prints and what the report shows. All numbers SI.
"""
from __future__ import annotations

import math

import numpy as np

from ..errors import UnbuildableError
from ..structure.assur import analyse
from .gait import gait_metrics, module_metrics
from .sampling import TWO_PI, Cycle
from .transmission import buildable_ranges, dead_centres, transmission_angles


def structure_summary(mech) -> dict:
    s = analyse(mech)
    out = {
        "name": mech.name,
        "mobility": s.mobility,
        "mobility_formula": (f"W = 3·{s.n_moving} − 2·{s.pair_counts['p5']} − {s.pair_counts['p4']} = {s.mobility}"
                             if s.formula_name == "Chebyshev" else
                             f"W = 6·{s.n_moving} − 5·{s.pair_counts['p5']} − 4·{s.pair_counts['p4']} − "
                             f"3·{s.pair_counts['p3']} − 2·{s.pair_counts['p2']} − {s.pair_counts['p1']} = {s.mobility}"),
        "formula": s.formula_name,
        "moving_links": s.n_moving,
        "pairs": dict(s.pair_counts),
        "drivers": [d.name for d in mech.drivers],
        "structural_formula": s.structural_formula if s.groups or s.drivers else None,
        "structural_formula_numbered": s.structural_formula_numbered if s.groups or s.drivers else None,
        "groups": s.describe(),
    }
    if s.idle:
        out["idle_freedoms"] = s.idle
        out["mobility_without_idle"] = s.mobility_without_idle
    return out


def analyze(plan, params=None, steps: int = 720) -> dict:
    """A JSON-ready summary of a compiled mechanism (see module docstring)."""
    mech = plan.mechanism
    out = structure_summary(mech)
    out["parameters"] = {n: float(v) for n, v in zip(plan.param_names, plan.defaults if params is None else params)}
    out["inputs"] = [{"name": n, "kind": k, "speed": float(s), "sketch": float(q)}
                     for n, k, s, q in zip(plan.input_names, plan.input_kinds, plan.speeds, plan.sketch_inputs)]
    out["steps"] = steps
    if plan.n_inputs != 1:
        out["unbuildable"] = None
        out["note"] = "cycle analysis needs a single input; use 'assur solve' for several inputs"
        return out
    if plan.input_kinds[0] == "rotary":
        ranges, bad, n = buildable_ranges(plan, params, steps)
        out["unbuildable"] = bad
        out["buildable_ranges"] = [{"start": a, "end": b} for a, b in ranges]
        out["full_rotation"] = bad == 0
        out["toggle_positions"] = [] if bad == 0 else sorted({a for r in ranges for a in r})
        cyc = Cycle(plan, params)
        q = np.linspace(0.0, TWO_PI, steps, endpoint=False)
        st = cyc.state(q)
        mu = transmission_angles(plan, st, params)
        out["transmission_angles"] = {
            k: {"min": _nanf(np.nanmin(v)), "max": _nanf(np.nanmax(v)),
                "worst_deviation_from_90": _nanf(np.nanmax(np.abs(v - math.pi / 2)))} for k, v in mu.items()}
        out["dead_centres"] = [{"angle": d.angle, "kind": d.kind, "link": d.link}
                               for d in dead_centres(plan, params)]
        g = mech.gait
        if g is not None:
            try:
                gm = gait_metrics(plan, params, steps=steps)
                out["gait"] = gm.as_dict()
                if len(g.phases) > 1:
                    out["module"] = module_metrics(gm, g.phases, steps).as_dict()
            except UnbuildableError as exc:
                out["gait"] = None
                out["gait_error"] = str(exc)
    else:
        from ..errors import SpecError
        from .actuators import stroke_summary
        try:
            out["actuators"] = stroke_summary(plan, params, steps=min(int(steps), 720))
            out["unbuildable"] = out["actuators"]["unbuildable"]
        except SpecError as exc:
            out["unbuildable"] = None
            out["note"] = f"a linear input has no natural cycle ({exc}); use 'assur solve' with a stroke range"
    return out


def _nanf(x):
    x = float(x)
    return None if not math.isfinite(x) else x


def format_number(v, digits: int = 6) -> str:
    """A number for people: ``digits`` significant digits, '—' for a missing or non-finite value."""
    if v is None:
        return "—"
    v = float(v)
    if not math.isfinite(v):
        return "—"
    if v == 0:
        return "0"
    return f"{v:.{digits}g}"


def gait_rows(g: dict, length_factor: float = 1.0, length_unit: str = "m") -> list[tuple[str, str, str]]:
    """The gait metrics of an ``analyze`` summary as (quantity, value, unit) rows; lengths are shown
    divided by ``length_factor`` (the file's unit), speeds in m/s. Shared by the CLI and the report."""
    n = format_number
    rows = [
        ("support definition", g["support"], ""),
        ("contact arc", f"{math.degrees(g['contact_start']) % 360:.2f} … {math.degrees(g['contact_end']) % 360:.2f}", "°"),
        ("step length", n(g["step_length"] / length_factor, 5), length_unit),
        ("lift (path height)", n(g["lift"] / length_factor, 5), length_unit),
        ("sag (support height variation)", n(g["sag"] / length_factor, 5), length_unit),
        ("duty factor", f"{g['duty_factor']:.4f}", ""),
        ("contact ratio (support / transfer)", n(g["contact_ratio"], 5), ""),
    ]
    for key, label in (("support_speed", "support speed |v|"), ("support_vx", "support speed |vx|")):
        for stat in ("max", "min", "mean", "midrange"):
            rows.append((f"{label} {stat}", n(g[key][stat], 5), "m/s"))
    rows.append(("support acceleration ax min", n(g["support_ax"]["min"], 5), "m/s²"))
    rows.append(("support acceleration ax max", n(g["support_ax"]["max"], 5), "m/s²"))
    rows.append(("crank speed ω", n(g["omega"], 5), "rad/s"))
    return rows


#: the envelope's quantities: (label, SI → shown factor kind, unit); kind "L" = the file's length unit
_ROD_QUANTITIES = (("extension", "length change L − L₀", "L", None), ("rate", "rate dL/dt", "v", "m/s"),
                   ("accel", "acceleration d²L/dt²", "a", "m/s²"), ("angle", "rotation from the start", "deg", "°"),
                   ("omega", "angular velocity ω", "1", "rad/s"), ("alpha", "angular acceleration ε", "1", "rad/s²"))


def actuator_rows(act: dict, length_factor: float = 1.0, length_unit: str = "m") -> dict:
    """The ``actuators`` entry of an ``analyze`` summary for people, shared by the CLI and the report.

    Returns ``{"stroke": [text lines], "extremes": [(rod, quantity, min, max, interior extrema, unit)],
    "pairs": [(quantity, value, note)], "lever": [(quantity, value, unit)]}``; lengths divided by
    ``length_factor`` (the file's unit), angles in degrees, rates in SI."""
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
    factors = {"L": (1.0 / Lf, length_unit), "v": (1.0, "m/s"), "a": (1.0, "m/s²"), "deg": (180.0 / math.pi, "°"),
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
            chop = lambda v: 0.0 if abs(v) <= max(1e-9 * big, 1e-12) else v  # noqa: E731 - rounding noise shows as 0
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
        d = lambda x: n(math.degrees(x) if abs(x) > 1e-12 else 0.0, 7)  # noqa: E731
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
