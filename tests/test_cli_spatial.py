"""The command line on spatial (dimension = 3) files: validate, info, solve, analyze, plot, animate
and report on examples/rssr.toml (docs/papers/003.md §9, P003-2) and examples/rssr_tilted.toml; bad input gives
``error: ...`` with exit status 1 and leaves no output behind. Expected numbers are P003-2's closed
forms (§9 of that page) or the library's own solve of the same file."""
from __future__ import annotations

import csv
import json
import math
from pathlib import Path

import numpy as np
import pytest

from assur.io.output import MARKER   # every output directory carries it (io/output.py)
import assur
from assur.cli.main import main

ROOT = Path(__file__).resolve().parents[1]
RSSR = ROOT / "examples" / "rssr.toml"
TILTED = ROOT / "examples" / "rssr_tilted.toml"


def run(argv, capsys):
    code = main([str(a) for a in argv])
    out, err = capsys.readouterr()
    return code, out, err


def test_validate_and_info(capsys):
    code, out, _ = run(["validate", RSSR], capsys)
    assert code == 0 and "spatial, W = 1 by Somov–Malyshev" in out and "R–S–S → P3" in out
    code, out, _ = run(["info", TILTED], capsys)
    assert code == 0
    assert "W = 6·3 − 5·2 − 4·1 − 3·1 − 2·0 − 0 = 1" in out
    assert "branch s = sign det[P2 − P4, e, P3 − P4] = +1" in out
    lines = [ln.split() for ln in out.splitlines()]
    assert ["P4.axis.gamma1", "=", "60", "°"] in lines and ["P4.axis.gamma2", "=", "20", "°"] in lines
    assert ["rocker.length", "=", "45", "mm"] in lines


def test_solve_csv_equals_the_library(tmp_path, capsys):
    out_csv = tmp_path / "rssr.csv"
    code, out, _ = run(["solve", TILTED, "--steps", "24", "--csv", out_csv, "--file-units"], capsys)
    assert code == 0 and "24 positions of crank over one turn (spatial); 0 cannot be assembled" in out
    with open(out_csv, newline="", encoding="utf-8") as fh:
        rows = list(csv.reader(fh))
    head, data = rows[0], np.array([[float(c) for c in r] for r in rows[1:]])
    plan = assur.compile(assur.load(TILTED))
    q = np.linspace(0, 2 * math.pi, 24, endpoint=False)
    s = assur.solve(plan, None, q)
    for name, col in (("C.x [mm]", s.pos[:, 4, 0] * 1e3), ("P3.vz [mm/s]", s.vel[:, 3, 2] * 1e3),
                      ("P3.ay [mm/s^2]", s.acc[:, 3, 1] * 1e3), ("C.dz_dq [mm/deg]", s.dpos_dq[:, 4, 2, 0] * 1e3 * math.pi / 180)):
        np.testing.assert_allclose(data[:, head.index(name)], col, rtol=1e-12, atol=1e-12)
    np.testing.assert_allclose(data[:, 0], np.degrees(q), rtol=1e-14)


def test_analyze_prints_the_sharp_check_values(capsys):
    """P003-2 (§9): swing 56.3411183°, θ4 ∈ [−146.3411°, −90°], μ_int ∈ [34.048°, 81.787°], dead centres at
    84.716440° (extended) and 286.260205° (folded); the paper's W undefined (V3_X ≡ 0)."""
    code, out, _ = run(["analyze", RSSR], capsys)
    assert code == 0
    assert "the crank turns fully" in out
    assert "swing 56.3411°" in out and "θ4 -146.3411° … -90.0000°" in out
    assert "μ_int 34.048° … 81.787°" in out
    assert "dead centre (extended) at 84.716440°" in out and "dead centre (folded) at 286.260205°" in out
    assert "W of (21): undefined" in out
    code, out, _ = run(["analyze", RSSR, "--json"], capsys)
    d = json.loads(out)
    (dy,) = d["dyads"]
    assert math.degrees(dy["swing"]) == pytest.approx(math.degrees(math.acos(-1 / 3) - math.acos(3 / 5)), abs=1e-7)
    assert dy["branch_s"] == 1 and d["full_rotation"] is True


