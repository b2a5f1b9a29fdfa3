"""The commands on a mechanism file, planar or spatial: validate, info, solve, analyze, plot, animate,
report (a report also takes a gear or wheel-step design). Each turns its arguments into calls of
:mod:`assur.analysis`, :mod:`assur.plot` and :mod:`assur.report` and prints what they return; a file's
dimension (``plan.dimension``) picks the planar or the spatial figures.
"""
from __future__ import annotations

from pathlib import Path

from ..analysis.sampling import CYCLE_STEPS
from ..errors import SpecError
from ..io.output import atomic_file
from .args import (ANIMATION_EXTENSIONS, MAX_BUDGET, MAX_DPI, MAX_FRAMES, PLOT_EXTENSIONS, add_range, compile_file,
                   document_format, fps_arg, input_ranges, load_mechanism, output_path, path_arg, positive, seed_arg)
from .progress import frame_progress


def add_units(sp) -> None:
    """The ``--units {file,si}`` option of a sub-parser."""
    sp.add_argument("--units", choices=("file", "si"), default="file",
                    help="lengths, speeds and accelerations in the file's length unit (default; mm, mm/s, mm/s² "
                         "for a mm file) or in SI (m, m/s, m/s²)")


def register(sub) -> None:
    """Add the mechanism commands to the argparse sub-parsers ``sub``."""
    def add(name, func, help_):
        sp = sub.add_parser(name, help=help_, description=help_)
        sp.add_argument("file", metavar="FILE", help="mechanism file (.toml)")
        sp.set_defaults(func=func)
        return sp

    add("validate", cmd_validate, "load and compile a mechanism file and report whether it is valid")
    sp = add("info", cmd_info, "structure (mobility, Assur groups, structural formula), parameters and drivers")
    sp.add_argument("--assemblies", action="store_true",
                    help="also list every assembly of the mechanism at one input (all combinations of its groups' "
                         "assemblies) and which one the sketch chose")
    sp.add_argument("--at", nargs="+", metavar="INPUT",
                    help="with --assemblies: the input(s) in the file's units, one per driver (default: the sketch's)")
    sp = add("solve", cmd_solve, "positions, velocities, accelerations and analogues over one turn")
    sp.add_argument("--steps", type=positive(1), required=True, metavar="N", help="number of input positions")
    sp.add_argument("--csv", type=path_arg, metavar="OUT", help="write every point's values to this CSV file")
    sp.add_argument("--file-units", action="store_true",
                    help="lengths in the file's unit and angles in degrees (default: SI, m and rad)")
    add_range(sp)
    sp = add("analyze", cmd_analyze, "buildability, transmission angles, dead centres and gait metrics")
    sp.add_argument("--steps", type=positive(16), default=CYCLE_STEPS, metavar="N",
                    help=f"samples per turn (default {CYCLE_STEPS})")
    sp.add_argument("--json", action="store_true", help="print one JSON object (SI units)")
    sp.add_argument("--at", action="append", metavar="INPUT",
                    help="also every relative instant centre at this input (file units; repeatable)")
    add_units(sp)
    sp = add("plot", cmd_plot, "a figure: paths, kinematic diagram, velocity and acceleration curves")
    sp.add_argument("-o", "--output", type=output_path(PLOT_EXTENSIONS), required=True, metavar="OUT",
                    help="output image (.png, .svg or .pdf; .html for an interactive 3D view of a spatial file)")
    sp.add_argument("--steps", type=positive(16), default=CYCLE_STEPS, metavar="N",
                    help=f"samples per turn (default {CYCLE_STEPS})")
    sp.add_argument("--dpi", type=positive(10, MAX_DPI), default=100, help="resolution of a PNG (default 100)")
    sp.add_argument("--positions", type=positive(1), default=None, metavar="K",
                    help="positions drawn in the kinematic diagram (default 6, or 3 for more than four moving links)")
    sp.add_argument("--forces", action="store_true",
                    help="draw the force analysis instead: driving torque and power, reaction hodographs, the forces "
                         "on the diagram and Zhukovsky's lever (planar, one driver)")
    sp.add_argument("--assemblies", action="store_true",
                    help="draw every assembly of the mechanism at one input side by side instead (planar)")
    sp.add_argument("--at", metavar="INPUT", help="with --forces: the input (file units) of the diagram and the lever "
                                                  "(default: where the driving effort peaks); with --centres or "
                                                  "--centrodes: the input drawn (default: the first of the run); with "
                                                  "--assemblies: the first driver's input (default: the sketch's)")
    sp.add_argument("--centres", action="store_true",
                    help="draw every relative instant centre with Kennedy's lines at --at (planar)")
    sp.add_argument("--centrodes", metavar="BODY",
                    help="draw the fixed and moving centrodes of BODY relative to the frame and its inflection "
                         "circle at --at (planar)")
    add_units(sp)
    add_range(sp)
    sp = add("animate", cmd_animate, "an animation of the mechanism over one turn with the traced path")
    sp.add_argument("-o", "--output", type=output_path(ANIMATION_EXTENSIONS), required=True, metavar="OUT",
                    help="output animation (.gif, .mp4 or .html)")
    sp.add_argument("--frames", type=positive(2, MAX_FRAMES), default=60, metavar="N", help="frames per turn (default 60)")
    sp.add_argument("--fps", type=fps_arg, default=20.0, metavar="F",
                    help="frames per second, 0.01 to 1000 (default 20)")
    add_range(sp)
    sp = add("report", cmd_report, "one self-contained HTML page with the structure, analysis, plots and animation")
    sp.add_argument("-o", "--output", type=path_arg, required=True, metavar="DIR", help="output directory (index.html)")
    sp.add_argument("--steps", type=positive(16), default=CYCLE_STEPS, metavar="N",
                    help=f"samples per turn (default {CYCLE_STEPS})")
    sp.add_argument("--frames", type=positive(2, MAX_FRAMES), default=36, metavar="N",
                    help="frames of the embedded animation (default 36)")
    sp.add_argument("--seed", type=seed_arg, default=None, metavar="S",
                    help="a synthesis problem file: the run's random seed (default 1)")
    sp.add_argument("--budget", type=positive(1, MAX_BUDGET), default=None, metavar="N",
                    help="a synthesis problem file: objective evaluations in all")
    sp.add_argument("--at", action="append", metavar="INPUT",
                    help="a section with every relative instant centre at this input (file units; repeatable)")
    add_units(sp)
    add_range(sp)


