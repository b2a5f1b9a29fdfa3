"""The widest constant-speed window in the atlas: the tables of docs/codesign.md, "The widest window in the atlas".

    assur atlas --walking-legs --links 6 --budget 4000 --rank window -o out/legs6w    # the ranking (see the page)
    .venv/bin/python docs/codesign/atlas_window.py out/legs6w                         # the tables, from its files
    .venv/bin/python docs/codesign/atlas_window.py out/legs6w --copy docs/codesign/widest_leg6.toml
    .venv/bin/python docs/codesign/atlas_window.py out/legs6w --widen 3000 --widen-top 3   # longer widening
    .venv/bin/python docs/codesign/atlas_window.py out/legs8 --screen out/legs8w.json --workers 2 --widen 450 \
        --widen-top 24                                       # a gait ranking: every feasible leg's window measured,
                                                             # the widest widened (the eight-link table)

Every number is re-measured here from the ranking's mechanism files (``assur.codesign.widest.widest_window`` of the
file's foot law, ``assur.gait_metrics``) and compared with what the ranking recorded; the shipped legs' windows are
measured the same way for comparison. ``--widen N`` runs the ranking's widening search again on the ``--widen-top``
widest legs with N designs (``assur.synthesis.leg_window.widen_window``, from each entry's design). ``--copy`` writes the widest leg's file (with a comment naming its source).

``--screen FILE`` reads a ranking by gait instead (``assur atlas --walking-legs`` without ``--rank window``): every
feasible leg's widest window is measured from its file (on ``--workers`` processes; the measures are kept in FILE and
a run that stops goes on from them), the legs are ranked by it, and ``--widen N`` widens the ``--widen-top`` widest:
the window ranking's second stage on the legs the first stage places first, where widening all of them would take
hours.
"""
from __future__ import annotations

import argparse
import json
import math
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT / "src"))

import assur  # noqa: E402
from assur.codesign.law import foot_law  # noqa: E402
from assur.codesign.widest import LOWEST, widest_window  # noqa: E402

SHIPPED = {"four-bar (004)": "walker_fourbar.toml", "six-bar (004)": "walker_sixbar.toml", "Jansen": "jansen.toml",
           "Klann": "klann.toml", "crank–slider (000)": "walker_crank_slider.toml"}


def _g(v, digits=3):
    return "—" if v is None else f"{v:.{digits}g}" if isinstance(v, float) else str(v)


def measure(plan, params=None) -> dict:
    """The widest window and the bound at 0.9 of a leg (at ``params``, default the plan's), and its gait (mm): one
    foot law and the gait metrics it carries."""
    law = foot_law(plan, params)
    w = widest_window(law)
    g = law.metrics
    return {"window": w.window, "worst": w.at_target.worst if w.at_target else None,
            "slack": w.at_target.slack if w.at_target else None,
            "bound": None if w.pressure_bound is None else math.degrees(w.pressure_bound),
            "step": g.step_length * 1000, "lift": g.lift * 1000, "sag": g.sag * 1000,
            "spread90": g.vx_spread["0.9"]}


def _widen_one(links: int, settings: dict, entry: dict, budget: int, offset: int) -> dict:
    """One leg's widening search (a worker's job) from its entry's design, seeded with the ranking's seed + offset
    (1: the ranking's own widening stage, as ``--rank window`` runs it; 2: another search after it): its window
    before, and :func:`measure` of the widened design."""
    import numpy as np

    from assur.io.mechanism_writer import dumps
    from assur.synthesis.design import mechanism_with_params
    from assur.synthesis.evaluate import Evaluator
    from assur.synthesis.legs import candidate_seed, leg_candidates, leg_problem
    from assur.synthesis.leg_window import widen_window
    candidate, = leg_candidates(links, entry["key"])
    problem = leg_problem(candidate, settings)
    x0 = problem.to_si(np.array([entry["variables"][n] for n in problem.names]))
    w = widen_window(problem, x0, budget=budget, seed=candidate_seed(settings["seed"] + offset, entry["key"]))
    base = problem.plan.mechanism
    mech = mechanism_with_params(problem.plan, Evaluator(problem).params(w["x"][None])[0], name=base.name,
                                 description=base.description)
    return {"start_window": w["start_window"], "moved": not np.array_equal(w["x"], x0),
            "variables": dict(zip(problem.names, problem.to_file(w["x"]).tolist())), "mechanism": dumps(mech),
            **measure(assur.compile(mech))}   # the file's own plan, as the ranking measures what it writes


