"""``assur cam FILE``: a mechanism's cam pair — its law (continuity, SVAJ peaks), its profile's checks (base and prime
circles, pressure angle, radii of curvature, undercut), the smallest base circle for its pressure-angle limit, and its
figure, DXF or SVG profile (mm) or JSON (docs/cams.md)."""
from __future__ import annotations

import math

import numpy as np

from ..errors import SpecError
from ..io.output import atomic_file
from .args import compile_file, output_path

EXTENSIONS = (".png", ".svg", ".pdf", ".dxf", ".json")


def register(sub) -> None:
    help_ = "a mechanism's cam pair: law continuity and SVAJ, profile, pressure angle, curvature, sizing; DXF/SVG"
    sp = sub.add_parser("cam", help=help_, description=help_)
    sp.add_argument("file", metavar="FILE", help="mechanism file (.toml) with [[cams]]")
    sp.add_argument("--name", metavar="CAM", help="the cam pair (default: the first)")
    sp.add_argument("-o", "--output", type=output_path(EXTENSIONS), metavar="OUT",
                    help="the figure (.png, .pdf), the profile in mm (.dxf, .svg: the profile and its pitch curve) or "
                         "the summary (.json)")
    sp.add_argument("--json", action="store_true", help="print one JSON object (SI units)")
    sp.set_defaults(func=cmd_cam)


def cam_summary(plan, geometry) -> dict:
    """The JSON-ready checks of one cam pair (SI)."""
    from ..cams.laws import continuity, peaks
    from ..cams.sizing import base_circle
    g = geometry
    speed = abs(float(plan.speeds[0])) if plan.n_inputs else None
    s = g.summary()
    c = continuity(g.law)
    out = {"name": g.name, "follower": {"motion": g.motion, "contact": g.contact, "roller_radius": g.roller_radius},
           "law": {"kind": g.law.kind, "continuous": {"s": c.smooth >= 0, "v": c.smooth >= 1, "a": c.smooth >= 2,
                                                       "j": c.smooth >= 3},
                   "fundamental_law": c.ok, "findings": c.findings(),
                   "peaks_per_rad": {k: v for k, v in peaks(g.law).items() if not k.endswith("_at")}}}
    if speed:
        out["law"]["peaks_at_speed"] = {k: v for k, v in peaks(g.law, speed=speed).items() if not k.endswith("_at")}
    out["profile"] = s
    try:
        if g.motion == "translating":
            d = g.direction
            offset = float(np.imag(np.conj(d) * (g.trace - g.pivot)))
            rb = base_circle(g.law, contact=g.contact, roller_radius=g.roller_radius, offset=offset,
                             max_pressure_angle=None if g.contact == "flat" else g.pressure_limit,
                             min_curvature=1e-9 if g.contact == "flat" else None, samples=1440, rtol=1e-6)
        else:
            rb = base_circle(g.law, motion="oscillating", contact=g.contact, roller_radius=g.roller_radius,
                             pivot_distance=abs(g.follower_pivot - g.pivot), arm_length=abs(g.trace - g.follower_pivot),
                             max_pressure_angle=None if g.contact == "flat" else g.pressure_limit,
                             min_curvature=1e-9 if g.contact == "flat" else None, samples=1440, rtol=1e-6)
        out["smallest_base_radius"] = rb
    except SpecError as exc:
        out["smallest_base_radius"] = None
        out["sizing_note"] = str(exc)
    return out


def cmd_cam(args) -> int:
    from ..cams.followers import from_plan
    from ..io.output import json_text
    m, plan = compile_file(args.file)
    if not m.cams:
        raise SpecError([("cams", f"{args.file} has no [[cams]]")])
    g = from_plan(plan, args.name if args.name is not None else 0)
    summary = cam_summary(plan, g)
    if args.json:
        print(json_text(summary))
    else:
        for line in summary_lines(summary):
            print(line)
    if args.output:
        _write(args, plan, g, summary)
    return 0


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


def _write(args, plan, g, summary):
    ext = args.output.suffix.lower()
    if ext in (".dxf", ".svg"):
        from ..cams.outline import write_profile
        write_profile(args.output, g)
    elif ext == ".json":
        from ..io.output import json_text
        with atomic_file(args.output) as tmp:
            tmp.write_text(json_text(summary) + "\n", encoding="utf-8")
    else:
        from ..plot.cams import cam_figure
        from ..plot.draw import close
        fig = cam_figure(g, speed=abs(float(plan.speeds[0])) if plan.n_inputs else None, title=g.name)
        try:
            with atomic_file(args.output) as tmp:
                fig.savefig(tmp, format=ext[1:])
        finally:
            close(fig)
    print(f"wrote {args.output}")