def _emit(lines) -> None:
    for line in lines:
        print(line)


def _title(m, path) -> str:
    return m.name or Path(path).stem


def cmd_validate(args) -> int:
    """``assur validate FILE``: load and compile the file, print one line on it."""
    from ..engine import compile as compile_
    from ..report.text import validation_line
    m = load_mechanism(args.file)
    if m.dimension == 3 and not any(j.axis for j in m.joints):
        from ..structure.assur import analyse
        print(validation_line(args.file, m, structure=analyse(m)))
        return 0
    print(validation_line(args.file, m, compile_(m)))
    return 0


def cmd_info(args) -> int:
    """``assur info FILE``: structure, parameters and drivers, each printed as soon as it is known (a file
    that does not compile still shows its structure)."""
    from ..analysis.overview import structure_summary
    from ..engine import compile as compile_
    from ..report import text
    m = load_mechanism(args.file)
    if args.at is not None and not args.assemblies:
        raise SpecError([("--at", "is for the assemblies: add --assemblies")])
    if args.assemblies and m.dimension == 3:
        raise SpecError([("--assemblies", "assemblies are listed for planar mechanisms (a spatial R–S–S dyad has "
                                          "its two branches, chosen by [branches])")])
    plan = q = None
    if args.assemblies:     # a bad --at is refused before anything is printed
        from ..report.assemblies import input_values
        plan = compile_(m)
        q = input_values(plan, args.at)
    s = structure_summary(m)
    _emit(text.info_head_lines(m, _title(m, args.file), args.file, s))
    if m.dimension == 3:
        _emit(text.point_lines(m))
        _emit(["atlas: spatial mechanism (the atlas holds planar chains only)"])
        if not any(j.axis for j in m.joints):
            _emit(text.structural_description_lines(m))
            return 0
        plan = compile_(m)
        _emit(text.spatial_plan_lines(plan) + text.parameter_lines(plan))
        return 0
    from ..structure.assur import analyse
    _emit(text.group_lines(s, getattr(analyse(m), "undetermined", ())))
    from ..structure.atlas.identify import identify
    entry = None if m.gears else identify(m)
    _emit([entry.line() if entry else "atlas: a geared mechanism (the atlas holds chains of lower pairs only)"
           if m.gears else "atlas: not a chain of the atlas (two pairs join the same two bodies, "
                           "or a body is joined to nothing)"])
    if plan is None:
        plan = compile_(m)
    from ..analysis.fourbar import four_bar_loops
    _emit([loop.describe() for loop in four_bar_loops(plan)])
    _emit(text.parameter_lines(plan) + text.gait_lines(m))
    if args.assemblies:
        from ..engine import assemblies
        from ..report.assemblies import assembly_lines
        _emit(assembly_lines(plan, assemblies(plan, q)[0], q))
    return 0