def test_analyze_names_the_buildable_range(tmp_path, capsys):
    text = RSSR.read_text(encoding="utf-8")
    text = (text.replace('length = 70 }', 'length = 50 }')
                .replace('rocker = { points = ["P4", "P3"], length = 50 }', 'rocker = { points = ["P4", "P3"], length = 20 }')
                .replace("P3 = [0, -9.294117647058824, 69.17647058823529]", "P3 = [0, 20, 50]")
                .replace("P2 = [0, -20, 0]", "P2 = [0, 20, 0]"))
    f = tmp_path / "short.toml"
    f.write_text(text, encoding="utf-8")
    code, out, _ = run(["analyze", f, "--steps", "360"], capsys)
    lo = math.degrees(math.atan2(4, 3) + math.acos(-0.375))          # 165.15°: |P2 P4| = 70 (§9 frame)
    hi = math.degrees(math.atan2(4, 3) + 2 * math.pi - math.acos(-0.375))
    assert code == 0 and "the crank cannot turn fully" in out
    assert f"buildable {hi:.1f}°…{lo:.1f}°" in out
    code, out, _ = run(["solve", f, "--steps", "36"], capsys)
    assert code == 0 and "the dyad solving P3 (cannot assemble (disc < 0)) at crank 170°…300°" in out


@pytest.mark.parametrize("ext", [".html", ".png", ".svg"])
def test_plot(tmp_path, capsys, ext):
    out = tmp_path / f"view{ext}"
    code, text, err = run(["plot", TILTED, "-o", out, "--steps", "72"], capsys)
    assert code == 0, err
    data = out.read_bytes()
    if ext == ".html":
        page = data.decode("utf-8")
        assert "scatter3d" in page and "Plotly.newPlot" in page
        assert "<script src=\"http" not in page                    # plotly.js inlined
        assert "projections of P3" in page                        # the paths projected on the coordinate planes
    elif ext == ".png":
        assert data[:8] == b"\x89PNG\r\n\x1a\n"
    else:
        assert b"<svg" in data[:400]


@pytest.mark.parametrize("ext", [".html", ".gif"])
def test_animate(tmp_path, capsys, ext):
    out = tmp_path / f"anim{ext}"
    code, text, err = run(["animate", RSSR, "-o", out, "--frames", "8"], capsys)
    assert code == 0, err
    assert "8 frames" in text
    data = out.read_bytes()
    if ext == ".html":
        page = data.decode("utf-8")
        assert page.count('"name":"') >= 8 and '"method":"animate"' in page.replace(" ", "")
    else:
        assert data[:6] in (b"GIF89a", b"GIF87a")


def test_report(tmp_path, capsys):
    out = tmp_path / "rep"
    code, text, err = run(["report", TILTED, "-o", out, "--steps", "72", "--frames", "8"], capsys)
    assert code == 0, err
    assert sorted(p.name for p in out.iterdir()) == [MARKER, "index.html"]
    page = (out / "index.html").read_text(encoding="utf-8")
    for s in ("3D view and animation", "Somov–Malyshev", "rocker swing", "P4.axis.gamma1", "scatter3d",
              "data:image/png;base64,", "dead centre (extended)"):
        assert s in page, s


def test_bad_spatial_file_is_an_error_and_leaves_nothing(tmp_path, capsys):
    text = RSSR.read_text(encoding="utf-8").replace(
        'P4 = { kind = "revolute", axis = { gamma1 = 90, gamma2 = 0 } }', 'P4 = "revolute"')
    f = tmp_path / "bad.toml"
    f.write_text(text, encoding="utf-8")
    for argv in (["validate", f], ["analyze", f], ["plot", f, "-o", tmp_path / "x.html"],
                 ["animate", f, "-o", tmp_path / "x.gif"], ["report", f, "-o", tmp_path / "rep"]):
        code, out, err = run(argv, capsys)
        assert code == 1 and err.startswith("error: joints.P4: a revolute of a spatial mechanism needs an axis")
    assert sorted(p.name for p in tmp_path.iterdir()) == ["bad.toml"]


def test_html_plot_of_a_planar_file_is_refused(tmp_path, capsys):
    code, out, err = run(["plot", ROOT / "examples" / "crank_rocker.toml", "-o", tmp_path / "x.html"], capsys)
    assert code == 1 and "an .html view is for spatial mechanisms" in err
    assert not (tmp_path / "x.html").exists()