def longer(data: dict, entries: list, budget: int, *, offset: int = 2, workers: int = 1, done=None,
           save=None) -> list:
    """The widening search with ``budget`` designs from each entry's design (``offset`` as :func:`_widen_one`), on
    ``workers`` processes: its window before and after, the sampled sag it keeps, the bound at 0.9 after. ``done``:
    results already found, by key (not searched again); ``save(key, result)`` is called as each one comes in.
    Returns the results in the entries' order."""
    from concurrent.futures import ProcessPoolExecutor
    done = {} if done is None else done
    print(f"\n| leg | widest window: before → after {budget} designs | worst margin at 0.9 | μ bound at 0.9 (°) | "
          f"step (mm) | lift (mm) | sag (mm) |\n|---|---|---|---:|---:|---:|---:|", flush=True)
    with ProcessPoolExecutor(max_workers=workers) as pool:
        jobs = [None if e["key"] in done else
                pool.submit(_widen_one, data["links"], data["settings"], e, budget, offset) for e in entries]
        out = []
        for e, job in zip(entries, jobs):
            m = done[e["key"]] if job is None else job.result()
            if job is not None and save is not None:
                save(e["key"], m)
            out.append(m)
            print(f"| {e['name']} | {_g(m['start_window'])} → {_g(m['window'])} | {m['worst']} | {_g(m['bound'])} | "
                  f"{m['step']:.1f} | {m['lift']:.1f} | {m['sag']:.1f} |", flush=True)
    return out


def _screen_one(path: str) -> dict:
    """:func:`measure` of one leg file (a worker's job)."""
    return measure(assur.compile(assur.load(path)))


#: mm: a foot that rises less than this above its own support arc in the swing does not lift off (it retraces it)
FLAT = 0.5


def clearance(m: dict) -> float:
    """How far the foot rises above its support in the swing (mm): the path's height range less the support's."""
    return max(m["lift"] - m["sag"], 0.0)         # lift ≥ sag: below zero only by round-off


def _write(path: Path, data: dict) -> None:
    """``data`` as JSON in ``path``, whole or not at all (a temporary file beside it, renamed)."""
    tmp = path.with_name(path.name + ".tmp")
    tmp.write_text(json.dumps(data, indent=1), encoding="utf-8")
    tmp.replace(path)


