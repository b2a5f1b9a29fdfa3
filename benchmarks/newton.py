#!/usr/bin/env python3
"""Compiled Newton groups: a triad six-bar against dyad six-bars, the throughput of a population, the designer's
preview and the kernels' compile cost, in one run.

Run: ``python benchmarks/newton.py`` (writes ``benchmarks/newton_results.md``; ``--out -`` prints only). All times
are CPU seconds of this process (``time.process_time``: the machine is shared, CPU time is the per-core cost) except
the designer's previews (wall-clock, as the user waits); the cases of a table run round-robin, so a busy machine slows
them alike; min and median over the repeats.

1. **One cycle, 720 samples, order 2**: ``assur.solve(plan, inputs=q, order=2)`` then ``pos``, ``vel``, ``acc``, for
   ``examples/triad_sixbar.toml`` (a class-III group) on the compiled backend under the default continuation (every
   sample continued from the sketch on its own) and with ``sweep=True``, and the dyad six-bars
   ``examples/stephenson3.toml`` and ``examples/watt2.toml`` (closed forms) compiled and on numpy; and the triad six-bar
   on the numpy backend. Ratios: each case's time over the compiled triad's.
2. **10 000 designs × 360 samples of the triad six-bar** (each parameter × (1 + 0.03·N(0, 1)), seed 0): the synthesis
   evaluator's compiled cycle reduction (``numba_backend.cycle_objective``: the cycle swept per design, the
   unassembled samples counted) and ``assur.solve(..., order=2, backend="numba", sweep=True)`` in chunks of 1 000
   designs then ``pos``, ``vel``, ``acc``; samples per CPU second.
3. **The designer's preview of the triad six-bar**: ``Session.handle`` answering a ``preview`` that moves the point B
   by a millimetre (benchmarks/designer.py's ``server_previews``: the server's own answer, no browser), the Newton
   kernel ready (compiled, as the designer compiles it in the background); p50 and p95 (ms).
4. **Compile cost** with empty caches (a fresh process, ``ASSUR_CACHE_DIR=off``, its own ``NUMBA_CACHE_DIR``; numba
   imported before): the CPU time of each kernel's first call minus a warm call, and the generated source's lines;
   beside it, the numpy backend's time for the same call (one cycle of 720 samples), so the compile's pay-back is
   read off.
5. **Agreement**: the triad six-bar's cycle, compiled against the numpy backend with the same options: the valid
   samples, the largest position difference over the mechanism's size, the velocities' and accelerations' relative
   difference.
6. **Where the compiled triad cycle's time goes** (case 1's cycle, round-robin): the whole ``assur.solve`` call, its
   kernel called alone with the same arguments (the rest is the Python around it: the batch's layout, the arguments,
   the State), and the same kernel with the triad's certificate (``reductions.triad_check``: the root-free bound on
   the distance to the other assemblies first, and where it proves nothing the polynomial's roots tracked, the
   nearest assembly and the separation) replaced by "passed" — on this mechanism every step passes it, so the walks
   and the numbers are the same (checked), and the difference is the certificate's cost; the rest is the
   continuation's Newton iterations and the derivatives.
7. **Without the vectorisers**: case 1's compiled cycles once more in a fresh process whose numba has LLVM's loop and
   SLP vectorisers off (``NUMBA_LOOP_VECTORIZE=0``, ``NUMBA_SLP_VECTORIZE=0``, empty caches, so every kernel is
   compiled that way), round-robin as in case 1: how much of the gap between the triad and the dyad six-bars is the
   dyad kernels running several samples at once (SIMD), which the Newton kernel's walks (a loop with branches per
   sample) do not.
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


def _round_robin(cases: dict, repeats: int) -> dict:
    """``{case: [CPU seconds]}`` of the warm callables ``cases``, round-robin, 20 calls per repeat (a call is about a
    millisecond)."""
    times = {k: [] for k in cases}
    for _ in range(repeats):
        for k, fn in cases.items():
            for _ in range(20):
                times[k].append(_timed(fn))
    return times


def _cycle(plan, backend="auto", sweep=False):
    import numpy as np

    import assur
    q = np.linspace(0.0, 2 * np.pi, 720, endpoint=False)

    def run():
        st = assur.solve(plan, inputs=q, order=2, backend=backend, sweep=sweep)
        return st.pos, st.vel, st.acc
    return run


#: the case of a numpy cycle that is its plan's first
FIRST_NUMPY = "triad six-bar, numpy, the plan's first cycle"


def _first_cycle(plan):
    """A numpy cycle of the plan as its first call: the file's design's whole steps of crank, which the numpy
    continuation keeps with the plan (assur.engine.planar.continuation.WholeSteps), dropped before each call."""
    from assur.engine.planar import continuation
    run = _cycle(plan, "numpy")

    def first():
        continuation._WHOLE_STEPS.pop(plan, None)
        return run()
    return first


def cycles(repeats: int) -> dict:
    import assur
    triad = assur.compile(assur.load(EX / "triad_sixbar.toml"))
    s3 = assur.compile(assur.load(EX / "stephenson3.toml"))
    w2 = assur.compile(assur.load(EX / "watt2.toml"))
    cases = {"triad six-bar, compiled (default continuation)": _cycle(triad, "numba"),
             "triad six-bar, compiled, sweep=True": _cycle(triad, "numba", True),
             "Stephenson III six-bar, dyads, compiled": _cycle(s3, "numba"),
             "Watt II six-bar, dyads, compiled": _cycle(w2, "numba"),
             "Stephenson III six-bar, dyads, numpy": _cycle(s3, "numpy"),
             "Watt II six-bar, dyads, numpy": _cycle(w2, "numpy")}
    slow = {"triad six-bar, numpy (default continuation)": _cycle(triad, "numpy"),
            FIRST_NUMPY: _first_cycle(triad)}
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
            st = assur.solve(plan, P[i:i + 1000, None, :], q[:, None], order=2, backend="numba", sweep=True)
            st.pos, st.vel, st.acc
    numba_backend.cycle_objective(plan, P[:10], q, 1e-12)
    assur.solve(plan, P[:2, None, :], q[:, None], order=2, backend="numba", sweep=True)
    times = {"cycle reduction (synthesis)": [], "solve, order 2, sweep=True, chunks of 1 000 designs": []}
    for _ in range(repeats):
        times["cycle reduction (synthesis)"].append(_timed(reduction))
        times["solve, order 2, sweep=True, chunks of 1 000 designs"].append(_timed(solve))
    return {"times": times, "samples": len(P) * len(q), "info": info}


def previews(count: int) -> list:
    """ms of the designer's answers to previews of the triad six-bar (module docstring, 3)."""
    from assur.designer.session import Session, document_of
    from assur.engine.planar import numba_backend
    sys.path.insert(0, str(HERE))
    from designer import server_previews
    doc, _ = document_of(EX / "triad_sixbar.toml")
    numba_backend.prepare_newton(Session(doc, None).entry(doc).plan)
    server_previews(doc, "B", 5)                              # warm: the structure's source traced, the kernel loaded
    return server_previews(doc, "B", count)


