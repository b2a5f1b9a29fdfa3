"""The output link (swing, extreme positions, time ratio), every link's motion in analyze / solve CSV / report,
the one rule that prints rounding noise as 0, and the --units option."""
from __future__ import annotations

import csv
import json
import math
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

import assur
from assur.analysis.links import link_motions, output_link, wrap_angle
from assur.analysis.sampling import Cycle
from assur.io.mechanism_writer import dumps
from assur.report.text import format_number, gait_rows

ROOT = Path(__file__).resolve().parents[1]
CRANK_ROCKER = ROOT / "examples" / "crank_rocker.toml"


def run(*args):
    return subprocess.run([sys.executable, "-m", "assur", *map(str, args)], capture_output=True, encoding="utf-8",
                          cwd=ROOT)


def fourbar_extremes(a, b, c, d):
    """Closed form of a Grashof crank-rocker (crank a from O2 = (0, 0), coupler b, rocker c from O4 = (d, 0),
    open assembly above the ground line): the rocker's extremes are where crank and coupler are collinear,
    |O2 B| = b + a (extended) and b − a (folded); triangle O2-O4-B gives the crank and rocker angles.
    Returns [(crank angle, rocker angle)] for the extended and the folded position, and the time ratio
    (180° + α)/(180° − α) with α the crank angle between the two positions less 180°."""
    out = []
    for r, crank_sign in ((b + a, 0.0), (b - a, math.pi)):
        phi = math.acos((d * d + r * r - c * c) / (2 * d * r))            # angle at O2 of O2-O4-B
        psi = math.acos((d * d + c * c - r * r) / (2 * d * c))            # angle at O4
        out.append(((phi + crank_sign) % (2 * math.pi), math.pi - psi))
    alpha = abs(((out[1][0] - out[0][0]) % (2 * math.pi)) - math.pi)
    return out, (math.pi + alpha) / (math.pi - alpha)


def test_crank_rocker_output_link_matches_the_closed_form():
    plan = assur.compile(assur.load(CRANK_ROCKER))
    o = output_link(Cycle(plan))
    assert o.link == "rocker" and o.motion == "swing"
    (ext, fold), ratio = fourbar_extremes(0.040, 0.120, 0.080, 0.100)
    got = {e.kind: e for e in o.extremes}
    # extended: the rocker's extreme nearer the crank pivot's far side; match each closed-form position
    for q, th in (ext, fold):
        e = min(o.extremes, key=lambda e: abs(wrap_angle(e.input - q)))
        assert abs(wrap_angle(e.input - q)) < 1e-9
        assert abs(wrap_angle(e.value - th)) < 1e-9
    assert set(got) == {"min", "max"}
    assert o.range == pytest.approx(abs(ext[1] - fold[1]), abs=1e-9)
    assert o.time_ratio == pytest.approx(ratio, rel=1e-9)
    assert o.forward_crank_angle + o.return_crank_angle == pytest.approx(2 * math.pi)
    # at 60 rpm the turn takes 1 s: the strokes' times are their crank angles / 2π
    assert o.forward_time == pytest.approx(o.forward_crank_angle / (2 * math.pi), rel=1e-12)


def test_link_motions_against_sampled_body_angles():
    """The rocker's range agrees with an independent sampling of atan2 of B − O4."""
    plan = assur.compile(assur.load(CRANK_ROCKER))
    mo = link_motions(Cycle(plan))
    q = np.linspace(0, 2 * np.pi, 3600, endpoint=False)
    st = assur.solve(plan, inputs=q)
    d = st.point("B").pos - st.point("O4").pos
    th = np.arctan2(d[:, 1], d[:, 0])
    assert mo["rocker"].angle_min == pytest.approx(th.min(), abs=1e-5)
    assert mo["rocker"].angle_max == pytest.approx(th.max(), abs=1e-5)
    assert mo["crank"].turns == 1 and mo["crank"].angle_min is None
    assert mo["crank"].omega_max == pytest.approx(2 * math.pi)       # 60 rpm


def test_an_offset_slider_crank_has_its_sliders_stroke_and_time_ratio():
    """examples/slider_crank.toml: crank r = 50 mm, rod l = 150 mm, the slide's line 20 mm above the crank pivot.
    Closed form: the slider's extremes are where crank and rod are collinear, at x = sqrt((l ± r)² − e²), the crank
    at asin(e/(l + r)) and π + asin(e/(l − r)) (an independent computation)."""
    plan = assur.compile(assur.load(ROOT / "examples" / "slider_crank.toml"))
    o = output_link(Cycle(plan))
    r, l_, e = 0.050, 0.150, 0.020
    assert o.link == "slot.block" and o.motion == "slide"
    x_max, x_min = math.sqrt((l_ + r) ** 2 - e * e), math.sqrt((l_ - r) ** 2 - e * e)
    assert o.value_max == pytest.approx(x_max, abs=1e-12) and o.value_min == pytest.approx(x_min, abs=1e-12)
    assert o.range == pytest.approx(x_max - x_min, abs=1e-12)
    q_ext, q_fold = math.asin(e / (l_ + r)), math.pi + math.asin(e / (l_ - r))
    ext = next(x for x in o.extremes if x.kind == "max")
    fold = next(x for x in o.extremes if x.kind == "min")
    assert abs(wrap_angle(ext.input - q_ext)) < 1e-9 and abs(wrap_angle(fold.input - q_fold)) < 1e-9
    slow = max(q_fold - q_ext, 2 * math.pi - (q_fold - q_ext))
    assert o.time_ratio == pytest.approx(slow / (2 * math.pi - slow), rel=1e-9)


