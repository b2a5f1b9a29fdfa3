"""A Study's analysis for people: the text of ``assur analyze`` (:func:`analysis_lines`) and the report's
Analysis section (:func:`analysis_html`), both formatted from the Study's typed fields (never from its JSON dict).

Rows that carry no information are left out: a transmission angle that stays the same over the turn (a pin in a
slot at 90°), the angle range of a link that keeps its orientation (a slider block). Angles in degrees; lengths,
speeds and accelerations in the file's length unit (``system`` 'file') or in metres ('si').
"""
from __future__ import annotations

import math

import numpy as np

from ..engine.options import ambiguous_note
from ..errors import SpecError
from .page import escape, png_tag, table
from .text import actuator_rows, deg_text, format_number, gait_rows, length_display, on_arc, phases_text

__all__ = ["analysis_html", "analysis_lines", "dyad_lines", "link_rows", "output_lines", "transmission_rows"]

#: a transmission angle whose range over the turn is below this (rad) is constant: its row says nothing
CONSTANT_ANGLE = 1e-9


def transmission_rows(study) -> list[tuple[str, float | None, float | None, float | None]]:
    """(solved point, min μ, max μ, worst deviation from 90°) in rad of each dyad whose μ varies over the turn
    (None where no position assembles)."""
    rows = []
    for k, v in (study.transmission or {}).items():
        if not np.isfinite(v).any():
            rows.append((k, None, None, None))
            continue
        lo, hi = float(np.nanmin(v)), float(np.nanmax(v))
        if hi - lo > CONSTANT_ANGLE:
            rows.append((k, lo, hi, float(np.nanmax(np.abs(v - math.pi / 2)))))
    return rows


def link_rows(study) -> list[tuple[str, str, str, str, str]]:
    """(link, angle range, swing, largest |ω|, largest |α|) per moving link (angles in degrees in (−180°, 180°],
    rates in rad/s and rad/s², noise as 0; a slider block that keeps its orientation says so)."""
    links = study.links or {}
    wscale = max((v.omega_max for v in links.values() if v.omega_max is not None), default=None)
    ascale = max((v.alpha_max for v in links.values() if v.alpha_max is not None), default=None)
    rows = []
    for name, v in links.items():
        if v.spatial:
            rng = swing = "—"       # a spatial link: no single angle
        elif v.translates:
            rng, swing = "translates (no rotation)", "—"
        elif v.angle_min is not None:
            rng, swing = f"{deg_text(v.angle_min)} … {deg_text(v.angle_max)}", deg_text(v.angle_max - v.angle_min)
        elif v.turns:
            rng, swing = (f"turns fully ({abs(v.turns)} turn{'s' if abs(v.turns) > 1 else ''} "
                          f"{'ccw' if v.turns > 0 else 'cw'} per input turn)"), "—"
        else:
            rng = swing = "—"
        alpha = format_number(v.alpha_max, 5, ascale) + (" (at a toggle)" if v.alpha_at_toggle else "")
        rows.append((name, rng, swing, format_number(v.omega_max, 5, wscale), alpha))
    return rows


def output_lines(study, length_factor: float = 1.0, length_unit: str = "m") -> list[str]:
    """The output member (a rocker's swing or a slide's stroke, its extreme positions and the time ratio) as
    sentences; [] without one. A slide's positions are shown in ``length_unit`` (divided by ``length_factor``)."""
    o = study.output_link
    if o is None:
        return []
    if o.motion == "slide":
        f = lambda v: f"{format_number(v / length_factor, 6)} {length_unit}"  # noqa: E731
        out = [f"output slider {o.link}: stroke {f(o.range)}, from {f(o.value_min)} to {f(o.value_max)} along "
               f"its guide"]
        what = "at"
    else:
        f = deg_text
        out = [f"output link {o.link}: swing {deg_text(o.range)}, from {deg_text(o.value_min)} to "
               f"{deg_text(o.value_max)}"]
        what = "at"
    for e in o.extremes:
        out.append(f"  extreme ({e.kind}): {o.link} {what} {f(e.value)} with the input at {deg_text(e.input)}")
    if o.time_ratio is not None:
        ft, rt = ((f" ({format_number(o.forward_time, 5)} s)", f" ({format_number(o.return_time, 5)} s)")
                  if o.forward_time is not None else ("", ""))
        word = "position" if o.motion == "slide" else "angle"
        out.append(f"  time ratio {o.time_ratio:.4f}: forward stroke ({o.forward} {word}) over "
                   f"{deg_text(o.forward_crank_angle)} of input{ft}, return stroke over "
                   f"{deg_text(o.return_crank_angle)}{rt}")
    return out


