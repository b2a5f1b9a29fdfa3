"""``assur synth PROBLEM.toml``: dimensional synthesis from a problem file (``format = "assur-synth/1"``).

Prints the objective reached, the evaluations, the wall time of the whole command (loading the problem,
starting and stopping the workers included) and the best design's variables and metrics; ``-o BEST.toml`` writes the best design as a mechanism file, ``--json`` prints one JSON
object. Ctrl-C, ``--budget`` and ``--time`` end the run early and keep the best design found; an interrupted run
(Ctrl-C) still reports and writes it, then exits with status 130 like every interrupted command (0 done, 3 no
feasible design, 1 bad input or a missing optional package such as cma for ``--method cmaes``).
"""
from __future__ import annotations

import sys
from pathlib import Path

from ..report.text import format_number
from .args import MAX_BUDGET, MAX_WORKERS, output_path, path_arg, positive, positive_float, seed_arg

#: the exit status of an interrupted run (as :mod:`assur.cli.main` uses for every command)
INTERRUPTED = 130
#: assur.synthesis.solver's METHODS, POLISHES and DEFAULT_BUDGET, repeated here so that the command line starts
#: without importing the synthesis package (tests/test_synthesis_defaults.py checks that they agree)
METHODS = ("restart", "de", "cmaes", "local", "lshade")
POLISHES = ("auto", "least_squares", "nelder-mead", "l-bfgs-b", "none")
DEFAULT_BUDGET = 300_000


def register(sub) -> None:
    """Add ``synth`` to the argparse sub-parsers ``sub``."""
    sp = sub.add_parser("synth", help="dimensional synthesis: optimise a mechanism's dimensions for a problem file",
                        description="Minimise a synthesis problem (format assur-synth/1): differential evolution "
                                    "restarted on stagnation (the default), one differential evolution, CMA-ES or a "
                                    "local polish, with multi-start, on this process, local workers or a Dask "
                                    "cluster. Options not given come from the file's [solver] table, then from the "
                                    "built-in defaults (method restart, budget 300000 evaluations).")
    sp.add_argument("file", metavar="PROBLEM", help="synthesis problem file (.toml)")
    sp.add_argument("-o", "--output", type=path_arg, metavar="BEST", help="write the best design as a mechanism file")
    sp.add_argument("--method", choices=METHODS, default=None,
                    help="global method (default restart: differential evolution restarted on stagnation)")
    sp.add_argument("--polish", choices=POLISHES, default=None,
                    help="local refinement of each start's (or restart's) best (default auto)")
    sp.add_argument("--seed", type=seed_arg, default=None, metavar="S", help="random seed (reproducible runs)")
    sp.add_argument("--budget", type=positive(1, MAX_BUDGET), default=None, metavar="N",
                    help=f"objective evaluations in all (default {DEFAULT_BUDGET} with the restart method)")
    sp.add_argument("--time", type=positive_float, default=None, metavar="T",
                    help="wall-time limit in seconds for the whole run (every start, worker, restart and polish); it "
                         "ends within one evaluation batch of the limit (docs/synthesis.md)")
    sp.add_argument("--starts", type=positive(1), default=None, metavar="K", help="independent starts (default 1)")
    sp.add_argument("--popsize", type=positive(2), default=None, metavar="P",
                    help="population per variable (default 15)")
    sp.add_argument("--maxiter", type=positive(1), default=None, metavar="G",
                    help="generations per start or restart (default 1000)")
    sp.add_argument("--target", type=float, default=None, metavar="F",
                    help="stop at the first feasible design with objective ≤ F (later starts are skipped)")
    sp.add_argument("--strategy", default=None, metavar="NAME",
                    help="scipy differential-evolution strategy (default best1bin; e.g. rand1bin, currenttobest1bin)")
    grp = sp.add_mutually_exclusive_group()
    grp.add_argument("--workers", type=positive(1, MAX_WORKERS), default=None, metavar="N", help="local worker processes")
    grp.add_argument("--dask", metavar="ADDR", default=None, help="address of a Dask scheduler (tcp://host:port)")
    sp.add_argument("--plot", type=output_path((".png", ".svg", ".pdf")), default=None, metavar="FIG",
                    help="draw the targets against the best design, the per-target distances and the convergence "
                         "history (.png, .svg or .pdf)")
    sp.add_argument("--backend", choices=("numpy", "numba"), default=None,
                    help="the engine of every evaluation (default: numba, when installed, for a run long enough to "
                         "win back the first compile of its kernels — about 10 s of numpy evaluations by an estimate "
                         "from the problem's size, or a time limit of at least 60 s; numpy for a shorter run)")
    sp.add_argument("--json", action="store_true", help="print one JSON object")
    sp.add_argument("--quiet", action="store_true", help="no progress bar")
    ex = sp.add_argument_group("exact synthesis (closed form, no optimiser): function targets (Freudenstein) or "
                                 "3–5 poses (Burmester) of a four-bar")
    ex.add_argument("--exact", action="store_true",
                    help="solve the problem's targets in closed form and print the ranked four-bars (residual, "
                         "Grashof class, rotatability, defects); -o writes the best")
    ex.add_argument("--grashof", default=None, metavar="CLASS",
                    help="with --exact: keep only this Grashof class (crank-rocker, double-crank, rocker-crank, "
                         "double-rocker, triple-rocker, grashof, crank)")
    ex.add_argument("--limit", type=positive(1), default=20, metavar="K", help="with --exact: candidates kept (20)")
    ex.add_argument("--report", type=path_arg, default=None, metavar="DIR",
                    help="with --exact: write the page of the candidates (DIR/index.html, DIR/best.toml)")
    sp.set_defaults(func=cmd_synth)


