"""Actuator kinematics of any mechanism (assur.analysis.actuators), the stroke envelope, the
buildable parts of a stroke (a guide out of the driving rod's reach), and their place in
``assur analyze`` and the report.

Reference values: the rods' lengths and angles from the solved positions (recomputed here), central
differences, the closed form of docs/papers/002.md §3–§4 (assur.analysis.lever, itself checked in
tests/test_paper002.py), and the guide's reach |h_A| = l1·sin(β − γ) (§2; § numbers in
this file are those of docs/papers/002.md).
"""
from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
import pytest

import assur
from assur.analysis.actuators import actuator_motions, rod_pairs, stroke_envelope, stroke_ranges, stroke_summary
from assur.analysis.lever import LeverManipulator
from assur.analysis.timelaw import ConstantSpeed, driver_law
from assur.cli.main import main

EXAMPLE = Path(__file__).resolve().parents[1] / "examples" / "lever_manipulator.toml"

# a crank O–A (rotary input) and a passive cylinder hinged at the frame point F, its rod at A (an RPR group)
CRANK_CYLINDER = """
format = "assur/1"
[units]
length = "m"
angle = "deg"
[points]
O = [0, 0]
F = [1.0, 0.4]
A = [0.3, 0.0]
[links]
frame = ["O", "F"]
crank = ["O", "A"]
[actuators.cyl]
between = ["F", "A"]
[[drivers]]
name = "crank"
link = "crank"
pivot = "O"
arm = "A"
speed = "30 rpm"
"""

# a boom lifted by a driven cylinder (RRR with the actuator as one side; tests/test_oracle.py m_boom)
BOOM = """
format = "assur/1"
[points]
O = [0.0, 0.0]
F = [0.4, -0.3]
B = [0.8, 0.5]
T = [2.0, 0.9]
[links]
frame = ["O", "F"]
boom = ["O", "B", "T"]
[actuators.cyl]
between = ["F", "B"]
[[drivers]]
name = "lift"
kind = "linear"
actuator = "cyl"
speed = "40 mm/s"
range = [0.85, 1.1]
"""


def wrap(x):
    return (x + math.pi) % (2 * math.pi) - math.pi


def test_passive_cylinder_on_a_crank():
    plan = assur.compile(assur.loads(CRANK_CYLINDER))
    q = np.linspace(0, 2 * np.pi, 25)
    st_ = assur.solve(plan, inputs=q)
    mo = actuator_motions(st_)["cyl"]
    assert not mo.driven
    F, A = st_.pos[:, plan.point_index("F")], st_.pos[:, plan.point_index("A")]
    np.testing.assert_allclose(mo.length, np.hypot(*(A - F).T), rtol=1e-14)
    np.testing.assert_allclose(mo.start_length, math.hypot(0.7, 0.4), rtol=1e-14)
    ang0 = math.atan2(-0.4, -0.7)
    np.testing.assert_allclose(wrap(mo.angle - (np.arctan2((A - F)[:, 1], (A - F)[:, 0]) - ang0)), 0, atol=1e-14)
    h = 1e-5
    lo, hi = (actuator_motions(assur.solve(plan, inputs=q + d)) ["cyl"] for d in (-h, h))
    np.testing.assert_allclose(mo.dlength_dq, (hi.length - lo.length) / (2 * h), rtol=1e-7, atol=1e-10)
    np.testing.assert_allclose(mo.d2length_dq2, (hi.length - 2 * mo.length + lo.length) / h ** 2, rtol=1e-4,
                               atol=1e-5)
    np.testing.assert_allclose(mo.dangle_dq, wrap(hi.angle - lo.angle) / (2 * h), rtol=1e-7, atol=1e-10)
    w = math.pi    # 30 rpm
    np.testing.assert_allclose(mo.rate, w * mo.dlength_dq, rtol=1e-12, atol=1e-15)
    np.testing.assert_allclose(mo.omega, w * mo.dangle_dq, rtol=1e-12, atol=1e-15)
    np.testing.assert_allclose(mo.alpha, w * w * mo.d2angle_dq2, rtol=1e-12, atol=1e-14)
    np.testing.assert_allclose(mo.areal_velocity, 0.5 * mo.length ** 2 * mo.omega, rtol=1e-15)
    # the engine's own cylinder body turns with the rod
    np.testing.assert_allclose(st_.body_omega[:, st_.body("cyl.cylinder")], mo.omega, rtol=1e-12, atol=1e-14)
    assert rod_pairs(st_) == []          # no driven rod: no pair