SHAPER = """
format = "assur/1"
name = "quick-return shaper"
[units]
length = "mm"
angle = "deg"
[points]
O2 = [0, 200]
A = [100, 200]
O4 = [0, 0]
B = [0, 500]
C = [100, 520]
[links]
frame = ["O2", "O4"]
crank = ["O2", "A"]
lever = ["O4", "B"]
rod = ["B", "C"]
[[prismatic]]
name = "slot"
point = "A"
guide = "lever"
through = "O4"
angle = 0
[[prismatic]]
name = "ram"
point = "C"
guide = "frame"
through = "O2"
angle = 0
offset = 320
[[drivers]]
name = "crank"
kind = "rotary"
link = "crank"
pivot = "O2"
arm = "A"
speed = "30 rpm"
"""


def test_a_quick_return_shaper_reports_its_rams_stroke_and_time_ratio(tmp_path):
    """Crank O2A (r = 100 mm) 200 mm above the lever's pivot O4 (d), A in the lever's slot, lever O4B (500 mm), rod
    BC (100 mm), the ram C on a horizontal guide 520 mm above O4. Independent closed form: the lever's extremes are
    where the crank is perpendicular to it, the lever then at ±asin(r/d) from the vertical and the crank angles
    between them 2·acos(r/d) (return) and 2π − that (forward); the ram there is where the rod from B meets the
    guide: x = x_B ± sqrt(BC² − (y_guide − y_B)²) on the branch the sketch shows."""
    path = tmp_path / "shaper.toml"
    path.write_text(SHAPER, encoding="utf-8")
    plan = assur.compile(assur.load(path))
    study = assur.Study(plan)
    o = study.output_link
    assert o.link == "ram.block" and o.motion == "slide"
    r, d, lever, rod, h = 0.100, 0.200, 0.500, 0.100, 0.520
    ret = 2 * math.acos(r / d)
    assert o.time_ratio == pytest.approx((2 * math.pi - ret) / ret, rel=1e-9)
    beta = math.asin(r / d)
    ends = []
    for sign in (1, -1):
        xb, yb = -sign * lever * math.sin(beta), lever * math.cos(beta)
        ends.append(xb + math.sqrt(rod ** 2 - (h - yb) ** 2))
    assert o.range == pytest.approx(abs(ends[0] - ends[1]), rel=1e-9)
    text = run("analyze", path).stdout
    assert "output slider ram.block: stroke" in text and "time ratio" in text
    assert "ram.block  0.00°" not in text and "translates (no rotation)" in text
    assert "transmission angle at A:" not in text       # a pin in a slot: μ is 90° throughout


def test_analyze_text_and_json_show_the_output_link():
    r = run("analyze", CRANK_ROCKER)
    assert r.returncode == 0, r.stderr
    assert "output link rocker: swing" in r.stdout and "time ratio" in r.stdout
    (ext, fold), ratio = fourbar_extremes(0.040, 0.120, 0.080, 0.100)
    assert f"time ratio {ratio:.4f}" in r.stdout
    r = run("analyze", CRANK_ROCKER, "--json")
    data = json.loads(r.stdout)
    assert data["output_link"]["time_ratio"] == pytest.approx(ratio, rel=1e-9)
    assert data["four_bars"][0]["kind"] == "crank-rocker" and data["four_bars"][0]["grashof"] is True
    assert set(data["links"]) == {"crank", "rocker", "coupler"}


def test_solve_csv_appends_link_columns(tmp_path):
    out = tmp_path / "cr.csv"
    r = run("solve", CRANK_ROCKER, "--steps", 12, "--csv", out)
    assert r.returncode == 0, r.stderr
    rows = list(csv.reader(out.open()))
    head = rows[0]
    plan = assur.compile(assur.load(CRANK_ROCKER))
    n_point_cols = 2 + plan.n_points * 10         # q, valid; x y vx vy ax ay dx dy d2x d2y per point
    assert head[:2] == ["crank.q [rad]", "valid"] and head[n_point_cols - 1].startswith("P.")
    assert head[n_point_cols:] == [f"{b}.{k} [{u}]" for b in ("crank", "rocker", "coupler")
                                   for k, u in (("theta", "rad"), ("omega", "rad/s"), ("alpha", "rad/s^2"))]
    data = np.array(rows[1:], dtype=float)
    q = data[:, 0]
    st = assur.solve(plan, inputs=q)
    d = st.point("B").pos - st.point("O4").pos      # the rocker's angle from its points
    np.testing.assert_allclose(data[:, head.index("rocker.theta [rad]")], np.arctan2(d[:, 1], d[:, 0]), atol=1e-12)
    # ω of the rocker: the velocity of B about O4, (r × v)/|r|²
    v = st.point("B").vel
    np.testing.assert_allclose(data[:, head.index("rocker.omega [rad/s]")],
                               (d[:, 0] * v[:, 1] - d[:, 1] * v[:, 0]) / (d ** 2).sum(-1), rtol=1e-10)


