"""Figures of a mechanism: point paths, kinematic diagrams, velocity and acceleration curves, the body's
path while a foot is planted, and the feet on the ground of a walking module.

A figure draws a solved run of the plan (a :class:`Sweep`): sampled here, or handed in already solved
(:meth:`Sweep.of_cycle`: the turn an analysis solved), so that one command solves one turn. matplotlib
is imported lazily inside the functions (``import assur`` stays light) and always with the
non-interactive "Agg" backend. Geometry, velocities and accelerations are drawn in the file's length unit
(mm, mm/s, mm/s² for a mm file; ``units="si"``: m, m/s, m/s²); crank angles in degrees.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..analysis.sampling import CYCLE_STEPS, tracked_point
from ..analysis.study import Study, Sweep
from ..errors import SpecError, UnbuildableError
from ..kernels.runs import cyclic_runs
from .draw import closed, draw_mechanism, file_scale, frame_guides, mpl, set_limits


# -- sampling -------------------------------------------------------------------------------------
def input_unit(plan, k: int) -> str:
    """The display unit of input ``k``: degrees for a crank, the file's length unit for an actuator."""
    return "°" if plan.input_kinds[k] == "rotary" else plan.mechanism.units.length


def study_of(source, params=None, steps: int = CYCLE_STEPS, ranges=None) -> Study:
    """``source`` when it is a Study, else the Study of the plan ``source`` over one turn (or ``ranges``)."""
    return Study.of(source, params, steps, ranges=ranges)


def sample(plan, steps: int = CYCLE_STEPS, params=None, ranges=None) -> Sweep:
    """The run of a plan over one turn (or over ``ranges``) as a :class:`Sweep` (``Study(...).sweep``; see
    :func:`~assur.analysis.sampling.sweep_inputs`)."""
    return study_of(plan, params, steps, ranges).sweep


def gait_curves_of(sweep, params=None):
    """Gait curves of a one-input leg over the turn ``sweep`` (from its solved state; a turn of fewer than 16
    samples is solved again at 16), or None (no foot, several inputs, not a turn, crank cannot turn fully)."""
    plan = sweep.plan
    if plan.mechanism.gait is None or plan.n_inputs != 1 or plan.input_kinds[0] != "rotary" or not sweep.cyclic:
        return None
    from ..analysis.gait import gait_curves
    try:
        return gait_curves(sweep.state if sweep.n >= 16 else plan, params, steps=16)
    except (UnbuildableError, SpecError):
        return None


def _shade_contact(ax, axis, contact, color="tab:green", alpha=0.10, label=None):
    """Shade the contact arc (a mask over the samples) on a plot against the crank angle."""
    if contact is None or not np.any(contact):
        return
    step = axis[1] - axis[0] if len(axis) > 1 else 1.0
    for i, j in cyclic_runs(contact):
        a, b = axis[i], axis[j] + step
        if j < i:  # wraps around
            ax.axvspan(a, axis[-1] + step, color=color, alpha=alpha, linewidth=0, label=label)
            ax.axvspan(axis[0], b, color=color, alpha=alpha, linewidth=0)
        else:
            ax.axvspan(a, b, color=color, alpha=alpha, linewidth=0, label=label)
        label = None


def default_positions(plan) -> int:
    """Positions drawn in a kinematic diagram by default: 6 for a mechanism of up to four moving links, 3 for
    more (the overlapping drawings of Jansen's or Klann's linkage are unreadable at 6)."""
    return 6 if plan.n_bodies - 1 <= 4 else 3


def diagram_indices(sweep: Sweep, positions: int = 6) -> list[int]:
    """Up to ``positions`` sample indices, evenly spread over the valid samples."""
    ok = np.nonzero(sweep.state.valid)[0]
    if not len(ok):
        return []
    if sweep.cyclic:
        want = np.arange(positions) * sweep.n / positions
        return sorted({int(ok[np.argmin(np.abs(ok - w))]) for w in want})
    pick = np.linspace(0, len(ok) - 1, min(positions, len(ok)))
    return sorted({int(ok[int(round(p))]) for p in pick})


