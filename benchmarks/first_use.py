#!/usr/bin/env python3
"""What the compiled extra costs on first use: the wall time of whole commands with an empty kernel cache (a new
``ASSUR_CACHE_DIR`` for every run), with a warm one, and on the numpy path, side by side in one run.

Run with ``.venv/bin/python benchmarks/first_use.py [--repeats 3]`` (numba installed). Each case is a separate
process (``python -m assur …``), the cases interleaved round-robin so that a busy machine slows them alike; the
table gives the minimum and the median of the repeats, and the compile lines the runs printed. It is a script, not
a test: nothing here asserts a speed (``tests/test_first_use.py`` checks what each command compiles).

Cases: the issue's synthesis ("motor leg": ``synth examples/synthesis/walker_fourbar_motor.toml --seed 1 --budget
1500 --popsize 10``) on numpy, compiled from an empty cache, compiled from a warm cache, and as the default command
runs it; the six-bar path problem of the README (``stephenson3_path.toml --budget 20000``, where the default
command compiles) on numpy and compiled from an empty and a warm cache; a solve of 20 000 samples of Jansen's linkage as the default
command runs it from an empty cache.
"""
from __future__ import annotations

import argparse
import os
import shutil
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
MOTOR = ["synth", "examples/synthesis/walker_fourbar_motor.toml", "--seed", "1", "--budget", "1500", "--popsize", "10",
         "--quiet"]
LONG = ["synth", "examples/synthesis/stephenson3_path.toml", "--seed", "1", "--budget", "20000", "--quiet"]
SOLVE = ["solve", "examples/jansen.toml", "--steps", "20000"]

#: (label, arguments, cache: "empty" | "warm")
CASES = [("motor leg, 1 500 evaluations: numpy", MOTOR + ["--backend", "numpy"], "empty"),
         ("motor leg, 1 500 evaluations: compiled, empty cache", MOTOR + ["--backend", "numba"], "empty"),
         ("motor leg, 1 500 evaluations: compiled, warm cache", MOTOR + ["--backend", "numba"], "warm"),
         ("motor leg, 1 500 evaluations: the default command (numpy here), empty cache", MOTOR, "empty"),
         ("six-bar path, 20 000 evaluations: numpy", LONG + ["--backend", "numpy"], "empty"),
         ("six-bar path, 20 000 evaluations: compiled, empty cache (the default command)", LONG, "empty"),
         ("six-bar path, 20 000 evaluations: compiled, warm cache (the default command)", LONG, "warm"),
         ("solve jansen.toml --steps 20000: the default command, empty cache", SOLVE, "empty")]


def run(args, cache: str) -> tuple[float, list[str]]:
    env = {**os.environ, "ASSUR_CACHE_DIR": cache}
    t0 = time.perf_counter()
    r = subprocess.run([sys.executable, "-m", "assur", *args], cwd=ROOT, env=env, capture_output=True, text=True)
    wall = time.perf_counter() - t0
    if r.returncode != 0:
        raise SystemExit(f"{' '.join(args)} failed:\n{r.stderr[-2000:]}")
    return wall, [ln for ln in r.stderr.splitlines() if "compil" in ln]


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeats", type=int, default=3)
    args = ap.parse_args(argv)
    try:
        import numba  # noqa: F401
    except ImportError:
        raise SystemExit("this benchmark compares the compiled backend: pip install 'assur[fast]'") from None
    base = Path(tempfile.mkdtemp(prefix="assur-first-use-"))
    warm = base / "warm"
    times = {label: [] for label, _, _ in CASES}
    notes = {}
    try:
        for label, a, cache in CASES:           # fill the warm cache (not timed)
            if cache == "warm":
                run(a, str(warm))
        for k in range(args.repeats):
            for label, a, cache in CASES:
                where = warm if cache == "warm" else base / f"empty-{k}-{len(times[label])}-{abs(hash(label))}"
                wall, compiles = run(a, str(where))
                times[label].append(wall)
                notes.setdefault(label, compiles)
                if cache == "empty":
                    shutil.rmtree(where, ignore_errors=True)
    finally:
        shutil.rmtree(base, ignore_errors=True)
    print(f"# First use of the compiled backend ({args.repeats} repeats, separate processes, round-robin)\n")
    print("| case | min [s] | median [s] | compile lines printed (first repeat) |\n|---|---:|---:|---|")
    for label, _, _ in CASES:
        t = times[label]
        said = "; ".join(ln.split(" (")[0] for ln in notes[label]) or "none"
        print(f"| {label} | {min(t):.2f} | {statistics.median(t):.2f} | {said} |")
    return 0


if __name__ == "__main__":
    sys.exit(main())
