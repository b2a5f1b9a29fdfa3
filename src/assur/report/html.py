"""``assur report``: one self-contained HTML page about a mechanism.

The page holds the structure (mobility, Assur groups, structural formula), the parameters, the
analysis summary (buildability, transmission angles, dead centres, gait and walking-module
metrics), the figure panels as embedded PNG, an embedded animation (``to_jshtml``) and a table of
positions. Nothing refers to an external file or the network. The page is written into a
temporary directory next to the output and moved into place, so a failure leaves nothing behind.
"""
from __future__ import annotations

import base64
import html
import math
from pathlib import Path

from ..analysis.summary import format_number, gait_rows
from ..errors import SpecError, UnbuildableError
from ..io.units import LENGTH
from ..io.units import param_unit as _param_unit

_CSS = """
body { font-family: system-ui, -apple-system, "Segoe UI", Helvetica, Arial, sans-serif; margin: 0 auto;
       max-width: 1240px; padding: 1em 2em 3em; color: #222; line-height: 1.45; }
h1 { margin-bottom: 0.1em; } h2 { border-bottom: 1px solid #ccc; margin-top: 1.8em; }
.meta { color: #666; font-size: 0.9em; }
.desc { white-space: pre-wrap; background: #f6f6f3; padding: 0.7em 1em; border-radius: 4px; font-size: 0.92em; }
table { border-collapse: collapse; margin: 0.6em 0 1em; font-size: 0.92em; }
th, td { border: 1px solid #ccc; padding: 0.25em 0.6em; text-align: left; }
th { background: #eef0f3; } td.num { text-align: right; font-variant-numeric: tabular-nums; }
code, .formula { font-family: ui-monospace, "SFMono-Regular", Menlo, Consolas, monospace; }
.formula { font-size: 1.1em; background: #f3f5fa; padding: 0.3em 0.6em; display: inline-block; border-radius: 3px; }
.ok { color: #1a7f37; font-weight: 600; } .bad { color: #b42318; font-weight: 600; }
img.figure { max-width: 100%; height: auto; border: 1px solid #ddd; }
.note { color: #666; font-style: italic; }
.scroll { overflow-x: auto; }
"""


def _e(x) -> str:
    return html.escape(str(x))


_num = format_number


def _deg(v, digits=2) -> str:
    return "—" if v is None or not math.isfinite(float(v)) else f"{math.degrees(float(v)):.{digits}f}°"


def _table(head, rows, num_cols=()) -> str:
    out = ["<table>", "<tr>" + "".join(f"<th>{_e(h)}</th>" for h in head) + "</tr>"]
    for r in rows:
        cells = []
        for i, c in enumerate(r):
            cls = ' class="num"' if i in num_cols else ""
            cells.append(f"<td{cls}>{_e(c)}</td>")
        out.append("<tr>" + "".join(cells) + "</tr>")
    out.append("</table>")
    return "\n".join(out)


def _png_tag(png: bytes, alt: str) -> str:
    return (f'<img class="figure" alt="{_e(alt)}" src="data:image/png;base64,'
            f'{base64.b64encode(png).decode("ascii")}">')


def _section(title, body) -> str:
    return f"<h2>{_e(title)}</h2>\n{body}\n"


# -- sections ---------------------------------------------------------------------------------------
def structure_html(summary: dict) -> str:
    s = summary
    pairs = ", ".join(f"{k} = {v}" for k, v in s["pairs"].items())
    parts = [f'<p>Mobility ({_e(s["formula"])}): <span class="formula">{_e(s["mobility_formula"])}</span></p>',
             f"<p>Moving links n = {s['moving_links']}; kinematic pairs {_e(pairs)}; drivers: "
             f"{_e(', '.join(s['drivers']) or 'none')}.</p>"]
    if s["groups"]:
        rows = []
        for i, g in enumerate(s["groups"], 1):
            from ..structure.assur import GroupKind
            try:
                n = GroupKind(g["kind"]).dyad_kind_number
            except ValueError:
                n = None
            kind = f"{g['kind']} (kind {n})" if n else g["kind"]
            rows.append((i, _roman(g["class"]), g["order"], kind, ", ".join(g["bodies"]), ", ".join(g["attaches_to"])))
        parts.append(_table(["#", "class", "order", "kind", "bodies", "attached to"], rows, num_cols=(0, 2)))
    if s.get("structural_formula"):
        parts.append(f'<p>Structural formula: <span class="formula">{_e(s["structural_formula"])}</span><br>'
                     f'numbered (frame 0, links in file order): '
                     f'<span class="formula">{_e(s["structural_formula_numbered"])}</span></p>')
    return "\n".join(parts)


def _roman(n):
    return {1: "I", 2: "II", 3: "III", 4: "IV", 5: "V", 6: "VI"}.get(n, str(n))


def parameters_html(plan) -> str:
    u = plan.mechanism.units
    rows = []
    for name, v in zip(plan.param_names, plan.defaults):
        f, unit = _param_unit(name, u)
        si = "m" if unit == u.length else ("rad" if unit else "")
        rows.append((name, _num(v * f, 8), unit, _num(v, 8), si))
    return _table(["parameter", "value", "unit", "SI value", "SI unit"], rows, num_cols=(1, 3))


