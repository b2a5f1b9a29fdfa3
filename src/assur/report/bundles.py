"""The outputs of a gear-pair design (``assur gears``) and of a wheel-step mover (``assur wheelstep``), written
into a directory; the report of a design document (:mod:`assur.report.documents`) shows them.

:func:`run_gears` writes, for a gear-pair design (format assur-gears/1):

- ``pitch.csv/json``: φ, θ, k = dθ/dφ, r1, r2 over the cycle; ``summary.json``: everything logged;
- envelope teeth (rack-cutter envelope along the exact pitch curves, :mod:`assur.gears.teeth`; the recommended
  outlines for manufacture): ``envelope_driving.dxf/.svg``, ``envelope_driven.dxf/.svg`` (each gear centred at
  its own origin), ``envelope_pair.dxf/.svg`` (assembled at φ = 0), ``envelope_*_outline.csv`` (x, y in mm),
  ``envelope_mesh.json``, ``envelope_mesh.html`` (animation of the meshing pair); where the pitch curves have
  corners (a rack cannot cut them) the law is rounded first (:func:`assur.gears.teeth.rounded_pair`) and the
  change of the speed law is reported;
- for ``teeth.method = "sectors"`` (the paper's scheme, reproduction mode) also ``table1/2/3.csv/json``, the
  sector outlines ``sectors_*.dxf/.svg`` (relieved linking lines) and ``sectors_mesh.json`` at the design and the
  installation centre distance;
- plots ``pitch.png``, ``teeth_envelope.png``, ``speed_envelope.png`` (and ``teeth_sectors.png``,
  ``speed_sectors.png``).

:func:`run_wheelstep` writes the shoe profile table, the displacement budget and ``shoe.png``, plus the gear
outputs of its drive in ``gears/``.
"""
from __future__ import annotations

import dataclasses
import math
from pathlib import Path

import numpy as np

from ..tolerances import DEFAULT as TOL
from .text import MM, mesh_text

DEG = 180.0 / math.pi
#: rack states per tooth pitch for the envelope teeth of ``assur gears`` (see docs/gears.md: the outline then stays
#: within 1 µm of the one cut with 256 states per pitch on the paper's pair)
STATES_PER_TOOTH = 64


def _shapes_pair(name, xy1, xy2, pair, references=True, bore=None):
    from ..io.cad import Shape
    L = pair.centre_distance
    th0 = float(pair.law(0.0))
    c, s = math.cos(-th0), math.sin(-th0)
    placed = np.stack([L + c * xy2[:, 0] - s * xy2[:, 1], s * xy2[:, 0] + c * xy2[:, 1]], axis=-1)
    r1 = (pair.driving.xy(2048),) if references else ()
    p2 = pair.driven.xy(4096)
    r2 = (np.stack([L + c * p2[:, 0] - s * p2[:, 1], s * p2[:, 0] + c * p2[:, 1]], axis=-1),) if references else ()
    return [Shape(f"{name}_driving", xy1, (0.0, 0.0), r1, bore=bore),
            Shape(f"{name}_driven", placed, (L, 0.0), r2, bore=bore)]


def _manufacturing(design) -> dict:
    """Face width and bore of a design (mm; "not given" when absent), for the file headers."""
    return {"face_width_mm": design.face_width * MM if design.face_width else "not given",
            "bore_mm": design.bore * MM if design.bore else "not given"}


