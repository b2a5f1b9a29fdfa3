"""The ``assur`` command line: validate, info, solve, analyze, plot, animate, report.

Bad input (an invalid file, a structure that cannot be solved, a missing file) prints one message
starting with ``error:`` to stderr and exits with status 1; usage errors exit with status 2
(argparse). Heavy modules (matplotlib) are imported only by the commands that draw.
"""
from __future__ import annotations

import argparse
import contextlib
import math
import os
import sys
from pathlib import Path

import numpy as np

from ..errors import AssurError, SpecError
from ..analysis.summary import format_number, gait_rows
from ..io.output import atomic_file as atomic_path
from ..io.output import json_text
from ..io.units import ANGLE, LENGTH
from ..io.units import param_unit as _param_unit

PLOT_EXTENSIONS = (".png", ".svg", ".pdf", ".html")   # .html: interactive 3D view (spatial files)
ANIMATION_EXTENSIONS = (".gif", ".mp4", ".html")


# -- helpers ---------------------------------------------------------------------------------------
class CommandError(Exception):
    """A failure to report as ``error: ...`` with exit status 1 (e.g. an output cannot be written)."""


def _positive(minimum=1):
    def parse(text):
        try:
            v = int(text)
        except ValueError:
            raise argparse.ArgumentTypeError(f"must be an integer: {text!r}") from None
        if v < minimum:
            raise argparse.ArgumentTypeError(f"must be at least {minimum}: {v}")
        return v
    return parse


def _positive_float(text):
    try:
        v = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"must be a number: {text!r}") from None
    if not (v > 0 and math.isfinite(v)):
        raise argparse.ArgumentTypeError(f"must be a positive number: {text!r}")
    return v


def _output(extensions):
    def parse(text):
        ext = Path(text).suffix.lower()
        if ext not in extensions:
            raise argparse.ArgumentTypeError(f"the output must end with {', '.join(extensions)}: {text!r}")
        return Path(text)
    return parse


def _load(path):
    from ..io.mechanism_file import load
    return load(path)


def _compile(path):
    from ..compile import compile as compile_
    m = _load(path)
    return m, compile_(m)


def document_format(path) -> str:
    """The top-level ``format`` key of a TOML document: "assur/1" (a mechanism, planar or spatial),
    "assur-gears/1", "assur-wheelstep/1" or "assur-synth/1". A missing key reads as "assur/1" so that the
    mechanism loader reports what is wrong with the file."""
    from ..io.mechanism_file import read_toml
    doc = read_toml(path)
    fmt = doc.get("format", "assur/1")
    return fmt if isinstance(fmt, str) else "assur/1"


def _ranges(plan, args):
    """--range pairs (file units) → SI, one per input; None when not given."""
    if not getattr(args, "range", None):
        return None
    u = plan.mechanism.units
    if len(args.range) != plan.n_inputs:
        raise SpecError([("--range", f"give one --range START STOP per input, in driver order "
                                     f"({plan.n_inputs}: {', '.join(plan.input_names)}): {len(args.range)} given")])
    out = []
    for k, (a, b) in enumerate(args.range):
        f = ANGLE[u.angle] if plan.input_kinds[k] == "rotary" else LENGTH[u.length]
        out.append((a * f, b * f))
    return out


def _angle_text(u):
    return "°" if u == "deg" else "rad"


_fmt = format_number


def _speed_text(kind, speed, units):
    if kind == "rotary":
        return f"{_fmt(speed * 60 / (2 * math.pi), 5)} rpm ({_fmt(speed, 5)} rad/s)"
    return f"{_fmt(speed / LENGTH[units.length], 5)} {units.length}/s ({_fmt(speed, 5)} m/s)"


def driver_lines(m) -> list[str]:
    out = []
    for d in m.drivers:
        if d.kind == "rotary":
            zero = d.zero / ANGLE[m.units.angle]
            out.append(f"{d.name}: rotary, link {d.link} about {d.pivot} (arm {d.arm}), zero = {_fmt(zero)}"
                       f"{_angle_text(m.units.angle)}, {'ccw' if d.sense > 0 else 'cw'}, "
                       f"speed {_speed_text('rotary', d.speed, m.units)}")
        else:
            ac = next((a for a in m.actuators if a.name == d.actuator), None)
            between = f" between {ac.between[0]} and {ac.between[1]}" if ac else ""
            out.append(f"{d.name}: linear, actuator {d.actuator}{between}, speed "
                       f"{_speed_text('linear', d.speed, m.units)}")
    return out


