#!/usr/bin/env python3
"""Compiled Newton groups: a triad six-bar against dyad six-bars on the default backend, the throughput of a
population, and the kernels' compile cost, in one run.

Run: ``python benchmarks/newton.py`` (writes ``benchmarks/newton_results.md``; ``--out -`` prints only). All times
are CPU seconds of this process (``time.process_time``: the machine is shared, CPU time is the per-core cost); the
cases of a table run round-robin, so a busy machine slows them alike; min and median over the repeats.

1. **One cycle, 720 samples, order 2, default backend**: ``assur.solve(plan, inputs=q, order=2)`` then ``pos``,
   ``vel``, ``acc``, for ``examples/triad_sixbar.toml`` (a class-III group: the compiled Newton kernel, its kernel
   compiled before timing) and the dyad six-bars ``examples/stephenson3.toml`` and ``examples/watt2.toml`` (closed
   forms; the default backend solves 720 samples with numpy); and the triad six-bar on the numpy backend (what the
   default backend did before the Newton kernels). Ratios: the triad's time over each dyad six-bar's.
2. **10 000 designs × 360 samples of the triad six-bar** (each parameter × (1 + 0.03·N(0, 1)), seed 0): the synthesis
   evaluator's compiled cycle reduction (``numba_backend.cycle_objective``: the cycle swept per design, the
   unassembled samples counted) and ``assur.solve(..., order=2, backend="numba")`` in chunks of 1 000 designs then
   ``pos``, ``vel``, ``acc``; samples per CPU second.
3. **Compile cost** with empty caches (a fresh process, ``ASSUR_CACHE_DIR=off``, its own ``NUMBA_CACHE_DIR``; numba
   imported before): the CPU time of each kernel's first call minus a warm call, and the generated source's lines;
   beside it, the numpy backend's time for the same call (one cycle of 720 samples), so the compile's pay-back is
   read off.
4. **Agreement**: the triad six-bar's cycle, compiled against ``solve(..., sweep=True, backend="numpy")``: the
   largest position difference over the mechanism's size, the velocities' and accelerations' relative difference.
"""
from __future__ import annotations

import argparse
import datetime
import json
import os
import platform
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

HERE = Path(__file__).resolve().parent
ROOT = HERE.parent
EX = ROOT / "examples"


def _timed(fn):
    t = time.process_time()
    fn()
    return time.process_time() - t


def _cycle(plan, backend="auto"):
    import numpy as np

    import assur
    q = np.linspace(0.0, 2 * np.pi, 720, endpoint=False)

    def run():
        st = assur.solve(plan, inputs=q, order=2, backend=backend)
        return st.pos, st.vel, st.acc
    return run


def cycles(repeats: int) -> dict:
    import assur
    triad = assur.compile(assur.load(EX / "triad_sixbar.toml"))
    cases = {"triad six-bar (default backend: compiled Newton)": _cycle(triad),
             "Stephenson III six-bar, dyads (default backend: numpy)": _cycle(
                 assur.compile(assur.load(EX / "stephenson3.toml"))),
             "Watt II six-bar, dyads (default backend: numpy)": _cycle(assur.compile(assur.load(EX / "watt2.toml")))}
    slow = {"triad six-bar, numpy backend (the default before)": _cycle(triad, "numpy")}
    for fn in list(cases.values()) + list(slow.values()):
        fn()
    times = {k: [] for k in list(cases) + list(slow)}
    for r in range(repeats):
        for k, fn in cases.items():
            for _ in range(20):          # 20 calls per repeat: a call is a millisecond
                times[k].append(_timed(fn))
        if r < 3:
            for k, fn in slow.items():
                times[k].append(_timed(fn))
    return times


def population(repeats: int) -> dict:
    import numpy as np

    import assur
    from assur.engine.planar import numba_backend
    plan = assur.compile(assur.load(EX / "triad_sixbar.toml"))
    rng = np.random.default_rng(0)
    P = plan.defaults * (1 + 0.03 * rng.standard_normal((10_000, plan.n_params)))
    q = np.linspace(0.0, 2 * np.pi, 360, endpoint=False)
    info = {}

    def reduction():
        r = numba_backend.cycle_objective(plan, P, q, 1e-12)
        info["buildable designs"] = int((r[:, 0] == 0).sum())

    def solve():
        for i in range(0, len(P), 1000):
            st = assur.solve(plan, P[i:i + 1000, None, :], q[:, None], order=2, backend="numba")
            st.pos, st.vel, st.acc
    numba_backend.cycle_objective(plan, P[:10], q, 1e-12)
    assur.solve(plan, P[:2, None, :], q[:, None], order=2, backend="numba")
    times = {"cycle reduction (synthesis)": [], "solve, order 2, chunks of 1 000 designs": []}
    for _ in range(repeats):
        times["cycle reduction (synthesis)"].append(_timed(reduction))
        times["solve, order 2, chunks of 1 000 designs"].append(_timed(solve))
    return {"times": times, "samples": len(P) * len(q), "info": info}


def agreement() -> dict:
    import numpy as np

    import assur
    plan = assur.compile(assur.load(EX / "triad_sixbar.toml"))
    q = np.linspace(0.0, 2 * np.pi, 720, endpoint=False)
    a = assur.solve(plan, inputs=q, order=2, backend="numpy", sweep=True)
    b = assur.solve(plan, inputs=q, order=2, backend="numba")
    rel = lambda x, y: float(np.max(np.abs(x - y)) / np.max(np.abs(x)))  # noqa: E731
    return {"valid": f"{int(a.valid.sum())} / {int(b.valid.sum())} of 720",
            "positions (of the size)": float(np.max(np.abs(a.pos - b.pos)) / plan.length_scale),
            "velocities": rel(a.vel, b.vel), "accelerations": rel(a.acc, b.acc)}


