"""``assur atlas --walking-legs``: the 1-DOF mechanisms of 6 or 8 links with a crank at the frame, a foot point on
each link, dimensioned by a short gait synthesis and ranked (docs/atlas.md, "Walking legs ranked by gait"); the
command-line face of :mod:`assur.synthesis.legs` and :mod:`assur.report.legs`.

Without ``-o`` it prints the ranking (``--json``: one JSON object, the mechanism files' texts left out); with
``-o DIR`` it also writes the report page ``DIR/index.html``, ``DIR/ranking.json`` and each entry's mechanism file
and drawing. ``--workers N`` runs the candidates on N local processes, ``--dask ADDR`` on a Dask cluster: the same
numbers as in-process for the same ``--seed``.
"""
from __future__ import annotations

import sys


def add_arguments(sp) -> None:
    """The walking-leg options of ``assur atlas``."""
    from .args import MAX_BUDGET, MAX_WORKERS, nonnegative_float, positive, seed_arg
    g = sp.add_argument_group("walking legs (with --walking-legs)")
    g.add_argument("--budget", type=positive(1, MAX_BUDGET), default=None, metavar="N",
                   help="objective evaluations per candidate, over its starts (default 8000)")
    g.add_argument("--starts", type=positive(1), default=None, metavar="K", help="starts per candidate (default 4)")
    g.add_argument("--seed", type=seed_arg, default=None, metavar="S", help="random seed of the ranking (default 0)")
    g.add_argument("--rank", choices=("gait", "window"), default=None,
                   help="rank by the search's gait objective (default) or by the widest constant-speed window the "
                        "co-design screen passes (docs/codesign.md)")
    g.add_argument("--clearance", type=nonnegative_float, default=None, metavar="R",
                   help="the foot must rise at least R crank lengths above its support in the swing (lift − sag; "
                        "default 0: no limit, a foot may retrace its support)")
    g.add_argument("--window-budget", type=positive(0, MAX_BUDGET), default=None, metavar="N",
                   help="with --rank window: designs of the window-widening search per candidate (default 450; 0: "
                        "rank the gait search's designs as they are)")
    g.add_argument("--triads", action="store_true",
                   help="deprecated, ignored: every candidate is dimensioned now, those with a class III or IV group "
                        "included")
    g.add_argument("--limit", type=positive(1), default=None, metavar="M",
                   help="rank only the first M candidates (a quick look)")
    ex = g.add_mutually_exclusive_group()
    ex.add_argument("--workers", type=positive(1, MAX_WORKERS), default=None, metavar="N", help="local worker processes")
    ex.add_argument("--dask", metavar="ADDR", default=None, help="address of a Dask scheduler (tcp://host:port)")


def _bad(option: str, message: str):
    from ..errors import SpecError
    return SpecError([(option, message)])


def cmd_walking_legs(args) -> int:
    """``assur atlas --walking-legs --links 6|8 ...``."""
    from ..errors import require
    from ..synthesis.executors import DASK_INSTALL, make_executor
    from ..synthesis.legs import FAILED, leg_candidates, rank_legs
    if args.links not in (6, 8):
        raise _bad("--links", f"walking legs are ranked for 6 or 8 links: {args.links}")
    if args.dof not in (None, 1):
        raise _bad("--dof", f"walking legs are 1-DOF mechanisms: leave out --dof or give 1, not {args.dof}")
    if args.dask:
        require("distributed", "--dask", DASK_INSTALL)
    if args.output is not None:
        from ..io.output import check_output_directory
        check_output_directory(args.output)
    settings = {k: getattr(args, k) for k in ("budget", "starts", "seed", "rank", "window_budget", "clearance")
                if getattr(args, k) is not None}
    if args.window_budget is not None and args.rank != "window":
        raise _bad("--window-budget", "only with --rank window")
    if args.triads:
        print("note: --triads is deprecated and ignored: every candidate is dimensioned now, those with a class III "
              "or IV group included", file=sys.stderr)
    candidates = leg_candidates(args.links)
    if args.limit is not None:
        candidates = candidates[:args.limit]
    print(f"{len(candidates)} walking-leg candidates of {args.links} links", file=sys.stderr)

    def progress(done, total):
        # on a terminal one line counts up; elsewhere (a log, a pipe) each count is its own line, so that other
        # notes (a kernel being compiled) never run into it
        live = sys.stderr.isatty() and done < total
        line = f"  {done}/{total} candidates dimensioned"
        print("\r" + line if live else line, end="" if live else "\n", file=sys.stderr, flush=True)

    executor = make_executor(args.workers, args.dask)
    try:
        ranking = rank_legs(args.links, settings=settings, executor=executor, candidates=candidates,
                            progress=progress)
    finally:
        executor.close()
    if args.output is not None:
        from ..report.legs import write_leg_ranking
        write_leg_ranking(ranking, args.output, candidates)
    for e in ranking.entries:
        if (e.get("skipped") or "").startswith(FAILED):
            print(f"warning: {e['name']} ({e['key']}) failed inside assur and is listed undimensioned: "
                  f"{e['skipped'][len(FAILED):]} (please report it)", file=sys.stderr)
    if args.json:
        from ..io.output import json_text
        data = ranking.as_dict()
        for e in data["entries"]:
            e.pop("mechanism", None)
        print(json_text(data))
        return 0
    _print(ranking)
    if args.output is not None:
        print(f"wrote {args.output}/index.html, ranking.json and {len(ranking.entries)} mechanism files")
    return 0


def _print(ranking) -> None:
    from ..report.legs import HEAD, WINDOW_HEAD, leg_rows
    rows = leg_rows(ranking.entries)
    head = HEAD + WINDOW_HEAD if rows and len(rows[0]) > len(HEAD) else HEAD
    widths = [max(len(h), *(len(r[i]) for r in rows)) for i, h in enumerate(head)]
    s = ranking.settings
    by = "the widest constant-speed window" if s.get("rank") == "window" else "gait"
    print(f"walking legs of {ranking.links} links ranked by {by} ({s['budget']} evaluations, {s['starts']} starts "
          f"per candidate, seed {s['seed']}, {ranking.executor}, {ranking.seconds:.0f} s)")
    print("  " + "  ".join(h.ljust(w) for h, w in zip(head, widths)))
    for r in rows:
        print("  " + "  ".join(c.ljust(w) if i in (1, 2) else c.rjust(w) for i, (c, w) in enumerate(zip(r, widths))))
    refused = [e for e in ranking.entries if e.get("refused")]
    if refused:
        print(f"{len(refused)} design{'s' if len(refused) > 1 else ''} the search found feasible "
              f"{'are' if len(refused) > 1 else 'is'} refused: the exact gait contradicts the search's samples "
              f"(each entry's \"refused\" says how; docs/atlas.md, \"Refused designs\")")