def _roman(n):
    return {1: "I", 2: "II", 3: "III", 4: "IV", 5: "V", 6: "VI"}.get(n, str(n))


def group_text(g) -> str:
    kind = g["kind"]
    from ..structure.assur import GroupKind
    try:
        num = GroupKind(kind).dyad_kind_number
    except ValueError:
        num = None
    kind_text = f"{kind} ({num}{ {1: 'st', 2: 'nd', 3: 'rd'}.get(num, 'th') } kind)" if num else kind
    return (f"class {_roman(g['class'])}, order {g['order']}, {kind_text}: bodies {', '.join(g['bodies'])}; "
            f"attached to {', '.join(g['attaches_to'])}")


def print_parameters_and_drivers(plan) -> None:
    """``info``'s parameter table (in the file's units) and driver lines, planar or spatial."""
    u = plan.mechanism.units
    print(f"parameters ({len(plan.param_names)}, in the file's units):")
    w = max(len(n) for n in plan.param_names)
    for name, v in zip(plan.param_names, plan.defaults):
        f, unit = _param_unit(name, u)
        print(f"  {name:<{w}} = {_fmt(v * f, 8)}" + (f" {unit}" if unit else ""))
    print("drivers:")
    for line in driver_lines(plan.mechanism):
        print("  " + line)


# -- commands ---------------------------------------------------------------------------------------
def cmd_validate(args) -> int:
    m = _load(args.file)
    from ..compile import compile as compile_
    if m.dimension == 3 and not any(j.axis for j in m.joints):
        from ..structure.assur import analyse
        s = analyse(m)
        print(f"{args.file}: ok (spatial, W = {s.mobility} by {s.formula_name}; a structural description: "
              f"without revolute axes it is not solved)")
        return 0
    plan = compile_(m)
    s = plan.structure
    if m.dimension == 3:
        idle = f", {s.idle} idle" if s.idle else ""
        print(f"{args.file}: ok (spatial, W = {s.mobility}{idle} by {s.formula_name}; "
              f"{', '.join('R–S–S → ' + st.key_point for st in plan.rss_steps())})")
        return 0
    print(f"{args.file}: ok (W = {s.mobility}, {s.structural_formula})")
    return 0


def cmd_info(args) -> int:
    from ..analysis.summary import structure_summary
    m = _load(args.file)
    s = structure_summary(m)
    u = m.units
    print(f"{m.name or Path(args.file).stem}  [{args.file}]")
    print(f"units: length {u.length}, angle {u.angle}" + (", spatial (dimension = 3)" if m.dimension == 3 else ""))
    pairs = ", ".join(f"{k} = {v}" for k, v in s["pairs"].items())
    print(f"mobility ({s['formula']}): {s['mobility_formula']}")
    if s.get("idle_freedoms"):
        print(f"  of which idle: {s['idle_freedoms']} (a link between two spherical joints spins about its axis); "
              f"W without idle freedoms = {s['mobility_without_idle']}")
    print(f"  moving links n = {s['moving_links']}; pairs {pairs}; drivers: {len(m.drivers)}"
          + (f" ({', '.join(s['drivers'])})" if s["drivers"] else ""))
    if m.dimension == 3:
        print("points:")
        w = max(len(n) for n in m.point_names)
        for name, xyz in m.points:
            print(f"  {name:<{w}} = [{', '.join(_fmt(c / LENGTH[u.length]) for c in xyz)}] {u.length}")
        from ..compile import compile as compile_
        from . import spatial
        if any(j.axis for j in m.joints):
            spatial.info(compile_(m))
            return 0
        joints = {j.point: j.kind for j in m.joints}
        if joints:
            print("joints: " + ", ".join(f"{p} {k}" for p, k in joints.items()))
        if m.drivers:
            print("drivers:")
            for line in driver_lines(m):
                print("  " + line)
        print("note: a structural description (no revolute axes): its mobility is computed, it is not solved")
        return 0
    if s["groups"]:
        print("Assur groups:")
        for i, g in enumerate(s["groups"], 1):
            print(f"  {i}. {group_text(g)}")
    if s["structural_formula"]:
        print(f"structural formula: {s['structural_formula']}")
        print(f"                    {s['structural_formula_numbered']}")
    from ..structure.assur import analyse
    undetermined = getattr(analyse(m), "undetermined", ())
    if undetermined:
        print(f"not determined by the drivers: {', '.join(undetermined)}")
    from ..compile import compile as compile_
    plan = compile_(m)
    print_parameters_and_drivers(plan)
    if m.gait is not None:
        g = m.gait
        print(f"gait: foot {g.foot}, ground [{', '.join(_fmt(c) for c in g.ground)}], up "
              f"[{', '.join(_fmt(c) for c in g.up_vector)}], phases "
              f"{', '.join(_fmt(math.degrees(p), 5) + '°' for p in g.phases)}")
    return 0


