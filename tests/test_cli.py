"""The command line end to end: ``assur.cli.main.main([...])`` and once ``python -m assur``.

Mechanism files are written into tmp_path from the TOML texts below (the four-bar and the
crank-slider walking legs of papers 004 and 000), so the tests do not depend on examples/.
"""
from __future__ import annotations

import csv
import io
import json
import math
import os
import subprocess
import sys
import xml.etree.ElementTree as ET

import numpy as np
import pytest

from assur.io.output import MARKER   # every output directory carries it (io/output.py)
import assur
from conftest import rssr
from assur.analysis.gait import gait_metrics
from assur.cli.main import main

FOURBAR = """\
format = "assur/1"
name = "Four-bar walking leg"
description = "Four-bar walking leg of paper 004 (mechanism a)."

[units]
length = "m"
angle = "deg"

[points]
O = [0.0, 0.0]
O1 = [0.567, 0.615]
K = [0.27, 0.0]
L = [0.915023163371, 0.0802814967134]
H = [0.77787367222, -0.559176099283]

[links]
frame = ["O", "O1"]

[links.crank]
points = ["O", "K"]
length = {crank}

[links.rocker]
points = ["O1", "L"]
length = 0.638

[links.coupler]
points = ["K", "L", "H"]
length = 0.65

[links.coupler.place.H]
from = "L"
toward = "K"
distance = 0.654
angle = 70.8

[[drivers]]
name = "crank"
kind = "rotary"
link = "crank"
pivot = "O"
arm = "K"
zero = 0
sense = "ccw"
speed = "27 rpm"

[branches]
L = {{ side = "right", of = ["K", "O1"] }}

[gait]
foot = "H"
ground = [1, 0]
up = [0, 1]
phases = {phases}
"""

CRANK_SLIDER = """\
format = "assur/1"
name = "Crank-slider walking leg"

[units]
length = "mm"
angle = "deg"

[points]
K = [0, 0]
C = [87.5, 151.554445662]
B = [0, 323.579879828]
A = [-74.8056994819, 470.648256188]

[links]
frame = ["K"]

[links.crank]
points = ["K", "C"]
length = 175

[links.rod]
points = ["C", "B", "A"]
length = 193

[links.rod.place.A]
from = "B"
toward = "C"
distance = 165
angle = 180

[[prismatic]]
name = "slider"
point = "B"
guide = "frame"
through = "K"
angle = 90

[[drivers]]
name = "crank"
kind = "rotary"
link = "crank"
pivot = "K"
arm = "C"
zero = 90
sense = "cw"
speed = "1 rad/s"

[gait]
foot = "A"
"""

BAD = """\
format = "assur/1"
name = "bad"
[units]
length = "m"
[points]
O = [0, 0]
O1 = [1, 0]
K = [0.2, 0]
L = [0.8, 0.5]
[links]
frame = ["O", "O1"]
crank = ["O", "K"]
coupler = ["K", "L", "Q"]
rocker = ["O1", "L"]
[[drivers]]
name = "crank"
kind = "rotary"
link = "crank"
pivot = "O"
arm = "K"
sense = "{sense}"
speed = "10 rpm"
"""

SPATIAL = rssr("mm", 100.0)

LINEAR = """\
format = "assur/1"
name = "Hydraulic boom"
[units]
length = "mm"
[points]
O = [0, 0]
C = [300, 0]
B = [200, 250]
T = [500, 400]
[links]
frame = ["O", "C"]
boom = ["O", "B", "T"]
[actuators.cyl]
between = ["C", "B"]
[[drivers]]
name = "cyl"
kind = "linear"
actuator = "cyl"
speed = "20 mm/s"
"""

FORMULA = "I(frame, crank) → II(rocker, coupler)"


def write(tmp_path, name, text):
    p = tmp_path / name
    p.write_text(text, encoding="utf-8")
    return p


@pytest.fixture
def fourbar(tmp_path):
    return write(tmp_path, "fourbar.toml", FOURBAR.format(crank=0.27, phases="[0]"))


