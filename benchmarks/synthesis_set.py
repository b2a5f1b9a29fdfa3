#!/usr/bin/env python3
"""The default command on the synthesis benchmark set: every problem, 5 seeds, the table of docs/synthesis.md.

The set: the shipped benchmark files (paper 000's six points, C1–C3 of docs/papers/synthesis_benchmarks.md §2) and
the wider cases of §4 (``json-set`` data blocks: problem file, best published objective). Each run is
``synthesize(problem, seed=s)`` — what ``assur synth FILE --seed S`` runs with no option (the file's ``[solver]``
table, else the built-in defaults) —, one process per run, ``--workers`` at a time (the machine's cores). Per
problem: the best published objective, the median and best f reached, the hit rate (runs whose best met it), the
median evaluations and wall / CPU seconds per run; per run the evaluations at which its best first met the target.

    .venv/bin/python benchmarks/synthesis_set.py --seeds 5 --workers 2          # writes benchmarks/synthesis_set.json
    .venv/bin/python benchmarks/synthesis_set.py --table                       # the Markdown table from the JSON
    .venv/bin/python benchmarks/synthesis_set.py --table --write-docs          # … into docs/synthesis.md
    .venv/bin/python benchmarks/synthesis_set.py --method lshade --only hcdj4_six_points_arc   # another method, the
                                                        # same runs otherwise (benchmarks/synthesis_set_lshade.json)

Results are appended run by run to the JSON file (``--out``), so an interrupted sweep keeps what it ran and
``--resume`` runs only what is missing.
"""
from __future__ import annotations

import argparse
import json
import multiprocessing
import re
import statistics
import sys
import time
from concurrent.futures import ProcessPoolExecutor, as_completed
from pathlib import Path

HERE = Path(__file__).resolve().parent
ROOT = HERE.parent
EXAMPLES = ROOT / "examples" / "synthesis"
DOCS = ROOT / "docs" / "synthesis.md"
SPEC = ROOT / "docs" / "papers" / "synthesis_benchmarks.md"
BEGIN, END = "<!-- synthesis-set table: begin -->", "<!-- synthesis-set table: end -->"

#: the shipped benchmarks: file, label, best published objective (docs/papers/synthesis_benchmarks.md §3.2; paper
#: 000: the lowest Δ1 found, docs/reproduction.md), its source
SHIPPED = [
    ("paper000_six_points.toml", "paper 000, six points, Δ1 (mm)", 99.85, "lowest Δ1 found (docs/reproduction.md)"),
    ("c1_six_points_line.toml", "C1, six points on a line, free timing", 1e-20, "exact optimum 0; ECA 1.96e-20"),
    ("c2_five_points_timed.toml", "C2, five points, prescribed timing", 1.284000e-6, "\"MUMSA\" (HCDJ code)"),
    ("c3_eighteen_points_closed.toml", "C3, eighteen points, closed curve", 1.607768e-2, "HCDJ 2022"),
]


def wider_set():
    """(file, label, target, source) of the json-set blocks of docs/papers/synthesis_benchmarks.md §4."""
    text = SPEC.read_text(encoding="utf-8")
    out = []
    for block in re.findall(r"```json-set\n(.*?)```", text, re.S):
        b = json.loads(block)
        best = min((e for e in b["published"] if e["feasible"]), key=lambda e: e["f_ref"])
        out.append((b["file"], f"{b['case']}: {Path(b['file']).stem}", b["target_f_max"], best["label"]))
    return out


def problems():
    return SHIPPED + wider_set()


def one_run(job):
    """One seeded run in a worker process (the default command, or ``method`` with every other setting as the
    default command's) → a JSON-able record."""
    file, seed, target, method = job
    from assur.synthesis import load_problem, synthesize
    problem = load_problem(EXAMPLES / file)
    w0, c0 = time.perf_counter(), time.process_time()
    r = synthesize(problem, method, seed=seed)
    wall, cpu = time.perf_counter() - w0, time.process_time() - c0
    hit = next((e for e, _, F in r.history if F <= target), None)
    return {"file": file, "seed": seed, "objective": r.objective, "feasible": bool(r.feasible),
            "evaluations": int(r.evaluations), "wall": wall, "cpu": cpu, "stopped": r.stopped,
            "first_hit": hit, "settings": {k: v for k, v in r.settings.items() if k != "sources"},
            "x": [float(v) for v in r.x_file]}


def load(path):
    return json.loads(Path(path).read_text(encoding="utf-8")) if Path(path).exists() else {"runs": []}


def run(args):
    data = load(args.out) if args.resume else {"runs": []}
    done = {(r["file"], r["seed"]) for r in data["runs"]}
    jobs = [(f, s, t, args.method) for f, _, t, _ in problems() if not args.only or Path(f).stem in args.only
            for s in range(args.seeds) if (f, s) not in done]
    jobs.sort(key=lambda j: j[0].startswith("c1_"))          # the longest runs (C1: 2 000 000 evaluations) last
    data.setdefault("started", time.strftime("%Y-%m-%dT%H:%M:%S%z"))
    if args.resume and "command" in data:                # a resumed sweep keeps the first command and adds its own
        data.setdefault("resumed", []).append(" ".join(sys.argv[1:]))
    else:
        data["command"] = " ".join(sys.argv)
    with ProcessPoolExecutor(args.workers, mp_context=multiprocessing.get_context("spawn")) as pool:
        futures = {pool.submit(one_run, j): j for j in jobs}
        for fut in as_completed(futures):
            rec = fut.result()
            data["runs"].append(rec)
            Path(args.out).write_text(json.dumps(data, indent=1), encoding="utf-8")
            print(f"{rec['file']} seed {rec['seed']}: f = {rec['objective']}, {rec['evaluations']} FE, "
                  f"{rec['wall']:.0f} s", file=sys.stderr, flush=True)