def solve_columns(plan, file_units: bool):
    """Column names of the solve CSV and the factor of each block (SI → output units)."""
    u = plan.mechanism.units
    L = u.length if file_units else "m"
    kL = 1.0 / LENGTH[u.length] if file_units else 1.0
    kA = 180.0 / math.pi if file_units else 1.0
    A = "deg" if file_units else "rad"
    n = plan.n_inputs
    iu = [A if plan.input_kinds[k] == "rotary" else L for k in range(n)]
    ik = [kA if plan.input_kinds[k] == "rotary" else kL for k in range(n)]
    cols = [f"{plan.input_names[k]}.q [{iu[k]}]" for k in range(n)] + ["valid"]
    for p in plan.point_names:
        cols += [f"{p}.x [{L}]", f"{p}.y [{L}]", f"{p}.vx [{L}/s]", f"{p}.vy [{L}/s]",
                 f"{p}.ax [{L}/s^2]", f"{p}.ay [{L}/s^2]"]
        for k in range(n):
            sfx = "" if n == 1 else f"_{plan.input_names[k]}"
            cols += [f"{p}.d{c}_dq{sfx} [{L}/{iu[k]}]" for c in "xy"]
        for i in range(n):
            for j in range(i, n):
                if n == 1:
                    cols += [f"{p}.d2{c}_dq2 [{L}/{iu[0]}^2]" for c in "xy"]
                else:
                    den = f"{iu[i]}^2" if iu[i] == iu[j] else f"({iu[i]}·{iu[j]})"
                    cols += [f"{p}.d2{c}_dq_{plan.input_names[i]}_dq_{plan.input_names[j]} [{L}/{den}]"
                             for c in "xy"]
    return cols, kL, ik


def solve_table(plan, q, state, file_units: bool) -> np.ndarray:
    """(n, n_columns) values of the solve CSV (see :func:`solve_columns`)."""
    cols, kL, ik = solve_columns(plan, file_units)
    n = plan.n_inputs
    rows = len(q)
    blocks = [q * np.asarray(ik)[None, :], state.valid.astype(float)[:, None]]
    pos, vel, acc = state.pos, state.vel, state.acc
    d1, d2 = state.dpos_dq, state.d2pos_dq2
    for pi in range(plan.n_points):
        blocks += [pos[:, pi] * kL, vel[:, pi] * kL, acc[:, pi] * kL]
        for k in range(n):
            blocks.append(d1[:, pi, :, k] * kL / ik[k])
        for i in range(n):
            for j in range(i, n):
                blocks.append(d2[:, pi, :, i, j] * kL / (ik[i] * ik[j]))
    out = np.concatenate([np.asarray(b, dtype=float).reshape(rows, -1) for b in blocks], axis=1)
    # unbuildable rows: NaN everywhere but the inputs and valid
    out[~state.valid, n + 1:] = np.nan
    return out


def _cell(v: float) -> str:
    if math.isnan(v):
        return "nan"
    if v == int(v) and abs(v) < 1e15:
        return str(int(v)) if v != 0 or math.copysign(1, v) > 0 else "0"
    return repr(float(v))


def cmd_solve(args) -> int:
    from ..plot.figures import sweep_inputs, tracked_point
    from ..solve import solve
    m, plan = _compile(args.file)
    if getattr(plan, "dimension", 2) == 3:
        from . import spatial
        return spatial.solve(args, plan)
    ranges = _ranges(plan, args)
    q, moving, cyclic = sweep_inputs(plan, args.steps, ranges)
    state = solve(plan, None, q)
    cols, kL, ik = solve_columns(plan, args.file_units)
    table = solve_table(plan, q, state, args.file_units)
    u = m.units
    L = u.length if args.file_units else "m"
    what = (f"{len(q)} positions of {plan.input_names[moving]} over one turn" if cyclic
            else f"{len(q)} samples of {', '.join(plan.input_names)} over the given range(s)")
    print(f"{args.file}: {what}; {state.n_unbuildable} cannot be assembled")
    foot = tracked_point(plan)
    fi = plan.point_index(foot)
    iu = [("°" if args.file_units else "rad") if k == "rotary" else L for k in plan.input_kinds]
    heads = ([f"{n} [{v}]" for n, v in zip(plan.input_names, iu)]
             + ["valid", f"{foot}.x [{L}]", f"{foot}.y [{L}]", f"|v| [{L}/s]", f"|a| [{L}/s²]"])
    def row(r):
        vals = list(table[r, :plan.n_inputs]) + [int(state.valid[r])]
        P = state.pos[r, fi] * kL
        V = state.vel[r, fi] * kL
        A = state.acc[r, fi] * kL
        return vals + [P[0], P[1], float(np.hypot(*V)), float(np.hypot(*A))]
    return print_rows_and_csv(args, heads, row, len(q), cols, table)