@pytest.fixture
def unbuildable(tmp_path):
    # a crank of 0.5 m: s + l = 0.5 + 0.8365 > p + q = 0.65 + 0.638, the crank cannot turn fully
    return write(tmp_path, "unbuildable.toml", FOURBAR.format(crank=0.5, phases="[0]"))


@pytest.fixture
def slider(tmp_path):
    return write(tmp_path, "slider.toml", CRANK_SLIDER)


def run(argv, capsys):
    code = main([str(a) for a in argv])
    out, err = capsys.readouterr()
    return code, out, err


# -- validate / errors --------------------------------------------------------------------------------
def test_validate_ok(fourbar, capsys):
    code, out, err = run(["validate", fourbar], capsys)
    assert code == 0
    assert out.strip() == f"{fourbar}: ok (W = 1, {FORMULA})"
    assert err == ""


def test_validate_unknown_point_exact_message(tmp_path, capsys):
    bad = write(tmp_path, "bad.toml", BAD.format(sense="ccw"))
    code, out, err = run(["validate", bad], capsys)
    assert code == 1
    assert out == ""
    assert err.splitlines()[0] == f"error: {bad}: links.coupler[2]: unknown point 'Q' (known: K, L, O, O1)"
    assert "Traceback" not in err


def test_validate_several_problems_one_line_each(tmp_path, capsys):
    bad = write(tmp_path, "bad2.toml", BAD.format(sense="clockwise"))
    code, _, err = run(["validate", bad], capsys)
    lines = err.splitlines()
    assert code == 1
    assert lines[0] == f"error: {bad}: 2 problems"
    assert lines[1] == "  links.coupler[2]: unknown point 'Q' (known: K, L, O, O1)"
    assert lines[2] == "  drivers[0].sense: must be 'ccw' or 'cw': 'clockwise'"
    assert len(lines) == 3


def test_missing_file(tmp_path, capsys):
    code, out, err = run(["info", tmp_path / "nope.toml"], capsys)
    assert code == 1
    assert err.startswith("error: ") and "nope.toml" in err and err.count("\n") == 1


def test_structure_error_is_one_message(tmp_path, capsys):
    # no driver: W = 1 but nothing drives the crank
    text = FOURBAR.format(crank=0.27, phases="[0]")
    text = text[:text.index("[[drivers]]")] + text[text.index("[branches]"):]
    f = write(tmp_path, "nodriver.toml", text)
    code, out, err = run(["validate", f], capsys)
    assert code == 1 and err.startswith("error: ") and "Traceback" not in err
    # info still shows what the structure is, then the error
    code, out, err = run(["info", f], capsys)
    assert code == 1 and "W = 3·3 − 2·4 − 0 = 1" in out
    assert err.startswith("error: ") and err.count("\n") == 1


@pytest.mark.parametrize("argv", [["frobnicate", "x.toml"], ["solve", "x.toml"], ["plot", "x.toml", "-o", "x.jpg"],
                                  ["animate", "x.toml", "-o", "x.avi"], ["analyze", "x.toml", "--steps", "4"],
                                  ["validate", "x.toml", "--bogus"], []])
def test_usage_errors_exit_2(argv, capsys):
    code, out, err = run(argv, capsys)
    assert code == 2
    assert "usage:" in err


@pytest.mark.parametrize("command", [["codesign", "M", "-o", "out"], ["atlas", "--walking-legs", "--links", "6", "-o", "out"],
                                     ["synth", "P", "-o", "out"], ["sensitivity", "M"], ["report", "M", "-o", "out"]])
@pytest.mark.parametrize("seed", ["-1", "4294967296", "7.5", "one"])
def test_a_bad_seed_is_a_usage_error_before_any_work(command, seed, fourbar, capsys, tmp_path, monkeypatch):
    """Every --seed is a whole number from 0 to 2³² − 1 (numpy's legacy generators, which scipy's optimisers seed,
    refuse others: a negative seed was a traceback in assur codesign and skipped every candidate of an atlas
    ranking); nothing is written."""
    monkeypatch.chdir(tmp_path)
    from conftest import EXAMPLES
    problem = EXAMPLES / "synthesis" / "c1_six_points_line.toml"
    argv = [fourbar if a == "M" else problem if a == "P" else a for a in command]
    code, out, err = run(argv + ["--seed", seed], capsys)
    assert code == 2 and f"argument --seed: must be a whole number from 0 to 4294967295: '{seed}'" in err
    assert not (tmp_path / "out").exists()


