"""``assur report`` for design documents: a gear pair (assur-gears/1) or a wheel-step mover (assur-wheelstep/1).

The page (``out_dir/index.html``) is self-contained — summary tables, the figures as embedded PNG, an embedded
animation of the meshing pair — and links to the CAD files (DXF, SVG) and tables (CSV, JSON) written beside it by
the same pipeline as ``assur gears`` / ``assur wheelstep`` (:mod:`assur.report.bundles`). Everything is written
atomically.
"""
from __future__ import annotations

import json
import math
from pathlib import Path

from .page import escape, header, page, png_tag, section, table
from .text import mm_text


def _mesh_rows(label, s):
    fine = s.get("fine_scan") or {}
    where = fine.get("interference_driving_ranges") or s.get("interference_driving_ranges") or "—"
    return [label, "interferes" if s["interference"] else "runs clear", where if s["interference"] else "—",
            mm_text(max(s.get("max_penetration") or 0.0, fine.get("max_penetration") or 0.0), 3),
            f"{mm_text(s['backlash_min'], 3)} … {mm_text(s['backlash_max'], 3)}" if s["backlash_min"] is not None else "—",
            f"{s['actual_ratio_min']:.4f} … {s['actual_ratio_max']:.4f}" if s["actual_ratio_min"] is not None else "—",
            f"{100 * s['max_ratio_deviation']:.2f} %" if s["max_ratio_deviation"] is not None else "—"]


def _links(tmp: Path, prefix: str = "") -> str:
    files = sorted(p for p in tmp.rglob("*") if p.is_file() and p.suffix in (".dxf", ".svg", ".csv", ".json"))
    items = [f'<a href="{escape(p.relative_to(tmp).as_posix())}">{escape(p.relative_to(tmp).as_posix())}</a>'
             for p in files]
    return "<p>" + " · ".join(items) + "</p>"


def _png(tmp: Path, name: str, alt: str) -> str:
    p = tmp / name
    return png_tag(p.read_bytes(), alt) if p.exists() else ""


def _gears_html(s: dict, tmp: Path, rel: str, frames: int) -> str:
    body = []
    clo = s["closure"]
    rows = [["centre distance", mm_text(s["centre_distance"])],
            ["driving turns per driven turn", s["driving_turns"]],
            ["pitch perimeters", f"{mm_text(clo['driving_perimeter'])} / {mm_text(clo['driven_perimeter'])} "
                                 f"(ratio {clo['perimeter_ratio']:.6f})"],
            ["closure θ(2π·n)", f"{math.degrees(clo['law_end']):.6f}°"],
            ["speed ratio dθ/dφ", f"{s['ratio_range'][0]:.5f} … {s['ratio_range'][1]:.5f}"],
            ["design teeth", f"{s['teeth'][0]} / {s['teeth'][1]}, module {mm_text(s['module'], 3)}"]]
    for g, c in s["curvature"].items():
        for k in c["corners"]:
            rows.append([f"{g} corner", f"body angle {math.degrees(k['angle']):.2f}°, tangent jump "
                                        f"{math.degrees(k['tangent_jump']):+.2f}°"])
    body.append(section("Pitch curves", table(["quantity", "value"], rows) + _png(tmp, f"{rel}pitch.png",
                                                                                      "pitch curves")))
    env = s["envelope"]
    txt = (f"<p>Rack-cutter envelope along the exact pitch curves: module {mm_text(env['module'], 5)}, "
           f"{env['teeth'][0]} / {env['teeth'][1]} teeth.")
    if "envelope_rounding" in s:
        r = s["envelope_rounding"]
        txt += (f" The pitch-curve corners are rounded first (σ = {math.degrees(r['width']):.2f}° of the driving "
                f"angle): the speed law changes by up to {100 * r['max_speed_deviation']:.2f} %.")
    txt += "</p>" + "".join(f'<p class="note">{escape(n)}</p>' for n in env["notes"])
    mesh = [_mesh_rows("envelope teeth", env["mesh"])]
    if "sectors" in s:
        for L, m in s["sectors"]["mesh"].items():
            mesh.append(_mesh_rows(f"paper sector scheme, L = {L}", m))
    checks = table(["outlines", "verdict", "where (driving angle)", "max penetration", "backlash",
                    "transmitted ratio", "max ratio deviation"], mesh)
    body.append(section("Teeth and mesh check", txt + checks + _png(tmp, f"{rel}teeth_envelope.png", "teeth")
                         + _png(tmp, f"{rel}speed_envelope.png", "speed law")))
    if "sectors" in s:
        sc = s["sectors"]
        rows = [["sector arc s", mm_text(sc["arc"], 6)],
                ["radial steps > 2m", ", ".join(f"{a}–{b}" for a, b in sc["steps_exceeding_2m"]) or "none"],
                ["working pressure angle", f"{math.degrees(sc['working_pressure_angle']):.3f}°"],
                ["mover speed / nominal (sector ratio)", f"{sc['speed_ripple_sector'][0]:.4f} … "
                                                         f"{sc['speed_ripple_sector'][1]:.4f}"],
                ["mover speed / nominal (involute pairs)", f"{sc['speed_ripple_involute'][0]:.4f} … "
                                                           f"{sc['speed_ripple_involute'][1]:.4f}"]]
        t1 = json.loads((tmp / f"{rel}table1.json").read_text(encoding="utf-8"))
        cells = [[f"{int(r[0])}"] + [f"{v:.2f}" for v in r[1:]] for r in t1["rows"]]
        t1_html = (f"<h3>{escape(t1['title'])}</h3>" + '<div class="scroll">'
                   + table(t1["columns"], cells, num_cols=tuple(range(len(t1["columns"])))) + "</div>")
        body.append(section("Paper sector scheme (reproduction mode)",
                             table(["quantity", "value"], rows) + t1_html
                             + _png(tmp, f"{rel}teeth_sectors.png", "sectors")
                             + _png(tmp, f"{rel}speed_sectors.png", "sector speed")))
    res = s["_results"]
    gt, cut_on, rep = res["envelope"]
    from ..plot.animation import jshtml
    from ..plot.draw import close
    from ..plot.gears import mesh_animation
    from .bundles import _plot_outline
    m = gt.tooth.module
    fig, anim = mesh_animation(_plot_outline(gt.driving.xy, m, 0.05), _plot_outline(gt.driven.xy, m, 0.05), cut_on,
                               frames=frames, report=rep)
    import matplotlib
    with matplotlib.rc_context({"animation.embed_limit": 60.0}):
        js = jshtml(anim, fps=12)
    close(fig)
    body.append(section("Animation of the meshing pair (envelope teeth)", js))
    body.append(section("Files", _links(tmp / rel) if rel else _links(tmp)))
    return "\n".join(body)