def cmd_solve(args) -> int:
    """``assur solve FILE --steps N``: solve a turn (or ``--range``), print an excerpt, write ``--csv``."""
    import sys

    from ..analysis.sampling import sweep_inputs, tracked_point
    from ..engine import solve
    from ..io.output import is_standard_output
    from ..report import table
    # the CSV on standard output (`--csv -`, `--csv /dev/stdout`): the report lines go to stderr, stdout is the CSV
    report = sys.stderr if is_standard_output(args.csv) else sys.stdout
    m, plan = compile_file(args.file)
    q, moving, cyclic = sweep_inputs(plan, args.steps, input_ranges(plan, args))
    state = solve(plan, None, q)
    cols, _, _ = table.solve_columns(plan, args.file_units)
    values = table.solve_table(plan, q, state, args.file_units)
    what = (f"{len(q)} positions of {plan.input_names[moving]} over one turn" if cyclic
            else f"{len(q)} samples of {', '.join(plan.input_names)} over the given range(s)")
    spatial = " (spatial)" if plan.dimension == 3 else ""
    from ..engine.options import ambiguous_note
    n_amb = int(state.ambiguous.sum())
    amb = f" ({ambiguous_note(n_amb)})" if n_amb else ""
    print(f"{args.file}: {what}{spatial}; {state.n_unbuildable} cannot be assembled{amb}", file=report)
    if plan.dimension == 3 and state.n_unbuildable:
        from ..engine.spatial.numpy_backend import unbuildable_message
        print("  " + unbuildable_message(plan, state.inputs, state.valid, state.status), file=report)
    heads, row = table.excerpt(plan, state, values, tracked_point(plan), args.file_units)
    for line in table.excerpt_lines(heads, row, len(q), bool(args.csv)):
        print(line, file=report)
    if args.csv:
        report.flush()
        table.write_csv(args.csv, cols, values)
        print(f"wrote {args.csv} ({len(values)} rows × {len(cols)} columns, "
              f"{'file units and degrees' if args.file_units else 'SI units: m, rad, s'})", file=report)
    return 0


def cmd_analyze(args) -> int:
    """``assur analyze FILE``: the analysis summary of the file's Study as text or ``--json``."""
    from ..analysis.study import Study
    from ..io.output import json_text
    from ..report.analysis import analysis_lines
    m, plan = compile_file(args.file)
    study = Study(plan, steps=args.steps)
    at = _centre_inputs(plan, args.at)
    summary = study.as_dict()
    if at is not None:
        from ..report.centres import centres_dict
        summary["instant_centres"] = centres_dict(study, at)
    if args.json:
        print(json_text({"file": str(args.file), **summary}))
        return 0
    print(f"{_title(m, args.file)}  [{args.file}]" + (" (spatial)" if plan.dimension == 3 else ""))
    _emit(analysis_lines(study, args.units))
    if "forces" in summary:
        from ..report.forces import summary_lines
        print("Forces (N, N·m, W, J):")
        _emit(summary_lines(summary["forces"], plan))
    if at is not None:
        from ..report.centres import centres_lines
        _emit(centres_lines(study, at, args.units))
    return 0