@pytest.mark.parametrize("fps", ["1e-320", "0", "0.001", "2000", "nan", "inf", "x"])
def test_a_frame_rate_out_of_range_is_a_usage_error(fps, fourbar, capsys, tmp_path):
    """A frame lasts from 1 ms to 100 s (1e-320 fps was a traceback: an infinite interval between frames)."""
    out = tmp_path / "a.gif"
    code, _, err = run(["animate", fourbar, "--fps", fps, "-o", out], capsys)
    assert code == 2 and f"--fps: must be a number of frames per second from 0.01 to 1000: '{fps}'" in err
    assert not out.exists()


@pytest.mark.parametrize("fps", [0, -1.0, float("nan"), 1e-320, None])
def test_the_animation_api_refuses_a_frame_rate_out_of_range(fps, fourbar):
    from assur.errors import SpecError
    from assur.plot.animation import animation
    plan = assur.compile(assur.load(fourbar))
    with pytest.raises(SpecError, match="fps: must be a number of frames per second from 0.01 to 1000"):
        animation(plan, 4, fps)


@pytest.mark.parametrize("value", ["nan", "inf", "1e999", "x"])
@pytest.mark.parametrize("command", [["solve", "M", "--steps", "10", "--range", "0", "V"],
                                     ["solve", "M", "--steps", "10", "--range", "V", "1"],
                                     ["simulate", "M", "--start", "V"],
                                     ["codesign", "M", "--direction", "V", "-o", "out"]])
def test_a_non_finite_number_is_a_usage_error(command, value, fourbar, capsys, tmp_path, monkeypatch):
    """--range, simulate's --start and codesign's --direction take finite numbers (nan ran a NaN table, inf a
    traceback after the co-design)."""
    monkeypatch.chdir(tmp_path)
    argv = [fourbar if a == "M" else value if a == "V" else a for a in command]
    code, _, err = run(argv, capsys)
    assert code == 2 and f"must be a finite number: '{value}'" in err
    assert [p.name for p in tmp_path.iterdir()] == [fourbar.name]


@pytest.mark.parametrize("command, most", [
    (["solve", "M", "--steps", "N"], 1_000_000), (["analyze", "M", "--steps", "N"], 1_000_000),
    (["plot", "M", "--positions", "N", "-o", "out.png"], 1_000_000), (["plot", "M", "--dpi", "N", "-o", "out.png"], 1200),
    (["animate", "M", "--frames", "N", "-o", "out.gif"], 10_000), (["report", "M", "--frames", "N", "-o", "out"], 10_000),
    (["forces", "M", "--steps", "N"], 1_000_000), (["sensitivity", "M", "--steps", "N"], 1_000_000),
    (["simulate", "M", "--samples", "N"], 1_000_000), (["synth", "P", "--workers", "N"], 256),
    (["synth", "P", "--budget", "N"], 1_000_000_000)])
@pytest.mark.parametrize("above", [1, 10 ** 20])
def test_a_count_too_large_is_a_usage_error(command, most, above, fourbar, capsys, tmp_path, monkeypatch):
    """Counts have a ceiling far above any use (1e20 steps was numpy's 'Maximum allowed size exceeded' traceback,
    1e9 ran out of memory or time)."""
    from conftest import EXAMPLES
    monkeypatch.chdir(tmp_path)
    n = str(most + above)
    argv = [fourbar if a == "M" else EXAMPLES / "synthesis" / "c1_six_points_line.toml" if a == "P"
            else n if a == "N" else a for a in command]
    code, _, err = run(argv, capsys)
    assert code == 2 and f"must be at most {most}: {n}" in err
    assert [p.name for p in tmp_path.iterdir()] == [fourbar.name]