def print_rows_and_csv(args, heads, row, n_rows, cols, table) -> int:
    """The ``solve`` output shared by planar and spatial files: a table of the tracked point (every row
    up to 10, else 8 spread over the sweep; ``row(r)`` gives a row's values) and, with ``--csv``, every
    column of ``table`` written atomically."""
    width = [max(11, len(h) + 1) for h in heads]
    print("".join(f"{h:>{w}}" for h, w in zip(heads, width)))
    rows_at = range(n_rows) if n_rows <= 10 else np.unique(np.linspace(0, n_rows - 1, 8).round().astype(int))
    for r in rows_at:
        cells = [str(v) if isinstance(v, int) else ("nan" if not np.isfinite(v) else f"{v:.5g}") for v in row(r)]
        print("".join(f"{c:>{w}}" for c, w in zip(cells, width)))
    if n_rows > 10:
        print(f"({len(rows_at)} of {n_rows} rows shown" + (", all points in --csv)" if not args.csv else ")"))
    if args.csv:
        with atomic_path(args.csv) as tmp:
            with open(tmp, "w", encoding="utf-8", newline="") as fh:
                fh.write(",".join(cols) + "\n")
                for line in table:
                    fh.write(",".join(_cell(v) for v in line) + "\n")
        print(f"wrote {args.csv} ({len(table)} rows × {len(cols)} columns, "
              f"{'file units and degrees' if args.file_units else 'SI units: m, rad, s'})")
    return 0


def analysis_lines(summary: dict, units) -> list[str]:
    """The human-readable analysis (lengths in the file's unit, speeds in m/s, angles in degrees)."""
    s = summary
    kL = 1.0 / LENGTH[units.length]
    Lu = units.length
    out = [f"mobility: {s['mobility_formula']} ({s['formula']})"]
    if s.get("structural_formula"):
        out.append(f"structural formula: {s['structural_formula']}   ({s['structural_formula_numbered']})")
    if s.get("note"):
        out.append(f"note: {s['note']}")
    act = s.get("actuators")
    if act:   # a linear driver's working stroke
        from ..analysis.summary import actuator_rows
        rows = actuator_rows(act, 1.0 / kL, Lu)
        out += rows["stroke"]
        if rows["lever"]:
            out.append("lever manipulator (paper 002 parametrisation):")
            out += [f"  {a}: {b} {u}".rstrip() for a, b, u in rows["lever"]]
        out.append("stroke envelope (extremes along the stroke; interior ones by a root of the derivative):")
        out += [f"  {rod}, {q} [{u}]: min {mn}; max {mx}; interior: {inner}"
                for rod, q, mn, mx, inner, u in rows["extremes"]]
        out += [f"  {a}: {b}" + (f" ({c})" if c else "") for a, b, c in rows["pairs"]]
        return out
    if s.get("unbuildable") is None:
        return out
    steps = s.get("steps")
    if s.get("full_rotation"):
        out.append(f"buildability: the crank turns fully (0 of {steps} positions unbuildable)")
    else:
        rng = ", ".join(f"{math.degrees(r['start']):.1f}°…{math.degrees(r['end']):.1f}°"
                        for r in s.get("buildable_ranges", []))
        out.append(f"buildability: the crank cannot turn fully: {s['unbuildable']} of {steps} positions cannot be "
                   f"assembled" + (f"; buildable {rng}" if rng else "; no position can be assembled"))
    for k, t in (s.get("transmission_angles") or {}).items():
        if t["min"] is None:
            out.append(f"transmission angle at {k}: no buildable position")
            continue
        out.append(f"transmission angle at {k}: min {math.degrees(t['min']):.2f}°, max {math.degrees(t['max']):.2f}°"
                   f" (worst deviation from 90°: {math.degrees(t['worst_deviation_from_90']):.2f}°)")
    dc = s.get("dead_centres") or []
    if dc:
        out.append("dead centres: " + ", ".join(f"{math.degrees(d['angle']):.2f}° ({d['kind']}, {d['link']})"
                                                for d in dc))
    else:
        out.append("dead centres: none found")
    g = s.get("gait")
    if g:
        out.append(f"gait of foot {g['foot']}:")
        rows = gait_rows(g, 1.0 / kL, Lu)
        w = max(len(r[0]) for r in rows)
        out += [f"  {a:<{w}}  {b} {u}".rstrip() for a, b, u in rows]
    elif s.get("gait_error"):
        out.append(f"gait: not available: {s['gait_error']}")
    mod = s.get("module")
    if mod:
        out.append(f"walking module ({len(mod['phases'])} legs at "
                   f"{', '.join(f'{math.degrees(p):.0f}°' for p in mod['phases'])}): feet on the ground min "
                   f"{mod['min_feet']}, max {mod['max_feet']}, mean {mod['mean_feet']:.3f}; airborne "
                   f"{100 * mod['airborne_fraction']:.1f}% of the cycle")
    return out


