#!/usr/bin/env python3
"""The compiled kernels of two source trees side by side in one run: speed, compile time and code size.

Run: ``python benchmarks/kernels.py --before REV`` (writes ``benchmarks/kernels_results.md``; ``--out -`` prints
only). The tree "before" is ``git archive REV src`` unpacked into a temporary directory; "after" is this
checkout's ``src``. Every measurement runs in a fresh process with that tree first on ``sys.path``, its own kernel
cache (``ASSUR_CACHE_DIR``) and numba cache (``NUMBA_CACHE_DIR``):

* speed: per round, one warm process per tree (the order alternates ABBA over the rounds), each timing every case
  ``--repeats`` times after a warm-up call; the rate is work / CPU seconds of the process (the machine is shared:
  CPU time is the per-core cost). Reported: min and median over all rounds and repeats, and after / before;
* compile time: one process per tree with empty caches, the CPU time of each case's first call minus its warm
  call (generating, compiling and caching its kernels; ``numba`` itself is imported before);
* code size: lines and bytes of the generated kernel sources the cold process wrote;
* agreement: every case's result arrays of the two trees, compared (max relative difference).

Cases (the synthesis benchmark's parts A and gait, and the engine's solve and force paths):

* ``path objective``: ``Evaluator(problem)(X)`` of ``benchmarks/fourbar_6targets.toml`` on 10 000 designs (the
  fused path reduction, ``numba_backend.path_objective``), evaluations/s;
* ``cycle reduction``: ``Evaluator(problem)(X)`` of ``examples/synthesis/walker_fourbar_gait.toml`` on 20 000
  designs (the fused cycle kernel, ``numba_backend.cycle_objective``: gait terms, transmission, buildability);
* ``solve order 2``: ``assur.solve(plan, params (D, 1, n), q (360,), order=2, backend="numba")`` of
  ``examples/walker_fourbar.toml`` on 500 designs and of ``examples/jansen.toml`` on one design × 3 600 angles,
  then reading ``pos``, ``vel``, ``acc``; samples/s;
* ``forces``: ``assur.forces(plan, params, q)`` of ``examples/walker_fourbar.toml`` on 500 designs × 360
  (kinematics then the traced force kernel); samples/s.
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
import tarfile
import tempfile
import time
from pathlib import Path

HERE = Path(__file__).resolve().parent
ROOT = HERE.parent
CASES = ("path objective", "cycle reduction", "solve order 2 (four-bar, 500 × 360)",
         "solve order 2 (Jansen, 1 × 3 600)", "forces (four-bar, 500 × 360)")


# ------------------------------------------------------------------------------------------------
# the worker: one tree, one process
# ------------------------------------------------------------------------------------------------

def _cases():
    """{name: (work units, unit, fn returning a dict of result arrays)}; built in the worker's tree."""
    import numpy as np

    import assur
    from assur.synthesis import Evaluator, load_problem
    sys.path.insert(0, str(HERE))
    from synthesis import EXAMPLES, PROBLEM_A, benchmark_designs

    pa = load_problem(PROBLEM_A)
    Xa = benchmark_designs(10_000)
    eva = Evaluator(pa)
    pg = load_problem(EXAMPLES / "walker_fourbar_gait.toml")
    lo, hi = pg.bounds.T
    Xg = lo + (hi - lo) * np.random.default_rng(7).random((20_000, pg.n_vars))
    evg = Evaluator(pg)
    four = assur.compile(assur.load(ROOT / "examples" / "walker_fourbar.toml"))
    rng = np.random.default_rng(2026)
    P4 = four.defaults * (1 + 0.01 * rng.standard_normal((500, four.n_params)))
    q360 = np.linspace(0, 2 * np.pi, 360, endpoint=False)
    jansen = assur.compile(assur.load(ROOT / "examples" / "jansen.toml"))
    q3600 = np.linspace(0, 2 * np.pi, 3600, endpoint=False)
    Pf = P4

    def solve(plan, params, q):
        st = assur.solve(plan, params, q, order=2, backend="numba")
        return {"pos": np.asarray(st.pos), "vel": np.asarray(st.vel), "acc": np.asarray(st.acc)}

    def evaluate(ev, X):
        e = ev(X)
        return {"penalised": e.penalised, "violation": e.violation}

    def forces():
        r = assur.forces(four, Pf[:, None, :], q360)
        return {"driver": np.asarray(r.driver), "reactions": np.asarray(r.reactions)}

    return {
        CASES[0]: (len(Xa), "evaluations", lambda: evaluate(eva, Xa)),
        CASES[1]: (len(Xg), "evaluations", lambda: evaluate(evg, Xg)),
        CASES[2]: (P4.shape[0] * 360, "samples", lambda: solve(four, P4[:, None, :], q360)),
        CASES[3]: (3600, "samples", lambda: solve(jansen, jansen.defaults, q3600)),
        CASES[4]: (Pf.shape[0] * 360, "samples", forces),
    }