def test_driven_cylinder_of_a_boom():
    plan = assur.compile(assur.loads(BOOM))
    q = np.linspace(0.85, 1.1, 7)
    st_ = assur.solve(plan, inputs=q)
    mo = actuator_motions(st_)["cyl"]
    assert mo.driven
    np.testing.assert_allclose(mo.length, q, rtol=1e-13)
    np.testing.assert_allclose(mo.dlength_dq, 1.0, rtol=1e-12)
    np.testing.assert_allclose(mo.d2length_dq2, 0.0, atol=1e-10)
    np.testing.assert_allclose(mo.rate, 0.04, rtol=1e-12)
    np.testing.assert_allclose(mo.extension, q - math.hypot(0.4, 0.8), rtol=1e-13, atol=1e-15)


def test_envelope_of_another_design_is_its_closed_form():
    """A changed design (A at x = 0.8 m): the stroke still starts at the file's input L = 0.5 m, where B
    sits at (0.8 − 0.3, 0.4); the envelope equals the closed form of that start triangle."""
    plan = assur.compile(assur.load(EXAMPLE))
    p = plan.params_with(**{"A.x": 0.8})
    g = LeverManipulator.from_points((0, 0), (0.8, 0), (0.5, 0.4), (-1, 0))
    assert g.l1 == pytest.approx(0.5, rel=1e-15)
    env = stroke_envelope(plan, driver_law(plan), params=p, steps=80)
    assert abs(env.past_foot["drive_rod/driven_rod"] - (g.l1 + g.foot_stroke)) < 1e-9
    (low,) = env.extremes[("driven_rod", "extension")]["interior"]
    # s2_max = b1 − h_O (§8b): the driven rod's length change there is −(b1 − h_O)
    np.testing.assert_allclose(low.value, -(g.b1 - g.h_O), rtol=1e-9)
    k = env.samples[("drive_rod/driven_rod", "K_omega")]
    np.testing.assert_allclose(k, g.exact(env.q - 0.5)["K_omega"], rtol=1e-9)


def test_envelope_v2_crosses_zero_at_the_foot():
    plan = assur.compile(assur.load(EXAMPLE))
    env = stroke_envelope(plan, driver_law(plan), steps=101)
    v2 = -env.samples[("driven_rod", "rate")]
    s_foot = math.sqrt(0.52) - 0.5          # §8
    before, after = env.q - 0.5 < s_foot - 1e-6, env.q - 0.5 > s_foot + 1e-6
    assert np.all(v2[before] > 0) and np.all(v2[after] < 0)
    assert np.all(np.diff(v2) < 0)           # §8b: V2 falls monotonically


# -- a guide out of the driving rod's reach -------------------------------------------------------------------
def reach_file(tmp_path, start_mm=300, stop_mm=700):
    text = EXAMPLE.read_text(encoding="utf-8").replace("range = [500, 1000]", f"range = [{start_mm}, {stop_mm}]")
    p = tmp_path / "reach.toml"
    p.write_text(text, encoding="utf-8")
    return p


