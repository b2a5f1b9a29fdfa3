"""``assur forces FILE``: the force analysis of a mechanism file (kinetostatics by Assur groups).

Without ``--at``: one crank turn (or the linear driver's working stroke) and the summary of the design
quantities; with ``--at``: the reactions, slide forces and couples, driving effort and power at each input.
``--json`` prints one JSON object, ``--csv OUT`` writes the per-sample rows.
"""
from __future__ import annotations

import contextlib
import math
import sys
from pathlib import Path

import numpy as np

from ..analysis.sampling import CYCLE_STEPS
from ..errors import SpecError
from .args import compile_file, path_arg, positive


def register(sub) -> None:
    """Add ``assur forces`` to the argparse sub-parsers ``sub``."""
    help_ = "reactions, driving torque or force, power and the design quantities of a cycle (kinetostatics)"
    sp = sub.add_parser("forces", help=help_, description=help_)
    sp.add_argument("file", metavar="FILE", help="mechanism file (.toml)")
    sp.add_argument("--steps", type=positive(2), default=CYCLE_STEPS, metavar="N",
                    help=f"samples of the turn or stroke (default {CYCLE_STEPS})")
    sp.add_argument("--at", action="append", metavar="INPUT",
                    help="the driver's input in the file's units (degrees of a deg file, the length unit for a "
                         "linear driver); repeat for several inputs")
    sp.add_argument("--json", action="store_true", help="print one JSON object (SI units; null where singular)")
    sp.add_argument("--csv", type=path_arg, metavar="OUT", help="write one row per sample to this CSV file")
    sp.add_argument("--friction", action="store_true", help="include the file's Coulomb friction")
    sp.set_defaults(func=cmd_forces)


def parse_at(plan, texts) -> np.ndarray:
    """The ``--at`` values (file units) → SI inputs (n,); SpecError naming a value that is not a number or lies
    outside a linear driver's working stroke."""
    from ..report.forces import input_unit
    fac, unit = input_unit(plan)
    out = []
    for t in texts:
        try:
            v = float(t)
        except ValueError:
            v = math.nan
        if not math.isfinite(v):
            raise SpecError([("--at", f"must be a number (the driver's input in {unit}): {t!r}")])
        out.append(v * fac)
    d = plan.mechanism.drivers[0]
    if plan.input_kinds[0] != "rotary" and d.range is not None:
        lo, hi = sorted(float(x) for x in d.range)
        for t, v in zip(texts, out):
            if not lo - 1e-12 <= v <= hi + 1e-12:
                raise SpecError([("--at", f"{t} {unit} is outside the working stroke {lo / fac:g}…{hi / fac:g} "
                                          f"{unit} (range of driver {d.name!r})")])
    return np.asarray(out, dtype=float)


def cmd_forces(args) -> int:
    """``assur forces FILE``: the cycle's (or ``--at`` inputs') forces as text or ``--json``; ``--csv`` the rows."""
    from ..io.output import check_writable, is_standard_output, write_csv
    from ..report import forces as text
    if args.csv:
        check_writable(args.csv)      # before any work: a file, a new name, `-`, a device or a pipe (io/output.py)
    # the CSV on standard output: the report goes to stderr, stdout is the CSV alone
    with contextlib.redirect_stdout(sys.stderr) if is_standard_output(args.csv) else contextlib.nullcontext():
        f = _report(args)
    if args.csv:
        header, rows = text.csv_table(f)
        write_csv(args.csv, header, rows)
        if not args.json:
            print(f"wrote {args.csv} ({len(rows)} rows × {len(header)} columns)",
                  file=sys.stderr if is_standard_output(args.csv) else sys.stdout)
    return 0


def _report(args):
    """Print the forces' report (text or JSON) and return the Forces whose rows ``--csv`` writes."""
    from ..io.output import json_text
    from ..kinetostatics import forces
    from ..kinetostatics.overview import NO_LOADS, check_one_driver, force_cycle, force_summary, has_loads
    from ..report import forces as text
    m, plan = compile_file(args.file)
    check_one_driver(plan)
    note = None if has_loads(m) else NO_LOADS
    if note and not args.json:
        print(f"note: {note}")             # the first line: the zeros below are not a result
    if args.at:
        q = parse_at(plan, args.at)
        f = forces(plan, None, q[:, None], friction=args.friction)
        bad = [t for t, ok, sg in zip(args.at, np.asarray(f.state.valid), np.asarray(f.singular)) if not ok]
        if bad:
            raise SpecError([("--at", f"the mechanism cannot be assembled at {', '.join(bad)}")])
        if args.json:
            data = {"note": note} if note else {}
            data |= {"file": str(args.file), "samples": [text.at_dict(f, i) for i in range(len(q))]}
            if args.friction:
                data["friction"] = {"iterations": int(f.iterations), "converged": bool(f.converged)}
            print(json_text(data))
        else:
            print(f"{m.name or Path(args.file).stem}  [{args.file}]: forces at {len(q)} input(s)")
            for i in range(len(q)):
                for line in text.at_lines(f, i):
                    print(line)
            if args.friction:
                print(f"friction: {f.iterations} iterations ({'converged' if f.converged else 'NOT converged'})")
    else:
        from ..analysis.study import Study
        study = Study(plan, steps=args.steps)
        cyc = study.force_cycle if not args.friction else force_cycle(study, friction=True)
        f = cyc.forces
        s = force_summary(cyc, friction=args.friction)
        if args.json:
            print(json_text({"note": s.pop("note")} | {"file": str(args.file), **s} if note else
                            {"file": str(args.file), **s}))
        else:
            print(f"{m.name or Path(args.file).stem}  [{args.file}]: forces over one "
                  f"{'turn' if cyc.turn else 'working stroke'} (N, N·m, W, J)")
            for line in text.summary_lines({k: v for k, v in s.items() if k != "note"}, plan):   # noted above
                print(line)
    return f