def _centre_inputs(plan, texts):
    """``--at`` values for the instant centres (file units) → SI inputs, or None; SpecError for a spatial file."""
    if not texts:
        return None
    if plan.dimension != 2:
        raise SpecError([("--at", "instant centres are for planar mechanisms")])
    from .forces import parse_at
    return [float(x) for x in parse_at(plan, texts)]


def cmd_plot(args) -> int:
    """``assur plot FILE -o OUT``: the figure of a turn (a 3D view of a spatial file; .html: interactive)."""
    m, plan = compile_file(args.file)
    ext = args.output.suffix.lower()
    if plan.dimension != 3 and ext == ".html":
        raise SpecError([("--output", "an .html view is for spatial mechanisms; use .png, .svg or .pdf")])
    ranges = input_ranges(plan, args)
    if getattr(args, "forces", False):
        if args.assemblies:
            raise SpecError([("--assemblies", "draws the assemblies, --forces the forces: give one of them")])
        return _plot_forces(args, plan, ext)
    if args.assemblies:
        if args.centres or args.centrodes:
            raise SpecError([("--assemblies", "draws the assemblies, --centres/--centrodes the centres: give one "
                                              "of them")])
        if plan.dimension == 3:
            raise SpecError([("--assemblies", "assemblies are drawn for planar mechanisms")])
        from ..engine import assemblies
        from ..plot.assemblies import assemblies_figure
        from ..report.assemblies import assembly_labels, input_text, input_values
        q = input_values(plan, None if args.at is None else [args.at])
        found = assemblies(plan, q)[0]
        fig = assemblies_figure(plan, found, assembly_labels(plan, found), input_text(plan, q),
                                dpi=args.dpi, units=args.units)
        return _save_figure(fig, args, ext)
    if args.centres or args.centrodes:
        return _plot_centres(args, plan, ext, ranges)
    if args.at is not None:
        raise SpecError([("--at", "is for the force, centre, centrode and assembly figures: add --forces, --centres, "
                                  "--centrodes or --assemblies")])
    if plan.dimension == 3:
        from ..plot import spatial as view
        if ext == ".html":
            fig = view.plotly_figure(plan, args.steps, positions=args.positions or 6, ranges=ranges, units=args.units)
            with atomic_file(args.output) as tmp:
                view.write_html(fig, tmp, title=plan.mechanism.name)
            print(f"wrote {args.output}")
            return 0
        fig = view.figure(plan, args.steps, positions=args.positions or 6, ranges=ranges, dpi=args.dpi,
                          units=args.units)
    else:
        from ..plot.figures import mechanism_figure
        fig = mechanism_figure(plan, args.steps, ranges=ranges, positions=args.positions, dpi=args.dpi,
                               units=args.units)
    return _save_figure(fig, args, ext)


def _save_figure(fig, args, ext) -> int:
    """Write a figure to ``args.output`` atomically (in the format of its extension) and close it."""
    from ..plot.draw import close
    try:
        with atomic_file(args.output) as tmp:
            fig.savefig(tmp, format=ext[1:], dpi=args.dpi)
    finally:
        close(fig)
    print(f"wrote {args.output}")
    return 0


def _plot_centres(args, plan, ext, ranges) -> int:
    """``assur plot FILE --centres`` / ``--centrodes BODY``: the instant centres or the centrodes at ``--at``."""
    from ..analysis.study import Study
    from ..plot.centres import centres_figure, centrodes_figure
    if plan.dimension != 2:
        raise SpecError([("--centres", "instant centres and centrodes are for planar mechanisms")])
    study = Study(plan, steps=args.steps, ranges=ranges)
    at = _centre_inputs(plan, [args.at]) if args.at is not None else None
    q = at[0] if at else float(study.q[0])
    if args.centrodes:
        if args.centrodes not in plan.body_names[1:]:
            raise SpecError([("--centrodes", f"unknown body {args.centrodes!r} (bodies: "
                                             f"{', '.join(plan.body_names[1:])})")])
        fig = centrodes_figure(study, args.centrodes, at=q, dpi=args.dpi)
    else:
        fig = centres_figure(study, q, dpi=args.dpi)
    return _save_figure(fig, args, ext)


