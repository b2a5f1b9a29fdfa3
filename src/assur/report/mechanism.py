"""``assur report``: one self-contained HTML page about a mechanism, planar or spatial.

The page holds the structure (mobility, Assur groups, structural formula), the parameters, the
analysis summary (buildability, transmission angles, dead centres, gait and walking-module metrics; a
spatial mechanism's dyads), the figure panels as embedded PNG, an animation (planar: embedded
``to_jshtml``; spatial: an interactive 3D view, plotly.js inlined) and a table of positions. The
analysis, the figures and the animation's path share one solved turn of
:data:`~assur.analysis.sampling.CYCLE_STEPS` samples (or ``steps``). Nothing refers to an external file
or the network. The page is written into a temporary directory next to the output and moved into
place, so a failure leaves nothing behind.
"""
from __future__ import annotations

from functools import partial
from pathlib import Path

from ..analysis.sampling import CYCLE_STEPS
from ..analysis.study import Study
from ..errors import SpecError
from .page import escape, header, page, png_tag, section, table
from .analysis import analysis_html
from .text import (deg_text, dyad_kind_number, format_number, length_display, on_arc, parameter_rows,
                   phases_text, roman, speed_text)

__all__ = ["build_report", "write_report"]


# -- sections of both pages ------------------------------------------------------------------------
def structure_html(summary: dict) -> str:
    """Mobility, pairs, drivers, the Assur groups and the structural formula of a summary."""
    s = summary
    pairs = ", ".join(f"{k} = {v}" for k, v in s["pairs"].items())
    parts = [f'<p>Mobility ({escape(s["formula"])}): <span class="formula">{escape(s["mobility_formula"])}</span></p>',
             f"<p>Moving links n = {s['moving_links']}; kinematic pairs {escape(pairs)}; drivers: "
             f"{escape(', '.join(s['drivers']) or 'none')}.</p>"]
    if s["groups"]:
        rows = []
        for i, g in enumerate(s["groups"], 1):
            n = dyad_kind_number(g["kind"])
            kind = f"{g['kind']} (kind {n})" if n else g["kind"]
            rows.append((i, roman(g["class"]), g["order"], kind, ", ".join(g["bodies"]), ", ".join(g["attaches_to"])))
        parts.append(table(["#", "class", "order", "kind", "bodies", "attached to"], rows, num_cols=(0, 2)))
    if s.get("structural_formula"):
        parts.append(f'<p>Structural formula: <span class="formula">{escape(s["structural_formula"])}</span><br>'
                     f'numbered (frame 0, links in file order): '
                     f'<span class="formula">{escape(s["structural_formula_numbered"])}</span></p>')
    return "\n".join(parts)


def atlas_html(mechanism) -> str:
    """The mechanism's entry in the atlas of chains (docs/atlas.md): chain ID, name and inversion."""
    from ..structure.atlas.identify import identify
    entry = identify(mechanism)
    if entry is None:
        return ""
    return (f'<p>Atlas: chain <span class="formula">{escape(entry.chain_id)}</span> {escape(entry.label)} '
            f'(frame: <span class="formula">{escape(entry.inversion_id)}</span>; {entry.links} links, '
            f'{entry.joints} pairs, F = {entry.dof}).</p>')


def parameters_html(plan) -> str:
    """The parameters in the file's units and in SI."""
    return table(["parameter", "value", "unit", "SI value", "SI unit"], parameter_rows(plan), num_cols=(1, 3))


def drivers_html(plan) -> str:
    """What each driver drives, and its speed."""
    m = plan.mechanism
    rows = []
    for d in m.drivers:
        if d.kind == "rotary":
            what = f"link {d.link} about {d.pivot} (arm {d.arm}), {'ccw' if d.sense > 0 else 'cw'}"
        else:
            what = f"actuator {d.actuator}"
        rows.append((d.name, d.kind, what, speed_text(d.kind, d.speed, m.units)))
    return table(["driver", "kind", "", "speed"], rows)


def module_html(summary: dict, plan, gait, steps: int) -> str:
    """The walking module's feet on the ground (``gait``: the leg's GaitMetrics), '' for a single leg."""
    mod = summary.get("module")
    if not mod:
        return ""
    rows = [("legs (phases)", phases_text(mod["phases"])),
            ("feet on the ground: min", mod["min_feet"]), ("feet on the ground: max", mod["max_feet"]),
            ("feet on the ground: mean", f"{mod['mean_feet']:.3f}"),
            ("airborne share of the cycle", f"{100 * mod['airborne_fraction']:.1f} %")]
    from ..plot.draw import close, figure_png
    from ..plot.figures import timeline_figure
    fig = timeline_figure(plan, gait, plan.mechanism.gait.phases, steps)
    out = [table(["walking module", "value"], rows, num_cols=(1,)),
           png_tag(figure_png(fig, dpi=90), "feet on the ground over one turn")]
    close(fig)
    return "\n".join(out)


