"""A mechanism's cam pairs on the report page and in ``assur cam``'s text (mm and degrees)."""
from __future__ import annotations

import math

from .page import escape, png_tag


def summary_lines(s: dict) -> list[str]:
    """The text form of :func:`cam_summary` (mm and degrees)."""
    f = s["follower"]
    law, p = s["law"], s["profile"]
    out = [f"cam {s['name']}: {f['motion']} {f['contact']} follower"
           + (f", roller {f['roller_radius'] * 1e3:g} mm" if f["contact"] == "roller" else "")]
    cont = "s, v, a continuous: the fundamental law of cam design holds" if law["fundamental_law"] else \
        "breaks the fundamental law of cam design: " + "; ".join(law["findings"])
    out.append(f"  law ({law['kind']}): {cont}")
    unit = "°" if f["motion"] == "oscillating" else "mm"
    k = math.degrees(1) if unit == "°" else 1e3
    pk = law.get("peaks_at_speed") or law["peaks_per_rad"]
    per = "/s" if "peaks_at_speed" in law else "/rad"
    out.append(f"  stroke {pk['stroke'] * k:.4g} {unit}; peak velocity {pk['v'] * k:.4g} {unit}{per}, acceleration "
               f"{pk['a'] * k:.4g} {unit}{per}², jerk {pk['j'] * k:.4g} {unit}{per}³")
    out.append(f"  base circle {p['base_radius'] * 1e3:.4g} mm, prime circle {p['prime_radius'] * 1e3:.4g} mm")
    ok = "within" if p["pressure_ok"] else "ABOVE"
    out.append(f"  largest pressure angle {math.degrees(p['pressure_angle_max']):.4g}° at {math.degrees(p['pressure_angle_at']):.4g}° "
               f"of the law ({ok} the limit {math.degrees(p['pressure_limit']):.4g}°)")
    rho = p["min_profile_radius"]
    out.append("  smallest convex radius of curvature " + ("none" if rho is None else f"{rho * 1e3:.4g} mm")
               + ("" if p["min_concave_radius"] is None else f"; concave down to {p['min_concave_radius'] * 1e3:.4g} mm "
                  "(the largest milling cutter)"))
    if p["roller_radius_limit"] is not None:
        out.append(f"  a roller up to {p['roller_radius_limit'] * 1e3:.4g} mm does not undercut"
                   + (": UNDERCUT" if p["undercut"] else ""))
    elif p["undercut"]:
        out.append("  the profile is undercut (not convex under a flat face)")
    if s.get("smallest_base_radius") is not None:
        out.append(f"  the smallest base circle for this follower and limit: {s['smallest_base_radius'] * 1e3:.4g} mm")
    return out


def cams_html(study) -> str:
    """The report's section: each cam pair's checks and its figure (law, profile, pressure angle, curvature)."""
    from ..cams.summary import cam_summary
    from ..plot.cams import cam_figure
    from ..plot.draw import close, figure_png
    plan = study.plan
    parts = []
    for name, g in study.cams.items():
        s = cam_summary(plan, g)
        parts.append(f"<h3>Cam pair {escape(name)}</h3>")
        parts.append("<p>" + "<br>".join(escape(line.strip()) for line in summary_lines(s)) + "</p>")
        fig = cam_figure(g, speed=abs(float(plan.speeds[0])) if plan.n_inputs else None, title=name)
        parts.append(png_tag(figure_png(fig, dpi=80), f"cam {name}: law, profile, pressure angle, curvature"))
        close(fig)
    return "\n".join(parts)
