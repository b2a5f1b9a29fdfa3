"""The command line's spatial (dimension = 3) branches: info, solve, analyze, plot, animate.

Called from :mod:`assur.cli.main` when the compiled plan is spatial; same options, same error
conventions (``error: ...`` with exit status 1 for bad input).
"""
from __future__ import annotations

import math
import sys
from pathlib import Path

import numpy as np

from ..analysis.summary import format_number as _fmt
from ..io.output import atomic_file
from ..io.units import LENGTH


def is_spatial(plan) -> bool:
    return getattr(plan, "dimension", 2) == 3


def branch_lines(plan) -> list[str]:
    out = []
    for st in plan.rss_steps():
        D, A, B = st.data[:3]
        out.append(f"{B}: R–S–S dyad (rocker {plan.body_names[st.body]} about {D}, coupler "
                   f"{plan.body_names[st.data[3]]} from {A}), branch s = sign det[{A} − {D}, e, {B} − {D}] = "
                   f"{st.branch:+d}")
    return out


def info(plan) -> None:
    """The spatial part of ``assur info``: parameters, axes, dyads and their branches."""
    m = plan.mechanism
    joints = {j.point: j for j in m.joints}
    if joints:
        parts = []
        for p, j in joints.items():
            ax = "" if j.axis is None else f" axis [{', '.join(_fmt(c, 6) for c in j.axis)}]"
            parts.append(f"{p} {j.kind}{ax}")
        print("joints: " + ", ".join(parts))
    print("solve plan: crank, then " + (", ".join(f"R–S–S dyad → {s.key_point}" for s in plan.rss_steps()) or "—"))
    for line in branch_lines(plan):
        print("  " + line)
    from .main import print_parameters_and_drivers
    print_parameters_and_drivers(plan)


def solve_columns(plan, file_units: bool):
    u = plan.mechanism.units
    L = u.length if file_units else "m"
    A = "deg" if file_units else "rad"
    cols = [f"{plan.input_names[k]}.q [{A}]" for k in range(plan.n_inputs)] + ["valid"]
    for p in plan.point_names:
        cols += [f"{p}.{c} [{L}]" for c in "xyz"] + [f"{p}.v{c} [{L}/s]" for c in "xyz"]
        cols += [f"{p}.a{c} [{L}/s^2]" for c in "xyz"]
        cols += [f"{p}.d{c}_dq [{L}/{A}]" for c in "xyz"] + [f"{p}.d2{c}_dq2 [{L}/{A}^2]" for c in "xyz"]
    return cols


def solve_table(plan, q, state, file_units: bool) -> np.ndarray:
    kL = 1.0 / LENGTH[plan.mechanism.units.length] if file_units else 1.0
    kA = 180.0 / math.pi if file_units else 1.0
    rows = len(q)
    blocks = [q * kA, state.valid.astype(float)[:, None]]
    for pi in range(plan.n_points):
        blocks += [state.pos[:, pi] * kL, state.vel[:, pi] * kL, state.acc[:, pi] * kL,
                   state.dpos_dq[:, pi, :, 0] * kL / kA, state.d2pos_dq2[:, pi, :, 0, 0] * kL / kA ** 2]
    out = np.concatenate([np.asarray(b, dtype=float).reshape(rows, -1) for b in blocks], axis=1)
    out[~state.valid, plan.n_inputs + 1:] = np.nan
    return out


def solve(args, plan) -> int:
    from ..plot.figures import sweep_inputs, tracked_point
    from ..solve import solve as solve_
    from .main import _ranges
    q, moving, cyclic = sweep_inputs(plan, args.steps, _ranges(plan, args))
    state = solve_(plan, None, q)
    m = plan.mechanism
    L = m.units.length if args.file_units else "m"
    kL = 1.0 / LENGTH[m.units.length] if args.file_units else 1.0
    cols = solve_columns(plan, args.file_units)
    table = solve_table(plan, q, state, args.file_units)
    what = (f"{len(q)} positions of {plan.input_names[moving]} over one turn" if cyclic
            else f"{len(q)} samples of {', '.join(plan.input_names)} over the given range(s)")
    print(f"{args.file}: {what} (spatial); {state.n_unbuildable} cannot be assembled")
    if state.n_unbuildable:
        from ..spatial_plan import unbuildable_message
        print("  " + unbuildable_message(plan, state.inputs, state.valid, state.status))
    foot = tracked_point(plan)
    fi = plan.point_index(foot)
    A = "°" if args.file_units else "rad"
    heads = [f"{plan.input_names[0]} [{A}]", "valid"] + [f"{foot}.{c} [{L}]" for c in "xyz"] + \
        [f"|v| [{L}/s]", f"|a| [{L}/s²]"]
    from .main import print_rows_and_csv

    def row(r):
        return [table[r, 0], int(state.valid[r])] + list(state.pos[r, fi] * kL) + \
            [float(np.linalg.norm(state.vel[r, fi])) * kL, float(np.linalg.norm(state.acc[r, fi])) * kL]
    return print_rows_and_csv(args, heads, row, len(q), cols, table)


