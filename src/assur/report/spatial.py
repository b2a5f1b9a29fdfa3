"""The report page of a spatial (dimension = 3) mechanism: structure, parameters, the dyads'
branch, swing, transmission angles and dead centres, an interactive 3D view with its animation
(plotly, plotly.js inlined: the page opens without network access), the static figure and a
table of positions. Built by :func:`assur.report.html.build_report` for spatial plans.
"""
from __future__ import annotations

from pathlib import Path

from ..errors import SpecError


def joints_html(plan) -> str:
    from .html import _num, _table
    rows = []
    for j in plan.mechanism.joints:
        ax = "" if j.axis is None else "[" + ", ".join(_num(c, 6) for c in j.axis) + "]"
        rows.append((j.point, j.kind, ax))
    return _table(["point", "joint", "axis (revolute; pin of a universal joint)"], rows)


def dyads_html(summary: dict) -> str:
    from .html import _deg, _e, _table
    parts = []
    for s in summary.get("dyads", []):
        w = ", ".join(f"{v:+.0f}" for v in s["paper_w"]) or "undefined (V3_X = 0)"
        rows = [("assembly branch s = sign det[A − D, e, B − D]", f"{s['branch_s']:+d}"),
                ("the paper's W of eq. (21) (= s·sign V3_X)", w),
                ("V3_X changes sign over the turn (a fixed W would jump)", "yes" if s["v3x_changes_sign"] else "no"),
                ("rocker angle θ4 min", _deg(s["rocker_angle_min"], 4)),
                ("rocker angle θ4 max", _deg(s["rocker_angle_max"], 4)),
                ("rocker swing", _deg(s["swing"], 4)),
                ("transmission angle μ_int min … max", f"{_deg(s['mu_int_min'], 3)} … {_deg(s['mu_int_max'], 3)}"),
                ("effective transmission angle μ_T min … max",
                 f"{_deg(s['mu_t_min'], 3)} … {_deg(s['mu_t_max'], 3)}")]
        rows += [(f"dead centre ({c['kind']})", f"crank {_deg(c['angle'], 6)}, θ4 = {_deg(c['rocker_angle'], 4)}")
                 for c in s["dead_centres"]]
        parts.append(f"<h3>Dyad solving {_e(s['point'])} (rocker {_e(s['rocker'])}, coupler {_e(s['coupler'])})</h3>")
        parts.append(_table(["quantity", "value"], rows, num_cols=(1,)))
    return "\n".join(parts)


def figures_html(plan, steps: int, frames: int, ranges=None) -> tuple[str, str]:
    """(static figure as PNG, interactive 3D view with its animation) as HTML."""
    from ..plot import spatial as view
    from ..plot.figures import close, figure_png
    from .html import _e, _png_tag
    try:
        fig = view.figure(plan, steps, ranges=ranges)
    except SpecError as exc:
        note = f'<p class="note">no figures: {_e(exc)}</p>'
        return note, note
    panels = _png_tag(figure_png(fig, dpi=90), "3D view with paths and projections; rocker and transmission angles")
    close(fig)
    pfig = view.plotly_figure(plan, steps, frames=frames, ranges=ranges)
    return panels, view.html_fragment(pfig, include_plotlyjs=True, div_id="view3d")


def build_spatial_report(plan, *, steps: int = 360, frames: int = 36, ranges=None, source: str | None = None) -> str:
    from .. import __version__
    from ..analysis.spatial import analyze_spatial
    from .html import _CSS, _e, _section, analysis_html, drivers_html, parameters_html, positions_html, structure_html
    m = plan.mechanism
    summary = analyze_spatial(plan, steps=steps)
    title = m.name or (Path(source).stem if source else "mechanism")
    panels, view = figures_html(plan, steps, frames, ranges)
    body = [f"<h1>{_e(title)}</h1>",
            f'<p class="meta">{_e(source or "")} — spatial (dimension = 3) — units: length {_e(m.units.length)}, '
            f"angle {_e(m.units.angle)} — assur {_e(__version__)}</p>"]
    if m.description.strip():
        body.append(f'<div class="desc">{_e(m.description.strip())}</div>')
    body.append(_section("Structure", structure_html(summary) + "\n" + joints_html(plan)))
    body.append(_section("Parameters", parameters_html(plan) + "\n" + drivers_html(plan)))
    body.append(_section("Analysis", analysis_html(summary, plan) + "\n" + dyads_html(summary)))
    body.append(_section("3D view and animation", '<p class="note">Drag to rotate, scroll to zoom; ▶ play animates '
                                                  "the mechanism. Dotted: the paths projected on the coordinate "
                                                  "planes (paper 003, Fig. 2–3).</p>\n" + view))
    body.append(_section("Plots", panels))
    body.append(_section("Positions", positions_html(plan, 12, ranges)))
    return ("<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n"
            f"<meta name=\"viewport\" content=\"width=device-width, initial-scale=1\">\n<title>{_e(title)}</title>\n"
            f"<style>{_CSS}</style>\n</head>\n<body>\n" + "\n".join(body) + "\n</body>\n</html>\n")


__all__ = ["build_spatial_report"]