# -- the compile cost: a worker process with empty caches -----------------------------------------------------------
def compile_worker() -> dict:
    import numba  # noqa: F401  (imported before timing)
    import numpy as np

    import assur
    from assur.engine.planar import numba_backend
    from assur.kernels import codegen
    plan = assur.compile(assur.load(EX / "triad_sixbar.toml"))
    q = np.linspace(0.0, 2 * np.pi, 720, endpoint=False)
    out = {}
    first = _timed(_cycle(plan, "numba"))
    warm = _timed(_cycle(plan, "numba"))
    out["solve kernel (order 2, points and bodies)"] = {
        "compile": first - warm, "lines": len(numba_backend.newton_kernels.solve_source(plan, 2).splitlines())}
    first = _timed(lambda: numba_backend.cycle_objective(plan, plan.defaults[None], q, 1e-12))
    warm = _timed(lambda: numba_backend.cycle_objective(plan, plan.defaults[None], q, 1e-12))
    src = numba_backend.cycle_source(plan, None, None, False)
    out["cycle reduction kernel (buildability)"] = {"compile": first - warm, "lines": len(src.splitlines())}
    out["numpy backend, one cycle (720, order 2)"] = {"compile": _timed(_cycle(plan, "numpy")), "lines": None}
    return out


def compile_cost() -> dict:
    with tempfile.TemporaryDirectory() as nb:
        env = dict(os.environ, ASSUR_CACHE_DIR="off", NUMBA_CACHE_DIR=nb,
                   PYTHONPATH=str(ROOT / "src") + os.pathsep + os.environ.get("PYTHONPATH", ""))
        r = subprocess.run([sys.executable, __file__, "--compile-worker"], env=env, capture_output=True, text=True,
                           check=True)
    return json.loads(r.stdout.strip().splitlines()[-1])


def _rate(work, ts):
    return work / min(ts), work / statistics.median(ts)


def report(repeats: int) -> str:
    import numba
    import numpy as np
    load0 = os.getloadavg()
    t0 = time.monotonic()
    cyc = cycles(repeats)
    pop = population(max(3, repeats // 2))
    agree = agreement()
    comp = compile_cost()
    load1 = os.getloadavg()
    med = {k: statistics.median(v) for k, v in cyc.items()}
    triad = next(k for k in med if k.startswith("triad six-bar (default"))
    lines = [
        "# Compiled Newton groups: a triad six-bar against dyad six-bars, a population, the compile cost",
        "",
        f"{datetime.date.today()}, Python {platform.python_version()}, numpy {np.__version__}, numba "
        f"{numba.__version__}, {os.cpu_count()} cores shared; load average {load0[0]:.1f} at the start and "
        f"{load1[0]:.1f} at the end; {time.monotonic() - t0:.0f} s in all. CPU-time min and median of the repeats. "
        "Command: `python benchmarks/newton.py`.",
        "",
        "## One cycle: 720 samples, order 2 (`assur.solve(plan, inputs=q, order=2)`, then pos, vel, acc)",
        "",
        "| case | min | median | median / triad six-bar's |",
        "|---|---|---|---|",
    ]
    for k, ts in cyc.items():
        lines.append(f"| {k} | {min(ts) * 1e3:.3f} ms | {med[k] * 1e3:.3f} ms | {med[k] / med[triad]:.2f} |")
    lines += ["", "The triad six-bar on the default backend takes " + ", ".join(
        f"{med[triad] / med[k]:.2f}× the time of the {k.split(' (')[0]}" for k in med if "dyads" in k) + "; on "
        "the numpy backend (the default before) it took "
        + ", ".join(f"{med[k] / med[d]:.0f}×" for k in med if "numpy backend" in k for d in med if "dyads" in d)
        + " of theirs.", ""]
    n = pop["samples"]
    lines += ["## 10 000 designs × 360 samples of the triad six-bar (±3 % per parameter)", "",
              "| case | min | median |", "|---|---|---|"]
    for k, ts in pop["times"].items():
        lo, md = _rate(n, ts)
        lines.append(f"| {k} | {lo / 1e6:.2f} M samples/s | {md / 1e6:.2f} M samples/s |")
    lines += ["", f"{pop['info']['buildable designs']} of the 10 000 designs turn fully.", "",
              "## Compile cost with empty caches (CPU seconds of the first call minus a warm call)", "",
              "| kernel | compile | generated lines |", "|---|---|---|"]
    for k, v in comp.items():
        if isinstance(v, dict):
            lines.append(f"| {k} | {v['compile']:.2f} s | {v['lines'] or ''} |")
    lines += ["", "The numpy row is the call the kernel replaces (no compile): the solve kernel pays back after "
              f"{comp['solve kernel (order 2, points and bodies)']['compile'] / comp['numpy backend, one cycle (720, order 2)']['compile']:.1f} "
              "such cycles, once per mechanism structure (the kernel depends on the structure only and is cached on "
              "disk).", "", "## Agreement with the numpy backend's sweep (one cycle)", ""]
    lines += [f"- {k}: {v if isinstance(v, str) else f'{v:.1e}'}" for k, v in agree.items()]
    return "\n".join(lines) + "\n"


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--repeats", type=int, default=7)
    ap.add_argument("--out", default=str(HERE / "newton_results.md"))
    ap.add_argument("--compile-worker", action="store_true", help=argparse.SUPPRESS)
    a = ap.parse_args()
    sys.path.insert(0, str(ROOT / "src"))
    if a.compile_worker:
        print(json.dumps(compile_worker()))
        return
    text = report(a.repeats)
    print(text)
    if a.out != "-":
        Path(a.out).write_text(text, encoding="utf-8")


if __name__ == "__main__":
    main()