def cmd_analyze(args) -> int:
    from ..analysis.summary import analyze
    m, plan = _compile(args.file)
    if getattr(plan, "dimension", 2) == 3:
        from . import spatial
        return spatial.analyze(args, plan, analysis_lines)
    summary = analyze(plan, steps=args.steps)
    if args.json:
        summary = {"file": str(args.file), **summary}
        print(json_text(summary))
        return 0
    print(f"{m.name or Path(args.file).stem}  [{args.file}]")
    for line in analysis_lines(summary, m.units):
        print(line)
    return 0


def cmd_plot(args) -> int:
    from ..plot.figures import close, mechanism_figure
    m, plan = _compile(args.file)
    if getattr(plan, "dimension", 2) == 3:
        from . import spatial
        return spatial.plot(args, plan)
    if args.output.suffix.lower() == ".html":
        raise SpecError([("--output", "an .html view is for spatial mechanisms; use .png, .svg or .pdf")])
    fig = mechanism_figure(plan, args.steps, ranges=_ranges(plan, args), positions=args.positions, dpi=args.dpi)
    try:
        with atomic_path(args.output) as tmp:
            fig.savefig(tmp, format=args.output.suffix.lower()[1:], dpi=args.dpi)
    finally:
        close(fig)
    print(f"wrote {args.output}")
    return 0


def cmd_animate(args) -> int:
    from ..plot.figures import animation, close, save_animation
    m, plan = _compile(args.file)
    if getattr(plan, "dimension", 2) == 3:
        from . import spatial
        return spatial.animate(args, plan)
    fig, anim = animation(plan, args.frames, args.fps, ranges=_ranges(plan, args))
    def show(i, n):
        print(f"\rframe {i + 1}/{n}", end="" if i + 1 < n else "\n", file=sys.stderr, flush=True)
    progress = show if sys.stderr.isatty() else None
    try:
        with atomic_path(args.output) as tmp:
            save_animation(anim, tmp, args.fps, progress=progress)
    finally:
        close(fig)
    print(f"wrote {args.output} ({args.frames} frames at {_fmt(args.fps)} fps)")
    return 0


def cmd_report(args) -> int:
    fmt = document_format(args.file)
    if fmt in ("assur-gears/1", "assur-wheelstep/1"):
        from ..report.documents import write_document_report
        path = write_document_report(args.file, args.output, frames=args.frames)
        print(f"wrote {path}")
        return 0
    from ..report.html import write_report
    m, plan = _compile(args.file)
    path = write_report(plan, args.output, steps=args.steps, frames=args.frames, ranges=_ranges(plan, args),
                        source=str(args.file))
    print(f"wrote {path}")
    return 0


