"""The designer in Chromium: a cam's profile drawn turning with its cam, and the "all centres (Kennedy)" toggle.

Reference values: the cam's profile from :mod:`assur.cams` turned by the cam's turn (computed here from the page's
own positions), and every instant centre from :mod:`assur.analysis.instant_centres` at the page's sample.
"""
from __future__ import annotations

import numpy as np
import pytest

import assur
from assur.analysis.instant_centres import instant_centres
from assur.cams.followers import from_plan
from designer_browser import EXAMPLES, browser, designer, needs_designer_browser, settle  # noqa: F401

pytestmark = [pytest.mark.slow, needs_designer_browser]


def _points(d, testid):
    text = d.testid(testid).get_attribute("points")
    got = np.array([[float(v) for v in pair.split(",")] for pair in text.split()])
    box = d.page.locator('[data-testid="canvas"]').bounding_box()
    return got + np.array([box["x"], box["y"]])


def test_the_cam_profile_turns_with_its_cam(designer):
    d = designer("cam_press.toml")
    plan = assur.compile(assur.load(EXAMPLES / "cam_press.toml"))
    g = from_plan(plan, "lift")
    k = 50
    d.set_sample(k)
    settle(d.page)
    pos = d.array("pos")[k]
    at = {name: complex(*pos[i][:2]) for i, name in enumerate(d.point_order())}
    turn = (at["K"] - at["O"]) / abs(at["K"] - at["O"]) / g.orientation
    world = at["O"] + turn * g.orientation * g.profile(240)
    to_screen = d.world_to_screen()
    want = np.array([to_screen((z.real, z.imag)) for z in world])
    np.testing.assert_allclose(_points(d, "cam-lift"), want, atol=0.6)


def test_all_centres_and_kennedy_lines_on_a_toggle(designer):
    d = designer("stephenson3.toml")
    assert d.testid("show-kennedy").is_checked() is False
    assert d.page.locator('[data-testid^="centre-"]').count() == 0
    k = 30
    d.set_sample(k)
    d.testid("show-kennedy").check()
    settle(d.page)
    plan = assur.compile(assur.load(EXAMPLES / "stephenson3.toml"))
    st = assur.solve(plan, inputs=d.array("q")[k:k + 1], order=1)
    ic = instant_centres(plan, st)
    to_screen = d.world_to_screen()
    box = d.page.locator('[data-testid="canvas"]').bounding_box()
    shown = 0
    for c, (i, j) in enumerate(ic.pairs):
        z = ic.points[0, c]
        loc = d.page.locator(f'[data-testid="centre-{i}-{j}"] circle')
        if not np.isfinite(z):
            assert loc.count() == 0
            continue
        x, y = to_screen((z.real, z.imag))
        if abs(x) > 1e5 or abs(y) > 1e5:
            continue
        cx, cy = float(loc.get_attribute("cx")) + box["x"], float(loc.get_attribute("cy")) + box["y"]
        assert abs(cx - x) <= 0.6 and abs(cy - y) <= 0.6
        shown += 1
    assert shown >= 12
    assert d.page.locator("line.asd-kennedy").count() >= 15