def _write_outlines(tmp: Path, prefix: str, xy1, xy2, pair, meta: dict, bore=None):
    from ..io.cad import Shape, write_dxf, write_outline_csv, write_svg
    files = []
    for gear, xy, curve in (("driving", xy1, pair.driving), ("driven", xy2, pair.driven)):
        shape = [Shape(f"{prefix}_{gear}", xy, (0.0, 0.0), (curve.xy(4096),), bore=bore)]
        m = {**meta, "gear": gear, "points": int(len(xy)),
             "handedness": "counter-clockwise outline; the driving gear turns ccw, the driven cw"}
        files.append(write_dxf(tmp / f"{prefix}_{gear}.dxf", shape, metadata=m))
        files.append(write_svg(tmp / f"{prefix}_{gear}.svg", shape, metadata=m))
        files.append(write_outline_csv(tmp / f"{prefix}_{gear}_outline.csv", xy, comments={
            "gear": f"{prefix} {gear}", "face width [mm]": meta.get("face_width_mm", "not given"),
            "bore [mm]": meta.get("bore_mm", "not given"), "units": "mm, counter-clockwise closed outline"}))
    pair_shapes = _shapes_pair(prefix, xy1, xy2, pair, bore=bore)
    files.append(write_dxf(tmp / f"{prefix}_pair.dxf", pair_shapes, metadata={**meta, "assembly": "phi = 0"}))
    files.append(write_svg(tmp / f"{prefix}_pair.svg", pair_shapes, metadata={**meta, "assembly": "phi = 0"}))
    return files


def _mesh_json(rep, pair):
    s = rep.summary()
    out = {k: v for k, v in s.items()}
    out["centre_distance"] = pair.centre_distance
    return out


def _design_key(design, *options):
    """The content of a gear design (every field that changes an output) and the run's options, as a key."""
    fields = [(f.name, repr(getattr(design, f.name))) for f in dataclasses.fields(design)
              if f.name not in ("law", "_cache", "source")]
    return repr((fields, options))


#: in-process cache of computed gear bundles: key → (files {relative path: bytes}, summary, results, log lines)
_CACHE: dict = {}
_CACHE_SIZE = 4


def run_gears(design, tmp: Path, *, mesh_steps: int = 360, figures: bool = True, log=print,
              frames: int = 0, progress=None) -> dict:
    """All outputs of a gear design into the directory ``tmp``; returns the summary (SI units, rad).

    The computed bundle (files, summary, results) is kept in memory keyed by the design's content and the
    options, so the same design run again in this process (``assur wheelstep`` after ``assur gears``, the report,
    the tests) writes the same files without recomputing them. ``progress(text)``: told as each slow step starts."""
    import copy
    key = _design_key(design, mesh_steps, figures, frames)
    hit = _CACHE.get(key)
    if hit is None:
        lines = []

        def both(text):
            lines.append(text)
            log(text)
        before = {p for p in tmp.rglob("*")}
        summary = _compute_gears(design, tmp, mesh_steps=mesh_steps, figures=figures, log=both, frames=frames,
                                 progress=progress or (lambda _: None))
        files = {p.relative_to(tmp).as_posix(): p.read_bytes() for p in sorted(tmp.rglob("*"))
                 if p.is_file() and p not in before}
        results = summary.pop("_results")
        while len(_CACHE) >= _CACHE_SIZE:
            _CACHE.pop(next(iter(_CACHE)))
        _CACHE[key] = (files, copy.deepcopy(summary), results, lines)
        summary["_results"] = results
        return summary
    files, summary, results, lines = hit
    for text in lines:
        log(text)
    for rel, data in files.items():
        (tmp / rel).parent.mkdir(parents=True, exist_ok=True)
        (tmp / rel).write_bytes(data)
    summary = copy.deepcopy(summary)
    summary["_results"] = results
    return summary


def _plot_outline(xy, module, within: float = 0.01):
    """An outline thinned for drawing, within ``within``·module (the figures' zoom: 1 %, 0.02 mm for m = 2 mm, a
    fraction of its pixel; the animation at 72 dpi, ~0.6 mm a pixel: 5 %): thousands of points fewer to draw."""
    import shapely
    g = shapely.simplify(shapely.Polygon(xy), within * module, preserve_topology=True)
    return np.asarray(g.exterior.coords)[:-1] if g.geom_type == "Polygon" and not g.is_empty else xy


def _mesh_polygon(xy, rays):
    """The outline itself for the mesh check when it is a simple polygon, else its polar form (the nearest
    crossing on ``rays`` rays from the centre: the material seen from the centre)."""
    import shapely
    from ..gears.mesh import polar_outline
    return polar_outline(xy, rays=rays)


