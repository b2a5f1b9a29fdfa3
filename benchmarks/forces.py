#!/usr/bin/env python3
"""Forces with kinematics against kinematics alone, side by side in one run.

Run: ``python benchmarks/forces.py`` (writes ``benchmarks/forces_results.md``; ``--out -`` prints only).

The mechanism is paper 004's four-bar walking leg (``examples/walker_fourbar.toml``: steel-bar masses, gravity;
the leg alone, no body weight). Cases: one design × 3 600 crank angles, and 10 000 designs (the file's dimensions
with 1 % random scatter) × 360 angles. Engines, timed round-robin inside each repeat so that machine noise hits
them alike:

* ``kinematics``: ``assur.solve(plan, params, q, order=2)`` (positions, velocities, accelerations; the compiled
  backend where numba is installed, as ``backend="auto"`` picks it for batches of 20 000 samples and more);
* ``kinematics + forces``: ``assur.forces(plan, params, q)`` (it solves the same kinematics, then the reactions,
  driving torque and power group by group);
* ``kinematics + forces (numpy)``: the same with ``backend="numpy"`` (one design only: the numpy backend is the
  reference, not the fast path).

Every kernel is compiled (and numba's disk cache filled) before timing. Reported: min and median of the
repeats and the ratio of each engine's median to the kinematics' median.
"""
from __future__ import annotations

import argparse
import datetime
import gc
import platform
import statistics
import time
from pathlib import Path

import numpy as np

import assur

from tables import publish

HERE = Path(__file__).resolve().parent
ROOT = HERE.parent


def timed(fn) -> float:
    gc.collect()
    t = time.perf_counter()
    fn()
    return time.perf_counter() - t


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeats", type=int, default=5)
    ap.add_argument("--designs", type=int, default=10_000)
    ap.add_argument("--out", default=str(HERE / "forces_results.md"), help="Markdown file to write ('-' for none)")
    args = ap.parse_args(argv)
    plan = assur.compile(assur.load(ROOT / "examples" / "walker_fourbar.toml"))
    rng = np.random.default_rng(2026)
    designs = plan.defaults * (1 + 0.01 * rng.standard_normal((args.designs, plan.n_params)))
    q1 = np.linspace(0, 2 * np.pi, 3600, endpoint=False)
    q2 = np.linspace(0, 2 * np.pi, 360, endpoint=False)
    backend = "numba" if _has_numba() else "numpy"
    cases = {
        "1 design × 3 600 angles": {
            "kinematics": lambda: assur.solve(plan, None, q1, order=2, backend=backend),
            "kinematics + forces": lambda: assur.forces(plan, None, q1, backend=backend),
            "kinematics + forces (numpy)": lambda: assur.forces(plan, None, q1, backend="numpy"),
        },
        f"{args.designs:,} designs × 360 angles".replace(",", " "): {
            "kinematics": lambda: assur.solve(plan, designs[:, None, :], q2[None, :, None], order=2,
                                              backend=backend),
            "kinematics + forces": lambda: assur.forces(plan, designs[:, None, :], q2[None, :, None],
                                                        backend=backend),
        },
    }
    for engines in cases.values():          # compile and warm every kernel before timing
        for fn in engines.values():
            fn()
    lines = [f"# Forces against kinematics ({datetime.date.today().isoformat()})", "",
             f"`python benchmarks/forces.py --repeats {args.repeats} --designs {args.designs}` on "
             f"{platform.machine()}, Python {platform.python_version()}, numpy {np.__version__}, "
             f"backend {backend}; {args.repeats} repeats, round-robin.", "",
             "| case | engine | min (s) | median (s) | median / kinematics |", "|---|---|---|---|---|"]
    for case, engines in cases.items():
        times = {name: [] for name in engines}
        for _ in range(args.repeats):
            for name, fn in engines.items():
                times[name].append(timed(fn))
        base = statistics.median(times["kinematics"])
        for name, ts in times.items():
            med = statistics.median(ts)
            lines.append(f"| {case} | {name} | {min(ts):.4g} | {med:.4g} | {med / base:.2f} |")
    return publish(lines, args.out)


def _has_numba() -> bool:
    try:
        import numba  # noqa: F401
    except ImportError:
        return False
    return True


if __name__ == "__main__":
    raise SystemExit(main())
