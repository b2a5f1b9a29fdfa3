"""More of the designer in Chromium: the slider, driver and link tools, a link's length lock, the driver speed
field, the point plots, the walking module's feet on the ground and the dead-centre marks.

Reference values come from the engine in the test (``assur.solve``, ``assur.dead_centres``, ``assur.gait_metrics``)
or from the geometry of the edit itself.
"""
from __future__ import annotations

import math

import numpy as np
import pytest

import assur
from designer_browser import browser, designer, needs_designer_browser, settle  # noqa: F401

pytestmark = [pytest.mark.slow, needs_designer_browser]


def sketch_of(d, name):
    order = d.point_order()
    return d.array("sketch")[order.index(name)]


def test_delete_and_add_a_slider_and_a_driver(designer):
    d = designer("slider_crank.toml")
    # delete the slot with the Delete tool: B is free, mobility 2 with one driver, no cycle, a diagnostic says why
    d.testid("tool-delete").click()
    before = d.seq()
    sx, sy = d.screen_of("B")
    box = d.testid("slider-slot").bounding_box()
    d.page.mouse.click(box["x"] + box["width"] - 3, box["y"] + box["height"] / 2)   # the block, right of the pin
    r = d.wait_result(before, "r.committed && !r.doc.prismatic")
    assert r["cycle"] is None and any("mobility" in g["message"] for g in r["diagnostics"])
    # a slider on B again with the tool: a horizontal line through B, so B moves on y = its sketch y
    d.testid("tool-add-slider").click()
    before = d.seq()
    d.page.mouse.click(sx, sy)
    r = d.wait_result(before, "r.committed && r.cycle !== null")
    (slot,) = r["doc"]["prismatic"]
    assert slot["point"] == "B" and slot["guide"] == "frame" and slot["angle"] == 0
    B = d.array("pos")[:, d.point_order().index("B")]
    assert r["cycle"]["assembled"] == 360
    np.testing.assert_allclose(B[:, 1], sketch_of(d, "B")[1], atol=1e-12)
    # delete the driver with its button, then add one with the tool (pivot O, then arm A)
    before = d.seq()
    d.testid("delete-driver-crank").click()
    r = d.wait_result(before, "r.committed && !(r.doc.drivers || []).length")
    assert r["cycle"] is None
    d.testid("tool-add-driver").click()
    before = d.seq()
    d.page.mouse.click(*d.screen_of("O"))
    d.page.mouse.click(*d.screen_of("A"))
    r = d.wait_result(before, "r.committed && r.cycle !== null")
    (drv,) = r["model"]["drivers"]
    assert (drv["pivot"], drv["arm"], drv["link"]) == ("O", "A", "crank")
    assert drv["speed_si"] == pytest.approx(2 * math.pi)
    # the page's cycle is the engine's for the edited document
    plan = assur.compile(assur.loads(r["toml"]))
    st = assur.solve(plan, None, d.array("q"), order=2)
    order = d.point_order()
    for name in plan.point_names:
        np.testing.assert_allclose(d.array("pos")[:, order.index(name)], st.point(name).pos, atol=1e-12)


def test_delete_a_link_and_lock_a_links_length(designer):
    d = designer("walker_fourbar.toml")
    # select the crank (a click on its bar) and lock its length
    o, k = d.screen_of("O"), d.screen_of("K")
    d.page.mouse.click((o[0] + k[0]) / 2, (o[1] + k[1]) / 2)
    before = d.seq()
    d.testid("lock-link").check()
    r = d.wait_result(before, "r.committed")
    assert r["model"]["locks"]["links"] == ["crank"]
    # dragging K elsewhere keeps |OK|: K lands on the circle of radius 0.27 m about O, in the dragged direction
    target = np.array([0.1, 0.3])
    d.drag("K", target, steps=6)
    settle(d.page)
    K = sketch_of(d, "K")
    assert math.hypot(*K) == pytest.approx(0.27, rel=1e-12)
    assert math.atan2(K[1], K[0]) == pytest.approx(math.atan2(*target[::-1]), abs=0.02)
    # delete the rocker with the Delete tool (a click on its bar): not a mechanism any more, and undo brings it back
    d.testid("tool-delete").click()
    a, b = d.screen_of("O1"), d.screen_of("L")
    before = d.seq()
    d.page.mouse.click((a[0] + b[0]) / 2, (a[1] + b[1]) / 2)
    r = d.wait_result(before, "r.committed && !r.model.links.some((l) => l.name === 'rocker')")
    assert r["cycle"] is None
    d.testid("undo").click()
    settle(d.page)
    assert any(lk["name"] == "rocker" for lk in d.state("result.model.links"))


def test_speed_field_point_plots_and_module_panel(designer):
    d = designer("walker_fourbar.toml")
    # the speed field in rpm: 27 rpm shown; typing 54 doubles every velocity and quadruples every acceleration
    field = d.testid("speed-crank")
    assert float(field.input_value()) == pytest.approx(27, rel=1e-6)
    vel0, acc0 = d.array("vel"), d.array("acc")
    before = d.seq()
    field.fill("54")
    field.dispatch_event("change")
    d.wait_result(before, "r.committed")
    assert d.state("result.model.drivers[0].speed_si") == pytest.approx(54 * 2 * math.pi / 60, rel=1e-12)
    np.testing.assert_allclose(d.array("vel"), 2 * vel0, rtol=1e-12, atol=1e-12)
    np.testing.assert_allclose(d.array("acc"), 4 * acc0, rtol=1e-12, atol=1e-9)
    # the point plots: |v| and |a| of the chosen point over the cycle, the maxima printed in the labels
    d.page.locator('[data-testid="plot-point"]').select_option("L")
    settle(d.page)
    i = d.point_order().index("L")
    speed = np.linalg.norm(d.array("vel")[:, i], axis=-1)
    line = d.testid("plot-vel-line")
    assert line.count() == 1 and line.get_attribute("d").count("L") >= 300     # one vertex per sample
    assert f"{speed.max():.6g}"[:5] in d.testid("plot-vel").text_content()
    # two legs in antiphase: the feet-on-ground count is 1 or 2 everywhere, from the gait's contact arc
    feet = d.array("feet")
    g = assur.gait_metrics(assur.compile(assur.loads(d.state("result.toml"))), steps=360)
    q = d.array("q")
    arc = lambda x: ((x - g.contact_start) % (2 * math.pi)) <= (g.contact_end - g.contact_start)  # noqa: E731
    expected = arc(q).astype(int) + arc(q + math.pi).astype(int)
    assert np.mean(feet == expected) > 0.98            # the page's sampled arc against the refined one
    assert set(np.unique(feet)) <= {1.0, 2.0}
    assert d.text("feet-on-ground").strip()[0] in "12"


def test_dead_centre_marks_are_the_engines(designer):
    d = designer("crank_rocker.toml")
    plan = assur.compile(assur.loads(d.state("result.toml")))
    ref = sorted(dc.angle for dc in assur.dead_centres(plan))
    marks = d.page.locator('[data-testid^="dead-centre-"]')
    assert marks.count() == len(ref) == 2
    got = sorted(d.state("result.cycle.dead_centres[%d].q" % k) for k in range(len(ref)))
    np.testing.assert_allclose(got, ref, atol=(2 * math.pi / 360) ** 2)   # interpolated on the 360-sample grid
