#!/usr/bin/env python3
"""How long ``synthesize(..., time_limit=T)`` really runs: the wall time of a run stopped by its time limit.

Run with ``.venv/bin/python benchmarks/time_limit.py`` (or the ``.bench-venv`` of ``make bench``). The problem is
``examples/synthesis/c2_five_points_timed.toml`` with ``seed=1, time_limit=1.0, maxiter=100000`` (a run that would
go on far longer without the limit), after one short warm-up run (numba import, compiled kernels). Prints the
minimum and the median wall time over the repeats, the overshoot past the limit, and the evaluations done. It is a
script, not a test: nothing here asserts a speed. It exits non-zero only if a run did not stop for the time limit
(``result.stopped != "time"``).
"""
from __future__ import annotations

import argparse
import statistics
import sys
import time
from pathlib import Path

HERE = Path(__file__).resolve().parent
PROBLEM = HERE.parent / "examples" / "synthesis" / "c2_five_points_timed.toml"


def run_once(problem, limit: float, seed: int):
    """One limited run → (wall seconds, result)."""
    from assur.synthesis import synthesize
    t0 = time.perf_counter()
    r = synthesize(problem, seed=seed, time_limit=limit, maxiter=100_000)
    return time.perf_counter() - t0, r


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeats", type=int, default=5, help="limited runs to time")
    ap.add_argument("--limit", type=float, default=1.0, help="time_limit of each run [s]")
    ap.add_argument("--seed", type=int, default=1)
    args = ap.parse_args(argv)
    from assur.synthesis import load_problem
    from assur.synthesis import synthesize
    problem = load_problem(PROBLEM)
    synthesize(problem, seed=args.seed, budget=200, polish="none")   # warm-up: numba import, compiled kernels
    walls, evaluations, stopped = [], [], []
    for _ in range(args.repeats):
        wall, r = run_once(problem, args.limit, args.seed)
        walls.append(wall)
        evaluations.append(r.evaluations)
        stopped.append(r.stopped)
    lo, med = min(walls), statistics.median(walls)
    print(f"# synthesize with time_limit={args.limit:g} s ({PROBLEM.name}, seed {args.seed}, "
          f"{args.repeats} repeats)\n")
    print("| | min | median |\n|---|---:|---:|")
    print(f"| wall time [s] | {lo:.3f} | {med:.3f} |")
    print(f"| past the limit [s] | {lo - args.limit:.3f} | {med - args.limit:.3f} |")
    print(f"| evaluations | {min(evaluations)} | {statistics.median(evaluations):g} |")
    bad = [s for s in stopped if s != "time"]
    if bad:
        print(f"runs not stopped by the time limit: {bad}", file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