#: the optimisers' options, which an exact synthesis refuses (it has no search to set)
SEARCH_OPTIONS = ("method", "polish", "seed", "budget", "time", "starts", "popsize", "maxiter", "target", "strategy",
                  "workers", "dask", "plot", "backend")


def cmd_exact(args) -> int:
    """``assur synth PROBLEM --exact``: the closed-form four-bars of the problem's targets, ranked."""
    from ..errors import SpecError
    from ..io.mechanism_file import dumps
    from ..io.output import atomic_file, check_output_directory, check_writable, json_text
    from ..synthesis import load_problem
    from ..synthesis.exact import GRASHOF_FILTERS
    from ..synthesis.exact_task import as_dict, exact_task, table_rows
    given = [f"--{o}" for o in SEARCH_OPTIONS if getattr(args, o, None) is not None]
    if given:
        raise SpecError([(", ".join(given), "is an option of the optimisers; --exact solves in closed form")])
    if args.grashof is not None and args.grashof not in GRASHOF_FILTERS:
        raise SpecError([("--grashof", f"must be one of {', '.join(GRASHOF_FILTERS)}: {args.grashof!r}")])
    if args.output is not None:
        check_writable(args.output)
    if args.report is not None:
        check_output_directory(args.report)
    problem = load_problem(args.file)
    task = exact_task(problem, grashof=args.grashof, limit=args.limit)
    c = task.candidates
    written = page = None
    if args.output is not None and len(c):
        with atomic_file(args.output) as tmp:
            tmp.write_text(dumps(c[0].mechanism, clean=True), encoding="utf-8")
        written = str(args.output)
    if args.report is not None:
        from ..report.exact import write_exact_report
        page = str(write_exact_report(problem, task, args.report, source=str(args.file)))
    if args.json:
        print(json_text({"problem": problem.name, "source": str(args.file), **as_dict(task), "written": written,
                         "report": page}))
        return 0 if len(c) else 3
    print(f"{problem.name or Path(args.file).stem}  [{args.file}]: exact synthesis")
    print(f"method: {task.method}")
    head, rows = table_rows(task)
    widths = [max(len(str(r[i])) for r in [head] + rows) for i in range(len(head))]
    for r in [head] + rows:
        print("  " + "  ".join(str(v).ljust(w) if i in (2, 3, 5, 6) else str(v).rjust(w)
                               for i, (v, w) in enumerate(zip(r, widths))).rstrip())
    print(f"ranked by {c.criterion}")
    if c.counts:
        print("dropped: " + ", ".join(f"{k}: {v}" for k, v in c.counts.items()))
    if not len(c):
        print(f"error: {c.reason}", file=sys.stderr)
    for what in (written, page):
        if what:
            print(f"wrote {what}")
    return 0 if len(c) else 3