def positions_html(study, n: int = 12, units: str = "file") -> str:
    """A table of the positions of every point at ``n`` inputs of the Study's run (12 crank angles: every 30°,
    taken from the run's samples)."""
    plan = study.plan
    try:
        sw = study.frame_sweep(n)
    except SpecError as exc:
        return f'<p class="note">{escape(exc)}</p>'
    Lf, Lu = length_display(plan.mechanism.units, units)
    kL = 1.0 / Lf
    axes = "xyz"[:plan.dimension]
    head = [sw.axis_label, "valid"] + [f"{p}.{c} [{Lu}]" for p in plan.point_names for c in axes]
    rows = []
    for i in range(sw.n):
        r = [f"{sw.axis[i]:.4g}", "yes" if sw.state.valid[i] else "no"]
        r += [format_number(v * kL, 6, plan.length_scale * kL) for v in sw.state.pos[i].reshape(-1)]
        rows.append(r)
    return '<div class="scroll">' + table(head, rows, num_cols=tuple(range(2, len(head))) + (0,)) + "</div>"


# -- the planar page -------------------------------------------------------------------------------
def _planar_figures(run: Study, gait, frames: int, units: str = "file", progress=None) -> tuple[str, str]:
    """(figure panels, embedded animation) of the solved run of ``run`` (``gait``: its GaitCurves) as HTML."""
    from ..plot.animation import animation, jshtml
    from ..plot.draw import close, figure_png
    from ..plot.figures import mechanism_figure
    plan = run.plan
    fig = mechanism_figure(plan, sweep=run.sweep, gait=gait, units=units)
    panels = png_tag(figure_png(fig, dpi=90), "paths, kinematic diagram, velocity and acceleration")
    close(fig)
    fig, anim = animation(run, frames, fps=12, figsize=(5.6, 5.6), dpi=72)
    import matplotlib
    with matplotlib.rc_context({"animation.embed_limit": 60.0}):
        js = jshtml(anim, fps=12, progress=progress)
    close(fig)
    return panels, js


def dynamics_section(study) -> str:
    """The run on the file's motor (start-up, steady speed, δ beside the kinetostatic estimate, peak reactions), ''
    without a ``[motor]``; a run that stops (a stall, a dead centre) says where."""
    from ..errors import AssurError
    if study.plan.mechanism.motor is None:
        return ""
    try:
        run = study.motor_run
    except AssurError as exc:
        return f'<p class="note">no run on the motor: {escape(exc)}</p>'
    if run is None:
        return ""
    from .dynamics import dynamics_html
    return dynamics_html(run)


def parts_section(study) -> str:
    """The parts of ``assur make`` for a file with a ``[make]`` table (layer chart, exploded view, clearances,
    certificate, bill of materials), or why they cannot be made."""
    from ..errors import AssurError
    from ..parts import report_section
    try:
        return report_section(study)
    except AssurError as exc:
        return f'<p class="note">the parts cannot be made: {escape(exc)}</p>'


def _planar_sections(study: Study, run: Study, panels: str, anim: str, units: str = "file",
                     at=None) -> list[str]:
    plan = study.plan
    summary = study.as_dict(forces=False)
    out = [section("Structure", structure_html(summary) + "\n" + atlas_html(plan.mechanism)),
           section("Parameters", parameters_html(plan) + "\n" + drivers_html(plan)),
           section("Analysis", analysis_html(study, units))]
    mod = module_html(summary, plan, study.gait, study.steps)
    if mod:
        out.append(section("Walking module", mod))
    from .forces import forces_html
    frc = forces_html(study)
    if frc:
        out.append(section("Forces", frc))
    dyn = dynamics_section(study)
    if dyn:
        out.append(section("Dynamics on the motor", dyn))
    if study.plan.mechanism.make is not None:
        out.append(section("Parts", parts_section(study)))
    if plan.mechanism.cams:
        from .cams import cams_html
        out.append(section("Cams", cams_html(study)))
    if at:
        from .centres import centres_html
        out.append(section("Instant centres", centres_html(study, at, units)))
    return out + [section("Plots", panels), section("Animation", anim),
                  section("Positions", positions_html(run, 12, units))]


# -- the spatial page -------------------------------------------------------------------------------
def joints_html(plan) -> str:
    """The joints of a spatial mechanism with their axes."""
    rows = []
    for j in plan.mechanism.joints:
        ax = "" if j.axis is None else "[" + ", ".join(format_number(c, 6, 1.0) for c in j.axis) + "]"
        rows.append((j.point, j.kind, ax))
    return table(["point", "joint", "axis (revolute; pin of a universal joint)"], rows)