# -- the figure ------------------------------------------------------------------------------------
def mechanism_figure(plan, steps: int = CYCLE_STEPS, *, params=None, ranges=None, positions: int | None = None,
                     sweep=None, gait=None, figsize=None, dpi: int = 100, units: str = "file"):
    """One figure: (a) point paths, (b) kinematic diagram in several positions, (c) velocity and
    (d) acceleration of the foot (or of the last point) against the input, and for a walking leg
    (e) the frame pivot's path while the foot is planted. ``sweep``: the solved run to draw (default:
    :func:`sample` of ``steps`` over one turn or ``ranges``); ``gait``: the GaitCurves of that run (default:
    :func:`gait_curves_of`); ``positions``: of the diagram (default :func:`default_positions`); ``units``:
    'file' (the file's length unit) or 'si'. ``plan`` may be a Study: its run and gait are drawn (nothing solved).
    Returns a matplotlib Figure."""
    _, plt = mpl()
    from matplotlib.gridspec import GridSpec
    if sweep is None:
        study = study_of(plan, params, steps, ranges)
        sweep = study.sweep
        if gait is None and study.turn and study.plan.mechanism.gait is not None:
            gait = study.gait_curves
    plan = sweep.plan
    sw = sweep
    st = sw.state
    k, unit = (file_scale(plan), plan.mechanism.units.length) if units != "si" else (1.0, "m")
    positions = default_positions(plan) if positions is None else positions
    foot = tracked_point(plan)
    fi = plan.point_index(foot)
    gc = gait if gait is not None else gait_curves_of(sw, params)
    has_e = gc is not None
    fig = plt.figure(figsize=figsize or ((16, 10) if has_e else (14, 10)), dpi=dpi)
    # fixed margins (tight_layout costs more than drawing the figure)
    gs = GridSpec(2, 6, figure=fig, height_ratios=[1.25, 1.0], left=0.055, right=0.985, bottom=0.065, top=0.9,
                  wspace=1.0, hspace=0.28)
    ax_a = fig.add_subplot(gs[0, 0:3])
    ax_b = fig.add_subplot(gs[0, 3:6])
    if has_e:
        ax_c, ax_d, ax_e = fig.add_subplot(gs[1, 0:2]), fig.add_subplot(gs[1, 2:4]), fig.add_subplot(gs[1, 4:6])
    else:
        ax_c, ax_d, ax_e = fig.add_subplot(gs[1, 0:3]), fig.add_subplot(gs[1, 3:6]), None
    title = plan.mechanism.name or "mechanism"
    bad = int(st.n_unbuildable)
    sub = f"{sw.n} samples" + (f", {bad} cannot be assembled" if bad else "")
    fig.suptitle(f"{title}  ({sub})", fontsize=13)
    pos = st.pos * k                                      # (n, n_points, 2) file units
    contact = None
    if gc is not None and len(gc.contact) == sw.n:
        contact = gc.contact
    # (a) paths
    frame_pts = set(plan.mechanism.frame.points)
    for i, p in enumerate(plan.point_names):
        if p in frame_pts:
            continue
        xy = closed(pos[:, i], sw.cyclic)
        if i == fi:
            continue
        ax_a.plot(xy[:, 0], xy[:, 1], color="0.55", linewidth=1.0)
        j = int(np.argmax(np.isfinite(xy[:, 0]))) if np.isfinite(xy[:, 0]).any() else None
        if j is not None:
            ax_a.annotate(p, xy[j], xytext=(4, 4), textcoords="offset points", fontsize=8, color="0.3")
    fxy = closed(pos[:, fi], sw.cyclic)
    ax_a.plot(fxy[:, 0], fxy[:, 1], color="tab:blue", linewidth=2.2, label=f"{foot} path")
    if contact is not None:
        cxy = np.where(contact[:, None], pos[:, fi], np.nan)
        # keep the arc continuous across the wrap
        cxy = closed(cxy, sw.cyclic)
        ax_a.plot(cxy[:, 0], cxy[:, 1], color="tab:green", linewidth=4.0, alpha=0.8, label="contact arc")
    for p in frame_pts:
        xy = pos[0, plan.point_index(p)]
        if np.all(np.isfinite(xy)):
            ax_a.plot(*xy, marker="^", color="0.2", markersize=7, linestyle="none")
            ax_a.annotate(p, xy, xytext=(4, -10), textcoords="offset points", fontsize=8, color="0.3")
    ax_a.set_title("(a) paths of the points" + (f" (foot {foot})" if plan.mechanism.gait else ""))
    ax_a.set_xlabel(f"x [{unit}]")
    ax_a.set_ylabel(f"y [{unit}]")
    ax_a.grid(True, alpha=0.3)
    ax_a.legend(loc="best", fontsize=8)
    set_limits(ax_a, pos.reshape(-1, 2))
    # (b) the diagram in several positions
    idx = diagram_indices(sw, positions)
    cmap = plt.get_cmap("viridis")
    frame_guides(ax_b, plan, st.pos, params=params, scale=k)
    ax_b.plot(fxy[:, 0], fxy[:, 1], color="0.6", linewidth=1.0, linestyle="--", zorder=1)
    shown = []
    for n_, i in enumerate(idx):
        col = cmap(0.9 * n_ / max(len(idx) - 1, 1))
        draw_mechanism(ax_b, plan, st.pos[i], params=params, color=col, alpha=0.95, linewidth=1.8,
                       labels=(n_ == 0), pivots=(n_ == 0), frame_guide=False, foot=foot, scale=k)
        ax_b.annotate(str(n_ + 1), pos[i, fi], xytext=(6, -12), textcoords="offset points", fontsize=9,
                      color=col, fontweight="bold")
        shown.append(f"{sw.axis[i]:.0f}" if plan.input_kinds[sw.moving] == "rotary" else f"{sw.axis[i]:.4g}")
    if not idx:
        ax_b.text(0.5, 0.5, "no position can be assembled", transform=ax_b.transAxes, ha="center")
    where = ""
    if shown:
        where = (f"\npositions 1–{len(idx)} at φ = {', '.join(shown)}°" if plan.input_kinds[sw.moving] == "rotary"
                 else f"\npositions 1–{len(idx)} at {plan.input_names[sw.moving]} = {', '.join(shown)} {unit}")
    ax_b.set_title(f"(b) kinematic diagram{where}", fontsize=11)
    ax_b.set_xlabel(f"x [{unit}]")
    ax_b.set_ylabel(f"y [{unit}]")
    ax_b.grid(True, alpha=0.3)
    set_limits(ax_b, pos.reshape(-1, 2))
    # (c) velocity, (d) acceleration of the foot
    x = sw.axis
    vel, acc = st.vel[:, fi] * k, st.acc[:, fi] * k
    for ax, val, name, u_ in ((ax_c, vel, "v", f"{unit}/s"), (ax_d, acc, "a", f"{unit}/s²")):
        ax.plot(x, np.hypot(val[:, 0], val[:, 1]), color="k", linewidth=1.8, label=f"|{name}|")
        ax.plot(x, val[:, 0], color="tab:red", linewidth=1.2, label=f"{name}x")
        ax.plot(x, val[:, 1], color="tab:blue", linewidth=1.2, label=f"{name}y")
        ax.axhline(0.0, color="0.5", linewidth=0.6)
        _shade_contact(ax, x, contact)
        if bad:
            _shade_contact(ax, x, ~st.valid, color="tab:red", alpha=0.12, label="cannot be assembled")
        ax.set_xlabel(sw.axis_label)
        ax.set_ylabel(f"{'velocity' if name == 'v' else 'acceleration'} of {foot} [{u_}]")
        if sw.cyclic and plan.input_kinds[sw.moving] == "rotary":
            ax.set_xlim(0, 360)
            ax.set_xticks(np.arange(0, 361, 60))
        ax.grid(True, alpha=0.3)
        ax.legend(loc="best", fontsize=8)
    ax_c.set_title(f"(c) velocity of {foot}" + (" (green: contact arc)" if contact is not None else ""))
    ax_d.set_title(f"(d) acceleration of {foot}")
    # (e) the body's path while the foot is planted
    if ax_e is not None:
        pivot = plan.mechanism.frame.points[0]
        bx, bv = gc.body_x * k, gc.body_v * k
        ax_e.plot(bx, bv, color="tab:purple", linewidth=2.0)
        ax_e.plot(bx[:1], bv[:1], marker="o", color="tab:purple", linestyle="none", label="touch-down")
        ax_e.plot(bx[-1:], bv[-1:], marker="s", color="tab:purple", linestyle="none", label="lift-off")
        ax_e.set_title(f"(e) path of the frame pivot {pivot} while {foot} is planted")
        ax_e.set_xlabel(f"horizontal displacement [{unit}]")
        ax_e.set_ylabel(f"vertical displacement [{unit}]")
        ax_e.grid(True, alpha=0.3)
        ax_e.legend(loc="best", fontsize=8)
        span = float(np.ptp(bv)) if len(bv) else 0.0
        if span < 1e-9:
            ax_e.set_ylim(-1, 1)
    return fig


def timeline_figure(plan, metrics, phases, steps: int = CYCLE_STEPS, figsize=(7, 2.4), dpi: int = 100):
    """Feet on the ground of a walking module over one crank turn (a step plot at ``steps`` angles)."""
    _, plt = mpl()
    from ..analysis.gait import module_timeline
    q, count = module_timeline(metrics, phases, steps)
    fig, ax = plt.subplots(figsize=figsize, dpi=dpi)
    ax.step(np.degrees(q), count, where="post", color="tab:green", linewidth=2)
    ax.fill_between(np.degrees(q), count, step="post", color="tab:green", alpha=0.2)
    ax.set_xlim(0, 360)
    ax.set_xticks(np.arange(0, 361, 60))
    ax.set_ylim(0, max(len(phases), 1) + 0.3)
    ax.set_yticks(range(0, len(phases) + 1))
    ax.set_xlabel("crank angle φ [°]")
    ax.set_ylabel("feet on ground")
    ax.set_title(f"walking module: {len(phases)} legs at phases "
                 + ", ".join(f"{math.degrees(p):.0f}°" for p in phases))
    ax.grid(True, alpha=0.3)
    fig.tight_layout()
    return fig