def cmd_synth(args) -> int:
    if args.exact:
        return cmd_exact(args)
    for opt in ("grashof", "report"):
        if getattr(args, opt) is not None:
            from ..errors import SpecError
            raise SpecError([(f"--{opt}", "is an option of the exact synthesis: add --exact")])
    import time
    started = time.monotonic()         # --time and the wall time printed count from here: the whole run
    from ..io.mechanism_file import dumps
    from ..io.output import atomic_file, check_writable, json_text
    from ..synthesis import load_problem, make_executor, synthesize
    check_packages(args)               # a missing optional package: say so before any work
    problem = load_problem(args.file)
    for out in (args.output, args.plot):
        if out is not None:
            check_writable(out)       # fail on an unusable output before the run, not after it
    progress = not args.quiet and not args.json and sys.stderr.isatty()
    if progress and _missing("tqdm"):
        from ..synthesis.optimize import TQDM_INSTALL
        print(f"note: no progress bar without the optional package 'tqdm': {TQDM_INSTALL}", file=sys.stderr)
    executor = make_executor(args.workers, args.dask)
    try:
        # the limit covers the whole command: what loading the problem took is spent already
        left = None if args.time is None else max(args.time - (time.monotonic() - started), 1e-3)
        result = synthesize(problem, args.method, seed=args.seed, budget=args.budget, time_limit=left,
                            starts=args.starts, polish=args.polish, popsize=args.popsize, maxiter=args.maxiter,
                            executor=executor, progress=progress, target=args.target, strategy=args.strategy,
                            backend=args.backend)
    finally:
        executor.close()
    result.seconds = time.monotonic() - started      # the real wall time: loading, workers' start and stop included
    if args.time is not None:
        result.settings["time"] = args.time
    written = unwritten = None
    best = None if args.output is None else result.mechanism()
    design = None if best is None else result.design_plan(best)
    if best is not None and design is None:
        # a file assur would refuse to load is no answer: nothing is written (the design is reported)
        unwritten = (f"not written: {args.output} (the best design does not assemble at its sketch, so its "
                     f"mechanism file would not load)")
    elif best is not None:
        text = dumps(best, clean=True)
        with atomic_file(args.output) as tmp:
            tmp.write_text(text, encoding="utf-8")
        written = str(args.output)
    plotted = None
    if args.plot is not None:
        from ..plot.draw import close
        from ..plot.synthesis import synthesis_figure
        fig = synthesis_figure(result)
        try:
            with atomic_file(args.plot) as tmp:
                fig.savefig(tmp, format=args.plot.suffix.lower()[1:])
        finally:
            close(fig)
        plotted = str(args.plot)
    from ..synthesis.space import solved_per_design
    solved = solved_per_design(problem)
    if args.json:
        d = result.as_dict()
        d["solved_per_design"] = solved
        d["written"] = written
        d["plot"] = plotted
        if unwritten:
            d["not_written"] = unwritten
        print(json_text(d))
        return _status(result, written)
    u = problem.length_unit
    du = u                                 # the deviation's unit: function targets measure angle errors
    if problem.targets is not None and problem.targets.kind == "function":
        du = problem.angle_unit
    unit = {"distance": f" {du}", "squared": f" {du}²"}.get(problem.deviation, "")
    print(f"{problem.name or Path(args.file).stem}  [{args.file}]")
    if result.feasible:
        print(f"objective: {result.objective:.10g}{unit} ({problem.deviation} deviation"
              f"{' + terms' if problem.terms else ''})")
    else:
        print(f"no feasible design found: least total violation {result.violation:.6g}")
    print(f"constraints: {', '.join(problem.constraints)}")
    if solved:
        parts = [f"{', '.join(solved[k])} ({k})" for k in ("free timing", "placement") if k in solved]
        size = f"; the size through {', '.join(solved['size'])}" if "size" in solved else ""
        print("solved per design: " + "; ".join(parts) + size)
    print(f"evaluations: {result.evaluations}  wall time: {result.seconds:.2f} s  stopped: {result.stopped}  "
          f"({result.settings['method']}, {len(result.starts)} start(s), seed {args.seed}, {result.executor})")
    print("settings: " + settings_line(result.settings))
    warning = result.bound_warning()
    if warning:
        print(warning)
    print("best design:")
    width = max(len(n) for n in problem.names)
    for name, v, var in zip(problem.names, result.x_file, problem.variables):
        vu = u if var.kind == "length" else problem.angle_unit if var.kind == "angle" else ""
        print(f"  {name:<{width}} = {format_number(float(v))} {vu}".rstrip())
    q = result.details["quantities"]
    if "distances" in q:
        print("target distances: " + ", ".join(format_number(d) for d in q["distances"]) + f" {du}")
    for k in sorted(q):
        if k not in ("distances", "offsets", "deviation") and not isinstance(q[k], list):
            print(f"  {k}: {format_number(q[k])}")
    bad = {k: v for k, v in result.details["violations"].items() if v}
    if bad:
        print("violated: " + ", ".join(f"{k} {v:.4g}" for k, v in bad.items()))
    g = result.gait(design)
    if g is not None:
        s = problem.length_scale
        print(f"gait (exact): step {format_number(g.step_length * s)} {u}, lift {format_number(g.lift * s)} {u}, "
              f"sag {format_number(g.sag * s)} {u}, duty {format_number(g.duty_factor)}, support speed "
              f"{format_number(g.support_speed.min * s)}…{format_number(g.support_speed.max * s)} {u}/s")
    if written:
        print(f"wrote {written}")
    if unwritten:
        print(unwritten)
    if plotted:
        print(f"wrote {plotted}")
    return _status(result, written)