def dyads_html(study) -> str:
    """Each R–S–S dyad's branch, swing, transmission angles and dead centres."""
    parts = []
    for s in study.spatial or []:
        w = ", ".join(f"{v:+.0f}" for v in s.paper_w) or "undefined (V3_X = 0)"
        rows = [("assembly branch s = sign det[A − D, e, B − D]", f"{s.branch_s:+d}"),
                ("the paper's W of eq. (21) (= s·sign V3_X)", w),
                ("V3_X changes sign over the turn (a fixed W would jump)", "yes" if s.v3x_changes_sign else "no"),
                ("rocker angle θ4 min", deg_text(s.rocker_angle_min, 4)),
                ("rocker angle θ4 max", deg_text(s.rocker_angle_max, 4)),
                ("rocker swing", deg_text(s.swing, 4)),
                ("transmission angle μ_int min … max", f"{deg_text(s.mu_int_min, 3)} … {deg_text(s.mu_int_max, 3)}"),
                ("effective transmission angle μ_T min … max",
                 f"{deg_text(s.mu_t_min, 3)} … {deg_text(s.mu_t_max, 3)}")]
        rows += [(f"dead centre ({c.kind})", f"crank {deg_text(c.angle, 6)}, θ4 = "
                  f"{deg_text(on_arc(c.rocker_angle, s.rocker_angle_min), 4)}") for c in s.dead_centres]
        parts.append(f"<h3>Dyad solving {escape(s.point)} (rocker {escape(s.rocker)}, coupler "
                     f"{escape(s.coupler)})</h3>")
        parts.append(table(["quantity", "value"], rows, num_cols=(1,)))
    return "\n".join(parts)


def _spatial_figures(run: Study, gait, frames: int, units: str = "file") -> tuple[str, str]:
    """(static figure as PNG, interactive 3D view with its animation) of the solved run of ``run`` as HTML."""
    from ..plot import spatial as view
    from ..plot.draw import close, figure_png
    fig = view.figure(run, units=units)
    panels = png_tag(figure_png(fig, dpi=90), "3D view with paths and projections; rocker and transmission angles")
    close(fig)
    pfig = view.plotly_figure(run, frames=frames, units=units)
    return panels, view.html_fragment(pfig, include_plotlyjs=True, div_id="view3d")


def _spatial_sections(study: Study, run: Study, panels: str, view: str, units: str = "file") -> list[str]:
    plan = study.plan
    summary = study.as_dict(forces=False)
    return [section("Structure", structure_html(summary) + "\n" + joints_html(plan)),
            section("Parameters", parameters_html(plan) + "\n" + drivers_html(plan)),
            section("Analysis", analysis_html(study, units) + "\n" + dyads_html(study)),
            section("3D view and animation", '<p class="note">Drag to rotate, scroll to zoom; ▶ play animates '
                                             "the mechanism. Dotted: the paths projected on the coordinate "
                                             "planes (paper 003, Fig. 2–3).</p>\n" + view),
            section("Plots", panels),
            section("Positions", positions_html(run, 12, units))]


# -- the page ---------------------------------------------------------------------------------------
def build_report(plan, *, steps: int = CYCLE_STEPS, frames: int = 36, ranges=None, source: str | None = None,
                 units: str = "file", progress=None, at=None) -> str:
    """The report page of a compiled mechanism (planar or spatial) as one HTML string. ``steps``: samples
    of the turn (or of ``ranges``, one (start, stop) per input, SI) that the analysis, the figures and the
    animation's path share; ``frames``: positions of the animation; ``units``: lengths, speeds and
    accelerations in the file's length unit ('file') or in SI ('si'); ``progress(i, n)``: called per frame of
    a planar animation drawn; ``at``: inputs (SI) of the moving input where the page shows every instant centre."""
    from ..version import __version__
    spatial = plan.dimension == 3
    study = Study(plan, steps=steps)          # the analysis: the natural cycle
    run = study if ranges is None else Study(plan, steps=steps, ranges=ranges)   # what the figures draw
    try:
        draw = _spatial_figures if spatial else partial(_planar_figures, progress=progress)
        figures = draw(run, study.gait_curves if run is study else None, frames, units)
    except SpecError as exc:    # nothing to draw (a linear input without a stroke, no position assembles)
        note = f'<p class="note">no figures: {escape(exc)}</p>'
        figures = (note, note)
    if spatial:
        body = _spatial_sections(study, run, *figures, units)
    else:
        body = _planar_sections(study, run, *figures, units, at=at)
    m = plan.mechanism
    title = m.name or (Path(source).stem if source else "mechanism")
    kind = " — spatial (dimension = 3)" if spatial else ""
    meta = (f"{escape(source or '')}{kind} — units: length {escape(m.units.length)}, angle {escape(m.units.angle)} "
            f"— assur {escape(__version__)}")
    return page(title, header(title, meta, m.description) + body)


def write_report(plan, out_dir, *, steps: int = CYCLE_STEPS, frames: int = 36, ranges=None,
                 source: str | None = None, units: str = "file", progress=None, at=None) -> Path:
    """Write ``out_dir/index.html`` atomically (``io.output.atomic_directory``): on failure nothing is
    left behind. Returns the page's path. ``progress(i, n)``: called per animation frame drawn."""
    from ..io.output import atomic_directory
    with atomic_directory(out_dir) as tmp:
        page_text = build_report(plan, steps=steps, frames=frames, ranges=ranges, source=source, units=units,
                                 progress=progress, at=at)
        (tmp / "index.html").write_text(page_text, encoding="utf-8")
    return Path(out_dir) / "index.html"