def four_bar_lines(study) -> list[str]:
    """One line per four-bar loop: its Grashof class and inversion."""
    return [loop.describe() for loop in study.four_bars]


def dyad_lines(study) -> list[str]:
    """The spatial dyads' outputs (angles in degrees); [] for a planar Study."""
    out = []
    for s in study.spatial or []:
        w = ", ".join(f"{v:+.0f}" for v in s.paper_w) or "undefined (V3_X = 0: the rocker axis lies in a plane with X)"
        out.append(f"dyad {s.point} (rocker {s.rocker}, coupler {s.coupler}): branch s = {s.branch_s:+d}; "
                   f"the paper's W of (21): {w}" + ("; V3_X changes sign over the turn, so a fixed W would jump "
                                                     "to the other assembly" if s.v3x_changes_sign else ""))
        out.append(f"  rocker angle θ4 {deg_text(s.rocker_angle_min, 4)} … {deg_text(s.rocker_angle_max, 4)}, "
                   f"swing {deg_text(s.swing, 4)}")
        out.append(f"  transmission μ_int {deg_text(s.mu_int_min, 3)} … {deg_text(s.mu_int_max, 3)}; "
                   f"μ_T (effective, 90° ideal) {deg_text(s.mu_t_min, 3)} … {deg_text(s.mu_t_max, 3)}")
        for c in s.dead_centres:
            out.append(f"  dead centre ({c.kind}) at {deg_text(c.angle, 6)}, "
                       f"θ4 = {deg_text(on_arc(c.rocker_angle, s.rocker_angle_min), 4)}")
    return out


def _stroke_lines(act: dict, length_factor: float, length_unit: str) -> list[str]:
    rows = actuator_rows(act, length_factor, length_unit)
    out = list(rows["stroke"])
    if rows["lever"]:
        out.append("lever manipulator (paper 002 parametrisation):")
        out += [f"  {a}: {b} {u}".rstrip() for a, b, u in rows["lever"]]
    out.append("stroke envelope (extremes along the stroke; interior ones by a root of the derivative):")
    out += [f"  {rod}, {q} [{u}]: min {mn}; max {mx}; interior: {inner}"
            for rod, q, mn, mx, inner, u in rows["extremes"]]
    out += [f"  {a}: {b}" + (f" ({c})" if c else "") for a, b, c in rows["pairs"]]
    return out


def stroke_html(act: dict, plan, length_factor: float, length_unit: str) -> list[str]:
    """A linear driver's working stroke: the envelope tables and the actuator figure."""
    rows = actuator_rows(act, length_factor, length_unit)
    parts = [f"<p>{escape(line)}</p>" for line in rows["stroke"]]
    if rows["lever"]:
        parts.append("<h3>Lever manipulator (paper 002 parametrisation)</h3>")
        parts.append(table(["quantity", "value", "unit"], rows["lever"], num_cols=(1,)))
    parts.append("<h3>Stroke envelope</h3>")
    parts.append('<p class="note">Extremes along the stroke; interior ones located by a root of the '
                 "derivative.</p>")
    parts.append('<div class="scroll">' + table(["rod", "quantity", "min (where)", "max (where)",
                                                 "interior extrema", "unit"], rows["extremes"]) + "</div>")
    if rows["pairs"]:
        parts.append("<h3>Rods hinged at one joint</h3>")
        parts.append(table(["quantity", "value", "note"], rows["pairs"], num_cols=(1,)))
    try:
        from ..plot.actuators import actuator_figure
        from ..plot.draw import close, figure_png
        fig = actuator_figure(plan)
        parts.append(png_tag(figure_png(fig, dpi=80), "angular velocities and accelerations of the rods, "
                                                      "K_ω and length changes along the stroke"))
        close(fig)
    except SpecError as exc:
        parts.append(f'<p class="note">no actuator figure: {escape(exc)}</p>')
    return parts