def _plot_forces(args, plan, ext) -> int:
    """``assur plot FILE --forces -o OUT``: the sheet of force figures."""
    from ..analysis.study import Study
    from ..kinetostatics.overview import NO_LOADS, check_one_driver, has_loads
    from ..plot.forces import forces_figure
    from .forces import parse_at
    if plan.dimension == 3:
        raise SpecError([("--forces", "the force figures are for planar mechanisms")])
    if not has_loads(plan.mechanism):          # a sheet of zeros would look like a result: nothing is drawn
        raise SpecError([("--forces", f"{NO_LOADS}; nothing was drawn")])
    check_one_driver(plan)
    at = None if args.at is None else float(parse_at(plan, [args.at])[0])
    fig = forces_figure(plan, at=at, cycle=Study(plan, steps=args.steps).force_cycle, dpi=args.dpi)
    return _save_figure(fig, args, ext)


def cmd_animate(args) -> int:
    """``assur animate FILE -o OUT``: an animation of a turn as GIF, MP4 or HTML."""
    from ..plot.animation import save_animation
    from ..plot.draw import close
    from ..report.text import format_number
    m, plan = compile_file(args.file)
    ranges = input_ranges(plan, args)
    if plan.dimension == 3:
        from ..plot import spatial as view
        if args.output.suffix.lower() in (".html", ".htm"):
            fig = view.plotly_figure(plan, frames=args.frames, ranges=ranges)
            with atomic_file(args.output) as tmp:
                view.write_html(fig, tmp, title=plan.mechanism.name)
            print(f"wrote {args.output} ({args.frames} frames at {format_number(args.fps)} fps)")
            return 0
        fig, anim = view.animation(plan, args.frames, args.fps, ranges=ranges)
    else:
        from ..plot.animation import animation
        fig, anim = animation(plan, args.frames, args.fps, ranges=ranges)
    try:
        with atomic_file(args.output) as tmp:
            save_animation(anim, tmp, args.fps, progress=frame_progress())
    finally:
        close(fig)
    print(f"wrote {args.output} ({args.frames} frames at {format_number(args.fps)} fps)")
    return 0


def cmd_report(args) -> int:
    """``assur report FILE -o DIR``: the page of a mechanism or of a gear or wheel-step design."""
    fmt = document_format(args.file)
    if fmt == "assur-synth/1":      # a synthesis problem: run it, then the page of its best design
        from ..report.synthesis import write_synthesis_report
        path, result = write_synthesis_report(args.file, args.output, seed=1 if args.seed is None else args.seed,
                                              budget=args.budget)
        print(f"wrote {path} (objective {result.objective!r} after {result.evaluations} evaluations, "
              f"stopped: {result.stopped})" if result.feasible else f"wrote {path} (no feasible design found)")
        return 0
    for opt in ("seed", "budget"):
        if getattr(args, opt) is not None:
            raise SpecError([(f"--{opt}", "is for a synthesis problem file (format assur-synth/1)")])
    if fmt in ("assur-gears/1", "assur-wheelstep/1"):
        from ..report.documents import write_document_report
        path = write_document_report(args.file, args.output, frames=args.frames)
        print(f"wrote {path}")
        return 0
    from ..report.mechanism import write_report
    m, plan = compile_file(args.file)
    path = write_report(plan, args.output, steps=args.steps, frames=args.frames, ranges=input_ranges(plan, args),
                        source=str(args.file), units=args.units, progress=frame_progress("animation frames"),
                        at=_centre_inputs(plan, args.at))
    print(f"wrote {path}")
    return 0