def settings_line(settings: dict) -> str:
    """The run's settings with where each came from: ``method restart (default), budget 20000 (file), …``."""
    sources = settings.get("sources", {})
    shown = []
    for key in ("method", "budget", "time", "target", "starts", "popsize", "strategy", "polish", "maxiter", "backend"):
        v = settings.get(key)
        if v is None:
            continue
        where = {"file": "file [solver]", "given": "option"}.get(sources.get(key), "default")
        shown.append(f"{key} {format_number(v) if isinstance(v, float) else v} ({where})")
    return ", ".join(shown)


def _status(result, written) -> int:
    """The exit status of a finished run: 130 interrupted (Ctrl-C; the best design so far is reported and
    written), 3 no feasible design, else 0."""
    if result.stopped == "interrupted":
        kept = f"; the best design found so far was written to {written}" if written else \
            "; the best design found so far is reported above"
        print(f"error: interrupted{kept}", file=sys.stderr)
        return INTERRUPTED
    return 0 if result.feasible else 3


def _missing(package: str) -> bool:
    """Whether an optional package cannot be found (without importing it)."""
    import importlib.util
    try:
        return importlib.util.find_spec(package) is None
    except (ImportError, ValueError):
        return True


def check_packages(args) -> None:
    """Raise MissingPackageError (with the install command) when an option needs an optional package that is not
    installed: ``--method cmaes`` needs cma, ``--dask`` needs dask.distributed."""
    from ..errors import require
    from ..synthesis.executors import DASK_INSTALL
    from ..synthesis.optimize import CMA_INSTALL
    if args.method == "cmaes":
        require("cma", "--method cmaes", CMA_INSTALL)
    if args.dask:
        require("distributed", "--dask", DASK_INSTALL)
    if getattr(args, "backend", None) == "numba":
        require("numba", "--backend numba", "pip install numba (or pip install 'assur[fast]')")
