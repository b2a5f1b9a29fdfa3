#!/usr/bin/env python3
"""Wall time of everyday commands, each run as its own process (start-up and imports included).

A script, not a test: ``python benchmarks/commands.py [--repeats 3] [--src DIR]`` prints the min and the median
of the repeats for each command. ``--src`` runs the ``assur`` package of another source tree (e.g. an earlier
version exported with ``git archive HEAD src | tar -x -C /tmp/old``) for a before/after comparison. The
kernel cache is a fresh temporary directory per command, so a command that compiles a kernel pays for it in
the first run only, as a user does.
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
COMMANDS = {
    "animate klann.toml → GIF (60 frames)": ["animate", "examples/klann.toml", "-o", "{out}/klann.gif"],
    "animate klann.toml → HTML (60 frames)": ["animate", "examples/klann.toml", "-o", "{out}/klann.html"],
    "report walker_fourbar.toml": ["report", "examples/walker_fourbar.toml", "-o", "{out}/report"],
    "report jansen.toml": ["report", "examples/jansen.toml", "-o", "{out}/jansen"],
}


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeats", type=int, default=3)
    ap.add_argument("--src", type=Path, default=ROOT / "src", help="the source tree whose assur is run")
    args = ap.parse_args(argv)
    print(f"| command ({args.repeats} runs, {args.src}) | min [s] | median [s] |")
    print("|---|---:|---:|")
    for name, cmd in COMMANDS.items():
        with tempfile.TemporaryDirectory() as out, tempfile.TemporaryDirectory() as cache:
            env = {**os.environ, "PYTHONPATH": str(args.src.resolve()), "ASSUR_CACHE_DIR": cache}
            times = []
            for _ in range(args.repeats):
                t0 = time.perf_counter()
                subprocess.run([sys.executable, "-m", "assur", *(c.format(out=out) for c in cmd)], cwd=ROOT,
                               env=env, check=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
                times.append(time.perf_counter() - t0)
        print(f"| {name} | {min(times):.2f} | {statistics.median(times):.2f} |", flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
