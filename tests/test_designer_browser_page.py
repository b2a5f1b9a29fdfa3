"""The designer's page in a real headless Chromium: the file Save writes, a reload that continues a session, the
view after Flip, the instant-centre labels, the torque plot's axes and the synthesis panel's unit.

Reference values: the page's own arrays (the engine's numbers, checked in test_designer_browser.py), and the
geometry of what Chromium laid out (bounding boxes of the SVG elements).
"""
from __future__ import annotations

import math

import numpy as np
import pytest

import assur
from designer_browser import browser, designer, needs_designer_browser, settle  # noqa: F401

pytestmark = [pytest.mark.slow, needs_designer_browser]

FOURBAR = "walker_fourbar.toml"


def number(text: str) -> float:
    return float(text.strip().replace("−", "-"))


def box(d, testid, page=None):
    b = d.testid(testid, page).bounding_box()
    assert b is not None, f"{testid} is not drawn"
    return b


def overlap(a, b) -> bool:
    return a["x"] < b["x"] + b["width"] and b["x"] < a["x"] + a["width"] and \
        a["y"] < b["y"] + b["height"] and b["y"] < a["y"] + a["height"]


def sketch_of(d, name):
    return d.array("sketch")[d.point_order().index(name)]


def test_save_names_its_file_writes_the_edit_only_and_nothing_without_one(designer):
    d = designer(FOURBAR)
    before = d.file.read_text()
    assert d.text("save-file") == f"→ {d.file.name}"
    assert d.testid("save-file").get_attribute("title") == f"Save writes {d.file}"
    d.testid("save").click()
    d.page.wait_for_function("() => document.querySelector('[data-testid=status]').textContent.includes('nothing')")
    assert d.file.read_text() == before
    d.drag("O1", sketch_of(d, "O1") + [0.02, 0.02], steps=4)
    settle(d.page)
    d.testid("save").click()
    d.page.wait_for_function("() => document.querySelector('[data-testid=status]').textContent.startsWith('saved')")
    after = d.file.read_text()
    assert str(d.file) in d.text("status")
    changed = [(a, b) for a, b in zip(before.splitlines(), after.splitlines()) if a != b]
    assert [b.split("=")[0].strip() for _, b in changed] == ["O1", "length"]      # the point and the rocker
    assert 'mass = "0.6358 kg"                 # 0.27 m of bar' in after
    np.testing.assert_allclose(assur.load(d.file).sketch("O1"), sketch_of(d, "O1"), atol=1e-12)


def test_a_reload_says_it_continues_the_sessions_history(designer):
    d = designer(FOURBAR)
    assert d.testid("resumed").is_hidden() and d.state("resumed") is False
    d.drag("O1", sketch_of(d, "O1") + [0.01, 0.0], steps=3)
    settle(d.page)
    d.page.reload()
    d.page.wait_for_function("() => window.__assur && window.__assur.ready === true")
    assert d.state("resumed") is True and d.state("history.undo") == 1
    text = d.text("resumed")
    assert d.testid("resumed").is_visible() and "1 undo" in text and "reload" in text


def test_flip_brings_the_whole_mechanism_back_into_view(designer):
    """The four-bar leg flipped about K–O1 swings its coupler and foot above the frame: after Flip, every point and
    every path lies inside the canvas."""
    d = designer(FOURBAR)
    d.testid("flip-0").click()
    d.wait_result(0, "r.committed && r.history.undo === 1")
    settle(d.page)
    canvas = box(d, "canvas")
    inside = d.page.evaluate("""() => [...document.querySelectorAll('[data-testid=canvas] [data-testid^="path-"], [data-testid=canvas] [data-testid^="point-"]')]
        .map((e) => { const b = e.getBoundingClientRect(); return [e.dataset.testid, b.x, b.y, b.right, b.bottom]; })""")
    assert inside
    for name, x0, y0, x1, y1 in inside:
        assert x0 >= canvas["x"] - 1 and y0 >= canvas["y"] - 1, name
        assert x1 <= canvas["x"] + canvas["width"] + 1 and y1 <= canvas["y"] + canvas["height"] + 1, name


def test_instant_centre_labels_clear_the_point_labels(designer):
    """The crank's instant centre relative to the frame is its pivot O and the rocker's is O1: their labels must not
    cover the pivots' labels (nor any other point's)."""
    d = designer(FOURBAR)
    d.set_sample(0)
    settle(d.page)
    for link, pivot in (("crank", "O"), ("rocker", "O1")):
        ic = d.testid(f"ic-{link}")
        assert math.dist((float(ic.get_attribute("data-x")), float(ic.get_attribute("data-y"))),
                         sketch_of(d, pivot)) < 1e-9
    ic_labels = [box(d, f"ic-label-{name}") for name in ("crank", "rocker", "coupler")]
    point_labels = [box(d, f"label-{name}") for name in d.point_order()]
    for a in ic_labels:
        assert not any(overlap(a, b) for b in point_labels)


def test_the_torque_plot_has_input_and_value_ticks(designer):
    """x: every quarter turn of the crank within the samples (0, 90, 180, 270 °); left: the torque's range (its largest value is the
    peak effort read-out when the torque is positive there); right: the power's."""
    d = designer(FOURBAR)
    ticks = d.page.evaluate("""() => [...document.querySelectorAll('[data-testid="torque-plot"] .asd-plot-tick')]
        .map((t) => [t.dataset.axis, Number(t.dataset.value), t.getBoundingClientRect().y])""")
    xs = [v for a, v, _ in ticks if a == "x"]
    assert xs == pytest.approx([0, 90, 180, 270], abs=1e-9)            # the samples run from 0 to 359°
    torque = d.array("torque")[d.array("valid") > 0]
    power = d.array("power")[d.array("valid") > 0]
    left = sorted(v for a, v, _ in ticks if a == "y0")
    right = sorted(v for a, v, _ in ticks if a == "y1")
    assert left[0] == pytest.approx(min(0, torque.min()), rel=1e-12) and left[-1] == pytest.approx(max(0, torque.max()), rel=1e-12)
    assert right[0] == pytest.approx(min(0, power.min()), rel=1e-12) and right[-1] == pytest.approx(max(0, power.max()), rel=1e-12)
    assert 0.0 in left
    # the highest tick label sits above the lowest (y grows downward on screen)
    y_of = {v: y for a, v, y in ticks if a == "y0"}
    assert y_of[left[-1]] < y_of[left[0]]


def test_the_synthesis_best_has_its_unit_and_a_budget_that_finds_something(designer):
    d = designer("crank_rocker.toml")
    budget = int(d.testid("synth-budget").input_value())
    assert budget == 2000                                   # benchmarks/designer_synthesis_results.md
    pos = d.array("pos")
    p = d.point_order().index("P")
    d.testid("synth-point").select_option("P")
    d.testid("synth-add-targets").check()
    for t in pos[::60, p] * [1.05, 0.95]:
        d.click_world(t)
    d.testid("synth-add-targets").uncheck()
    d.testid("synth-budget").fill("300")
    d.testid("synth-run").click()
    d.page.wait_for_function("() => window.__assur.synth.running === false && window.__assur.synth.status !== 'starting'",
                             timeout=120_000)
    best = d.state("synth.best")
    assert best is not None and math.isfinite(best)
    unit = d.text("synth-best-unit")
    assert unit == d.state("units.length") == "mm"          # crank_rocker.toml is a mm file
    assert number(d.text("synth-best")) == pytest.approx(1000 * best, rel=1e-5)
    assert "distance" in d.testid("synth-best").get_attribute("title")