def test_a_walking_leg_ranking_refuses_a_negative_seed():
    from assur.errors import SpecError
    from assur.synthesis.legs import settings_of
    with pytest.raises(SpecError, match="seed: must be a whole number ≥ 0: -1"):
        settings_of({"seed": -1})
    assert settings_of({"seed": 0})["seed"] == 0


@pytest.mark.slow
def test_python_m_assur(fourbar, tmp_path):
    env = {**os.environ, "PYTHONIOENCODING": "utf-8"}
    r = subprocess.run([sys.executable, "-m", "assur", "validate", str(fourbar)], capture_output=True, encoding="utf-8",
                       env=env, timeout=120)
    assert r.returncode == 0, r.stderr
    assert r.stdout.strip() == f"{fourbar}: ok (W = 1, {FORMULA})"
    bad = write(tmp_path, "bad.toml", BAD.format(sense="ccw"))
    r = subprocess.run([sys.executable, "-m", "assur", "validate", str(bad)], capture_output=True, encoding="utf-8",
                       env=env, timeout=120)
    assert r.returncode == 1
    assert r.stderr.startswith("error: ") and "Traceback" not in r.stderr


def test_import_stays_light():
    code = ("import sys, assur, assur.cli.main, assur.plot, assur.report; "
            "print('matplotlib' in sys.modules)")
    r = subprocess.run([sys.executable, "-c", code], capture_output=True, encoding="utf-8", timeout=120)
    assert r.returncode == 0, r.stderr
    assert r.stdout.strip() == "False"


# -- info ------------------------------------------------------------------------------------------------
def test_info(fourbar, capsys):
    code, out, _ = run(["info", fourbar], capsys)
    assert code == 0
    assert f"structural formula: {FORMULA}" in out
    assert "I(0,1) → II(2,3)" in out
    assert "W = 3·3 − 2·4 − 0 = 1" in out
    assert "class II, order 2, RRR" in out
    lines = {ln.split("=")[0].strip(): ln.split("=", 1)[1].strip() for ln in out.splitlines()
             if ln.startswith("  ") and "=" in ln and "." in ln.split("=")[0]}
    assert lines["coupler.H.angle"] == "70.8 °"
    assert lines["crank.length"] == "0.27 m"
    assert "27 rpm" in out


def test_info_file_units(slider, capsys):
    code, out, _ = run(["info", slider], capsys)
    assert code == 0
    assert any(ln.split() == ["crank.length", "=", "175", "mm"] for ln in out.splitlines())
    assert any(ln.split() == ["crank.zero", "=", "90", "°"] for ln in out.splitlines())


def test_info_spatial(tmp_path, capsys):
    f = write(tmp_path, "rssr.toml", SPATIAL)
    code, out, _ = run(["info", f], capsys)
    assert code == 0
    assert "Somov–Malyshev" in out
    assert "W = 6·3 − 5·2 − 4·0 − 3·2 − 2·0 − 0 = 2" in out
    code, out, _ = run(["validate", f], capsys)
    assert code == 0 and "spatial" in out


# -- solve ----------------------------------------------------------------------------------------------
def read_csv(path):
    with open(path, newline="", encoding="utf-8") as fh:
        rows = list(csv.reader(fh))
    return rows[0], np.array([[float(c) for c in r] for r in rows[1:]])


