"""``assur simulate FILE``: how the machine runs on its motor (forward dynamics, docs/dynamics.md).

Runs the mechanism on the file's ``[motor]`` (or ``--motor``) from rest to its periodic steady state (or for
``--time`` seconds or ``--cycles`` turns) and prints the start-up time to 95 % of the steady speed, the steady mean
speed and its fluctuation δ beside the kinetostatic estimate, the motor's peak torque, current and power and every
joint's peak reaction over the run. ``--csv`` writes the samples (time, input, speed, acceleration, motor, every
joint's reaction), ``--json`` prints the summary, ``--plot`` draws speed against time at start-up.
"""
from __future__ import annotations

from pathlib import Path

from ..errors import SpecError
from .args import finite_float, output_path, path_arg, positive, positive_float

PLOT_EXTENSIONS = (".png", ".svg", ".pdf")


def register(sub) -> None:
    """Add ``assur simulate`` to the argparse sub-parsers ``sub`` (``assur export --to mjcf`` is a row of the
    export table, :mod:`assur.cli.exchange`)."""
    help_ = "run the mechanism on its motor: start-up, steady speed and fluctuation, stall, reactions over time"
    sp = sub.add_parser("simulate", help=help_, description=help_)
    sp.add_argument("file", metavar="FILE", help="mechanism file (.toml)")
    sp.add_argument("--motor", metavar="KEYS",
                    help='the motor instead of the file\'s [motor]: its keys as in the file, e.g. \'kind = "dc", '
                         'stall_torque = "2 N*m", no_load_speed = "3000 rpm", gear_ratio = 10\'; "none": no motor '
                         "(the mechanism moves freely from its file speed)")
    span = sp.add_mutually_exclusive_group()
    span.add_argument("--time", type=positive_float, metavar="T", help="run T seconds (default: to steady state)")
    span.add_argument("--cycles", type=positive(1), metavar="N", help="run N turns of the input")
    sp.add_argument("--from-rest", action="store_true", help="start at rest (the default with a motor)")
    sp.add_argument("--start", type=finite_float, metavar="INPUT",
                    help="the input to start at, in the file's units (default: the sketch's)")
    sp.add_argument("--speed", metavar="SPEED", help='the input speed to start with, e.g. "100 rpm" (default: rest '
                                                     "with a motor, the driver's file speed without)")
    sp.add_argument("--friction", action="store_true", help="include the file's Coulomb joint friction (slow)")
    sp.add_argument("--method", default="auto", choices=("auto", "DOP853", "RK45", "Radau", "BDF", "LSODA"),
                    help="the integrator (default auto: DOP853, Radau when the motor makes the equation stiff)")
    sp.add_argument("--exact", action="store_true", help="evaluate the equation's terms exactly at every step instead "
                                                         "of interpolating them (slower)")
    sp.add_argument("--samples", type=positive(2), metavar="N", help="output samples (default 96 per turn)")
    sp.add_argument("--json", action="store_true", help="print one JSON object (SI units)")
    sp.add_argument("--csv", type=path_arg, metavar="OUT", help="write one row per sample to this CSV file")
    sp.add_argument("--plot", type=output_path(PLOT_EXTENSIONS), metavar="F",
                    help="draw speed against time at start-up beside the kinetostatic estimate (.png, .svg, .pdf)")
    sp.set_defaults(func=cmd_simulate)


def _start(plan, args):
    """(q0, speed0) in SI from --start, --speed and --from-rest (None: the defaults)."""
    from ..io.units import parse_speed
    from ..report.forces import input_unit
    q0 = speed0 = None
    if args.start is not None:
        from ..dynamics.api import check_start
        q0 = args.start * input_unit(plan)[0]
        check_start(plan, q0, name="--start", given=args.start)
    if args.speed is not None:
        if args.from_rest:
            raise SpecError([("--speed", "give --speed or --from-rest, not both")])
        try:
            speed0 = parse_speed(args.speed, plan.input_kinds[0], plan.mechanism.units)
        except SpecError as exc:
            raise SpecError([("--speed", str(exc))]) from None
    if args.from_rest:
        speed0 = 0.0
    return q0, speed0


def cmd_simulate(args) -> int:
    from ..dynamics.cycle import MotorRun, run_forces
    from ..dynamics.compare import kinetostatic_estimate
    from ..dynamics.api import simulate
    from ..io.output import atomic_file, check_writable, json_text, write_csv
    from ..report import dynamics as text
    from .args import compile_file
    if args.csv:
        check_writable(args.csv)      # before any work: a file, a new name, `-`, a device or a pipe (io/output.py)
    if args.plot:
        check_writable(args.plot)
    m, plan = compile_file(args.file)
    motor = False if args.motor is not None and args.motor.strip().lower() == "none" else args.motor
    if motor is None and m.motor is None and args.time is None and args.cycles is None:
        raise SpecError([("--motor", "the file has no [motor]: give one with --motor 'kind = \"dc\", stall_torque = "
                                     "…, no_load_speed = …', or run freely with --motor none --time T")])
    q0, speed0 = _start(plan, args)
    sim = simulate(plan, time=args.time, cycles=args.cycles, motor=motor, q0=q0, speed0=speed0,
                   friction=args.friction, method=args.method, mode="exact" if args.exact else "series",
                   samples=args.samples)
    run = MotorRun(sim, kinetostatic_estimate(sim), run_forces(sim))
    if args.plot:
        from ..plot.draw import close
        from ..plot.dynamics import startup_figure
        fig = startup_figure(run)
        try:
            with atomic_file(args.plot) as tmp:
                fig.savefig(tmp, format=args.plot.suffix.lower()[1:])
        finally:
            close(fig)
    if args.csv:
        header, rows = text.csv_table(run)
        write_csv(args.csv, header, rows)
    if args.json:
        print(json_text({"file": str(args.file), **run.summary()}))
    else:
        print(f"{m.name or Path(args.file).stem}  [{args.file}]: run on the motor")
        for line in text.summary_lines(run):
            print(line)
        if args.csv:
            print(f"wrote {args.csv} ({sim.t.size} rows)")
        if args.plot:
            print(f"wrote {args.plot}")
    return 0