def fmt(v):
    return "–" if v is None else f"{v:.6g}"


def table(data, method=None) -> str:
    """The Markdown table of docs/synthesis.md from the recorded runs (of the default command, or of ``method``:
    then only the problems it was run on)."""
    rows = [f"| problem | best published f (source) | {method or 'default'} median / best f | hit rate "
            "| evaluations (median) | wall / CPU s per run (median) |", "|---|---|---:|---:|---:|---:|"]
    met = 0
    counted = 0
    for file, label, target, source in problems():
        runs = [r for r in data["runs"] if r["file"] == file]
        if not runs:
            if method is None:
                rows.append(f"| {label} (`{file}`) | {target:.7g} ({source}) | not run | | | |")
            continue
        fs = [r["objective"] if r["feasible"] else float("inf") for r in runs]
        hits = sum(r["feasible"] and r["objective"] <= target for r in runs)
        counted += 1
        met += hits >= 0.8 * len(runs)
        rows.append(f"| {label} (`{file}`) | {target:.7g} ({source}) | {fmt(statistics.median(fs))} / {fmt(min(fs))} "
                    f"| {hits}/{len(runs)} | {statistics.median(r['evaluations'] for r in runs):,.0f} "
                    f"| {statistics.median(r['wall'] for r in runs):.1f} / "
                    f"{statistics.median(r['cpu'] for r in runs):.1f} |")
    rows.append("")
    who = f"`--method {method}`" if method else "the defaults"
    rows.append(f"Problems whose best published objective {who} meet in at least 4 of 5 runs: {met} of "
                f"{counted}. Runs: `{data.get('command', '')}` (started {data.get('started', '?')})"
                + "".join(f"; then `{r}`" for r in data.get("resumed", [])) + ".")
    return "\n".join(rows) + "\n"


#: the README's synthesis table: the shipped files' settings column and the lower values found here
README_SETTINGS = {"paper000_six_points.toml": "budget 20 000 (file)",
                   "c1_six_points_line.toml": "budget 2 000 000, target 1e-20, free_timing explicit (file)",
                   "c2_five_points_timed.toml": "budget 300 000 (default)",
                   "c3_eighteen_points_closed.toml": "budget 300 000 (default)"}
README_LOWER = {"c2_five_points_timed.toml": 7.4158e-7, "c3_eighteen_points_closed.toml": 9.0289e-3}


def readme_table(data) -> str:
    """The README's synthesis table (the shipped files, the default command) from the recorded runs."""
    rows = ["| file (`examples/synthesis/`) | settings (default command) | best published f | runs meeting it | "
            "best / median f reached | FE to first meet it | lower value found here: runs meeting it |",
            "|---|---|---:|---:|---:|---:|---:|"]
    for file, label, target, source in SHIPPED:
        runs = [r for r in data["runs"] if r["file"] == file]
        if not runs:
            continue
        fs = [r["objective"] if r["feasible"] else float("inf") for r in runs]
        met = [r for r in runs if r["feasible"] and r["objective"] <= target]
        hits = [r["first_hit"] for r in met if r["first_hit"] is not None]
        fe = "–" if not hits else (f"{min(hits) / 1000:.1f}–{max(hits) / 1000:.1f} k" if max(hits) < 1e6 else
                                   f"{min(hits) / 1e6:.2f}–{max(hits) / 1e6:.2f} M")
        low = README_LOWER.get(file)
        lower = "–" if low is None else f"≤ {low:g}: {sum(f <= low for f in fs)}/{len(runs)}"
        rows.append(f"| `{file}` | {README_SETTINGS[file]} | {target:g} ({source}) | {len(met)}/{len(runs)} | "
                    f"{min(fs):.7g} / {statistics.median(fs):.7g} | {fe} | {lower} |")
    return "\n".join(rows) + "\n"


def write_docs(text):
    doc = DOCS.read_text(encoding="utf-8")
    if BEGIN not in doc:
        raise SystemExit(f"{DOCS} has no {BEGIN} … {END} block")
    start, end = doc.index(BEGIN) + len(BEGIN), doc.index(END)
    from assur.io.output import atomic_file
    with atomic_file(DOCS) as tmp:
        Path(tmp).write_text(doc[:start] + "\n" + text + doc[end:], encoding="utf-8")


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--seeds", type=int, default=5)
    ap.add_argument("--workers", type=int, default=2)
    ap.add_argument("--only", nargs="*", help="problem file stems to run (default: all)")
    ap.add_argument("--resume", action="store_true", help="keep the runs already in --out, run the rest")
    ap.add_argument("--method", help="run this method instead of the default command's (its runs go to "
                    "benchmarks/synthesis_set_METHOD.json unless --out is given; no --write-docs)")
    ap.add_argument("--out", help="the runs' JSON file (default benchmarks/synthesis_set.json)")
    ap.add_argument("--table", action="store_true", help="print the table from --out instead of running")
    ap.add_argument("--write-docs", action="store_true", help="with --table: write it into docs/synthesis.md")
    ap.add_argument("--readme", action="store_true", help="with --table: the README's table of the shipped files")
    args = ap.parse_args(argv)
    if args.out is None:
        args.out = str(HERE / (f"synthesis_set_{args.method}.json" if args.method else "synthesis_set.json"))
    if args.table:
        text = readme_table(load(args.out)) if args.readme else table(load(args.out), args.method)
        print(text)
        if args.write_docs and not args.method:
            write_docs(text)
        return 0
    run(args)
    print(table(load(args.out), args.method))
    return 0


if __name__ == "__main__":
    sys.exit(main())