def test_solve_csv_matches_solve(fourbar, tmp_path, capsys):
    out_csv = tmp_path / "out.csv"
    code, out, _ = run(["solve", fourbar, "--steps", 24, "--csv", out_csv], capsys)
    assert code == 0
    header, data = read_csv(out_csv)
    plan = assur.compile(assur.load(fourbar))
    names = plan.point_names
    assert header[:2] == ["crank.q [rad]", "valid"]
    assert header[2:14] == ["O.x [m]", "O.y [m]", "O.vx [m/s]", "O.vy [m/s]", "O.ax [m/s^2]", "O.ay [m/s^2]",
                            "O.dx_dq [m/rad]", "O.dy_dq [m/rad]", "O.d2x_dq2 [m/rad^2]", "O.d2y_dq2 [m/rad^2]",
                            "O1.x [m]", "O1.y [m]"]
    assert len(header) == 2 + 10 * len(names) + 3 * (plan.n_bodies - 1)   # then θ, ω, α per moving link
    assert data.shape == (24, len(header))
    # independent computation
    q = 2 * math.pi * np.arange(24) / 24
    st = assur.solve(plan, inputs=q)
    col = {h: i for i, h in enumerate(header)}
    np.testing.assert_allclose(data[:, col["crank.q [rad]"]], q, rtol=0, atol=1e-15)
    assert np.all(data[:, col["valid"]] == 1)
    for i, p in enumerate(names):
        np.testing.assert_allclose(data[:, col[f"{p}.x [m]"]], st.pos[:, i, 0], rtol=1e-14, atol=1e-15)
        np.testing.assert_allclose(data[:, col[f"{p}.y [m]"]], st.pos[:, i, 1], rtol=1e-14, atol=1e-15)
        np.testing.assert_allclose(data[:, col[f"{p}.vy [m/s]"]], st.vel[:, i, 1], rtol=1e-14, atol=1e-15)
        np.testing.assert_allclose(data[:, col[f"{p}.ax [m/s^2]"]], st.acc[:, i, 0], rtol=1e-14, atol=1e-15)
        np.testing.assert_allclose(data[:, col[f"{p}.dx_dq [m/rad]"]], st.dpos_dq[:, i, 0, 0], rtol=1e-14,
                                   atol=1e-15)
        np.testing.assert_allclose(data[:, col[f"{p}.d2y_dq2 [m/rad^2]"]], st.d2pos_dq2[:, i, 1, 0, 0],
                                   rtol=1e-14, atol=1e-15)
    # the short table on stdout
    assert "24 positions of crank over one turn; 0 cannot be assembled" in out
    assert f"wrote {out_csv}" in out
    assert len([ln for ln in out.splitlines() if ln.strip()[:1].isdigit()]) <= 10


def test_solve_file_units(slider, tmp_path, capsys):
    out_csv = tmp_path / "mm.csv"
    code, _, _ = run(["solve", slider, "--steps", 8, "--csv", out_csv, "--file-units"], capsys)
    assert code == 0
    header, data = read_csv(out_csv)
    col = {h: i for i, h in enumerate(header)}
    plan = assur.compile(assur.load(slider))
    q = 2 * math.pi * np.arange(8) / 8
    st = assur.solve(plan, inputs=q)
    a = plan.point_index("A")
    np.testing.assert_allclose(data[:, col["crank.q [deg]"]], np.arange(8) * 45.0, atol=1e-12)
    np.testing.assert_allclose(data[:, col["A.x [mm]"]], st.pos[:, a, 0] * 1000, rtol=1e-13, atol=1e-9)
    np.testing.assert_allclose(data[:, col["A.vx [mm/s]"]], st.vel[:, a, 0] * 1000, rtol=1e-13, atol=1e-9)
    np.testing.assert_allclose(data[:, col["A.dy_dq [mm/deg]"]], st.dpos_dq[:, a, 1, 0] * 1000 * math.pi / 180,
                               rtol=1e-13, atol=1e-9)
    np.testing.assert_allclose(data[:, col["A.d2x_dq2 [mm/deg^2]"]],
                               st.d2pos_dq2[:, a, 0, 0, 0] * 1000 * (math.pi / 180) ** 2, rtol=1e-13, atol=1e-12)


def test_solve_unbuildable_rows_are_nan(unbuildable, tmp_path, capsys):
    out_csv = tmp_path / "u.csv"
    code, out, err = run(["solve", unbuildable, "--steps", 36, "--csv", out_csv], capsys)
    assert code == 0, err
    header, data = read_csv(out_csv)
    valid = data[:, header.index("valid")]
    bad = valid == 0
    assert 0 < bad.sum() < 36
    assert np.all(np.isnan(data[bad, 2:])) and np.all(np.isfinite(data[~bad, 2:]))
    assert np.all(np.isfinite(data[:, 0]))
    assert f"{int(bad.sum())} cannot be assembled" in out