def _fine_ranges(corners_phi, offsets, bad, period):
    """Interference ranges (text) of a fine scan made of one block of driving angles per corner (corner +
    offsets): runs are taken within each block, never across blocks."""
    from ..kernels.runs import runs
    parts = []
    blocks = bad.reshape(len(corners_phi), len(offsets))
    for c, row in sorted(zip(np.mod(corners_phi, period), blocks), key=lambda x: x[0]):
        for s, e in runs(row):
            parts.append(f"[{math.degrees(np.mod(c + offsets[s], period)):.1f}°, "
                         f"{math.degrees(np.mod(c + offsets[e], period)):.1f}°]")
    return ", ".join(parts)


def _compute_gears(design, tmp: Path, *, mesh_steps: int, figures: bool, log, frames: int, progress) -> dict:
    from ..gears.mesh import mesh_check
    from ..gears.pitch import closure_report, curvature_report
    from ..gears.teeth import cut_pair, rounded_pair
    from ..io.cad import write_json, write_table
    pair = design.pair()
    n = pair.driving_turns
    clo = closure_report(pair)
    summary = {"name": design.name, "method": design.method, "centre_distance": pair.centre_distance,
               "installation_distance": design.installation_distance, "driving_turns": n,
               "closure": dataclasses.asdict(clo), "module": design.module,
               "pressure_angle": design.pressure_angle, "backlash": design.backlash,
               "teeth": [design.driving_teeth, design.driven_teeth]}
    log(f"{design.name or 'gear pair'}: centre distance {pair.centre_distance * MM:.4f} mm, driving turns {n} "
        f"per driven turn")
    log(f"pitch perimeters: driving {clo.driving_perimeter * MM:.4f} mm, driven {clo.driven_perimeter * MM:.4f} mm "
        f"(ratio {clo.perimeter_ratio:.6f}, must be {n}); closure: θ(2π·{n}) = {math.degrees(clo.law_end):.6f}°, "
        f"max |r1 + r2 − L| = {clo.centre_distance_error * MM:.2e} mm")
    # pitch table
    phi = np.linspace(0.0, 2 * math.pi * n, 721 * n)[:-1] if n else None
    r1, r2 = pair.contact_radii(phi)
    k = pair.ratio(phi)
    write_table(tmp / "pitch", ["phi [deg]", "theta [deg]", "k = dtheta/dphi", "r1 [mm]", "r2 [mm]"],
                np.column_stack([phi * DEG, pair.law(phi) * DEG, k, r1 * MM, r2 * MM]).tolist(),
                meta={"title": "pitch curves at the contact point over the cycle"})
    summary["ratio_range"] = [float(k.min()), float(k.max())]
    log(f"speed ratio dθ/dφ: {k.min():.5f} … {k.max():.5f}")
    curv = {}
    for name, curve in (("driving", pair.driving), ("driven", pair.driven)):
        rep = curvature_report(curve, module=design.module, pressure_angle=design.pressure_angle)
        curv[name] = {"corners": [dataclasses.asdict(c) for c in rep.corners],
                      "min_convex_radius": rep.min_convex_radius, "concave_ranges": rep.concave_ranges,
                      "min_concave_radius": rep.min_concave_radius, "undercut_ranges": rep.undercut_ranges}
        for c in rep.corners:
            log(f"{name} pitch curve: {c.kind} corner at body angle {math.degrees(c.angle):.2f}°, tangent jump "
                f"{math.degrees(c.tangent_jump):+.2f}°")
    summary["curvature"] = curv
    meta = {"design": design.name, "units": "mm", "centre_distance_mm": pair.centre_distance * MM,
            "driving_turns": n}
    figs = {}

    # ---- envelope teeth (recommended for manufacture) ----------------------------------------------------
    z1 = design.driving_teeth
    corners = any(curv[g]["corners"] for g in curv)
    if corners:
        m0 = pair.driving.perimeter / (math.pi * z1)
        cut_on, width = rounded_pair(pair, m0, design.pressure_angle)
        ph = np.linspace(0, 2 * math.pi * n, 4001)
        dev = cut_on.ratio(ph) / pair.ratio(ph) - 1
        summary["envelope_rounding"] = {"width": width, "max_speed_deviation": float(np.max(np.abs(dev))),
                                        "max_theta_deviation": float(np.max(np.abs(cut_on.law(ph) - pair.law(ph))))}
        log(f"envelope teeth: the pitch-curve corners are rounded (Gaussian smoothing of k over σ = "
            f"{math.degrees(width):.2f}° of φ near each corner): the speed law changes by up to "
            f"{100 * np.max(np.abs(dev)):.2f} %, θ by up to {math.degrees(summary['envelope_rounding']['max_theta_deviation']):.3f}°")
    else:
        cut_on = pair
    module = design.module if (design.method == "envelope" and not corners) else None
    progress("cutting the envelope teeth")
    gt = cut_pair(cut_on, module=module, teeth=z1, pressure_angle=design.pressure_angle,
                  addendum=design.addendum, clearance=design.clearance, backlash=design.backlash,
                  tip_radius=design.tip_radius, profile_shift=design.profile_shift,
                  print_clearance=design.print_clearance, states_per_tooth=STATES_PER_TOOTH)
    m = gt.tooth.module
    if design.method != "envelope" or corners:
        log(f"envelope teeth: module {m * MM:.5f} mm = driving perimeter / (π·{z1}) (the design's "
            f"{design.module * MM:g} mm would need {cut_on.driving.perimeter / (math.pi * design.module):.3f} teeth)")
    for note in gt.notes:
        log("envelope teeth: " + note)
    env_meta = {**meta, "method": "rack-cutter envelope", "module_mm": m * MM,
                "pressure_angle_deg": math.degrees(design.pressure_angle), "backlash_mm": design.backlash * MM,
                "addendum": design.addendum, "clearance": design.clearance,
                "tip_radius": design.tip_radius, "profile_shift": design.profile_shift,
                "print_clearance_mm": design.print_clearance * MM,
                "teeth_driving": gt.driving.teeth, "teeth_driven": gt.driven.teeth, **_manufacturing(design)}
    progress("writing the envelope outlines (DXF, SVG, CSV)")
    _write_outlines(tmp, "envelope", gt.driving.xy, gt.driven.xy, cut_on, env_meta, bore=design.bore)
    progress("mesh check of the envelope teeth")
    rep = mesh_check(gt.driving, gt.driven, cut_on, steps=mesh_steps)
    ms = _mesh_json(rep, cut_on)
    write_json(tmp / "envelope_mesh.json", ms)
    summary["envelope"] = {"module": m, "teeth": [gt.driving.teeth, gt.driven.teeth], "notes": list(gt.notes),
                           "undercut_driving": gt.driving.undercut_text, "undercut_driven": gt.driven.undercut_text,
                           "mesh": ms}
    log(mesh_text(ms, "envelope teeth"))
    results = {"pair": pair, "envelope": (gt, cut_on, rep)}

    # ---- the paper's sector scheme (reproduction mode) --------------------------------------------------
    if design.method == "sectors":
        from ..gears.sectors import sector_findings, sector_outline, table1, table2, table3
        model = design.sector_model()
        for base, tab in (("table1", table1(model, design.module)),
                          ("table2", table2(model, design.module, design.backlash)),
                          ("table3", table3(model, design.module, design.backlash))):
            head = [f"{c} [{u}]" if u else c for c, u in zip(tab.columns, tab.units)]
            write_table(tmp / base, head, tab.data.tolist(), meta={"title": tab.title})
        f = sector_findings(model, design.law, design.module)
        summary["sectors"] = {"arc": model.arc, "steps_exceeding_2m": [list(p) for p in f.steps_exceeding],
                              "working_pressure_angle": f.working_pressure_angle,
                              "speed_ripple_sector": list(f.speed_ripple_sector),
                              "speed_ripple_involute": list(f.speed_ripple_involute)}
        log(f"sector scheme: {model.n_sectors} sectors of arc s = {model.arc * MM:.6f} mm; radial steps > 2m at "
            f"sectors {', '.join(f'{a}–{b}' for a, b in f.steps_exceeding) or 'none'}; mover speed ripple "
            f"{f.speed_ripple_sector[0]:.4f}…{f.speed_ripple_sector[1]:.4f} (sector ratio), "
            f"{f.speed_ripple_involute[0]:.4f}…{f.speed_ripple_involute[1]:.4f} (involute pairs)")
        so = sector_outline(model, design.module, design.backlash, linking="relieved", dedendum=design.dedendum)
        sec_meta = {**meta, "method": "paper sector scheme (eqs. 11-14), relieved linking lines",
                    "module_mm": design.module * MM, "backlash_mm": design.backlash * MM,
                    "teeth_driving": so.teeth[0], "teeth_driven": so.teeth[1], **_manufacturing(design)}
        progress("writing the sector-scheme outlines")
        _write_outlines(tmp, "sectors", so.driving, so.driven, pair, sec_meta, bore=design.bore)
        p1 = _mesh_polygon(so.driving, 512 * so.teeth[0])
        p2 = _mesh_polygon(so.driven, 512 * so.teeth[1])
        summary["sectors"]["mesh"] = {}
        reps = {}
        distances = [design.centre_distance]
        if abs(design.installation_distance - design.centre_distance) > TOL.distinct_distance * design.centre_distance:
            distances.append(design.installation_distance)
        # the step boundaries (the driving curve's corners) are where the scheme is tight: scan ±12° around
        # each at 0.25° besides the coarse cycle (docs/papers/001.md B6.9)
        phi_c = np.unique(np.round(np.mod([-c["angle"] for c in curv["driving"]["corners"]], 2 * math.pi), 9))
        offsets = np.radians(np.arange(-12.0, 12.01, 0.25))
        fine = (phi_c[:, None] + offsets[None, :]).ravel()
        for L in distances:
            progress(f"mesh check of the sector scheme at L = {L * MM:g} mm")
            at = dataclasses.replace(pair, centre_distance=L)
            r = mesh_check(p1, p2, at, steps=mesh_steps, pitch=math.pi * design.module)
            js = _mesh_json(r, at)
            if fine.size:
                rf = mesh_check(p1, p2, at, phi=fine, pitch=math.pi * design.module, ratio_window=0)
                js["fine_scan"] = {"driving_angles": "±12° around the step boundaries φ = " + ", ".join(
                    f"{math.degrees(a):.1f}°" for a in phi_c) + ", every 0.25°",
                    "interference_driving_ranges": _fine_ranges(phi_c, offsets, rf.interferes, 2 * math.pi * n),
                    "max_penetration": float(rf.penetration[rf.interferes].max()) if rf.any_interference else 0.0}
                if rf.any_interference:
                    js["interference"] = True
            summary["sectors"]["mesh"][f"{L * MM:g} mm"] = js
            reps[L] = r
            log(mesh_text(js, f"sector scheme at L = {L * MM:g} mm"))
        write_json(tmp / "sectors_mesh.json", summary["sectors"]["mesh"])
        results["sectors"] = (so, reps)

    if figures:
        progress("plots")
        from ..plot.draw import close, figure_png
        from ..plot.gears import pitch_figure, speed_figure, teeth_figure
        fig = pitch_figure(pair, title=f"pitch curves, L = {pair.centre_distance * MM:.2f} mm")
        figs["pitch.png"] = fig
        d1, d2 = _plot_outline(gt.driving.xy, m), _plot_outline(gt.driven.xy, m)
        figs["teeth_envelope.png"] = teeth_figure(d1, d2, cut_on, title=f"envelope teeth, m = {m * MM:.4f} mm")
        ref = (np.linspace(0, 2 * math.pi * n, 2001), pair.ratio(np.linspace(0, 2 * math.pi * n, 2001)))
        figs["speed_envelope.png"] = speed_figure(rep, law_name="law (rounded)" if corners else "law",
                                                  reference=ref if corners else None)
        if "sectors" in results:
            so, reps = results["sectors"]
            figs["teeth_sectors.png"] = teeth_figure(_plot_outline(so.driving, design.module),
                                                     _plot_outline(so.driven, design.module), pair,
                                                     title="paper sector scheme")
            figs["speed_sectors.png"] = speed_figure(reps[design.centre_distance], law_name="law")
        for name, fig in figs.items():
            (tmp / name).write_bytes(figure_png(fig, dpi=100))
            close(fig)
        if frames:
            progress(f"animation ({frames} frames)")
            from ..plot.animation import save_animation
            from ..plot.gears import mesh_animation
            a1, a2 = _plot_outline(gt.driving.xy, m, 0.05), _plot_outline(gt.driven.xy, m, 0.05)
            fig, anim = mesh_animation(a1, a2, cut_on, frames=frames, report=rep)
            save_animation(anim, tmp / "envelope_mesh.html", fps=8, title="meshing pair (envelope teeth)")
            close(fig)
    write_json(tmp / "summary.json", summary)
    summary["_results"] = results
    return summary