def drivers_html(plan) -> str:
    m = plan.mechanism
    rows = []
    for d in m.drivers:
        if d.kind == "rotary":
            what = f"link {d.link} about {d.pivot} (arm {d.arm}), {'ccw' if d.sense > 0 else 'cw'}"
            speed = f"{_num(d.speed * 60 / (2 * math.pi), 5)} rpm ({_num(d.speed, 5)} rad/s)"
        else:
            what = f"actuator {d.actuator}"
            speed = f"{_num(d.speed / LENGTH[m.units.length], 5)} {m.units.length}/s ({_num(d.speed, 5)} m/s)"
        rows.append((d.name, d.kind, what, speed))
    return _table(["driver", "kind", "", "speed"], rows)


def analysis_html(summary: dict, plan) -> str:
    s = summary
    u = plan.mechanism.units
    kL = 1.0 / LENGTH[u.length]
    Lu = u.length
    parts = []
    if s.get("note"):
        parts.append(f'<p class="note">{_e(s["note"])}</p>')
    act = s.get("actuators")
    if act:   # a linear driver's working stroke
        from ..analysis.summary import actuator_rows
        rows = actuator_rows(act, 1.0 / kL, Lu)
        parts += [f"<p>{_e(line)}</p>" for line in rows["stroke"]]
        if rows["lever"]:
            parts.append("<h3>Lever manipulator (paper 002 parametrisation)</h3>")
            parts.append(_table(["quantity", "value", "unit"], rows["lever"], num_cols=(1,)))
        parts.append("<h3>Stroke envelope</h3>")
        parts.append('<p class="note">Extremes along the stroke; interior ones located by a root of the '
                     "derivative.</p>")
        parts.append('<div class="scroll">' + _table(["rod", "quantity", "min (where)", "max (where)",
                                                      "interior extrema", "unit"], rows["extremes"]) + "</div>")
        if rows["pairs"]:
            parts.append("<h3>Rods hinged at one joint</h3>")
            parts.append(_table(["quantity", "value", "note"], rows["pairs"], num_cols=(1,)))
        try:
            from ..plot.actuators import actuator_figure
            from ..plot.figures import close, figure_png
            fig = actuator_figure(plan)
            parts.append(_png_tag(figure_png(fig, dpi=80), "angular velocities and accelerations of the rods, "
                                                           "K_ω and length changes along the stroke"))
            close(fig)
        except SpecError as exc:
            parts.append(f'<p class="note">no actuator figure: {_e(exc)}</p>')
        return "\n".join(parts)
    if s.get("unbuildable") is None:
        return "\n".join(parts)
    steps = s.get("steps")
    if s.get("full_rotation"):
        parts.append(f'<p>Buildability: <span class="ok">the crank turns fully</span> '
                     f'(0 of {steps} positions unbuildable).</p>')
    else:
        rng = ", ".join(f"{_deg(r['start'], 1)} … {_deg(r['end'], 1)}" for r in s.get("buildable_ranges", []))
        parts.append(f'<p>Buildability: <span class="bad">the crank cannot turn fully</span>: '
                     f'{s["unbuildable"]} of {steps} positions cannot be assembled (unbuildable: {s["unbuildable"]}). '
                     + (f"Buildable ranges: {_e(rng)}." if rng else "No position can be assembled.") + "</p>")
    ta = s.get("transmission_angles") or {}
    if ta:
        rows = [(k, _deg(t["min"]), _deg(t["max"]), _deg(t["worst_deviation_from_90"])) for k, t in ta.items()]
        parts.append("<h3>Transmission angles</h3>")
        parts.append(_table(["dyad (solved point)", "min μ", "max μ", "worst deviation from 90°"], rows,
                            num_cols=(1, 2, 3)))
    dc = s.get("dead_centres") or []
    parts.append("<h3>Dead centres</h3>")
    if dc:
        parts.append(_table(["crank angle", "kind", "link"], [(_deg(d["angle"]), d["kind"], d["link"]) for d in dc],
                            num_cols=(0,)))
    else:
        parts.append('<p class="note">none found</p>')
    g = s.get("gait")
    if g:
        parts.append(f"<h3>Gait of foot {_e(g['foot'])}</h3>")
        rows = gait_rows(g, 1.0 / kL, Lu)
        parts.append(_table(["quantity", "value", "unit"], rows, num_cols=(1,)))
    elif s.get("gait_error"):
        parts.append(f'<h3>Gait</h3><p class="note">not available: {_e(s["gait_error"])}</p>')
    return "\n".join(parts)