def analysis_lines(study, system: str = "file") -> list[str]:
    """The human-readable analysis of a Study (``assur analyze``)."""
    plan = study.plan
    head = study.header
    Lf, Lu = length_display(plan.mechanism.units, system)
    out = [f"mobility: {head['mobility_formula']} ({head['formula']})"]
    if head.get("structural_formula"):
        out.append(f"structural formula: {head['structural_formula']}   ({head['structural_formula_numbered']})")
    out += four_bar_lines(study)
    if head.get("note"):
        out.append(f"note: {head['note']}")
    if plan.n_inputs != 1:
        return out
    if plan.dimension == 2 and not study.turn:
        act = study.actuators
        return out + ([f"note: {act['note']}"] if "note" in act else _stroke_lines(act, Lf, Lu))
    b = study.buildable
    if b is None:
        return out
    if b.full_rotation:
        out.append(f"buildability: the crank turns fully (0 of {b.steps} positions unbuildable)")
    else:
        rng = ", ".join(f"{math.degrees(s):.1f}°…{math.degrees(e):.1f}°" for s, e in b.ranges)
        out.append(f"buildability: the crank cannot turn fully: {b.unbuildable} of {b.steps} positions cannot be "
                   f"assembled" + (f" ({ambiguous_note(b.ambiguous)})" if b.ambiguous else "")
                   + (f"; buildable {rng}" if rng else "; no position can be assembled"))
    if plan.dimension == 3:
        for d in study.spatial or []:
            for label, lo, hi, worst in ((f"{d.point} (μ_T)", d.mu_t_min, d.mu_t_max, math.pi / 2 - d.mu_t_min),
                                         (f"{d.point} (μ_int)", d.mu_int_min, d.mu_int_max,
                                          max(abs(d.mu_int_min - math.pi / 2), abs(d.mu_int_max - math.pi / 2)))):
                out.append(f"transmission angle at {label}: min {math.degrees(lo):.2f}°, max {math.degrees(hi):.2f}°"
                           f" (worst deviation from 90°: {math.degrees(worst):.2f}°)")
        dc = [c for d in study.spatial or [] for c in d.dead_centres]
        out.append("dead centres: " + (", ".join(f"{math.degrees(c.angle):.2f}° ({c.kind}, {c.link})" for c in dc)
                                       if dc else "none found"))
        return out + _links_lines(study) + dyad_lines(study)
    for k, lo, hi, worst in transmission_rows(study):
        if lo is None:
            out.append(f"transmission angle at {k}: no buildable position")
            continue
        out.append(f"transmission angle at {k}: min {math.degrees(lo):.2f}°, max {math.degrees(hi):.2f}°"
                   f" (worst deviation from 90°: {math.degrees(worst):.2f}°)")
    dc = study.dead_centres
    out.append("dead centres: " + (", ".join(f"{math.degrees(d.angle):.2f}° ({d.kind}, {d.link})" for d in dc)
                                   if dc else "none found"))
    if study.gait is not None:
        out.append(f"gait of foot {study.gait.foot}:")
        rows = gait_rows(study.gait.as_dict(), Lf, Lu)
        w = max(len(r[0]) for r in rows)
        out += [f"  {a:<{w}}  {b} {u}".rstrip() for a, b, u in rows]
    elif study.gait_error:
        out.append(f"gait: not available: {study.gait_error}")
    out += _links_lines(study)
    out += output_lines(study, Lf, Lu)
    mod = study.module
    if mod is not None:
        out.append(f"walking module ({len(mod.phases)} legs at {phases_text(mod.phases)}): feet on the ground "
                   f"min {mod.min_feet}, max {mod.max_feet}, mean {mod.mean_feet:.3f}; airborne "
                   f"{100 * mod.airborne_fraction:.1f}% of the cycle")
    return out


