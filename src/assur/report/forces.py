"""The force analysis as text and table rows: the cycle summary (:func:`summary_rows`, :func:`summary_lines`),
the reactions at given inputs (:func:`at_lines`, :func:`at_dict`) and the per-sample CSV table (:func:`csv_table`).
Forces in N, torques in N·m, power in W, energy in J; inputs in the file's units (angle unit of a crank,
length unit of a linear driver).
"""
from __future__ import annotations


import numpy as np

from ..io.units import ANGLE, LENGTH
from .text import format_number


def input_unit(plan, k: int = 0) -> tuple[float, str]:
    """(factor, unit) of input ``k`` in the file: an SI value divided by the factor is in the unit."""
    u = plan.mechanism.units
    if plan.input_kinds[k] == "rotary":
        return ANGLE[u.angle], "°" if u.angle == "deg" else "rad"
    return LENGTH[u.length], u.length


def _n(v, scale=None) -> str:
    return format_number(v, 5, scale)


def summary_rows(s: dict, plan) -> list[tuple[str, str, str]]:
    """(quantity, value, unit) rows of a :func:`~assur.kinetostatics.overview.force_summary`."""
    f, iu = input_unit(plan)
    eu = s["effort_unit"]
    what = "torque" if s["effort"] == "torque" else "force"
    span = (f"one turn, {s['samples']} samples" if s["cycle"] == "turn" else
            f"stroke {_n(s['start'] / f)}…{_n(s['stop'] / f)} {iu}, {s['samples']} samples")
    speed_u = "rad/s" if s["effort"] == "torque" else "m/s"
    rows = [("cycle", span, ""), ("driver", s["driver"], ""), ("speed", _n(s.get("speed")), speed_u),
            (f"peak driving {what}", _n(s.get("peak")), eu), (f"RMS driving {what}", _n(s.get("rms")), eu),
            (f"mean driving {what}", _n(s.get("mean"), s.get("peak")), eu), ("peak motor power", _n(s.get("power_peak")), "W")]
    if "power_mean" in s:
        scale = (s.get("peak") or 0.0) * abs(s["stop"] - s["start"] or 1.0)
        rows += [("mean motor power", _n(s["power_mean"], s.get("power_peak")), "W")]
        if s["cycle"] == "turn":
            rows += [("energy per cycle", _n(s["energy"], scale), "J"),
                     ("kinetic-energy fluctuation ΔE", _n(s["energy_fluctuation"]), "J")]
        else:
            rows.append(("work over the stroke", _n(s["energy"], scale), "J"))
    if s.get("flywheel_inertia") is not None or (s["effort"] == "torque" and "flywheel_delta" in s):
        rows.append((f"flywheel inertia for δ = {s['flywheel_delta']:g}", _n(s.get("flywheel_inertia")), "kg·m²"))
    rows += [("peak shaking force", _n(s["shaking_force_peak"]), "N"),
             ("peak shaking moment", _n(s["shaking_moment_peak"]), "N·m")]
    rows += [(f"peak load at {k}", _n(v), "N") for k, v in s["joint_peaks"].items()]
    for name, gs in s.get("gears", {}).items():
        rows += [(f"gear pair {name}: peak tooth force", _n(gs["tooth_force_peak"]), "N"),
                 (f"gear pair {name}: peak torque on the driven link", _n(gs["torque_peak"]), "N·m")]
    rows.append(("singular samples (forces undefined)", str(s["singular"]), ""))
    if s.get("unassembled"):
        rows.append(("samples that cannot be assembled", str(s["unassembled"]), ""))
    if "friction" in s:
        fr = s["friction"]
        rows.append(("friction iterations", f"{fr['iterations']} ({'converged' if fr['converged'] else 'NOT converged'})",
                     ""))
    g = s.get("gait")
    if g:
        rows += [("module: body weight", _n(g["weight"]), "N"), ("module: legs", str(g["legs"]), ""),
                 ("module: peak shaft torque", _n(g["module_peak"]), "N·m"),
                 ("module: RMS shaft torque", _n(g["module_rms"]), "N·m"),
                 ("module: mean shaft torque", _n(g["module_mean"], g["module_peak"]), "N·m")]
    return rows


def summary_lines(s: dict, plan) -> list[str]:
    """The summary as aligned text lines (with the no-load note first when the file has none)."""
    rows = summary_rows(s, plan)
    w = max(len(r[0]) for r in rows)
    out = [f"note: {s['note']}"] if s.get("note") else []
    return out + [f"  {a:<{w}}  {b} {c}".rstrip() for a, b, c in rows]


def _vector_heads(dim: int) -> tuple[str, ...]:
    return ("Rx", "Ry", "Rz")[:dim]


def pair_label(f, k: int) -> str:
    """A pair's name, with its bodies when another pair has the same name."""
    if f.pair_names.count(f.pair_names[k]) > 1:
        return f"{f.pair_names[k]} ({f.pair_bodies[k][0]}–{f.pair_bodies[k][1]})"
    return f.pair_names[k]


