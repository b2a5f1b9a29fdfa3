"""``assur synth PROBLEM --exact``: the closed-form four-bars of a problem's function or pose targets, as a ranked
table (residual, Grashof class, rotatability, defects), ``-o`` the best, ``--json``, ``--report`` the page.

The checks are independent of the table: the written best motion generator is solved by the engine over its turn
and its coupler point must pass through the three poses of the problem file (their positions and angles); the
function generator's output is compared with the file's pairs the same way.
"""
import json
import math
from pathlib import Path

import numpy as np
import pytest

import assur
from assur.cli.main import main
from assur.synthesis import load_problem

ROOT = Path(__file__).resolve().parents[1]
SYN = ROOT / "examples" / "synthesis"


def _run(capsys, *args):
    code = main([str(a) for a in args])
    out, err = capsys.readouterr()
    return code, out, err


def test_motion_generation_table_and_the_best_design_meets_the_poses(capsys, tmp_path):
    best = tmp_path / "best.toml"
    code, out, err = _run(capsys, "synth", SYN / "motion_three_poses.toml", "--exact", "--limit", "5", "-o", best)
    assert code == 0, err
    lines = out.splitlines()
    head = next(line for line in lines if "rank" in line)
    for col in ("residual [mm]", "Grashof class", "crank", "worst μ", "defects"):
        assert col in head
    rows = [line.split() for line in lines[lines.index(head) + 1:] if line.strip()[:1].isdigit()]
    assert [int(r[0]) for r in rows] == [1, 2, 3, 4, 5]
    assert "ranked by the worst transmission angle" in out and f"wrote {best}" in out
    # the written design, solved over its turn by the engine, carries P through the file's poses
    m = assur.load(best)
    plan = assur.compile(m)
    q = np.linspace(0, 2 * math.pi, 7201)
    st = assur.solve(plan, inputs=q, order=0, on_unbuildable="nan")
    P, A, B = (st.point(n).pos * 1e3 for n in "PAB")            # mm
    poses = np.array([[138.08, 235.93, 35.5675], [28.00, 278.41, 22.5334], [-92.76, 184.26, 25.0741]])
    lines = []
    for x, y, ang in poses:
        d = np.hypot(P[:, 0] - x, P[:, 1] - y)
        k = int(np.nanargmin(d))
        assert d[k] < 0.05                                          # on the path (0.05° samples of the turn)
        lines.append(math.degrees(math.atan2(B[k, 1] - A[k, 1], B[k, 0] - A[k, 0])))
    # the coupler turns between the poses as the poses' angles do (its line A → B keeps a fixed offset)
    for k in (1, 2):
        turn = (lines[k] - lines[0]) - (poses[k, 2] - poses[0, 2])
        assert abs((turn + 180) % 360 - 180) < 0.1


def test_function_generation_json_and_report(capsys, tmp_path):
    code, out, err = _run(capsys, "synth", SYN / "function_fourbar.toml", "--exact", "--json", "--limit", "3",
                          "--report", tmp_path / "page")
    assert code == 0, err
    d = json.loads(out)
    assert d["kind"] == "function" and d["residual_unit"] == "rad" and len(d["candidates"]) == 3
    assert [c["rank"] for c in d["candidates"]] == [1, 2, 3]
    res = [c["residual"] for c in d["candidates"]]
    assert res == sorted(res) and all(c["defects"] == [] for c in d["candidates"])
    assert all(c["defects"] for c in d["rejected"]) and sum(d["counts"].values()) > 0
    html = (tmp_path / "page" / "index.html").read_text(encoding="utf-8")
    assert "Grashof class" in html and "data:image/png;base64," in html and 'href="best.toml"' in html
    best = assur.load(tmp_path / "page" / "best.toml")
    # the best design's residual, recomputed: its rocker's angle change against the file's pairs, with the crank
    # started where it fits best (the table's input start is free: scanned here over a fine grid)
    p = load_problem(SYN / "function_fourbar.toml")
    x, y = p.targets.xy.T
    plan = assur.compile(best)
    B0 = np.asarray(best.sketch("B0"))
    starts = np.linspace(0, 2 * math.pi, 3600, endpoint=False)
    st = assur.solve(plan, inputs=(starts[:, None] + x[None, :]).ravel(), order=0, on_unbuildable="nan")
    B = st.point("B").pos.reshape(len(starts), len(x), 2)
    psi = np.unwrap(np.arctan2(B[..., 1] - B0[1], B[..., 0] - B0[0]), axis=1)
    err = np.abs((psi - psi[:, :1]) - (y - y[0])[None, :]).max(axis=1)
    assert np.nanmin(err) == pytest.approx(d["candidates"][0]["residual"], rel=0.05, abs=2e-3)


def test_an_empty_result_says_why_and_exits_3(capsys):
    code, out, err = _run(capsys, "synth", SYN / "motion_three_poses.toml", "--exact", "--grashof", "double-crank")
    assert code == 3
    assert err.count("\n") == 1 and err.startswith("error: no candidate kept") and "grashof filter" in err


@pytest.mark.parametrize("args, where", [
    (["--exact", "--budget", "100"], "--budget"),
    (["--exact", "--grashof", "cranky"], "--grashof"),
    (["--grashof", "crank"], "--grashof"),
])
def test_bad_exact_options_are_one_error_line(capsys, args, where):
    code, out, err = _run(capsys, "synth", SYN / "motion_three_poses.toml", *args)
    assert code == 1 and err.count("\n") == 1 and err.startswith("error: ") and where in err


def test_path_targets_have_no_exact_method(capsys):
    code, out, err = _run(capsys, "synth", SYN / "c2_five_points_timed.toml", "--exact")
    assert code == 1 and "targets.kind" in err and "points" in err


def test_results_read_as_one_line(capsys):
    from assur.synthesis import synthesize
    r = synthesize(load_problem(SYN / "paper000_six_points.toml"), seed=1, budget=300, polish="none")
    text = repr(r)
    assert text.startswith("SynthesisResult(") and "\n" not in text and "evaluations" in text and len(text) < 600
