"""Notebook display: the ``_repr_html_`` tables of mechanisms, states and results, and ``assur.plot.mechanism``."""
import html
import math

import numpy as np
import pytest

import assur
from assur.analysis.actuators import Envelope, Extreme
from assur.analysis.gait import GaitMetrics, ModuleMetrics, Stats
from assur.analysis.spatial import dyad_summaries
from assur.analysis.transmission import DeadCentre
from assur.model.display import fmt, html_table

NASTY = "Four-bar <b>bold</b> & \"co\""


def fourbar(name=NASTY):
    """The README's four-bar (mm): crank OA = 30, coupler AB, rocker CB, frame OC = 100."""
    return (assur.Builder(units="mm", name=name)
            .point("O", 0, 0).point("C", 100, 0).point("A", 30, 0).point("B", 80, 90)
            .frame("O", "C").link("crank", "O", "A").link("coupler", "A", "B").link("rocker", "C", "B")
            .crank("crank", pivot="O", arm="A", speed="60 rpm", name="drive")
            .build())


def is_table(text):
    return isinstance(text, str) and text.startswith("<table") and text.endswith("</table>")


def test_html_table_escapes_and_formats():
    out = html_table("<t>", [("a<b", 1.234567891), ("arr", np.arange(12.0).reshape(3, 4)), ("none", None)],
                     units={"a<b": "m"})
    assert is_table(out)
    assert "&lt;t&gt;" in out and "a&lt;b" in out and "<t>" not in out
    assert "1.23457 m" in out                      # six significant digits, then the unit
    assert "array (3 × 4), 0 … 11" in out          # shape and range, not every number
    assert fmt(float("nan")) == "nan" and fmt(True) == "yes"
    assert fmt([{"a": 1}, {"a": 2}]) == "a: 1; a: 2" and fmt({"L": {"min": 0.5}}) == "L: (min: 0.5)"


def test_mechanism_repr_html():
    m = fourbar()
    out = m._repr_html_()
    assert is_table(out)
    assert html.escape(NASTY) in out and "<b>bold</b>" not in out
    for name in ("O", "C", "A", "B", "crank", "coupler", "rocker", "drive"):
        assert name in out
    # 60 rpm = 2π rad/s (independent: 60 rev/min · 2π / 60 s)
    assert f"{2 * math.pi:.6g} rad/s" in out
    assert "0.03, 0" in out                        # A = (30 mm, 0) shown in SI


def test_state_repr_html_counts_unbuildable():
    plan = assur.compile(fourbar())
    q = np.linspace(0, 2 * np.pi, 36, endpoint=False)
    state = assur.solve(plan, inputs=q)
    out = state._repr_html_()
    assert is_table(out) and out.startswith("<table") and ">State<" in out
    assert html.escape(NASTY) in out and "<b>bold</b>" not in out
    assert "36 of 36" in out and "pos, vel, acc" in out and "O, C, A, B" in out
    # crank 150 mm: at q = π, |A C| = 250 mm > coupler + rocker = √(50² + 90²) + √(20² + 90²) = 195.2 mm (no
    # assembly), at q = 0, |A C| = 50 mm lies between their difference and sum (assembles): part of the turn fails
    params = plan.defaults.copy()
    params[plan.param_index("crank.length")] = 0.15
    bad = assur.solve(plan, params, q, order=0)
    n_bad = int((~bad.valid).sum())
    assert 0 < n_bad < 36
    out = bad._repr_html_()
    assert f"{36 - n_bad} of 36" in out and "solved</th><td style=\"padding:1px 8px\">pos<" in out


def test_spatial_state_and_dyad_summary_repr_html():
    plan = assur.compile(assur.load("examples/rssr.toml"))
    state = assur.solve(plan, inputs=np.linspace(0, 2 * np.pi, 12))
    out = state._repr_html_()
    assert is_table(out) and ">SpatialState<" in out and "12 of 12" in out
    (dyad,) = dyad_summaries(plan)
    out = dyad._repr_html_()
    assert is_table(out) and dyad.point in out and dyad.rocker in out
    assert f"{dyad.swing:.6g} rad" in out


def test_gait_and_module_repr_html():
    plan = assur.compile(assur.load("examples/walker_fourbar.toml"))
    g = assur.gait_metrics(plan)
    out = g._repr_html_()
    assert is_table(out) and "Gait metrics of H" in out
    assert f"{g.step_length:.6g} m" in out and f"{g.duty_factor:.6g}" in out
    assert f"{g.duty_factor / (1 - g.duty_factor):.6g}" in out      # contact_ratio = duty / (1 − duty)
    s = Stats(1.0, 0.5, 0.75, 0.75)
    odd = GaitMetrics("<foot>", "arc", 1.0, 0.0, 3.0, 0.1, 0.02, 0.001, 0.5, s, s, (-1.0, 1.0), 10)
    assert "&lt;foot&gt;" in odd._repr_html_() and "<foot>" not in odd._repr_html_()
    mod = ModuleMetrics((0.0, math.pi), 1, 2, 1.5, 0.0)
    assert is_table(mod._repr_html_()) and "airborne_fraction" in mod._repr_html_()


def test_dead_centre_analysis_envelope_repr_html():
    dc = DeadCentre("drive", 1.5, "extended", "<rod>")
    out = dc._repr_html_()
    assert is_table(out) and "1.5 rad" in out and "&lt;rod&gt;" in out
    plan = assur.compile(fourbar("plain"))
    out = assur.Study(plan)._repr_html_()
    assert is_table(out) and "mobility" in out
    e1, e2 = Extreme(0.5, 0.0, 0.5, False), Extreme(0.9, 2.0, 0.9, True)
    env = Envelope(np.zeros(5), np.zeros(5), np.ones(5, bool), {}, {("<cyl>", "length"): {"min": e1, "max": e2}},
                   {}, {})
    out = env._repr_html_()
    assert is_table(out) and "&lt;cyl&gt; length" in out and "max 0.9 (t 2 s)" in out
    assert "Extreme" in e1._repr_html_()


def test_synthesis_result_repr_html():
    from assur.synthesis import load_problem, synthesize
    problem = load_problem("examples/synthesis/paper000_six_points.toml")
    best = synthesize(problem, "de", seed=1, popsize=8, budget=200, polish="none")
    out = best._repr_html_()
    assert is_table(out) and html.escape(problem.name) in out
    assert f"{best.objective:.6g}" in out and str(best.evaluations) in out
    for name, value in best.variables.items():
        assert f"x: {name}" in out and f"{value:.6g}" in out


def test_plot_mechanism_one_line(tmp_path):
    import matplotlib.figure
    fig = assur.plot.mechanism("examples/walker_fourbar.toml", steps=72)
    assert isinstance(fig, matplotlib.figure.Figure)
    assert len(fig.axes) == 5          # paths, diagram, velocity, acceleration and (a walking leg) the body path
    fig = assur.plot.mechanism(assur.compile(assur.load("examples/rssr.toml")), steps=36)
    assert any(ax.name == "3d" for ax in fig.axes)
    fig = assur.plot.mechanism(fourbar(), steps=36)
    assert len(fig.axes) == 4
    with pytest.raises(assur.SpecError, match="needs a plan, a Mechanism"):
        assur.plot.mechanism(42)