def screen(args, data: dict) -> int:
    """``--screen``: every feasible leg of a gait ranking measured, ranked by window, the widest widened."""
    from concurrent.futures import ProcessPoolExecutor

    kept = json.loads(args.screen.read_text(encoding="utf-8")) if args.screen.exists() else {}
    entries = [e for e in data["entries"] if e["feasible"] and e.get("file")]
    todo = [e for e in entries if e["key"] not in kept]
    print(f"{data['links']} links: {len(data['entries'])} candidates, {len(entries)} feasible; "
          f"{len(entries) - len(todo)} measured before, {len(todo)} to measure", flush=True)
    with ProcessPoolExecutor(max_workers=args.workers) as pool:
        jobs = {e["key"]: pool.submit(_screen_one, str(args.ranking / e["file"])) for e in todo}
        for n, (key, job) in enumerate(jobs.items(), 1):
            try:
                kept[key] = job.result()
            except assur.AssurError as exc:              # a leg the gait search kept that the exact law refuses
                kept[key] = {"window": None, "error": str(exc)}
            if n % 25 == 0 or n == len(jobs):
                _write(args.screen, kept)
                print(f"  {n} / {len(jobs)} measured", flush=True)
    ranked = sorted((e for e in entries if kept[e["key"]].get("window")),
                    key=lambda e: (-kept[e["key"]]["window"], e["rank"]))
    print(f"\n{len(ranked)} of the {len(entries)} feasible legs pass the screen at {LOWEST} or wider\n")
    header = ("| rank | leg (gait rank) | widest window | worst margin at 0.9 | μ bound at 0.9 (°) | step (mm) | "
              "lift (mm) | sag (mm) | clearance (mm) | vx spread 90 % (uniform crank) |\n"
              "|---:|---|---:|---|---:|---:|---:|---:|---:|---:|")

    def table(rows):
        print(header)
        for i, e in rows:
            m = kept[e["key"]]
            print(f"| {i} | {e['name']} ({e['rank']}) | {m['window']:.3f} | {m['worst']} | {_g(m['bound'])} | "
                  f"{m['step']:.1f} | {m['lift']:.1f} | {m['sag']:.1f} | {clearance(m):.1f} | {m['spread90']:.3f} |")
    table(list(enumerate(ranked, 1))[:args.top])
    known = [kept[e["key"]]["bound"] for e in ranked if kept[e["key"]]["bound"] is not None]
    if known:
        print(f"\nμ bound at 0.9 over the {len(known)} legs with a 0.9 window: least {min(known):.1f}°, "
              f"median {sorted(known)[len(known) // 2]:.1f}°; {sum(b > 30 for b in known)} of them above 30°")
    flat = sum(clearance(kept[e["key"]]) < FLAT for e in ranked)
    walking = [(i, e) for i, e in enumerate(ranked, 1) if clearance(kept[e["key"]]) > kept[e["key"]]["sag"]]
    print(f"\n{flat} of the {len(ranked)} legs lift the foot less than {FLAT} mm above their support (a foot that "
          f"retraces its support in the swing); {len(walking)} lift it clear by more than the support sags, the "
          f"widest of them:\n")
    table(walking[:args.top])
    if args.widen > 0:
        widened = kept.setdefault("widened", {})

        def save(key, result):
            widened[key] = result
            _write(args.screen, kept)
        longer(data, ranked[:args.widen_top], args.widen, offset=1, workers=args.workers, done=widened, save=save)
    return 0


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("ranking", type=Path, help="the output directory of assur atlas --walking-legs --rank window")
    ap.add_argument("--top", type=int, default=10, help="rows of the ranking's table")
    ap.add_argument("--copy", type=Path, default=None, help="write the widest leg's mechanism file there")
    ap.add_argument("--widen", type=int, default=0, metavar="N", help="a longer widening search of N designs")
    ap.add_argument("--widen-top", type=int, default=3, metavar="K", help="on the K widest legs")
    ap.add_argument("--screen", type=Path, default=None, metavar="FILE",
                    help="the ranking is by gait: measure every feasible leg's window (kept in FILE), rank by it")
    ap.add_argument("--workers", type=int, default=1, help="processes measuring the legs (with --screen)")
    args = ap.parse_args(argv)
    data = json.loads((args.ranking / "ranking.json").read_text(encoding="utf-8"))
    if args.screen is not None:
        if args.copy is not None:
            raise SystemExit("error: --copy writes the widest leg of a ranking by window; with --screen, copy the "
                             "widened leg's \"mechanism\" from FILE")
        return screen(args, data)
    if data["settings"].get("rank") != "window":
        raise SystemExit("error: that ranking is not by window (run assur atlas --walking-legs --rank window)")
    entries = [e for e in data["entries"] if e["feasible"] and e["metrics"] and e["metrics"].get("window")]
    s = data["settings"]
    print(f"{data['links']} links: {len(data['entries'])} candidates, {len(entries)} with a screened window; "
          f"gait search {s['budget']} evaluations, {s['starts']} starts, widening {s['window_budget']} designs, "
          f"seed {s['seed']}\n")
    print("| rank | leg | widest window (gait search → widened) | worst margin at 0.9 | μ bound at 0.9 (°) | "
          "step (mm) | lift (mm) | sag (mm) | vx spread 90 % (uniform crank) |")
    print("|---:|---|---|---|---:|---:|---:|---:|---:|")
    bounds = []
    for e in entries:
        plan = assur.compile(assur.load(args.ranking / e["file"]))
        m = measure(plan)
        assert abs(m["window"] - e["metrics"]["window"]) < 1e-9, (e["key"], m["window"], e["metrics"]["window"])
        bounds.append(m["bound"])
        if e["rank"] <= args.top:
            start = e.get("widening", {}).get("start_window")
            print(f"| {e['rank']} | {e['name']} (`{e['file']}`) | {_g(start)} → {m['window']:.3f} | {m['worst']} | "
                  f"{_g(m['bound'])} | {m['step']:.1f} | {m['lift']:.1f} | {m['sag']:.1f} | {m['spread90']:.3f} |")
    known = [b for b in bounds if b is not None]
    print(f"\nμ bound at 0.9 over the {len(known)} legs with a 0.9 window: least {min(known):.1f}°, "
          f"median {sorted(known)[len(known) // 2]:.1f}°; {sum(b > 30 for b in known)} of them above 30°")
    print("\n| shipped leg | widest window | worst margin at 0.9 | μ bound at 0.9 (°) |\n|---|---:|---|---:|")
    for name, file in SHIPPED.items():
        m = measure(assur.compile(assur.load(ROOT / "examples" / file)))
        print(f"| {name} | {m['window']:.3f} | {m['worst']} | {_g(m['bound'])} |")
    if args.widen > 0:
        longer(data, entries[:args.widen_top], args.widen, workers=args.workers)
    if args.copy is not None and entries:
        best = entries[0]
        text = (args.ranking / best["file"]).read_text(encoding="utf-8")
        head = (f"# The widest constant-speed window of the {data['links']}-link atlas ranking (docs/codesign.md, "
                f"\"The widest window in the atlas\"):\n# {best['name']}, {best['key']}, widest screened window "
                f"{best['metrics']['window']:.4f};\n# made by assur atlas --walking-legs --links {data['links']} "
                f"--budget {s['budget']} --rank window (seed {s['seed']}).\n")
        args.copy.write_text(head + text, encoding="utf-8")
        print(f"\nwrote {args.copy}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
