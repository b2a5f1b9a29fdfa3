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
        out["unbuildable"] = None
        out["note"] = "a linear input has no natural cycle; use 'assur solve' with a stroke range"
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
