#!/usr/bin/env python3
"""Wall time of ``assur make``, cold: each run its own process (start-up, imports, the gear cache and the kernel
cache all fresh), on Jansen's leg (the issue's bound: 60 s on a 2-core machine, STEP and STL included) and on the
geared four-bar leg (its gear outlines cut in the run), with ``--layers-only`` beside them.

A script, not a test: ``python benchmarks/make.py [--repeats 3]`` prints the min and the median of the repeats
and the phases of one in-process run of Jansen (the cycle, the certified conflicts, the layer program, the
solids, the files); ``--out FILE`` also writes the table (default benchmarks/make_results.md, ``-`` for none).
"""
from __future__ import annotations

import argparse
import os
import platform
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
COMMANDS = {
    "make jansen.toml (STEP, STL, 3MF, page)": ["make", "examples/jansen.toml", "-o", "{out}/jansen"],
    "make jansen.toml --layers-only": ["make", "examples/jansen.toml", "-o", "{out}/jansen", "--layers-only"],
    "make walker_fourbar_geared.toml (gears cut cold)": ["make", "examples/walker_fourbar_geared.toml", "-o",
                                                         "{out}/geared"],
}


def cold(cmd, repeats: int) -> list[float]:
    times = []
    for _ in range(repeats):
        with tempfile.TemporaryDirectory() as out, tempfile.TemporaryDirectory() as cache:
            env = {**os.environ, "PYTHONPATH": str(ROOT / "src"), "ASSUR_CACHE_DIR": cache}
            t0 = time.perf_counter()
            subprocess.run([sys.executable, "-m", "assur", *(c.format(out=out) for c in cmd)], cwd=ROOT, env=env,
                           check=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
            times.append(time.perf_counter() - t0)
    return times


def phases() -> list[tuple[str, float]]:
    """The phases of one in-process run of Jansen (imports already paid)."""
    sys.path.insert(0, str(ROOT / "src"))
    import assur
    from assur.analysis.study import Study
    from assur.parts.api import make_parts
    from assur.parts.files import write_all
    import build123d  # noqa: F401  (imported here so the phases below do not pay for it)
    out = []
    t = time.perf_counter()
    plan = assur.compile(assur.load(ROOT / "examples" / "jansen.toml"))
    cyc = Study(plan)
    cyc.grid()
    out.append(("load, compile, solve 720 inputs", time.perf_counter() - t))
    t = time.perf_counter()
    result = make_parts(cyc)
    out.append((f"parts, {len(result.conflicts.all())} certified pairs, layer program", time.perf_counter() - t))
    t = time.perf_counter()
    result.solids()
    result.flat_meshes()
    out.append((f"{len(result.parts)} B-rep solids and meshes", time.perf_counter() - t))
    with tempfile.TemporaryDirectory() as d:
        t = time.perf_counter()
        write_all(result, Path(d))
        out.append(("STL, 3MF, STEP, checks, parts.json, bom.csv, page", time.perf_counter() - t))
    return out


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeats", type=int, default=3)
    ap.add_argument("--out", default=str(ROOT / "benchmarks" / "make_results.md"))
    args = ap.parse_args(argv)
    lines = [f"`python benchmarks/make.py --repeats {args.repeats}` — {time.strftime('%Y-%m-%d')}, Python "
             f"{platform.python_version()}, nproc {os.cpu_count()}", "",
             f"| command, cold ({args.repeats} runs) | min [s] | median [s] |", "|---|---:|---:|"]
    print("\n".join(lines), flush=True)
    for name, cmd in COMMANDS.items():
        times = cold(cmd, args.repeats)
        row = f"| {name} | {min(times):.1f} | {statistics.median(times):.1f} |"
        lines.append(row)
        print(row, flush=True)
    lines += ["", "| phase of one in-process run of jansen.toml | [s] |", "|---|---:|"]
    print("\n".join(lines[-3:]))
    for name, seconds in phases():
        row = f"| {name} | {seconds:.2f} |"
        lines.append(row)
        print(row, flush=True)
    if args.out != "-":
        Path(args.out).write_text("\n".join(lines) + "\n", encoding="utf-8")
    return 0


if __name__ == "__main__":
    sys.exit(main())