def test_stroke_ranges_name_the_unreachable_part():
    """Below L = |h_A| = 0.4 m the driving rod cannot reach the guide (§2: h_A = l1·sin(β − γ))."""
    plan = assur.compile(assur.load(EXAMPLE))
    r = stroke_ranges(plan, 0.3, 0.7, steps=50)
    ((a, b),) = r["unbuildable"]
    ((c, d),) = r["buildable"]
    assert a == 0.3 and abs(b - 0.4) < 1e-9 and abs(c - 0.4) < 1e-9 and d == 0.7
    assert abs(r["fraction_unbuildable"] - 0.25) < 1e-8
    st_ = assur.solve(plan, inputs=np.array([0.35, 0.45]))
    assert st_.valid.tolist() == [False, True] and np.all(np.isnan(st_.pos[0]))
    with pytest.warns(assur.UnbuildableWarning, match="drive=0.35 m"):
        assur.solve(plan, inputs=np.array([0.35, 0.45]), on_unbuildable="warn")


def test_analyze_names_the_unreachable_stroke(tmp_path, capsys):
    f = reach_file(tmp_path)
    assert main(["analyze", str(f), "--steps", "80"]) == 0
    out = capsys.readouterr().out
    line = next(ln for ln in out.splitlines() if ln.startswith("buildability"))
    assert "cannot be assembled for drive_rod = 300 … 400 mm" in line
    assert main(["analyze", str(f), "--steps", "80", "--json"]) == 0
    js = json.loads(capsys.readouterr().out)
    ((r,),) = [js["actuators"]["unbuildable_ranges"]]
    assert r["start"] == 0.3 and abs(r["end"] - 0.4) < 1e-9
    assert js["unbuildable"] == int(np.count_nonzero(np.linspace(0.3, 0.7, 80) < 0.4))


# -- analyze, report -----------------------------------------------------------------------------------------------
def test_analyze_shows_the_envelope_and_k_omega(capsys):
    assert main(["analyze", str(EXAMPLE), "--steps", "100"]) == 0
    out = capsys.readouterr().out
    assert "stroke: drive drives drive_rod from 500 to 1000 mm (constant speed 0.1 m/s, t = 0 … 5 s)" in out
    # K_ω from 1 (t = 0, L = b) to its interior maximum 4 (tests/test_paper002.py derives it)
    assert "K_ω = ω(driven_rod) / ω(drive_rod): 1 … 4 (interior extrema: 4 at t = 3.944 s, drive_rod = 894.43 mm)" in out
    assert "areal-velocity ratio driven_rod / drive_rod: 1 (constant along the stroke)" in out
    assert "driven_rod lengthens (past the foot of its pivot): from drive_rod = 721.1103 mm" in out   # 500 + 221.1103
    assert "s2 max = b1 − h_O: 100 mm" in out


def test_summary_json_is_strict_and_complete():
    plan = assur.compile(assur.load(EXAMPLE))
    s = assur.Study(plan, steps=60).as_dict()
    act = s["actuators"]
    from assur.analysis.summary import structure_summary
    assert s["pairs"] == structure_summary(plan.mechanism)["pairs"]     # the kinematic pair counts stay untouched
    assert set(act["rods"]) == {"drive_rod", "driven_rod"} and act["rods"]["drive_rod"]["driven"]
    from assur.io.output import json_ready
    json.dumps(json_ready(s), allow_nan=False)
    assert act["lever"]["area_ratio"] == pytest.approx(1.0, rel=1e-12)


def test_stroke_summary_without_speed_uses_analogues():
    plan = assur.compile(assur.loads(EXAMPLE.read_text(encoding="utf-8").replace('speed = "100 mm/s"\n', "")))
    s = stroke_summary(plan, steps=40)
    assert s["stroke"]["analogues"] and "analogues" in s["stroke"]["law"]
    om = s["rods"]["drive_rod"]["quantities"]["omega"]["max"]
    # dψ/ds1 at s1 = 0: h_A / (l1·sqrt(l1² − h_A²)) = 0.4 / (0.5·0.3) (§4)
    assert om["value"] == pytest.approx(0.4 / 0.15, rel=1e-12) and om["q"] == 0.5


