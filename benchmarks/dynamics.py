#!/usr/bin/env python3
"""A population of slider-crank designs run from rest to their steady state on the motor, against one design at a time.

Run: ``python benchmarks/dynamics.py`` (writes ``benchmarks/dynamics_results.md``; ``--out -`` prints only).

The mechanism is ``examples/slider_crank_motor.toml`` (a slider-crank pump on a DC gear motor with a flywheel);
the designs scatter its crank and rod lengths (crank × U(0.8, 1.2), rod × U(0.9, 1.3)). Engines, timed round-robin
inside each repeat:

* ``population``: ``assur.simulate(plan, params=(n, n_params))``, everything included: the designs' grid solve, the
  force analysis on it, the Fourier terms, and the vectorised Dormand–Prince run of every design from rest to its
  detected periodic steady state (:mod:`assur.dynamics.population`);
* ``one at a time``: ``assur.simulate(plan, params=p)`` for the first ``--singles`` designs (solve_ivp's DOP853
  on each design's own equation), extrapolated per design to the population (the table says so).

Correctness: the population's steady mean speed, δ and start-up time of the single-run designs against the single
runs (largest relative difference). Reported: min and median of the repeats, and the rate in designs per second.
"""
from __future__ import annotations

import argparse
import datetime
import gc
import os
import platform
import statistics
import time
from pathlib import Path

import numpy as np

import assur
from assur.dynamics.batch import compiled_available

HERE = Path(__file__).resolve().parent
ROOT = HERE.parent


def timed(fn):
    gc.collect()
    t = time.perf_counter()
    out = fn()
    return time.perf_counter() - t, out


def designs(plan, n: int, seed: int = 2026) -> np.ndarray:
    rng = np.random.default_rng(seed)
    P = np.tile(plan.defaults, (n, 1))
    P[:, plan.param_index("crank.length")] *= rng.uniform(0.8, 1.2, n)
    P[:, plan.param_index("rod.length")] *= rng.uniform(0.9, 1.3, n)
    return P


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--designs", type=int, default=1000)
    ap.add_argument("--singles", type=int, default=5)
    ap.add_argument("--repeats", type=int, default=3)
    ap.add_argument("--out", default=str(HERE / "dynamics_results.md"), help="Markdown file to write ('-' for none)")
    args = ap.parse_args(argv)
    plan = assur.compile(assur.load(ROOT / "examples" / "slider_crank_motor.toml"))
    P = designs(plan, args.designs)
    assur.simulate(plan, params=P[:4])          # compile and warm every kernel before timing
    assur.simulate(plan, params=P[0])
    pop_times, one_times = [], []
    pop = singles = None
    for _ in range(args.repeats):
        t, pop = timed(lambda: assur.simulate(plan, params=P))
        pop_times.append(t)
        t, singles = timed(lambda: [assur.simulate(plan, params=p) for p in P[: args.singles]])
        one_times.append(t * args.designs / args.singles)
    worst = {}
    for name, a, b in (("mean speed", pop.mean_speed, [s.mean_speed for s in singles]),
                       ("δ", pop.delta, [s.delta for s in singles]),
                       ("start-up time", pop.startup_time, [s.startup_time for s in singles])):
        b = np.asarray(b)
        worst[name] = float(np.max(np.abs(a[: args.singles] - b) / np.abs(b)))
    steady = int(np.sum(pop.steady))
    turns = pop.turns[pop.steady]
    cmd = f"python benchmarks/dynamics.py --designs {args.designs} --singles {args.singles} --repeats {args.repeats}"
    lines = [f"# Dynamics of a population ({datetime.date.today().isoformat()})", "",
             f"`{cmd}` on {platform.machine()} ({os.cpu_count()} cores), Python {platform.python_version()}, "
             f"numpy {np.__version__}; {args.repeats} repeats, round-robin.", "",
             f"{args.designs} slider-crank designs of `examples/slider_crank_motor.toml` from rest to their steady "
             f"state: {steady} reached it (turns {int(turns.min())}–{int(turns.max())}, median "
             f"{int(np.median(turns))}); start-up times {np.nanmin(pop.startup_time):.3f}–"
             f"{np.nanmax(pop.startup_time):.3f} s, δ {np.nanmin(pop.delta):.4f}–{np.nanmax(pop.delta):.4f}; "
             f"accepted steps per design {int(np.min(pop.steps))}–{int(np.max(pop.steps))} (the "
             f"{'compiled' if compiled_available() else 'numpy'} route).", "",
             "| engine | min (s) | median (s) | designs / s (median) |", "|---|---|---|---|",
             f"| population (vectorised) | {min(pop_times):.3f} | {statistics.median(pop_times):.3f} | "
             f"{args.designs / statistics.median(pop_times):.0f} |",
             f"| one at a time (solve_ivp, {args.singles} designs, extrapolated) | {min(one_times):.3f} | "
             f"{statistics.median(one_times):.3f} | {args.designs / statistics.median(one_times):.0f} |", "",
             "Largest relative difference of the population from the single runs: "
             + ", ".join(f"{k} {v:.1e}" for k, v in worst.items()) + "."]
    text = "\n".join(lines) + "\n"
    print(text)
    if args.out != "-":
        Path(args.out).write_text(text, encoding="utf-8")
    return 0 if max(worst.values()) < 1e-3 and steady == args.designs else 1


if __name__ == "__main__":
    raise SystemExit(main())