def build_document_page(design, s: dict, tmp: Path, *, frames: int = 36, source: str = "") -> str:
    from ..version import __version__
    from ..gears.design import GearDesign
    title = design.name or Path(source).stem
    body = header(title, f"{escape(source)} — assur {escape(__version__)}", design.description)
    if isinstance(design, GearDesign):
        body.append(_gears_html(s, tmp, "", frames))
    else:
        rows = [["a, b, c", f"{s['a']:g} m, {s['b']:g} m, {s['c']:.6g} m"],
                ["R_min = a − 4b + c (eq. 9)", f"{s['r_min']:.6g} m"],
                ["X_I = 6b (eq. 5)", f"{s['X_I']:.4f} m"],
                ["X_II = (a − b + c)·π/2 − 3b (eq. 6 corrected)", f"{s['X_II']:.4f} m"],
                ["X_II by eq. (10)", f"{s['X_II_eq10']:.4f} m"],
                ["X_01 = X_I + X_II (eq. 4)", f"{s['X_01']:.4f} m"],
                ["rolling share", f"{100 * s['rolling_share']:.2f} %"]]
        body.append(section("Support shoe and displacement budget", table(["quantity", "value"], rows)
                             + _png(tmp, "shoe.png", "shoe profile")))
        if "gears" in s:
            body.append(section("Gear drive", ""))
            body.append(_gears_html(s["gears"], tmp, "gears/", frames))
        else:
            body.append(section("Files", _links(tmp)))
    return page(title, body)


def write_document_report(path, out_dir, *, frames: int = 36, mesh_steps: int = 180) -> Path:
    """Write ``out_dir/index.html`` and the CAD/table files of the design document ``path`` (a gear pair or a
    wheel-step mover) atomically; returns the page's path."""
    from .bundles import run_gears, run_wheelstep
    from ..gears.design import GearDesign
    from ..io.gear_file import load_design
    from ..io.output import atomic_directory
    design = load_design(path)
    runner = run_gears if isinstance(design, GearDesign) else run_wheelstep
    with atomic_directory(out_dir) as tmp:
        tmp = Path(tmp)
        s = runner(design, tmp, mesh_steps=mesh_steps, log=lambda _: None)
        page = build_document_page(design, s, tmp, frames=frames, source=str(path))
        (tmp / "index.html").write_text(page, encoding="utf-8")
    return Path(out_dir) / "index.html"


__all__ = ["build_document_page", "write_document_report"]
