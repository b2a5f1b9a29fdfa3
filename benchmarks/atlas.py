#!/usr/bin/env python3
"""Enumeration time of the atlas of planar 1-DOF kinematic chains (8, 10 and 12 links).

Run: ``python benchmarks/atlas.py`` (writes ``benchmarks/atlas_results.md``; ``--out -`` prints only).

Each repeat enumerates from nothing (every cache cleared, the contracted graphs included): contracted graphs,
binary-link distributions, canonical certificates, the all-subsets degeneracy test, planarity and the chains'
canonical IDs, i.e. ``assur.structure.atlas.chains.chains(n, 1)``. The mechanisms (automorphism orbits) are not
timed. Reported: min and median of the repeats, and the number of chains found (the literature's 16, 230 and
6 856, docs/atlas.md).
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

from assur.structure.atlas.chains import chains, clear_cache

from tables import publish

HERE = Path(__file__).resolve().parent


def timed(links: int, dof: int) -> tuple[float, int]:
    clear_cache()
    gc.collect()
    t = time.perf_counter()
    found = len(chains(links, dof))
    return time.perf_counter() - t, found


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeats", type=int, default=5)
    ap.add_argument("--out", default=str(HERE / "atlas_results.md"), help="Markdown file to write ('-' for none)")
    args = ap.parse_args(argv)
    import networkx
    import pynauty
    lines = [f"# Atlas enumeration time ({datetime.date.today().isoformat()})", "",
             f"`python benchmarks/atlas.py --repeats {args.repeats}` on {platform.machine()}, "
             f"Python {platform.python_version()}, numpy {np.__version__}, pynauty {pynauty.__version__}, "
             f"networkx {networkx.__version__}; {args.repeats} repeats, each from empty caches.", "",
             "| links | DOF | chains | min (s) | median (s) |", "|---|---|---|---|---|"]
    for links in (8, 10, 12):
        runs = [timed(links, 1) for _ in range(args.repeats)]
        times = [t for t, _ in runs]
        found = {c for _, c in runs}
        assert len(found) == 1, found
        lines.append(f"| {links} | 1 | {found.pop()} | {min(times):.4g} | {statistics.median(times):.4g} |")
    return publish(lines, args.out)


if __name__ == "__main__":
    raise SystemExit(main())