# -- the parser -------------------------------------------------------------------------------------
def build_parser() -> argparse.ArgumentParser:
    from .. import __version__
    p = argparse.ArgumentParser(prog="assur", description="Structural and kinematic analysis of planar mechanisms "
                                "described in mechanism files (format assur/1).")
    p.add_argument("--version", action="version", version=f"assur {__version__}")
    sub = p.add_subparsers(dest="command", metavar="COMMAND", required=True)

    def add(name, func, help_):
        sp = sub.add_parser(name, help=help_, description=help_)
        sp.add_argument("file", metavar="FILE", help="mechanism file (.toml)")
        sp.set_defaults(func=func)
        return sp

    def add_range(sp):
        sp.add_argument("--range", nargs=2, type=float, action="append", metavar=("START", "STOP"),
                        help="run an input from START to STOP (the file's angle or length unit); once per input, "
                             "in driver order; needed for a linear input or several moving inputs")

    add("validate", cmd_validate, "load and compile a mechanism file and report whether it is valid")
    add("info", cmd_info, "structure (mobility, Assur groups, structural formula), parameters and drivers")
    sp = add("solve", cmd_solve, "positions, velocities, accelerations and analogues over one turn")
    sp.add_argument("--steps", type=_positive(1), required=True, metavar="N", help="number of input positions")
    sp.add_argument("--csv", type=Path, metavar="OUT", help="write every point's values to this CSV file")
    sp.add_argument("--file-units", action="store_true",
                    help="lengths in the file's unit and angles in degrees (default: SI, m and rad)")
    add_range(sp)
    sp = add("analyze", cmd_analyze, "buildability, transmission angles, dead centres and gait metrics")
    sp.add_argument("--steps", type=_positive(16), default=720, metavar="N", help="samples per turn (default 720)")
    sp.add_argument("--json", action="store_true", help="print one JSON object (SI units)")
    sp = add("plot", cmd_plot, "a figure: paths, kinematic diagram, velocity and acceleration curves")
    sp.add_argument("-o", "--output", type=_output(PLOT_EXTENSIONS), required=True, metavar="OUT",
                    help="output image (.png, .svg or .pdf; .html for an interactive 3D view of a spatial file)")
    sp.add_argument("--steps", type=_positive(16), default=360, metavar="N", help="samples per turn (default 360)")
    sp.add_argument("--dpi", type=_positive(10), default=100, help="resolution of a PNG (default 100)")
    sp.add_argument("--positions", type=_positive(1), default=6, metavar="K",
                    help="positions drawn in the kinematic diagram (default 6)")
    add_range(sp)
    sp = add("animate", cmd_animate, "an animation of the mechanism over one turn with the traced path")
    sp.add_argument("-o", "--output", type=_output(ANIMATION_EXTENSIONS), required=True, metavar="OUT",
                    help="output animation (.gif, .mp4 or .html)")
    sp.add_argument("--frames", type=_positive(2), default=60, metavar="N", help="frames per turn (default 60)")
    sp.add_argument("--fps", type=_positive_float, default=20.0, metavar="F", help="frames per second (default 20)")
    add_range(sp)
    sp = add("report", cmd_report, "one self-contained HTML page with the structure, analysis, plots and animation")
    sp.add_argument("-o", "--output", type=Path, required=True, metavar="DIR", help="output directory (index.html)")
    sp.add_argument("--steps", type=_positive(16), default=360, metavar="N", help="samples per turn (default 360)")
    sp.add_argument("--frames", type=_positive(2), default=36, metavar="N",
                    help="frames of the embedded animation (default 36)")
    add_range(sp)
    from .synth import register as register_synth
    from .gears import register as register_gears
    register_synth(sub)
    register_gears(sub)   # `assur gears` and `assur wheelstep`
    return p


def format_error(exc: BaseException) -> str:
    return f"error: {exc}"


def main(argv=None) -> int:
    """Run the command line; returns the exit status (0 ok, 1 bad input, 2 usage error)."""
    parser = build_parser()
    try:
        args = parser.parse_args(argv)
    except SystemExit as exc:  # usage errors (2) and --help/--version (0)
        return int(exc.code) if isinstance(exc.code, int) else (0 if exc.code is None else 2)
    try:
        return int(args.func(args) or 0)
    except (AssurError, CommandError) as exc:
        print(format_error(exc), file=sys.stderr)
        return 1
    except ImportError as exc:   # an optional dependency (e.g. imageio-ffmpeg for MP4)
        print(format_error(exc), file=sys.stderr)
        return 1
    except BrokenPipeError:      # e.g. `assur analyze --json f | head`
        with contextlib.suppress(OSError):
            os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())
        return 1
    except OSError as exc:       # an output cannot be written
        name = f" {exc.filename}" if getattr(exc, "filename", None) else ""
        print(f"error: cannot write{name}: {exc.strerror or exc}", file=sys.stderr)
        return 1
    except KeyboardInterrupt:
        print("error: interrupted", file=sys.stderr)
        return 130


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