def test_solve_linear_input_needs_range(tmp_path, capsys):
    f = write(tmp_path, "boom.toml", LINEAR)
    code, out, err = run(["solve", f, "--steps", 5], capsys)
    assert code == 1
    assert err.startswith("error: --range:") and "cyl" in err
    out_csv = tmp_path / "boom.csv"
    code, out, err = run(["solve", f, "--steps", 5, "--range", 200, 300, "--csv", out_csv], capsys)
    assert code == 0, err
    header, data = read_csv(out_csv)
    assert header[0] == "cyl.q [m]"
    np.testing.assert_allclose(data[:, 0], np.linspace(0.2, 0.3, 5))
    plan = assur.compile(assur.load(f))
    st = assur.solve(plan, inputs=np.linspace(0.2, 0.3, 5))
    np.testing.assert_allclose(data[:, header.index("T.y [m]")], st.pos[:, plan.point_index("T"), 1], rtol=1e-14)
    code, _, err = run(["solve", f, "--steps", 5, "--range", 200, 300, "--range", 1, 2], capsys)
    assert code == 1 and "--range" in err


def test_solve_failed_write_leaves_nothing(fourbar, tmp_path, capsys):
    target = tmp_path / "missing_dir" / "out.csv"
    code, _, err = run(["solve", fourbar, "--steps", 4, "--csv", target], capsys)
    assert code == 1 and err.startswith("error: ")
    assert not target.parent.exists()
    assert sorted(p.name for p in tmp_path.iterdir()) == ["fourbar.toml"]


# -- analyze -------------------------------------------------------------------------------------------
def test_analyze_json(fourbar, capsys):
    code, out, _ = run(["analyze", fourbar, "--steps", 90, "--json"], capsys)
    assert code == 0
    d = json.loads(out)                      # exactly one JSON object
    assert isinstance(d, dict)
    for key in ("mobility", "structural_formula", "unbuildable", "gait", "transmission_angles", "dead_centres"):
        assert key in d
    assert d["mobility"] == 1 and d["unbuildable"] == 0 and d["structural_formula"] == FORMULA
    plan = assur.compile(assur.load(fourbar))
    gm = gait_metrics(plan, steps=90)
    assert d["gait"]["step_length"] == pytest.approx(gm.step_length, rel=1e-12)
    assert d["gait"]["support_speed"]["max"] == pytest.approx(gm.support_speed.max, rel=1e-12)


def test_analyze_text(fourbar, capsys):
    code, out, _ = run(["analyze", fourbar, "--steps", 90], capsys)
    assert code == 0
    assert FORMULA in out
    assert "the crank turns fully" in out
    assert "step length" in out and " m" in out
    assert "transmission angle at L" in out and "dead centres:" in out


def test_analyze_module(tmp_path, capsys):
    f = write(tmp_path, "module.toml", FOURBAR.format(crank=0.27, phases="[0, 180]"))
    code, out, _ = run(["analyze", f, "--steps", 72, "--json"], capsys)
    d = json.loads(out)
    assert code == 0 and d["module"]["max_feet"] >= 1
    code, out, _ = run(["analyze", f, "--steps", 72], capsys)
    assert "walking module (2 legs" in out


def test_analyze_unbuildable(unbuildable, capsys):
    code, out, err = run(["analyze", unbuildable, "--steps", 72, "--json"], capsys)
    assert code == 0 and "Traceback" not in err
    d = json.loads(out)
    assert 0 < d["unbuildable"] < 72
    assert d["gait"] is None and "cannot turn fully" in d["gait_error"]
    code, out, err = run(["analyze", unbuildable, "--steps", 72], capsys)
    assert code == 0
    assert f"{d['unbuildable']} of 72 positions cannot be assembled" in out


# -- plot / animate ------------------------------------------------------------------------------------
@pytest.mark.slow
def test_plot_png_and_svg(fourbar, tmp_path, capsys):
    png, svg = tmp_path / "f.png", tmp_path / "f.svg"
    assert run(["plot", fourbar, "-o", png, "--steps", 36], capsys)[0] == 0
    data = png.read_bytes()
    assert data[:8] == b"\x89PNG\r\n\x1a\n" and len(data) > 10_000
    assert run(["plot", fourbar, "-o", svg, "--steps", 24], capsys)[0] == 0
    root = ET.parse(svg).getroot()
    assert root.tag == "{http://www.w3.org/2000/svg}svg"
    leftovers = [p.name for p in tmp_path.iterdir() if p.name.startswith(".")]
    assert leftovers == []