def run_wheelstep(design, tmp: Path, *, mesh_steps: int = 360, figures: bool = True, log=print,
                  frames: int = 0, progress=None) -> dict:
    """Shoe outputs into ``tmp`` and the drive's gear outputs into ``tmp/gears``; returns the summary."""
    from ..io.cad import write_json, write_table
    shoe = design.shoe
    b = shoe.budget
    summary = {"name": design.name, "a": shoe.a, "b": shoe.b, "c": shoe.c, "r_min": shoe.r_min,
               "r_step_end": shoe.r_step_end, "X_I": b.crank, "X_II": b.rolling, "X_01": b.total,
               "rolling_share": b.rolling_share, "X_II_eq10": shoe.rolling_eq10()}
    log(f"{design.name or 'wheel-step mover'}: a = {shoe.a:g} m, b = {shoe.b:g} m, c = {shoe.c:.6g} m "
        f"(c = R_min − a + 4b with R_min = {shoe.r_min:.6g} m)")
    log(f"displacement per step: X_I = 6b = {b.crank:.4f} m, X_II = (a − b + c)·π/2 − 3b = {b.rolling:.4f} m "
        f"(corrected eq. 6), X_01 = {b.total:.4f} m, rolling share {100 * b.rolling_share:.2f} %")
    phi = np.linspace(-math.pi / 4, math.pi / 4, 91)
    xy = shoe.profile(phi)
    rho, alpha = shoe.profile_polar(phi)
    rows = np.column_stack([phi * DEG, xy[:, 0], xy[:, 1], rho, alpha * DEG, shoe.curvature_radius(phi),
                            shoe.displacement(phi, periodic=False), shoe.rolling_displacement(phi),
                            shoe.crank_displacement(phi)])
    write_table(tmp / "shoe_profile", ["phi [deg]", "X [m]", "Y [m]", "rho [m]", "alpha [deg]", "R [m]",
                                       "X_mover [m]", "X_rolling [m]", "X_crank [m]"], rows.tolist(),
                meta={"title": "support-shoe profile over one step (eqs. 1-3, 7-9) and the mover displacement"})
    write_json(tmp / "budget.json", summary)
    if figures:
        from ..plot.draw import close, figure_png
        from ..plot.gears import shoe_figure
        fig = shoe_figure(shoe)
        (tmp / "shoe.png").write_bytes(figure_png(fig))
        close(fig)
    if design.gears is not None:
        (tmp / "gears").mkdir()
        summary["gears"] = run_gears(design.gears, tmp / "gears", mesh_steps=mesh_steps, figures=figures, log=log,
                                     frames=frames, progress=progress)
    return summary


def public_summary(summary: dict) -> dict:
    """A bundle's summary without its in-memory results (the keys starting with ``_``), at any depth."""
    return {k: (public_summary(v) if isinstance(v, dict) else v) for k, v in summary.items() if not k.startswith("_")}


__all__ = ["public_summary", "run_gears", "run_wheelstep"]