def _links_lines(study) -> list[str]:
    lr = link_rows(study)
    if not lr:
        return []
    w = max(len(r[0]) for r in lr)
    return ["links (angle over the turn; largest |ω| rad/s, |α| rad/s²):"] + [
        f"  {a:<{w}}  " + (f"{b}; " if b != "—" else "") + (f"swing {c}; " if c != "—" else "")
        + f"|ω| max {d}; |α| max {e}" for a, b, c, d, e in lr]


def analysis_html(study, units: str = "file") -> str:
    """The report's Analysis section of a Study: a stroke, or buildability, transmission angles, dead centres,
    the four-bar loops, the links' motion, the output member and the gait."""
    plan = study.plan
    head = study.header
    Lf, Lu = length_display(plan.mechanism.units, units)
    parts = []
    if head.get("note"):
        parts.append(f'<p class="note">{escape(head["note"])}</p>')
    if plan.n_inputs != 1:
        return "\n".join(parts)
    if plan.dimension == 2 and not study.turn:
        act = study.actuators
        if "note" in act:
            return "\n".join(parts + [f'<p class="note">{escape(act["note"])}</p>'])
        return "\n".join(parts + stroke_html(act, plan, Lf, Lu))
    b = study.buildable
    if b is None:
        return "\n".join(parts)
    if b.full_rotation:
        parts.append(f'<p>Buildability: <span class="ok">the crank turns fully</span> '
                     f'(0 of {b.steps} positions unbuildable).</p>')
    else:
        rng = ", ".join(f"{deg_text(s, 1)} … {deg_text(e, 1)}" for s, e in b.ranges)
        parts.append(f'<p>Buildability: <span class="bad">the crank cannot turn fully</span>: '
                     f'{b.unbuildable} of {b.steps} positions cannot be assembled (unbuildable: {b.unbuildable}'
                     f'{"; " + escape(ambiguous_note(b.ambiguous)) if b.ambiguous else ""}). '
                     + (f"Buildable ranges: {escape(rng)}." if rng else "No position can be assembled.") + "</p>")
    if study.four_bars:
        parts.append("<h3>Four-bar loops</h3>")
        parts.append(table(["ground", "input", "coupler", "output", "class", "Barker", "shortest"],
                           [(f.ground, f.input, f.coupler, f.output,
                             ("Grashof " if f.grashof else "change point " if f.change_point else "non-Grashof ")
                             + f.kind, f.barker, f.shortest) for f in study.four_bars]))
    if plan.dimension == 3:
        return "\n".join(parts + _links_html(study))
    rows = [(k, deg_text(lo), deg_text(hi), deg_text(w)) for k, lo, hi, w in transmission_rows(study)]
    if rows:
        parts.append("<h3>Transmission angles</h3>")
        parts.append(table(["dyad (solved point)", "min μ", "max μ", "worst deviation from 90°"], rows,
                           num_cols=(1, 2, 3)))
    parts.append("<h3>Dead centres</h3>")
    dc = study.dead_centres
    if dc:
        parts.append(table(["input angle", "kind", "crank", "link"],
                           [(deg_text(d.angle), d.kind, d.crank, d.link) for d in dc], num_cols=(0,)))
    else:
        parts.append('<p class="note">none found</p>')
    parts += _links_html(study)
    ol = output_lines(study, Lf, Lu)
    if ol:
        o = study.output_link
        parts.append(f"<h3>Output {'slider' if o.motion == 'slide' else 'link'} {escape(o.link)}</h3>")
        parts.append("<ul>" + "".join(f"<li>{escape(line.strip())}</li>" for line in ol) + "</ul>")
    if study.gait is not None:
        parts.append(f"<h3>Gait of foot {escape(study.gait.foot)}</h3>")
        parts.append(table(["quantity", "value", "unit"], gait_rows(study.gait.as_dict(), Lf, Lu), num_cols=(1,)))
    elif study.gait_error:
        parts.append(f'<h3>Gait</h3><p class="note">not available: {escape(study.gait_error)}</p>')
    return "\n".join(parts)


def _links_html(study) -> list[str]:
    lr = link_rows(study)
    if not lr:
        return []
    return ["<h3>Links</h3>", table(["link", "angle over the turn", "swing", "largest |ω| [rad/s]",
                                     "largest |α| [rad/s²]"], lr, num_cols=(2, 3, 4))]