def test_plot_slider_and_unbuildable(slider, unbuildable, tmp_path, capsys):
    for f in (slider, unbuildable):
        out = tmp_path / f"{f.stem}.png"
        code, _, err = run(["plot", f, "-o", out, "--steps", 24], capsys)
        assert code == 0, err
        assert out.read_bytes()[:4] == b"\x89PNG"


def test_animate_gif_mp4_html(slider, tmp_path, capsys):
    gif, mp4, page = tmp_path / "a.gif", tmp_path / "a.mp4", tmp_path / "a.html"
    assert run(["animate", slider, "-o", gif, "--frames", 3, "--fps", 5], capsys)[0] == 0
    assert gif.read_bytes()[:4] == b"GIF8"
    assert run(["animate", slider, "-o", mp4, "--frames", 3], capsys)[0] == 0
    assert mp4.read_bytes()[4:8] == b"ftyp"
    assert run(["animate", slider, "-o", page, "--frames", 3], capsys)[0] == 0
    text = page.read_text(encoding="utf-8")
    assert text.lstrip().lower().startswith("<!doctype html>")
    assert "data:image/png;base64," in text
    assert "http://" not in text.replace("http://www.w3.org", "") and "https://" not in text


# -- report --------------------------------------------------------------------------------------------
def _assert_self_contained(text):
    import re
    assert 'src="http' not in text and "src='http" not in text
    for src in re.findall(r'src\s*=\s*["\']([^"\']*)["\']', text):
        assert src.startswith("data:"), src
    assert not re.search(r'<link[^>]+href\s*=\s*["\'](?!#|data:)', text)
    assert "https://" not in text


@pytest.mark.slow
def test_report(fourbar, tmp_path, capsys):
    out = tmp_path / "rep"
    code, stdout, err = run(["report", fourbar, "-o", out, "--steps", 36, "--frames", 3], capsys)
    assert code == 0, err
    assert sorted(p.name for p in out.iterdir()) == [MARKER, "index.html"]
    text = (out / "index.html").read_text(encoding="utf-8")
    assert FORMULA in text and "I(0,1) → II(2,3)" in text
    assert '<img class="figure"' in text and "data:image/png;base64," in text
    assert "coupler.H.angle" in text and "step length" in text
    _assert_self_contained(text)
    assert [p.name for p in tmp_path.iterdir() if p.name.startswith(".")] == []
    # a second run replaces the page in place
    code, _, _ = run(["report", fourbar, "-o", out, "--steps", 24, "--frames", 2], capsys)
    assert code == 0 and sorted(p.name for p in out.iterdir()) == [MARKER, "index.html"]


@pytest.mark.slow
def test_report_module_timeline(tmp_path, capsys):
    f = write(tmp_path, "module.toml", FOURBAR.format(crank=0.27, phases="[0, 120, 240]"))
    out = tmp_path / "mod"
    code, _, err = run(["report", f, "-o", out, "--steps", 36, "--frames", 2], capsys)
    assert code == 0, err
    text = (out / "index.html").read_text(encoding="utf-8")
    assert "Walking module" in text and "feet on the ground" in text
    assert text.count("data:image/png;base64,") >= 2
    _assert_self_contained(text)


def test_report_unbuildable(unbuildable, tmp_path, capsys):
    out = tmp_path / "unb"
    code, _, err = run(["report", unbuildable, "-o", out, "--steps", 36, "--frames", 2], capsys)
    assert code == 0 and "Traceback" not in err
    text = (out / "index.html").read_text(encoding="utf-8")
    plan = assur.compile(assur.load(unbuildable))
    from assur.analysis.api import buildable_ranges
    n_bad = buildable_ranges(plan, steps=36)[1]
    assert n_bad > 0
    assert f"{n_bad} of 36 positions cannot be assembled" in text
    assert "cannot turn fully" in text


