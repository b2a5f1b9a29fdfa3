#!/usr/bin/env python3
"""Newton-solved groups and the automatic backend, side by side in one run (issue 26).

    python benchmarks/groups.py [--repeats 5] [--out benchmarks/groups_results.md | -]

A script, not a test: it prints a Markdown table (min and median wall time of the repeats, the cases of one table
timed round-robin inside each repeat so that machine noise hits them alike) and writes it to
``benchmarks/groups_results.md``.

1. One cycle (720 crank angles, order 2) with the default ``assur.solve``: the triad six-bar and the class-IV six-bar
   (Newton-solved groups, certified continuation) against the dyad six-bar ``stephenson3`` on the numpy backend.
2. ``assur.assemblies`` at one input: the triad six-bar (its degree-6 polynomial), the class-IV six-bar (the
   certified one-parameter reduction), and the four-bar (two closed-form branches).
3. ``backend="auto"`` on a mechanism whose kernel is loaded: 360 samples of ``walker_sixbar`` (order 2) with
   ``backend="numpy"``, ``"auto"`` and ``"numba"``.
"""
from __future__ import annotations

import argparse
import datetime
import os
import platform
import statistics
import sys
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "src"))
import assur  # noqa: E402

EX = ROOT / "examples"


def timed(cases: dict, repeats: int) -> dict:
    """{name: (min, median)} seconds; cases run round-robin inside each repeat (after one warm-up call each)."""
    for f in cases.values():
        f()
    times = {k: [] for k in cases}
    for _ in range(repeats):
        for k, f in cases.items():
            t = time.perf_counter()
            f()
            times[k].append(time.perf_counter() - t)
    return {k: (min(v), statistics.median(v)) for k, v in times.items()}


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--repeats", type=int, default=5)
    ap.add_argument("--out", default=str(ROOT / "benchmarks" / "groups_results.md"))
    args = ap.parse_args()
    plans = {n: assur.compile(assur.load(EX / f"{n}.toml"))
             for n in ("triad_sixbar", "classiv_sixbar", "stephenson3", "crank_rocker", "walker_sixbar")}
    q720 = np.linspace(0, 2 * np.pi, 720, endpoint=False)
    q360 = np.linspace(0, 2 * np.pi, 360, endpoint=False)
    lines = [f"# Newton-solved groups and the automatic backend ({datetime.date.today()})", "",
             f"Python {platform.python_version()}, numpy {np.__version__}, {os.cpu_count()} cores (shared); "
             f"`python benchmarks/groups.py --repeats {args.repeats}`; min and median of the repeats.", ""]

    cycle = timed({"triad six-bar (class III, Newton)": lambda: assur.solve(plans["triad_sixbar"], inputs=q720),
                   "class-IV six-bar (Newton)": lambda: assur.solve(plans["classiv_sixbar"], inputs=q720),
                   "Stephenson III six-bar (dyads, numpy)":
                       lambda: assur.solve(plans["stephenson3"], inputs=q720, backend="numpy")}, args.repeats)
    dyad = cycle["Stephenson III six-bar (dyads, numpy)"][0]
    lines += ["## One cycle: 720 crank angles, order 2, default solve", "",
              "| mechanism | min [ms] | median [ms] | × the dyad six-bar (min) |", "|---|---|---|---|"]
    lines += [f"| {k} | {a * 1e3:.1f} | {b * 1e3:.1f} | {a / dyad:.0f} |" for k, (a, b) in cycle.items()]

    at = 1.0
    enum = timed({"triad six-bar (polynomial)": lambda: assur.assemblies(plans["triad_sixbar"], at),
                  "class-IV six-bar (certified reduction)": lambda: assur.assemblies(plans["classiv_sixbar"], at),
                  "four-bar (two branches)": lambda: assur.assemblies(plans["crank_rocker"], at)}, args.repeats)
    counts = {k: len(assur.assemblies(plans[n], at)[0]) for k, n in
              zip(enum, ("triad_sixbar", "classiv_sixbar", "crank_rocker"))}
    lines += ["", "## Every assembly at one input (crank at 1 rad)", "",
              "| mechanism | assemblies | min [ms] | median [ms] |", "|---|---|---|---|"]
    lines += [f"| {k} | {counts[k]} | {a * 1e3:.1f} | {b * 1e3:.1f} |" for k, (a, b) in enum.items()]

    p = plans["walker_sixbar"]
    try:
        import numba  # noqa: F401
        assur.solve(p, inputs=q360, backend="numba")                  # the kernel compiled (or loaded) once
        auto = timed({"numpy": lambda: assur.solve(p, inputs=q360, backend="numpy"),
                      "auto": lambda: assur.solve(p, inputs=q360),
                      "numba": lambda: assur.solve(p, inputs=q360, backend="numba")}, max(args.repeats, 20))
        base = auto["numpy"][0]
        lines += ["", "## backend=\"auto\" on a loaded kernel: walker_sixbar, 360 samples, order 2", "",
                  "| backend | min [ms] | median [ms] | numpy / this (min) |", "|---|---|---|---|"]
        lines += [f"| {k} | {a * 1e3:.3f} | {b * 1e3:.3f} | {base / a:.1f} |" for k, (a, b) in auto.items()]
    except ImportError:
        lines += ["", "(numba is not installed: the automatic backend is numpy)"]
    text = "\n".join(lines) + "\n"
    print(text)
    if args.out != "-":
        Path(args.out).write_text(text, encoding="utf-8")
    return 0


if __name__ == "__main__":
    sys.exit(main())
