#!/usr/bin/env python3
"""Wall time of ``assur gears`` and ``assur wheelstep`` on the paper-001 files, each run as its own process.

A script, not a test: ``python benchmarks/gears.py [--repeats 3] [--src DIR] [--out FILE]`` prints the min and the
median of the repeats of

- ``assur gears examples/gears_001.toml`` cold: the gear cache off (``ASSUR_CACHE_DIR=off``), everything computed;
- ``assur wheelstep examples/wheelstep_001.toml`` cold (an empty gear cache: computed, then stored) and warm (the
  cache filled by a previous run: the outlines and mesh checks read back, :mod:`assur.gears.cache`);
- ``assur gears`` warm, for comparison.

``--src`` runs the ``assur`` package of another source tree (e.g. an earlier version exported with
``git archive HEAD src | tar -x -C /tmp/old``) for a before/after comparison; a tree without the gear cache runs
"warm" like "cold". The outputs go to a temporary directory; the machine's load average is printed with the table,
since the machine may be shared.
"""
from __future__ import annotations

import argparse
import os
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
GEARS = ["gears", "examples/gears_001.toml"]
WHEELSTEP = ["wheelstep", "examples/wheelstep_001.toml"]


def run(cmd, out: Path, src: Path, cache: str) -> float:
    """Wall time (s) of ``python -m assur CMD -o OUT`` with ASSUR_CACHE_DIR=cache."""
    env = {**os.environ, "PYTHONPATH": str(src.resolve()), "ASSUR_CACHE_DIR": cache}
    t0 = time.perf_counter()
    subprocess.run([sys.executable, "-m", "assur", *cmd, "-o", str(out)], cwd=ROOT, env=env, check=True,
                   stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    return time.perf_counter() - t0


def measure(repeats: int, src: Path) -> dict:
    """{case: [seconds per repeat]}; within a repeat the cases run one after the other."""
    times = {"gears, cold (cache off)": [], "wheelstep, cold (empty cache)": [],
             "wheelstep, warm (cache filled)": [], "gears, warm (cache filled)": []}
    for i in range(repeats):
        with tempfile.TemporaryDirectory() as tmp:
            tmp = Path(tmp)
            times["gears, cold (cache off)"].append(run(GEARS, tmp / "g0", src, "off"))
            cache = str(tmp / "cache")                       # a fresh, empty cache
            times["wheelstep, cold (empty cache)"].append(run(WHEELSTEP, tmp / "w1", src, cache))
            times["wheelstep, warm (cache filled)"].append(run(WHEELSTEP, tmp / "w2", src, cache))
            times["gears, warm (cache filled)"].append(run(GEARS, tmp / "g2", src, cache))
        print(f"repeat {i + 1}/{repeats}: " + ", ".join(f"{v[-1]:.2f} s" for v in times.values()),
              file=sys.stderr, flush=True)
    return times


def table(times: dict, repeats: int, src: Path) -> str:
    load = os.getloadavg() if hasattr(os, "getloadavg") else ("?",) * 3
    lines = [f"| command ({repeats} runs, {src}, load average {load[0]:.2f}) | min [s] | median [s] |",
             "|---|---:|---:|"]
    lines += [f"| {name} | {min(t):.2f} | {statistics.median(t):.2f} |" for name, t in times.items()]
    return "\n".join(lines) + "\n"


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeats", type=int, default=3)
    ap.add_argument("--src", type=Path, default=ROOT / "src", help="the source tree whose assur is run")
    ap.add_argument("--out", type=Path, default=None, help="also write the table to this file")
    args = ap.parse_args(argv)
    text = table(measure(args.repeats, args.src), args.repeats, args.src)
    print(text, end="")
    if args.out is not None:
        args.out.write_text(text, encoding="utf-8")
    return 0


if __name__ == "__main__":
    sys.exit(main())