def test_failing_report_leaves_nothing(fourbar, tmp_path, capsys, monkeypatch):
    bad = write(tmp_path, "bad.toml", BAD.format(sense="ccw"))
    out = tmp_path / "out" / "rep"
    code, _, err = run(["report", bad, "-o", out], capsys)
    assert code == 1 and err.startswith("error: ")
    assert not (tmp_path / "out").exists()

    import assur.report.mechanism as report_page

    def boom(*a, **k):
        raise assur.UnbuildableError("simulated failure while drawing")
    monkeypatch.setattr(report_page, "positions_html", boom)
    code, _, err = run(["report", fourbar, "-o", out, "--steps", 24, "--frames", 2], capsys)
    assert code == 1 and err.strip() == "error: simulated failure while drawing"
    assert not (tmp_path / "out").exists()
    assert sorted(p.name for p in tmp_path.iterdir()) == ["bad.toml", "fourbar.toml"]


def test_json_is_strict(unbuildable, capsys):
    # NaN never leaks into the JSON (it would not parse in strict readers)
    code, out, _ = run(["analyze", unbuildable, "--steps", 32, "--json"], capsys)
    json.loads(out, parse_constant=lambda c: pytest.fail(f"non-standard JSON constant {c}"))
    assert io.StringIO(out).read().count("\n{") == 0


def test_plot_positions_option(fourbar, tmp_path, capsys):
    """--positions sets how many positions the kinematic diagram draws (its title lists them)."""
    from assur.plot.draw import close
    from assur.plot.figures import mechanism_figure
    import assur as _assur
    plan = _assur.compile(_assur.load(fourbar))
    fig = mechanism_figure(plan, 36, positions=3)
    titles = [ax.get_title() for ax in fig.axes]
    close(fig)
    assert any("positions 1–3" in t for t in titles)
    out = tmp_path / "three.png"
    assert run(["plot", fourbar, "-o", out, "--steps", 36, "--positions", "3"], capsys)[0] == 0
    assert out.read_bytes()[:4] == b"\x89PNG"
    assert run(["plot", fourbar, "-o", out, "--positions", "0"], capsys)[0] == 2


def test_one_solve_of_the_turn_serves_the_analysis_and_the_figure(tmp_path, monkeypatch):
    """summarize solves the turn once (buildability, transmission angles, gait and module all read that grid,
    dead centres scan their own grid of positions) and the figure drawn from it solves nothing new;
    its numbers equal a plain analyze at the same sample count."""
    import assur.analysis.sampling as sampling
    from assur.analysis.study import Study
    from assur.plot.draw import close
    from assur.plot.figures import mechanism_figure
    plan = assur.compile(assur.loads(FOURBAR.format(crank=0.27, phases="[0, 180]")))
    expected = Study(plan, steps=90).as_dict()
    grids = []
    solve = sampling.solve

    def counting(plan_, params, q, **kw):
        if np.shape(q) == (90, 1) and np.array_equal(q[:, 0], np.linspace(0, 2 * math.pi, 90, endpoint=False)):
            grids.append(kw.get("order"))          # the uniform grid of the turn (not a refinement)
        return solve(plan_, params, q, **kw)
    monkeypatch.setattr(sampling, "solve", counting)
    study = Study(plan, steps=90)
    summary = study.as_dict()
    assert grids == [2]
    assert summary == expected and summary["module"]["max_feet"] >= 1
    assert study.gait.as_dict() == expected["gait"] and len(study.gait_curves.q) == 90
    fig = mechanism_figure(study)
    close(fig)
    assert grids == [2]


def test_analyze_report_and_plot_share_the_documented_sample_count():
    from assur.analysis.sampling import CYCLE_STEPS
    from assur.cli.main import build_parser
    parser = build_parser()
    for argv in (["analyze", "f.toml"], ["report", "f.toml", "-o", "d"], ["plot", "f.toml", "-o", "f.png"]):
        assert parser.parse_args(argv).steps == CYCLE_STEPS == 720