def breakdown(repeats: int) -> dict:
    """CPU ms of one cycle (module docstring, 6): ``{case: [times]}`` and whether the kernel without the certificate
    gave the same valid samples and numbers."""
    import numpy as np

    import assur
    from assur.engine.planar import newton_kernels, numba_backend
    from assur.kernels import codegen
    from assur.tolerances import DEFAULT
    plan = assur.compile(assur.load(EX / "triad_sixbar.toml"))
    q = np.linspace(0.0, 2 * np.pi, 720, endpoint=False)
    whole = _cycle(plan, "numba")
    whole()
    kernel = numba_backend._KERNELS[plan][numba_backend._newton_key(True)]      # the one ``whole`` loaded
    call = "tok0, tsep0 = triad_check(TA, TS, RT0, asep * ls)"
    src = newton_kernels.solve_source(plan, 2, True)
    assert src.count(call) == 1, "the triad's certificate call is not where this benchmark expects it"
    bare = codegen.load(src.replace(call, "tok0, tsep0 = True, True"), "the kernel without the certificate")
    designs, rows, _ = newton_kernels.layout(plan, plan.defaults, q[:, None], q.shape)
    args = newton_kernels.arguments(plan, designs, rows, DEFAULT, True)
    n = 6 * (len(plan.point_names) + len(plan.body_names)) + sum(3 * len(st.bodies) + 1 for st in plan.steps
                                                                  if st.kind == "newton") + 1    # + the ambiguous row
    outs = {}

    def alone(k, name):
        out, valid = np.empty((n, 1, q.size)), np.empty((1, q.size), dtype=np.bool_)
        outs[name] = (out, valid)
        return lambda: k(*args, 1.0, 1.0, 0.0, out, valid)
    cases = {"assur.solve, the whole call": whole, "its kernel alone": alone(kernel, "kernel"),
             "the kernel without the triad's certificate": alone(bare, "bare")}
    for fn in cases.values():
        fn()
    (a, va), (b, vb) = outs["kernel"], outs["bare"]
    same = bool(np.array_equal(va, vb) and np.array_equal(a, b, equal_nan=True))
    return {"times": _round_robin(cases, repeats), "same": same}