def worker(mode: str, repeats: int, save: str | None) -> dict:
    import gc

    import numba  # noqa: F401  (imported before any timing)
    import numpy as np
    cases = _cases()
    out = {}
    for name, (work, unit, fn) in cases.items():
        c0 = time.process_time()
        result = fn()
        first = time.process_time() - c0
        if mode == "cold":
            c0 = time.process_time()
            fn()
            out[name] = {"compile": first - (time.process_time() - c0)}
            if save:
                np.savez(Path(save) / f"{CASES.index(name)}.npz", **result)
            continue
        cpu = []
        for _ in range(repeats):
            gc.collect()
            gc.disable()
            c0 = time.process_time()
            fn()
            cpu.append(time.process_time() - c0)
            gc.enable()
        out[name] = {"cpu": cpu, "work": work, "unit": unit}
    return out


# ------------------------------------------------------------------------------------------------
# the driver
# ------------------------------------------------------------------------------------------------

def export(rev: str, into: Path) -> Path:
    """``git archive REV src`` unpacked into ``into``; returns its src directory."""
    data = subprocess.run(["git", "-C", str(ROOT), "archive", rev, "src"], check=True, capture_output=True).stdout
    into.mkdir(parents=True, exist_ok=True)
    path = into / "archive.tar"
    path.write_bytes(data)
    with tarfile.open(path) as tar:
        tar.extractall(into, filter="data")
    return into / "src"


def run_worker(src: Path, caches: Path, mode: str, repeats: int, save: Path | None = None) -> dict:
    env = dict(os.environ, PYTHONPATH=str(src), ASSUR_CACHE_DIR=str(caches / "assur"),
               NUMBA_CACHE_DIR=str(caches / "numba"), PYTHONDONTWRITEBYTECODE="1")
    cmd = [sys.executable, __file__, "--worker", mode, "--repeats", str(repeats)]
    if save is not None:
        cmd += ["--save", str(save)]
    r = subprocess.run(cmd, env=env, capture_output=True, text=True)
    if r.returncode:
        raise SystemExit(f"worker ({src}, {mode}) failed:\n{r.stderr}")
    return json.loads(r.stdout.strip().splitlines()[-1])


def code_size(caches: Path) -> tuple[int, int, int]:
    """(kernels, lines, bytes) of the generated kernel sources in a cache."""
    files = sorted((caches / "assur" / "kernels").glob("assur_kernel_*.py"))
    text = [f.read_text(encoding="utf-8") for f in files]
    return len(files), sum(t.count("\n") for t in text), sum(len(t.encode()) for t in text)