def module_html(summary: dict, plan, steps: int) -> str:
    mod = summary.get("module")
    if not mod:
        return ""
    rows = [("legs (phases)", ", ".join(f"{math.degrees(p):.0f}°" for p in mod["phases"])),
            ("feet on the ground: min", mod["min_feet"]), ("feet on the ground: max", mod["max_feet"]),
            ("feet on the ground: mean", f"{mod['mean_feet']:.3f}"),
            ("airborne share of the cycle", f"{100 * mod['airborne_fraction']:.1f} %")]
    out = [_table(["walking module", "value"], rows, num_cols=(1,))]
    try:
        from ..analysis.gait import gait_metrics
        from ..plot.figures import close, figure_png, timeline_figure
        gm = gait_metrics(plan, steps=steps)
        fig = timeline_figure(plan, gm, plan.mechanism.gait.phases, steps)
        out.append(_png_tag(figure_png(fig, dpi=90), "feet on the ground over one turn"))
        close(fig)
    except (UnbuildableError, SpecError) as exc:
        out.append(f'<p class="note">{_e(exc)}</p>')
    return "\n".join(out)


def positions_html(plan, n: int = 12, ranges=None) -> str:
    """A table of the positions of every point at ``n`` inputs (12 crank angles: every 30°)."""
    from ..plot.figures import sample
    try:
        sw = sample(plan, n, ranges=ranges)
    except SpecError as exc:
        return f'<p class="note">{_e(exc)}</p>'
    u = plan.mechanism.units
    kL = 1.0 / LENGTH[u.length]
    axes = "xyz"[:getattr(plan, "dimension", 2)]          # planar or spatial plans
    head = [sw.axis_label, "valid"] + [f"{p}.{c} [{u.length}]" for p in plan.point_names for c in axes]
    rows = []
    for i in range(sw.n):
        r = [f"{sw.axis[i]:.4g}", "yes" if sw.state.valid[i] else "no"]
        r += [_num(v * kL, 6) for v in sw.state.pos[i].reshape(-1)]
        rows.append(r)
    return '<div class="scroll">' + _table(head, rows, num_cols=tuple(range(2, len(head))) + (0,)) + "</div>"


def figures_html(plan, steps: int, frames: int, ranges=None) -> tuple[str, str]:
    """(figure panels, embedded animation) as HTML."""
    from ..plot.figures import animation, close, figure_png, jshtml, mechanism_figure
    try:
        fig = mechanism_figure(plan, steps, ranges=ranges)
    except SpecError as exc:
        note = f'<p class="note">no figures: {_e(exc)}</p>'
        return note, note
    panels = _png_tag(figure_png(fig, dpi=90), "paths, kinematic diagram, velocity and acceleration")
    close(fig)
    fig, anim = animation(plan, frames, fps=12, ranges=ranges, figsize=(5.6, 5.6), dpi=72)
    import matplotlib
    with matplotlib.rc_context({"animation.embed_limit": 60.0}):
        js = jshtml(anim, fps=12)
    close(fig)
    return panels, js


def build_report(plan, *, steps: int = 360, frames: int = 36, ranges=None, source: str | None = None) -> str:
    """The report page as one HTML string."""
    if getattr(plan, "dimension", 2) == 3:   # a spatial plan: 3D views (report/spatial.py)
        from .spatial import build_spatial_report
        return build_spatial_report(plan, steps=steps, frames=frames, ranges=ranges, source=source)
    from .. import __version__
    from ..analysis.summary import analyze
    m = plan.mechanism
    summary = analyze(plan, steps=steps)
    title = m.name or (Path(source).stem if source else "mechanism")
    panels, anim = figures_html(plan, steps, frames, ranges)
    body = [f"<h1>{_e(title)}</h1>",
            f'<p class="meta">{_e(source or "")} — units: length {_e(m.units.length)}, angle {_e(m.units.angle)} '
            f"— assur {_e(__version__)}</p>"]
    if m.description.strip():
        body.append(f'<div class="desc">{_e(m.description.strip())}</div>')
    body.append(_section("Structure", structure_html(summary)))
    body.append(_section("Parameters", parameters_html(plan) + "\n" + drivers_html(plan)))
    body.append(_section("Analysis", analysis_html(summary, plan)))
    mod = module_html(summary, plan, steps)
    if mod:
        body.append(_section("Walking module", mod))
    body.append(_section("Plots", panels))
    body.append(_section("Animation", anim))
    body.append(_section("Positions", positions_html(plan, 12, ranges)))
    return ("<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n"
            f"<meta name=\"viewport\" content=\"width=device-width, initial-scale=1\">\n<title>{_e(title)}</title>\n"
            f"<style>{_CSS}</style>\n</head>\n<body>\n" + "\n".join(body) + "\n</body>\n</html>\n")


def write_report(plan, out_dir, *, steps: int = 360, frames: int = 36, ranges=None, source: str | None = None) -> Path:
    """Write ``out_dir/index.html`` atomically (``io.output.atomic_directory``): on failure nothing is
    left behind. Returns the page's path."""
    from ..io.output import atomic_directory
    with atomic_directory(out_dir) as tmp:
        page = build_report(plan, steps=steps, frames=frames, ranges=ranges, source=source)
        (tmp / "index.html").write_text(page, encoding="utf-8")
    return Path(out_dir) / "index.html"


__all__ = ["build_report", "write_report"]