def agreement() -> dict:
    import numpy as np

    import assur
    plan = assur.compile(assur.load(EX / "triad_sixbar.toml"))
    q = np.linspace(0.0, 2 * np.pi, 720, endpoint=False)
    rel = lambda x, y: float(np.max(np.abs(x - y)) / np.max(np.abs(x)))  # noqa: E731
    out = {}
    for sweep in (False, True):
        a = assur.solve(plan, inputs=q, order=2, backend="numpy", sweep=sweep)
        b = assur.solve(plan, inputs=q, order=2, backend="numba", sweep=sweep)
        name = "sweep=True" if sweep else "default continuation"
        out[f"{name}: valid (numpy / compiled)"] = f"{int(a.valid.sum())} / {int(b.valid.sum())} of 720"
        out[f"{name}: positions (of the size)"] = float(np.max(np.abs(a.pos - b.pos)) / plan.length_scale)
        out[f"{name}: velocities"] = rel(a.vel, b.vel)
        out[f"{name}: accelerations"] = rel(a.acc, b.acc)
    return out


# -- the compile cost: a worker process with empty caches -----------------------------------------------------------
def compile_worker() -> dict:
    import numba  # noqa: F401  (imported before timing)
    import numpy as np

    import assur
    from assur.engine.planar import numba_backend
    plan = assur.compile(assur.load(EX / "triad_sixbar.toml"))
    q = np.linspace(0.0, 2 * np.pi, 720, endpoint=False)
    out = {}
    first = _timed(_cycle(plan, "numba"))
    warm = _timed(_cycle(plan, "numba"))
    out["solve kernel (order 2, points and bodies)"] = {
        "compile": first - warm, "lines": len(numba_backend.newton_kernels.solve_source(plan, 2).splitlines())}
    first = _timed(_cycle(plan, "numba", True))
    warm = _timed(_cycle(plan, "numba", True))
    out["solve kernel, sweep=True"] = {
        "compile": first - warm, "lines": len(numba_backend.newton_kernels.solve_source(plan, 2, False).splitlines())}
    first = _timed(lambda: numba_backend.cycle_objective(plan, plan.defaults[None], q, 1e-12))
    warm = _timed(lambda: numba_backend.cycle_objective(plan, plan.defaults[None], q, 1e-12))
    src = numba_backend.cycle_source(plan, None, None, False)
    out["cycle reduction kernel (buildability)"] = {"compile": first - warm, "lines": len(src.splitlines())}
    out["numpy backend, one cycle (720, order 2)"] = {"compile": _timed(_cycle(plan, "numpy")), "lines": None}
    return out


#: case 1's compiled cycles that section 7 runs again without the vectorisers
SCALAR_CASES = ("triad six-bar, compiled (default continuation)", "Stephenson III six-bar, dyads, compiled",
                "Watt II six-bar, dyads, compiled")


def scalar_worker(repeats: int) -> dict:
    """Case 1's compiled cycles :data:`SCALAR_CASES` in this process (whose environment turned the vectorisers off):
    ``{case: [CPU seconds]}``, round-robin, 20 calls per repeat."""
    import assur
    files = dict(zip(SCALAR_CASES, ("triad_sixbar.toml", "stephenson3.toml", "watt2.toml")))
    cases = {k: _cycle(assur.compile(assur.load(EX / f)), "numba") for k, f in files.items()}
    for fn in cases.values():
        fn()
    return _round_robin(cases, repeats)


def scalar_cycles(repeats: int) -> dict:
    """:func:`scalar_worker` in a fresh process with LLVM's loop and SLP vectorisers off and empty caches."""
    return _fresh_process(["--scalar-worker", "--repeats", str(repeats)],
                          NUMBA_LOOP_VECTORIZE="0", NUMBA_SLP_VECTORIZE="0")


def _fresh_process(args: list, **env) -> dict:
    """This script run with ``args`` in a fresh process with empty caches (``ASSUR_CACHE_DIR=off``, its own
    ``NUMBA_CACHE_DIR``) and ``env`` besides: the JSON its last line prints."""
    with tempfile.TemporaryDirectory() as nb:
        env = dict(os.environ, ASSUR_CACHE_DIR="off", NUMBA_CACHE_DIR=nb, **env,
                   PYTHONPATH=str(ROOT / "src") + os.pathsep + os.environ.get("PYTHONPATH", ""))
        r = subprocess.run([sys.executable, __file__, *args], env=env, capture_output=True, text=True, check=True)
    return json.loads(r.stdout.strip().splitlines()[-1])