def test_noise_prints_as_zero_relative_to_a_scale():
    assert format_number(2.3543e-16, 5, 0.18) == "0"
    assert format_number(2.3543e-16, 5) == "2.3543e-16"       # without a scale nothing is hidden
    assert format_number(1e-6, 5, 0.18) == "1e-06"
    g = {"support": "arc", "contact_start": 0.0, "contact_end": 1.0, "step_length": 0.3, "lift": 0.1, "sag": 0.01,
         "duty_factor": 0.5, "contact_ratio": 1.0, "omega": 1.0,
         "support_speed": {"max": 0.175, "min": 0.04, "mean": 0.1, "midrange": 0.1},
         "support_vx": {"max": 0.15, "min": 1.9877e-17, "mean": 0.09, "midrange": 0.07},
         "support_ax": {"min": -0.15, "max": 0.15}}
    rows = {a: (b, u) for a, b, u in gait_rows(g, 1e-3, "mm")}
    assert rows["support speed |vx| min"] == ("0", "mm/s")
    assert rows["support speed |v| max"] == ("175", "mm/s")        # 0.175 m/s in mm/s
    assert rows["support acceleration ax max"] == ("150", "mm/s²")


def test_info_prints_no_noise():
    r = run("info", ROOT / "examples" / "rssr_tilted.toml")
    assert r.returncode == 0, r.stderr
    assert "e-15" not in r.stdout and "e-17" not in r.stdout


def test_writer_uses_fewest_digits_and_writes_noise_as_zero():
    m = assur.load(CRANK_ROCKER)
    pts = dict(m.points)
    import dataclasses
    noisy = dataclasses.replace(m, points=tuple((n, (xy[0] + (5.2e-18 if n == "O2" else 0.0), xy[1]))
                                                for n, xy in m.points))
    assert "5.2e-15" in dumps(noisy)                         # a plain dump loads back exactly
    text = dumps(noisy, clean=True)                          # as `assur synth -o` writes a design
    line = next(ln for ln in text.splitlines() if ln.startswith("O2 ="))
    assert line == "O2 = [0, 0]"
    back = assur.loads(text)
    assert dict(back.points)["B"] == pts["B"]                # still exact where it is not noise
    assert "O4 = [100, 0]" in text


def test_units_option_mm_and_si():
    r = run("analyze", ROOT / "examples" / "walker_crank_slider.toml")
    assert "mm/s" in r.stdout and " m/s" not in r.stdout.replace("rad/s", "")
    r = run("analyze", ROOT / "examples" / "walker_crank_slider.toml", "--units", "si")
    assert " m/s" in r.stdout and "mm/s" not in r.stdout
    r = run("analyze", CRANK_ROCKER, "--units", "feet")
    assert r.returncode == 2 and "invalid choice" in r.stderr


def test_plot_figure_in_file_units():
    from assur.plot.figures import default_positions, mechanism_figure
    plan = assur.compile(assur.load(CRANK_ROCKER))
    fig = mechanism_figure(plan, 90)
    labels = [ax.get_ylabel() for ax in fig.axes]
    assert any("[mm/s]" in lb for lb in labels) and any("[mm/s²]" in lb for lb in labels)
    fig_si = mechanism_figure(plan, 90, units="si")
    assert any("[m/s]" in ax.get_ylabel() for ax in fig_si.axes)
    # the velocity curve in mm/s is the SI one × 1000
    y_mm = fig.axes[2].lines[0].get_ydata()
    y_si = fig_si.axes[2].lines[0].get_ydata()
    np.testing.assert_allclose(y_mm, 1000 * y_si, rtol=1e-12)
    assert default_positions(plan) == 6
    assert default_positions(assur.compile(assur.load(ROOT / "examples" / "jansen.toml"))) == 3


def test_spatial_views_follow_the_units_option():
    """examples/rssr.toml is in mm: its 3D views are drawn in mm by default and in m with units="si", so every
    drawn coordinate differs by the factor 1000 (the definition of the millimetre)."""
    from pathlib import Path
    from assur.plot import spatial as view
    plan = assur.compile(assur.load(Path(__file__).resolve().parents[1] / "examples" / "rssr.toml"))
    mm, m = (view.plotly_figure(plan, 24, positions=2, frames=4, units=u) for u in ("file", "si"))
    xs_mm = np.concatenate([np.asarray(t.x, dtype=float) for t in mm.data if t.x is not None])
    xs_m = np.concatenate([np.asarray(t.x, dtype=float) for t in m.data if t.x is not None])
    ok = np.isfinite(xs_mm)
    assert ok.sum() > 10
    np.testing.assert_allclose(xs_mm[ok], 1000.0 * xs_m[ok], rtol=1e-12)
    assert "mm" in mm.layout.scene.xaxis.title.text and "mm" not in m.layout.scene.xaxis.title.text
