#!/usr/bin/env python3
"""How large a budget the designer's path synthesis needs to find something, on the shipped examples.

Run: ``python benchmarks/designer_synthesis.py`` (writes ``benchmarks/designer_synthesis_results.md``; ``--out -``
prints only).

For every shipped planar example with one rotary driver and closed-form groups only, the point the page would pick (the gait's foot, else the
last moving point) gets six targets the current design misses: its path at six crank angles, each moved by
``--shift`` of the mechanism's size, alternately outward and inward from the path's centre. A run is the designer's
own (:func:`assur.designer.synthesis_job._worker`, in this process: the local search from the current design, then
the restarted differential evolution, seeds 1 to ``--seeds``), for each budget. A run **finds something** when its
best design's cost (the sum of the targets' distances to the point's path) is at most half the current design's.
Reported per budget: the share of runs that found something, the median ratio best / current cost and the median
wall time.
"""
from __future__ import annotations

import argparse
import math
import queue
import statistics
import sys
import threading
import time
from pathlib import Path

import numpy as np

from tables import publish

HERE = Path(__file__).resolve().parent
ROOT = HERE.parent


#: the examples left out (a Newton-solved group: the path over a turn costs seconds per design)
skipped: list[str] = []


def cases() -> list[tuple[str, dict, str, list]]:
    """(file, document, point, targets (m)) of every shipped planar example with one rotary driver and closed-form
    groups only."""
    import warnings

    import assur
    from assur.designer.session import document_of
    out = []
    for path in sorted((ROOT / "examples").glob("*.toml")):
        if 'format = "assur/1"' not in path.read_text():
            continue
        try:
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")
                m = assur.load(path)
                plan = assur.compile(m)
        except assur.AssurError:
            continue
        if m.dimension != 2 or plan.n_inputs != 1 or plan.input_kinds[0] != "rotary" or m.gears:
            continue
        if any(st.kind == "newton" for st in plan.steps):
            skipped.append(path.name)       # seconds per design evaluation: see the note under the table
            continue
        frame = set(m.frame.points)
        moving = [p for p in plan.point_names if p not in frame]
        point = m.gait.foot if m.gait is not None else moving[-1]
        q = np.linspace(0, 2 * np.pi, 6, endpoint=False)
        xy = assur.solve(plan, inputs=q, order=0).point(point).pos.reshape(-1, 2)
        if not np.isfinite(xy).all():
            continue
        out.append((path.name, document_of(path)[0], point, xy))
    return out


def shifted(xy: np.ndarray, size: float, shift: float) -> list:
    centre = xy.mean(axis=0)
    out = []
    for k, p in enumerate(xy):
        away = p - centre
        away = away / (np.linalg.norm(away) or 1.0)
        out.append(list(p + (1 if k % 2 == 0 else -1) * shift * size * away))
    return out


def run(doc, point, targets, budget: int, seed: int) -> tuple[float, float, float]:
    """(current cost, best cost, wall time s) of one designer synthesis run in this process."""
    from assur.designer.synthesis_job import _worker, build_problem
    from assur.synthesis.evaluate import Evaluator
    data, problem, x0, targets, budget, seed = build_problem(doc, point, targets, budget, seed)
    row = Evaluator(problem)(np.asarray(x0)[None, :], detail=True).row(0)
    start = row["objective"] / problem.length_scale if row["feasible"] else math.inf
    out, cancel = queue.Queue(), threading.Event()
    t = time.perf_counter()
    _worker("bench", doc, data, x0, budget, seed, time.time(), out, cancel)
    wall = time.perf_counter() - t
    done = [m for m in iter_queue(out) if m.get("type") == "synth_done"][-1]
    return start, done["best"] if done["best"] is not None else math.inf, wall


def iter_queue(q):
    while True:
        try:
            yield q.get_nowait()
        except queue.Empty:
            return


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--budgets", default="300,1000,2000,3000", help="budgets (evaluations), comma separated")
    ap.add_argument("--seeds", type=int, default=2, help="seeds per case and budget")
    ap.add_argument("--shift", type=float, default=0.05, help="how far the targets are moved (share of the size)")
    ap.add_argument("--out", default=str(HERE / "designer_synthesis_results.md"), help="Markdown file ('-': none)")
    args = ap.parse_args(argv)
    import logging
    logging.disable(logging.WARNING)
    budgets = [int(b) for b in args.budgets.split(",")]
    rows = {b: [] for b in budgets}
    for name, doc, point, xy in cases():
        import assur
        from assur.io.mechanism_file import from_dict
        size = float(assur.compile(from_dict(doc)).length_scale)
        targets = shifted(xy, size, args.shift)
        for budget in budgets:
            for seed in range(1, args.seeds + 1):
                start, best, wall = run(doc, point, targets, budget, seed)
                rows[budget].append((name, start, best, wall))
                print(f"{name} {point} budget {budget} seed {seed}: {start:.4g} → {best:.4g} m in {wall:.1f} s",
                      file=sys.stderr)
    files = sorted({r[0] for r in rows[budgets[0]]})
    lines = ["# The designer's path synthesis: the budget that finds something", "",
             f"`python benchmarks/designer_synthesis.py --budgets {args.budgets} --seeds {args.seeds} --shift "
             f"{args.shift:g}` on {len(files)} shipped examples ({', '.join(files)}): six targets off the point's "
             f"path by {args.shift:g} of the mechanism's size; a run finds something when its best cost is at most "
             "half the current design's.", "",
             "| budget (evaluations) | runs | found something | median best / current | median wall time (s) |",
             "|---|---|---|---|---|"]
    for budget in budgets:
        r = rows[budget]
        if not r:
            continue
        found = sum(1 for _, s, b, _ in r if b <= 0.5 * s)
        ratio = statistics.median(b / s for _, s, b, _ in r if s > 0)
        lines.append(f"| {budget} | {len(r)} | {found} ({100 * found / len(r):.0f} %) | {ratio:.3f} | "
                     f"{statistics.median(w for *_, w in r):.1f} |")
    if skipped:
        lines += ["", f"Left out: {', '.join(skipped)} (a Newton-solved group: one design's path over a turn costs "
                      "seconds there, so a run of this size takes hours; the page's synthesis is not meant for it "
                      "yet)."]
    return publish(lines, args.out)


if __name__ == "__main__":
    raise SystemExit(main())