def test_report_section_has_the_envelope_and_the_figure():
    from assur.report.analysis import analysis_html
    plan = assur.compile(assur.load(EXAMPLE))
    page = analysis_html(assur.Study(plan, steps=60))
    assert "Stroke envelope" in page and "K_ω = ω(driven_rod) / ω(drive_rod)" in page
    assert "Lever manipulator (paper 002 parametrisation)" in page
    assert page.count("data:image/png;base64,") == 1


def test_actuator_figure_for_several_speeds():
    from assur.plot.actuators import actuator_figure
    from assur.plot.draw import close
    plan = assur.compile(assur.load(EXAMPLE))
    fig = actuator_figure(plan, speeds=(0.08, 0.10, 0.17), steps=40)
    ax_w = fig.axes[0]
    labels = [ln.get_label() for ln in ax_w.lines]
    assert sum("V1 = 0.17 m/s" in lb for lb in labels) == 2 and any("paper eq. (12)" in lb for lb in labels)
    # the curves for 0.17 m/s end at t = 0.5 / 0.17 s (the same stroke, faster)
    end = max(ln.get_xdata()[-1] for ln in ax_w.lines if "0.17" in ln.get_label())
    assert end == pytest.approx(0.5 / 0.17)
    close(fig)
    with pytest.raises(assur.SpecError, match="single linear driver"):
        actuator_figure(assur.compile(assur.loads(CRANK_CYLINDER)))


@pytest.mark.slow
def test_report_of_the_example(tmp_path, capsys):
    out = tmp_path / "rep"
    assert main(["report", str(EXAMPLE), "-o", str(out), "--steps", "40", "--frames", "4"]) == 0
    page = (out / "index.html").read_text(encoding="utf-8")
    assert "Stroke envelope" in page and "no figures" not in page


@pytest.mark.parametrize("gamma_deg, beta_deg", [(0, 53), (-30, 40), (90, 75), (20, 100)])
def test_reach_of_the_guide_is_the_distance_of_a(gamma_deg, beta_deg):
    """The driving rod reaches the guide exactly from L = |h_A| = l1·|sin(β − γ)| on (§2, §3:
    σ = sqrt(L² − h_A²) − d_A), for guides with γ < 0, γ = 90° and β < γ."""
    g = LeverManipulator(0.4, math.radians(60), math.radians(beta_deg), math.radians(gamma_deg))
    plan = assur.compile(g.mechanism(speed=0.1))
    reach = abs(g.h_A)
    r = stroke_ranges(plan, 0.5 * reach, g.l1 + 0.5, steps=60)
    ((a, b),) = r["unbuildable"]
    assert a == 0.5 * reach and abs(b - reach) < 1e-9 * g.l1
    assert abs(r["buildable"][0][0] - reach) < 1e-9 * g.l1


def test_layouts_other_than_the_papers_are_not_recognised():
    from assur.analysis.lever import lever_layout
    assert lever_layout(assur.compile(assur.loads(BOOM))) is None            # one actuator only
    assert lever_layout(assur.compile(assur.loads(CRANK_CYLINDER))) is None  # a crank input
    assert "lever" not in stroke_summary(assur.compile(assur.loads(BOOM)), steps=20)


def test_envelope_warns_or_raises_with_the_unreachable_range():
    plan = assur.compile(assur.load(EXAMPLE))
    law = ConstantSpeed.over(0.5, 0.1, (0.3, 0.7))
    with pytest.warns(assur.UnbuildableWarning, match=r"drive = 0\.3 … 0\.4 m \(25 % of the stroke"):
        env = stroke_envelope(plan, law, steps=40, on_unbuildable="warn")   # no sample at L = 0.4 exactly
    assert np.all(np.isnan(env.samples[("driven_rod", "omega")][~env.valid]))
    assert env.valid.tolist() == (env.q > 0.4).tolist()
    with pytest.raises(assur.UnbuildableError, match=r"cannot be assembled for drive = 0\.3 … 0\.4 m"):
        stroke_envelope(plan, law, steps=41, on_unbuildable="raise")
