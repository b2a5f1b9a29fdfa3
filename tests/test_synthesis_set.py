"""The wider synthesis benchmark set (docs/papers/synthesis_benchmarks.md §4): every printed design of the set's data
blocks re-evaluates, through its problem file with the timing as printed, to the objective and feasibility recorded
there; with free timing solved per design the same design variables are never worse."""
import json
import re
import tomllib
from pathlib import Path

import numpy as np
import pytest

from assur.synthesis import Evaluator, load_problem, problem_from_dict

ROOT = Path(__file__).resolve().parents[1]
SPEC = ROOT / "docs" / "papers" / "synthesis_benchmarks.md"
SYN = ROOT / "examples" / "synthesis"
BLOCKS = [json.loads(b) for b in re.findall(r"```json-set\n(.*?)```", SPEC.read_text(encoding="utf-8"), re.S)]
ENTRIES = [(b, e) for b in BLOCKS for e in b["published"]]


def explicit(path):
    """The problem file with free timing as design variables (a printed vector carries its own angles)."""
    data = tomllib.loads(path.read_text(encoding="utf-8"))
    if data["targets"].get("timing") == "free":
        data["targets"]["free_timing"] = "explicit"
    return problem_from_dict(data, base_dir=path.parent, source=str(path))


def closed_form_f(x, xy, theta):
    """Σ squared distances of the "+"-branch coupler point (docs/papers/synthesis_benchmarks.md §1.2, geometric form)
    of x = [r1, r2, r3, r4, rcx, rcy, x0, y0, θ0] at the crank angles theta, written here."""
    r1, r2, r3, r4, rcx, rcy, x0, y0, t0 = x[:9]
    ax, ay = r2 * np.cos(theta), r2 * np.sin(theta)
    d = np.hypot(r1 - ax, ay)
    t3 = np.arctan2(-ay, r1 - ax) + np.arccos((r3 * r3 + d * d - r4 * r4) / (2 * r3 * d))
    px, py = ax + rcx * np.cos(t3) - rcy * np.sin(t3), ay + rcx * np.sin(t3) + rcy * np.cos(t3)
    P = np.stack([np.cos(t0) * px - np.sin(t0) * py + x0, np.sin(t0) * px + np.cos(t0) * py + y0], axis=-1)
    return float(np.sum((P - xy) ** 2))


def test_the_set_has_its_problem_files():
    assert len(BLOCKS) >= 2
    for b in BLOCKS:
        p = load_problem(SYN / b["file"])
        assert p.deviation == "squared" and b["target_f_max"] > 0


@pytest.mark.parametrize("block,entry", ENTRIES, ids=[f"{b['case']}-{e['label'][:24]}" for b, e in ENTRIES])
def test_printed_designs_reproduce(block, entry):
    path = SYN / block["file"]
    p = explicit(path)
    x = np.array(entry["x"])
    e = Evaluator(p)(x[None, :], detail=True)
    f = float((e.quantities["distances"][0] ** 2).sum())
    assert f == pytest.approx(entry["f_ref"], rel=1e-6)
    assert bool(e.feasible[0]) == entry["feasible"]
    t = p.targets
    theta = t.inputs if t.timing == "prescribed" else x[9:]
    assert closed_form_f(x, t.xy, theta) == pytest.approx(f, rel=1e-9)    # the independent closed form agrees
    inner = load_problem(path)
    if inner.targets.timing == "free" and entry["feasible"]:
        fi = Evaluator(inner)(x[None, :]).objective[0]
        assert fi <= f * (1 + 1e-9)


def test_each_target_is_the_lowest_feasible_printed_objective():
    for b in BLOCKS:
        best = min(e["f_ref"] for e in b["published"] if e["feasible"])
        assert best <= b["target_f_max"] <= best * (1 + 1e-6)