def compile_cost() -> dict:
    return _fresh_process(["--compile-worker"])


def _rate(work, ts):
    return work / min(ts), work / statistics.median(ts)


def report(repeats: int, moves: int) -> str:
    import numba
    import numpy as np
    load0 = os.getloadavg()
    t0 = time.monotonic()
    cyc = cycles(repeats)
    pop = population(max(3, repeats // 2))
    prev = previews(moves)
    agree = agreement()
    brk = breakdown(repeats)
    comp = compile_cost()
    scalar = scalar_cycles(repeats)
    load1 = os.getloadavg()
    med = {k: statistics.median(v) for k, v in cyc.items()}
    triad = "triad six-bar, compiled (default continuation)"
    lines = [
        "# Compiled Newton groups: a triad six-bar against dyad six-bars, a population, the designer, the compile cost",
        "",
        f"{datetime.date.today()}, Python {platform.python_version()}, numpy {np.__version__}, numba "
        f"{numba.__version__}, {os.cpu_count()} cores shared; load average {load0[0]:.1f} at the start and "
        f"{load1[0]:.1f} at the end; {time.monotonic() - t0:.0f} s in all. CPU-time min and median of the repeats. "
        f"Command: `python benchmarks/newton.py --repeats {repeats} --moves {moves}`.",
        "",
        "## One cycle: 720 samples, order 2 (`assur.solve(plan, inputs=q, order=2)`, then pos, vel, acc)",
        "",
        "| case | min | median | median / compiled triad's |",
        "|---|---|---|---|",
    ]
    for k, ts in cyc.items():
        lines.append(f"| {k} | {min(ts) * 1e3:.3f} ms | {med[k] * 1e3:.3f} ms | {med[k] / med[triad]:.2f} |")
    ratio = {k: med[triad] / med[k] for k in med if "dyads" in k}
    lines += ["", "The compiled triad six-bar takes " + ", ".join(f"{v:.1f}× the time of the {k}"
                                                               for k, v in ratio.items()) + "; "
              f"numpy takes {med['triad six-bar, numpy (default continuation)'] / med[triad]:.0f}× its time for it "
              f"once the plan keeps its whole steps of crank, "
              f"{med[FIRST_NUMPY] / med[triad]:.0f}× on the "
              "plan's first cycle.", ""]
    n = pop["samples"]
    lines += ["## 10 000 designs × 360 samples of the triad six-bar (±3 % per parameter)", "",
              "| case | min | median |", "|---|---|---|"]
    for k, ts in pop["times"].items():
        lo, md = _rate(n, ts)
        lines.append(f"| {k} | {lo / 1e6:.2f} M samples/s | {md / 1e6:.2f} M samples/s |")
    lines += ["", f"{pop['info']['buildable designs']} of the 10 000 designs turn fully. (Under the default "
              "continuation every sample of a changed design walks from the file's design at the sketch on its own, "
              "about ten times the work: the synthesis evaluator sweeps, as `sweep=True`.)", "",
              "## The designer's preview of the triad six-bar (server's answer, wall-clock)", "",
              "| previews | min | p50 | p95 | max |", "|---|---|---|---|---|",
              f"| {len(prev)} | {min(prev):.1f} ms | {np.percentile(prev, 50):.1f} ms | {np.percentile(prev, 95):.1f} ms "
              f"| {max(prev):.1f} ms |", "",
              "## Compile cost with empty caches (CPU seconds of the first call minus a warm call)", "",
              "| kernel | compile | generated lines |", "|---|---|---|"]
    for k, v in comp.items():
        if isinstance(v, dict):
            lines.append(f"| {k} | {v['compile']:.2f} s | {v['lines'] or ''} |")
    lines += ["", "The numpy row is the call the kernel replaces (no compile): the solve kernel pays back after "
              f"{comp['solve kernel (order 2, points and bodies)']['compile'] / comp['numpy backend, one cycle (720, order 2)']['compile']:.1f} "
              "such cycles, once per mechanism structure (the kernel depends on the structure only and is cached on "
              "disk).", "", "## Agreement with the numpy backend (one cycle, the same options)", ""]
    lines += [f"- {k}: {v if isinstance(v, str) else f'{v:.1e}'}" for k, v in agree.items()]
    bmed = {k: statistics.median(v) for k, v in brk["times"].items()}
    whole, alone, bare = (bmed[k] for k in brk["times"])
    lines += ["", "## Where the compiled triad cycle's time goes (720 samples, order 2)", "",
              "| case | min | median |", "|---|---|---|"]
    for k, ts in brk["times"].items():
        lines.append(f"| {k} | {min(ts) * 1e3:.3f} ms | {statistics.median(ts) * 1e3:.3f} ms |")
    lines += ["", f"Medians: the Python around the kernel {(whole - alone) * 1e3:.3f} ms, the triad's certificate "
              f"{(alone - bare) * 1e3:.3f} ms, the rest of the kernel (about one certified Newton solve per sample, "
              f"the continuation's bookkeeping, the derivatives) {bare * 1e3:.3f} ms. The kernel without the "
              f"certificate gave {'the same' if brk['same'] else 'DIFFERENT'} valid samples and numbers.", ""]
    smed = {k: statistics.median(v) for k, v in scalar.items()}
    lines += ["## Without the vectorisers (a fresh process: `NUMBA_LOOP_VECTORIZE=0 NUMBA_SLP_VECTORIZE=0`)", "",
              "| case | median, vectorised (above) | min, scalar | median, scalar | median / compiled triad's, scalar |",
              "|---|---|---|---|---|"]
    for k, ts in scalar.items():
        lines.append(f"| {k} | {med[k] * 1e3:.3f} ms | {min(ts) * 1e3:.3f} ms | {smed[k] * 1e3:.3f} ms | "
                     f"{smed[k] / smed[triad]:.2f} |")
    sdyad = min(smed[k] for k in smed if "dyads" in k)
    dyad = min(med[k] for k in med if "dyads, compiled" in k)
    # across the two processes the fastest runs (min) are compared: a shared machine's load moves the medians
    smin = {k: min(v) for k, v in scalar.items()}
    vmin = {k: min(cyc[k]) for k in SCALAR_CASES}
    dmin = min(smin[k] for k in smin if "dyads" in k) / min(vmin[k] for k in vmin if "dyads" in k)
    lines += ["", f"Without the vectorisers the compiled triad six-bar takes {smed[triad] / sdyad:.1f}× the time of the "
              f"faster dyad six-bar, against {med[triad] / dyad:.1f}× with them (medians, each in its own process); "
              f"by the fastest runs (min) the dyad six-bar's call is {dmin:.1f}× slower without them, the triad's "
              f"{smin[triad] / vmin[triad]:.2f}×. The dyad "
              "kernels' sample loop is straight-line code that LLVM runs on several samples at once; the Newton "
              "kernel walks each sample with branches and loops (the iterations, the step control, the "
              "certificate), which run one sample at a time either way.", ""]
    lines += ["## The targets (issue 26, section 4)", "",
              f"- a triad six-bar cycle within 3× a compiled dyad six-bar's time: {med[triad] / dyad:.1f}× "
              f"({'met' if med[triad] <= 3 * dyad else 'not met'}); the kernel's certified Newton solves and the "
              f"triad's certificate alone take {bare / dyad:.1f}× and {(alone - bare) / dyad:.1f}× the dyad "
              "six-bar's whole call;",
              f"- the designer's preview of it at p95 < 30 ms: {np.percentile(prev, 95):.1f} ms on the server "
              f"({'met' if np.percentile(prev, 95) < 30 else 'not met'} there; the browser's round trip is "
              "benchmarks/designer.py's);",
              f"- 10 000 designs × 360 at ≥ 1 M samples/s on one core: the cycle reduction "
              f"{_rate(n, pop['times']['cycle reduction (synthesis)'])[1] / 1e6:.2f} M/s (median), the order-2 solve "
              f"{_rate(n, pop['times']['solve, order 2, sweep=True, chunks of 1 000 designs'])[1] / 1e6:.2f} M/s."]
    return "\n".join(lines) + "\n"


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--repeats", type=int, default=7)
    ap.add_argument("--moves", type=int, default=200, help="designer previews timed")
    ap.add_argument("--out", default=str(HERE / "newton_results.md"))
    ap.add_argument("--compile-worker", action="store_true", help=argparse.SUPPRESS)
    ap.add_argument("--scalar-worker", action="store_true", help=argparse.SUPPRESS)
    a = ap.parse_args()
    sys.path.insert(0, str(ROOT / "src"))
    if a.compile_worker:
        print(json.dumps(compile_worker()))
        return
    if a.scalar_worker:
        print(json.dumps(scalar_worker(a.repeats)))
        return
    text = report(a.repeats, a.moves)
    print(text)
    if a.out != "-":
        Path(a.out).write_text(text, encoding="utf-8")


if __name__ == "__main__":
    main()