def dyad_lines(summary: dict, units) -> list[str]:
    """The spatial dyads' outputs of an ``analyze`` summary, for people (angles in degrees)."""
    out = []
    deg = math.degrees

    def d(v, digits=4):
        return "—" if v is None else f"{deg(v):.{digits}f}°"

    for s in summary.get("dyads", []):
        w = ", ".join(f"{v:+.0f}" for v in s["paper_w"]) or "undefined (V3_X = 0: the rocker axis lies in a plane with X)"
        out.append(f"dyad {s['point']} (rocker {s['rocker']}, coupler {s['coupler']}): branch s = {s['branch_s']:+d}; "
                   f"the paper's W of (21): {w}" + ("; V3_X changes sign over the turn, so a fixed W would jump "
                                                     "to the other assembly" if s["v3x_changes_sign"] else ""))
        out.append(f"  rocker angle θ4 {d(s['rocker_angle_min'])} … {d(s['rocker_angle_max'])}, swing "
                   f"{d(s['swing'])}")
        out.append(f"  transmission μ_int {d(s['mu_int_min'], 3)} … {d(s['mu_int_max'], 3)}; "
                   f"μ_T (effective, 90° ideal) {d(s['mu_t_min'], 3)} … {d(s['mu_t_max'], 3)}")
        for c in s["dead_centres"]:
            out.append(f"  dead centre ({c['kind']}) at {d(c['angle'], 6)}, θ4 = {d(c['rocker_angle'])}")
    return out


def analyze(args, plan, analysis_lines) -> int:
    from ..analysis.spatial import analyze_spatial
    from ..io.output import json_text
    m = plan.mechanism
    summary = analyze_spatial(plan, steps=args.steps)
    if args.json:
        summary = {"file": str(args.file), **summary}
        print(json_text(summary))
        return 0
    print(f"{m.name or Path(args.file).stem}  [{args.file}] (spatial)")
    for line in analysis_lines(summary, m.units):
        print(line)
    for line in dyad_lines(summary, m.units):
        print(line)
    return 0


def plot(args, plan) -> int:
    from ..plot import spatial as view
    from ..plot.figures import close
    from .main import _ranges
    ranges = _ranges(plan, args)
    if args.output.suffix.lower() == ".html":
        fig = view.plotly_figure(plan, args.steps, positions=args.positions, ranges=ranges)
        with atomic_file(args.output) as tmp:
            view.write_html(fig, tmp, title=plan.mechanism.name)
    else:
        fig = view.figure(plan, args.steps, positions=args.positions, ranges=ranges, dpi=args.dpi)
        try:
            with atomic_file(args.output) as tmp:
                fig.savefig(tmp, format=args.output.suffix.lower()[1:], dpi=args.dpi)
        finally:
            close(fig)
    print(f"wrote {args.output}")
    return 0


def animate(args, plan) -> int:
    from ..plot import spatial as view
    from ..plot.figures import close, save_animation
    from .main import _ranges
    ranges = _ranges(plan, args)
    if args.output.suffix.lower() in (".html", ".htm"):
        fig = view.plotly_figure(plan, max(4 * args.frames, 180), frames=args.frames, ranges=ranges)
        with atomic_file(args.output) as tmp:
            view.write_html(fig, tmp, title=plan.mechanism.name)
    else:
        fig, anim = view.animation(plan, args.frames, args.fps, ranges=ranges)

        def show(i, n):
            print(f"\rframe {i + 1}/{n}", end="" if i + 1 < n else "\n", file=sys.stderr, flush=True)
        try:
            with atomic_file(args.output) as tmp:
                save_animation(anim, tmp, args.fps, progress=show if sys.stderr.isatty() else None)
        finally:
            close(fig)
    print(f"wrote {args.output} ({args.frames} frames at {_fmt(args.fps)} fps)")
    return 0
