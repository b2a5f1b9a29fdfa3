"""The widest constant-speed window in the atlas: the tables of docs/codesign.md, "The widest window in the atlas".

    assur atlas --walking-legs --links 6 --budget 4000 --rank window -o out/legs6w    # the ranking (see the page)
    .venv/bin/python docs/codesign/atlas_window.py out/legs6w                         # the tables, from its files
    .venv/bin/python docs/codesign/atlas_window.py out/legs6w --copy docs/codesign/widest_leg6.toml
    .venv/bin/python docs/codesign/atlas_window.py out/legs6w --widen 3000 --widen-top 3   # longer widening

Every number is re-measured here from the ranking's mechanism files (``assur.codesign.widest.widest_window`` of the
file's foot law, ``assur.gait_metrics``) and compared with what the ranking recorded; the shipped legs' windows are
measured the same way for comparison. ``--widen N`` runs the ranking's widening search again on the ``--widen-top``
widest legs with N designs (``assur.synthesis.leg_window.widen_window``, from each entry's design). ``--copy`` writes the widest leg's file (with a comment naming its source).
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
from assur.codesign.widest import widest_window  # noqa: E402

SHIPPED = {"four-bar (004)": "walker_fourbar.toml", "six-bar (004)": "walker_sixbar.toml", "Jansen": "jansen.toml",
           "Klann": "klann.toml", "crank–slider (000)": "walker_crank_slider.toml"}


def _g(v, digits=3):
    return "—" if v is None else f"{v:.{digits}g}" if isinstance(v, float) else str(v)


def measure(plan) -> dict:
    """The widest window and the bound at 0.9 of a leg, and its gait (mm)."""
    w = widest_window(foot_law(plan))
    g = assur.gait_metrics(plan)
    return {"window": w.window, "worst": w.at_target.worst if w.at_target else None,
            "slack": w.at_target.slack if w.at_target else None,
            "bound": None if w.pressure_bound is None else math.degrees(w.pressure_bound),
            "step": g.step_length * 1000, "lift": g.lift * 1000, "sag": g.sag * 1000,
            "spread90": g.vx_spread["0.9"]}


def longer(data: dict, entries: list, budget: int) -> None:
    """The widening search again with ``budget`` designs from each entry's design: its window before and after,
    the sampled sag it keeps, the bound at 0.9 after."""
    import numpy as np

    from assur.synthesis.evaluate import Evaluator
    from assur.synthesis.legs import candidate_seed, leg_candidates, leg_problem
    from assur.synthesis.leg_window import widen_window
    by_key = {c.key: c for c in leg_candidates(data["links"])}
    print(f"\n| leg | widest window: ranking → {budget} more designs | μ bound at 0.9 (°) | sag (mm) |\n"
          f"|---|---|---:|---:|")
    for e in entries:
        problem = leg_problem(by_key[e["key"]], data["settings"])
        x0 = problem.to_si(np.array([e["variables"][n] for n in problem.names]))
        w = widen_window(problem, x0, budget=budget, seed=candidate_seed(data["settings"]["seed"] + 2, e["key"]))
        plan = problem.plan
        m = measure_params(plan, Evaluator(problem).params(w["x"][None])[0])
        print(f"| {e['name']} | {w['start_window']:.3f} → {m['window']:.3f} | {_g(m['bound'])} | {m['sag']:.1f} |")


def measure_params(plan, params) -> dict:
    """:func:`measure` of a plan at other parameters."""
    from assur.analysis.study import Study
    w = widest_window(foot_law(plan, params))
    g = Study(plan, params).gait
    return {"window": w.window, "bound": None if w.pressure_bound is None else math.degrees(w.pressure_bound),
            "sag": g.sag * 1000}


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("ranking", type=Path, help="the output directory of assur atlas --walking-legs --rank window")
    ap.add_argument("--top", type=int, default=10, help="rows of the ranking's table")
    ap.add_argument("--copy", type=Path, default=None, help="write the widest leg's mechanism file there")
    ap.add_argument("--widen", type=int, default=0, metavar="N", help="a longer widening search of N designs")
    ap.add_argument("--widen-top", type=int, default=3, metavar="K", help="on the K widest legs")
    args = ap.parse_args(argv)
    data = json.loads((args.ranking / "ranking.json").read_text(encoding="utf-8"))
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
        longer(data, entries[:args.widen_top], args.widen)
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