def agreement(a: Path, b: Path) -> dict:
    import numpy as np
    out = {}
    for i, name in enumerate(CASES):
        fa, fb = np.load(a / f"{i}.npz"), np.load(b / f"{i}.npz")
        worst, same_nan = 0.0, True
        for k in fa.files:
            x, y = fa[k], fb[k]
            same_nan &= bool(np.array_equal(np.isnan(x), np.isnan(y)))
            ok = np.isfinite(x) & np.isfinite(y)
            if ok.any():
                scale = max(float(np.max(np.abs(x[ok]))), 1e-300)
                worst = max(worst, float(np.max(np.abs(x[ok] - y[ok]))) / scale)
        out[name] = (worst, same_nan)
    return out


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--before", default="main", help="the git revision to compare with (default main)")
    ap.add_argument("--rounds", type=int, default=4, help="warm processes per tree (alternating ABBA)")
    ap.add_argument("--repeats", type=int, default=5, help="timed calls per case and process")
    ap.add_argument("--out", default=str(HERE / "kernels_results.md"), help="Markdown file ('-' for none)")
    ap.add_argument("--worker", choices=("warm", "cold"), help=argparse.SUPPRESS)
    ap.add_argument("--save", help=argparse.SUPPRESS)
    args = ap.parse_args(argv)
    if args.worker:
        print(json.dumps(worker(args.worker, args.repeats, args.save)))
        return 0
    t_start = time.perf_counter()
    with tempfile.TemporaryDirectory(prefix="assur-bench-kernels-") as tmp:
        tmp = Path(tmp)
        trees = {"before": export(args.before, tmp / "before"), "after": ROOT / "src"}
        results = {t: {"cold": None, "warm": []} for t in trees}
        sizes, saves = {}, {}
        for t, src in trees.items():                      # cold: empty caches, compile times and code size
            caches, saves[t] = tmp / f"cold-{t}", tmp / f"results-{t}"
            saves[t].mkdir()
            results[t]["cold"] = run_worker(src, caches, "cold", 0, saves[t])
            sizes[t] = code_size(caches)
        order = list(trees)
        for r in range(args.rounds):                      # warm: ABBA
            for t in (order if r % 2 == 0 else order[::-1]):
                results[t]["warm"].append(run_worker(trees[t], tmp / f"warm-{t}", "warm", args.repeats))
        agree = agreement(saves["before"], saves["after"])
    text = report(args, results, sizes, agree, time.perf_counter() - t_start)
    print(text)
    if args.out != "-":
        Path(args.out).write_text(text, encoding="utf-8")
    return 0 if all(w <= 1e-9 and n for w, n in agree.values()) else 1


def _rev(rev: str) -> str:
    r = subprocess.run(["git", "-C", str(ROOT), "rev-parse", "--short", rev], capture_output=True, text=True)
    return r.stdout.strip() or rev


def fmt(r: float) -> str:
    return f"{r / 1e6:.3f} M" if r >= 1e6 else f"{r / 1e3:.1f} k"


def report(args, results, sizes, agree, seconds) -> str:
    import numba
    import numpy as np
    lines = [f"# Compiled kernels: before ({args.before} = {_rev(args.before)}) and after ({_rev('HEAD')} + working "
             "tree), side by side", "",
             f"{datetime.date.today().isoformat()}, Python {platform.python_version()}, numpy {np.__version__}, "
             f"numba {numba.__version__}, {os.cpu_count()} cores, load average "
             f"{' '.join(f'{x:.1f}' for x in os.getloadavg())} at the end; {args.rounds} warm processes per tree "
             f"(ABBA) × {args.repeats} calls; {seconds:.0f} s in all. Command: "
             f"`python benchmarks/kernels.py --before {args.before} --rounds {args.rounds} --repeats {args.repeats}`.",
             "", "| case | before min / median | after min / median | after / before (medians) | max rel. diff |",
             "|---|---|---|---|---|"]
    for name in CASES:
        row = []
        med = {}
        for t in ("before", "after"):
            cpu = [c for w in results[t]["warm"] for c in w[name]["cpu"]]
            work, unit = results[t]["warm"][0][name]["work"], results[t]["warm"][0][name]["unit"]
            med[t] = work / statistics.median(cpu)
            row.append(f"{fmt(work / min(cpu))} / {fmt(med[t])} {unit}/s")
        worst, same_nan = agree[name]
        lines.append(f"| {name} | {row[0]} | {row[1]} | {med['after'] / med['before']:.3f} | "
                     f"{worst:.1e}{'' if same_nan else ' (NaN masks differ)'} |")
    lines += ["", "Compile time (first call with empty caches minus a warm call, CPU seconds) and generated code:", "",
              "| case | before | after |", "|---|---|---|"]
    for name in CASES:
        lines.append(f"| {name} | {results['before']['cold'][name]['compile']:.2f} s | "
                     f"{results['after']['cold'][name]['compile']:.2f} s |")
    (kb, lb, bb), (ka, la, ba) = sizes["before"], sizes["after"]
    lines += [f"| generated kernel sources | {kb} files, {lb} lines, {bb / 1e3:.1f} kB | "
              f"{ka} files, {la} lines, {ba / 1e3:.1f} kB |", ""]
    return "\n".join(lines)


if __name__ == "__main__":
    sys.exit(main())