def at_dict(f, i: int) -> dict:
    """The forces of sample ``i`` of a (n,) result as a JSON-ready dict (SI, NaN where singular)."""
    plan = f.plan
    dim = f.reactions.shape[-1]
    joints = []
    for k in f.joint_pairs:
        r = f.reactions[i, k]
        entry = {"pair": f.pair_names[k], "kind": f.pair_kinds[k], "bodies": list(f.pair_bodies[k]),
                 "reaction": [float(x) for x in r], "magnitude": float(np.sqrt(np.sum(r * r)))}
        if f.pair_kinds[k] == "P":
            entry["normal"] = float(f.normal[i, k])
            entry["couple"] = float(f.couples[i, k])
        joints.append(entry)
    fac, _ = input_unit(plan)
    return {"input": float(f.inputs[i, 0]) / fac, "input_si": float(f.inputs[i, 0]),
            "valid": bool(f.valid[i]), "singular": bool(f.singular[i]), "condition": float(f.condition[i]),
            "driver": float(f.driver[i, 0]), "power": float(f.power[i]), "dimension": dim, "joints": joints}


def at_lines(f, i: int) -> list[str]:
    """The table of sample ``i``: every joint's reaction, slide forces and couples, the driving effort, power."""
    plan = f.plan
    d = at_dict(f, i)
    fac, iu = input_unit(plan)
    eu = "N·m" if plan.input_kinds[0] == "rotary" else "N"
    what = "torque" if plan.input_kinds[0] == "rotary" else "force"
    head = f"{plan.input_names[0]} = {_n(d['input'])} {iu}"
    if not d["valid"]:
        why = "a toggle (singular): the forces are undefined" if d["singular"] else "cannot be assembled"
        return [f"{head}: {why}"]
    dim = d["dimension"]
    heads = [f"{h} [N]" for h in _vector_heads(dim)] + ["|R| [N]", "normal [N]", "couple [N·m]"]
    rows = []
    for k, j in zip(f.joint_pairs, d["joints"]):
        big = max(j["magnitude"], 1e-300)
        cells = [_n(x, big) for x in j["reaction"]] + [_n(j["magnitude"])]
        cells += [_n(j["normal"], big), _n(j["couple"])] if "normal" in j else ["", ""]
        rows.append([f"{j['pair']} ({j['bodies'][0]}→{j['bodies'][1]})"] + cells)
    w0 = max([len("joint")] + [len(r[0]) for r in rows])
    ws = [max(len(h), *(len(r[c + 1]) for r in rows)) for c, h in enumerate(heads)]
    out = [head, "  " + "  ".join(["joint".ljust(w0)] + [h.rjust(w) for h, w in zip(heads, ws)]).rstrip()]
    out += ["  " + "  ".join([r[0].ljust(w0)] + [c.rjust(w) for c, w in zip(r[1:], ws)]).rstrip() for r in rows]
    out.append(f"  driving {what}: {_n(d['driver'])} {eu}   power: {_n(d['power'])} W   "
               f"condition: {format_number(d['condition'], 3)}")
    return out


def csv_table(f) -> tuple[list[str], list[list]]:
    """(header, rows) of a (n,) result: input (file units), driver, power, each joint's reaction components."""
    plan = f.plan
    fac, iu = input_unit(plan)
    eu = "N·m" if plan.input_kinds[0] == "rotary" else "N"
    dim = f.reactions.shape[-1]
    ks = f.joint_pairs
    header = [f"{plan.input_names[0]} [{iu}]", f"driver [{eu}]", "power [W]"]
    header += [f"{pair_label(f, k)} {h} [N]" for k in ks for h in _vector_heads(dim)]
    rows = []
    for i in range(f.shape[0]):
        row = [float(f.inputs[i, 0]) / fac, float(f.driver[i, 0]), float(f.power[i])]
        row += [float(f.reactions[i, k, c]) for k in ks for c in range(dim)]
        rows.append(row)
    return header, rows


def forces_html(study) -> str:
    """The report's forces section of a Study ('' when the file has no masses or loads, or more than one driver):
    the summary table and the sheet of force figures, from the Study's force cycle (no new solve)."""
    from ..errors import AssurError
    from .page import escape, png_tag, table
    plan = study.plan
    if not study.has_loads or plan.n_inputs != 1:
        return ""
    try:
        cyc = study.force_cycle
        summary = study.force_summary
    except AssurError as exc:
        return f'<p class="note">no force analysis: {escape(exc)}</p>'
    rows = [(a, f"{b} {c}".strip()) for a, b, c in summary_rows(summary, plan)]
    out = [table(["forces (SI)", "value"], rows, num_cols=(1,))]
    if plan.dimension == 2:
        from ..plot.draw import close, figure_png
        from ..plot.forces import forces_figure
        fig = forces_figure(plan, cycle=cyc, dpi=80)
        out.append(png_tag(figure_png(fig, dpi=80), "driving torque and power, reaction hodographs, forces on the "
                                                    "kinematic diagram, Zhukovsky's lever"))
        close(fig)
    return "\n".join(out)
