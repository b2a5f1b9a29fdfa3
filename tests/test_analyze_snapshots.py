"""The numbers of ``assur analyze --json`` stay put: every shipped example's output is compared with the output of
the same command at commit 9a7a4e5 (tests/data/analyze/*.json, generated once by running ``assur analyze FILE
--json`` there, before the Study refactor).

A refactor changes no number. The only differences allowed are the ones another issue asks for; each is listed in
:data:`CHANGES` with its reason: the JSON paths (``*`` for any list index or key) whose values may differ from
the old output, or that are new.
"""
from __future__ import annotations

import io
import json
import math
import re
from contextlib import redirect_stdout
from pathlib import Path

import pytest

from assur.cli.main import main

ROOT = Path(__file__).resolve().parents[1]
DATA = ROOT / "tests" / "data" / "analyze"
NAMES = sorted(p.stem for p in DATA.glob("*.json"))

#: (example or "*", path pattern, reason): values allowed to differ from (or be absent in) the old output
CHANGES = [
    ("*", "dead_centres[*].crank",
     "issue 25 A1: a dead centre names the crank it belongs to (a geared mechanism's crank is not its motor)"),
    ("walker_fourbar_geared", "dead_centres",
     "issue 25 A1: the geared leg's dead centres, in the motor's angle (the old output had none)"),
    ("walker_fourbar_geared", "dead_centres[*]*", "issue 25 A1: as above"),
    ("*", "four_bars", "issue 25 A6: every four-bar loop's Grashof class and inversion"),
    ("slider_crank", "output_link", "issue 25 A5: a slider's stroke, extremes and time ratio (the output member was "
                                    "none: only a rocker hinged to the frame counted)"),
    ("walker_crank_slider", "output_link", "issue 25 A5: as above"),
    ("*", "gait.vx_spread.*",
     "issue 26 §6: the spread over a central fraction of the stride is taken between the window's exact ends (on the "
     "samples alone it stopped up to a sample short of them: the geared four-bar's 0.037 over 90 % is 0.041; "
     "tests/test_gait.py checks the closed form to 1e-9)"),
    ("*", "gait.clearance", "issue 26 §6: how far the foot rises above its support in the swing (lift − sag), new"),
    ("*", "ambiguous", "issue 26 §3: of the unbuildable samples, those on two assemblies (one each way round from the "
                       "sketch), new; 0 on every example (tests/test_continuation_closure.py checks a leg with them)"),
]

#: relative and absolute tolerance of a number (the old numbers were computed with other operation orders in places:
#: the dead centres bracketed on another grid and refined by Brent's method to 1e-13 rad)
REL, ABS = 1e-9, 1e-10


def _allowed(name: str, path: str) -> bool:
    """Whether ``path`` of example ``name`` matches a listed change (``*`` matches anything, brackets are literal)."""
    return any(ex in ("*", name) and re.fullmatch(re.escape(pat).replace(r"\*", ".*"), path) for ex, pat, _ in CHANGES)


def compare(name: str, old, new, path: str = "") -> list[str]:
    """The differences of two JSON values (old → new), skipping the allowed changes."""
    if _allowed(name, path):
        return []
    if isinstance(old, dict) and isinstance(new, dict):
        out = []
        for k in old.keys() | new.keys():
            p = f"{path}.{k}" if path else str(k)
            if k not in new:
                out += [] if _allowed(name, p) else [f"{p}: missing (was {old[k]!r})"]
            elif k not in old:
                out += [] if _allowed(name, p) else [f"{p}: new key"]
            else:
                out += compare(name, old[k], new[k], p)
        return out
    if isinstance(old, list) and isinstance(new, list):
        if len(old) != len(new):
            return [f"{path}: {len(old)} items became {len(new)}"]
        return [d for i, (a, b) in enumerate(zip(old, new)) for d in compare(name, a, b, f"{path}[{i}]")]
    if isinstance(old, bool) or isinstance(new, bool) or isinstance(old, str) or old is None or new is None:
        return [] if old == new else [f"{path}: {old!r} became {new!r}"]
    if isinstance(old, (int, float)) and isinstance(new, (int, float)):
        return [] if math.isclose(old, new, rel_tol=REL, abs_tol=ABS) else [f"{path}: {old!r} became {new!r}"]
    return [] if old == new else [f"{path}: {old!r} became {new!r}"]


def analyze_json(path: Path) -> dict:
    out = io.StringIO()
    with redirect_stdout(out):
        assert main(["analyze", str(path), "--json"]) == 0
    return json.loads(out.getvalue())


@pytest.mark.parametrize("name", [pytest.param(n, marks=() if n == "walker_fourbar" else pytest.mark.slow)
                                  for n in NAMES])
def test_analyze_json_is_unchanged(name, monkeypatch):
    monkeypatch.chdir(ROOT)      # the old outputs name their file relative to the project
    old = json.loads((DATA / f"{name}.json").read_text(encoding="utf-8"))
    new = analyze_json(Path(old["file"]))
    diffs = compare(name, old, new)
    assert not diffs, f"{name}: " + "; ".join(sorted(diffs)[:20])


def test_the_comparison_sees_a_changed_number_a_missing_key_and_a_new_key():
    old = {"a": 1.0, "b": [{"c": 2.0}], "d": "x"}
    assert compare("t", old, old) == []
    assert compare("t", old, {**old, "a": 1.0 + 1e-6})
    assert compare("t", old, {"b": old["b"], "d": "x"})
    assert compare("t", old, {**old, "e": 0})
    assert compare("t", old, {**old, "b": [{"c": 2.0}, {"c": 3.0}]})
    assert compare("t", old, {**old, "d": "y"})
    assert compare("t", {"x": 1.0}, {"x": 1.0 + 1e-13}) == []
    assert compare("t", {"dead_centres": [{"a": 1}]}, {"dead_centres": [{"a": 1, "crank": "c"}]}) == []
    assert compare("t", {"dead_centres": [{"a": 1}]}, {"dead_centres": [{"a": 1, "cranks": "c"}]})
