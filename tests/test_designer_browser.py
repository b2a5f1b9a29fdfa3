"""The designer's page (`assur design`) in a real headless Chromium: numbers, not pixels.

Every reference number comes from the engine in this test (``assur.solve``, ``assur.transmission_angles``,
``assur.gait_metrics``, ``assur.forces``) or from a difference quotient of the page's own positions; gestures are
real mouse and keyboard events. The fixtures (``tests/designer_browser.py``) fail a test on any console error, page
error or request to another host, and save one screenshot per test under ``$ASSUR_TEST_ARTIFACTS``.
"""
from __future__ import annotations

import math
import socket
import tomllib
import urllib.error
import urllib.request

import numpy as np
import pytest

import assur
from designer_browser import EXAMPLES, browser, designer, needs_designer_browser, settle  # noqa: F401

pytestmark = [pytest.mark.slow, needs_designer_browser]

FOURBAR = "walker_fourbar.toml"
#: the readouts are printed with 6 significant digits (the page's formatNumber)
PRINTED = 1e-5


def number(text: str) -> float:
    return float(text.strip().replace("−", "-"))


def close_printed(text: str, value: float, rel: float = PRINTED) -> bool:
    """A read-out printed with 6 significant digits equals ``value``."""
    return math.isclose(number(text), value, rel_tol=rel, abs_tol=1e-12 + rel * 1e-6)


def plan_of_toml(text: str):
    return assur.compile(assur.loads(text))


def engine_state(d, page=None):
    """(plan, q, state): the engine solved at the page's inputs ``arrays.q`` for the page's document."""
    plan = plan_of_toml(d.state("result.toml", page))
    q = d.array("q", page)
    return plan, q, assur.solve(plan, None, q, order=2)


def by_name(d, array: np.ndarray, plan, page=None) -> dict:
    """{point name: (n, 2) of a page array}, matched by name with the plan's point order."""
    order = d.point_order(page)
    return {name: array[:, order.index(name)] for name in plan.point_names}


def mirror(p, a, b):
    """``p`` mirrored across the line through ``a`` and ``b``."""
    p, a, b = (np.asarray(v, dtype=float) for v in (p, a, b))
    u = (b - a) / np.linalg.norm(b - a)
    foot = a + u * np.dot(p - a, u)
    return 2 * foot - p


def sketch_of(d, name, page=None):
    order = d.point_order(page)
    return d.array("sketch", page)[order.index(name)]


# -- numbers, not pixels ------------------------------------------------------------------------------------------

@pytest.mark.parametrize("example", [FOURBAR, "jansen.toml"])
def test_positions_are_the_engines(designer, example):
    d = designer(example)
    plan, q, state = engine_state(d)
    valid = d.array("valid") > 0.5
    np.testing.assert_array_equal(valid, np.asarray(state.valid, dtype=bool))
    pos = by_name(d, d.array("pos"), plan)
    scale = float(np.nanmax(np.abs(state.pos)))
    for i, name in enumerate(plan.point_names):
        np.testing.assert_allclose(pos[name][valid], state.pos[valid, i], atol=1e-12 * scale, rtol=1e-12)
    # the drawn circles (data-x, data-y) at a few samples of the scrub bar
    for k in (0, 37, 181, len(q) - 1):
        d.set_sample(k)
        for i, name in enumerate(plan.point_names):
            c = d.testid(f"point-{name}")
            xy = [float(c.get_attribute("data-x")), float(c.get_attribute("data-y"))]
            np.testing.assert_allclose(xy, state.pos[k, i], atol=1e-12 * scale)


def test_velocity_readouts_are_difference_quotients(designer):
    d = designer(FOURBAR)
    q, pos, vel, acc = (d.array(n) for n in ("q", "pos", "vel", "acc"))
    omega = d.state("result.cycle.input.speed")
    n = len(q)
    order = d.point_order()
    for name in ("H", "L", "K"):
        p = order.index(name)
        d.testid("plot-point").select_option(name)
        for k in (5, 90, 200, 333):
            dq = math.remainder(q[(k + 1) % n] - q[k - 1], 2 * math.pi) / 2
            dt = dq / omega
            central = (pos[(k + 1) % n, p] - pos[k - 1, p]) / (2 * dt)
            second = (pos[(k + 1) % n, p] - 2 * pos[k, p] + pos[k - 1, p]) / dt ** 2
            # truncation errors h²/6·|x'''| and h²/12·|x''''|, the derivatives estimated from the page's acc
            jerk = (acc[(k + 1) % n, p] - acc[k - 1, p]) / (2 * dt)
            snap = (acc[(k + 1) % n, p] - 2 * acc[k, p] + acc[k - 1, p]) / dt ** 2
            tol_v = 2 * dt ** 2 / 6 * np.linalg.norm(jerk) + 1e-9
            tol_a = 2 * dt ** 2 / 12 * np.linalg.norm(snap) + 1e-9 / dt
            assert np.linalg.norm(vel[k, p] - central) <= tol_v
            assert np.linalg.norm(acc[k, p] - second) <= tol_a
            d.set_sample(k)
            assert d.state("units.length") == "m"          # the file is in m: the read-outs are in m/s, m/s²
            v_text, a_text = d.text(f"readout-vel-{name}"), d.text(f"readout-acc-{name}")
            assert abs(number(v_text) - np.linalg.norm(central)) <= tol_v + PRINTED * np.linalg.norm(central)
            assert abs(number(a_text) - np.linalg.norm(second)) <= tol_a + PRINTED * np.linalg.norm(second)
            # the drawn velocity vector carries the same numbers
            line = d.testid(f"vel-{name}")
            v_drawn = [float(line.get_attribute("data-vx")), float(line.get_attribute("data-vy"))]
            assert np.linalg.norm(np.subtract(v_drawn, central)) <= tol_v


def test_instant_centre_is_where_the_link_velocity_vanishes(designer):
    d = designer(FOURBAR)
    plan, q, state = engine_state(d)
    links = {lk.name: lk.points for lk in plan.mechanism.links}
    checked = 0
    for k in (0, 45, 100, 250):
        d.set_sample(k)
        for b, link in enumerate(plan.body_names):
            if b == 0:
                continue
            marker = d.testid(f"ic-{link}")
            if marker.count() == 0:       # the page hides a centre off the canvas (a link in translation)
                continue
            ic = np.array([float(marker.get_attribute("data-x")), float(marker.get_attribute("data-y"))])
            w = float(state.body_omega[k, b])
            for name in links[link]:
                i = plan.point_index(name)
                v_at_ic = state.vel[k, i] + w * np.array([-(ic[1] - state.pos[k, i, 1]), ic[0] - state.pos[k, i, 0]])
                assert np.linalg.norm(v_at_ic) <= 1e-9 * max(1.0, float(np.abs(state.vel[k]).max())), (k, link, name)
            checked += 1
    assert checked >= 8


def test_transmission_readouts_are_the_engines(designer):
    d = designer(FOURBAR)
    plan, q, state = engine_state(d)
    mu = assur.transmission_angles(plan, state)
    groups = d.state("result.model.groups")
    assert groups
    assert d.state("units.angle") == "deg"
    for k in (0, 60, 170, 300):
        d.set_sample(k)
        for g in groups:
            assert close_printed(d.text(f"transmission-{g['index']}"), math.degrees(mu[g["point"]][k]))


def test_gait_panel_agrees_with_the_engine_after_a_commit(designer):
    d = designer(FOURBAR)
    gait = d.state("result.cycle.gait")
    assert gait["exact"]
    o1 = sketch_of(d, "O1")
    seen = []
    d.drag("O1", o1 + [0.03, 0.02], steps=6, release=False,
           on_step=lambda i: seen.append(d.state("result.cycle.gait")))
    assert any(g and not g["exact"] for g in seen), "the gait during a drag is on the samples (exact false)"
    before = d.seq()
    d.page.mouse.up()
    r = d.wait_result(before, "r.committed && r.history.undo === 1")
    gait = r["cycle"]["gait"]
    assert gait["exact"]
    m = assur.gait_metrics(plan_of_toml(r["toml"]))
    ref = {"step_length": m.step_length, "lift": m.lift, "sag": m.sag, "duty_factor": m.duty_factor,
           "support_speed_mean": m.support_speed.mean}
    for key, value in ref.items():
        assert math.isclose(gait[key], value, rel_tol=1e-9), key
        assert close_printed(d.text(f"gait-{key}"), value), key      # the file is in m: lengths shown in m


def test_torque_peak_is_the_engines(designer):
    d = designer(FOURBAR)
    plan, q, state = engine_state(d)
    f = assur.forces(plan, None, q)
    valid = np.asarray(state.valid, dtype=bool)
    torque = np.asarray(f.driver)[..., 0]
    np.testing.assert_allclose(d.array("torque")[valid], torque[valid], rtol=1e-9, atol=1e-9)
    assert d.testid("torque-panel").is_visible()
    assert close_printed(d.text("torque-peak"), float(np.max(np.abs(torque[valid]))))
    assert close_printed(d.text("power-peak"), float(np.max(np.abs(np.asarray(f.power)[valid]))))


# -- gestures -----------------------------------------------------------------------------------------------------

def test_a_drag_is_one_undo_entry_and_undo_redo_round_trip(designer):
    d = designer(FOURBAR)
    toml0 = d.state("result.toml")
    branches0 = [g["branch"] for g in d.state("result.model.groups")]
    target = sketch_of(d, "O1") + [0.04, -0.03]
    branches = []
    d.drag("O1", target, steps=10, release=False,
           on_step=lambda i: branches.append([g["branch"] for g in d.state("result.model.groups")]))
    before = d.seq()
    d.page.mouse.up()
    r = d.wait_result(before, "r.committed")
    settle(d.page)
    wire = d.wire()
    assert wire["ops"].count("commit") == 1 and wire["ops"].count("preview") >= 3
    assert all(b == branches0 for b in branches), "a drag never changes a branch"
    assert r["history"]["undo"] == 1 and r["history"]["redo"] == 0
    toml1 = r["toml"]
    assert toml1 != toml0
    px = 1 / d.world_to_screen().scale
    np.testing.assert_allclose(sketch_of(d, "O1"), target, atol=2 * px)
    d.testid("undo").click()
    settle(d.page)
    assert d.state("result.toml") == toml0 and d.state("history.redo") == 1
    d.testid("redo").click()
    settle(d.page)
    assert d.state("result.toml") == toml1 and d.state("history.undo") == 1
    # the keyboard does the same
    d.page.keyboard.press("Control+z")
    settle(d.page)
    assert d.state("result.toml") == toml0
    d.page.keyboard.press("Control+Shift+z")
    settle(d.page)
    assert d.state("result.toml") == toml1


def test_escape_during_a_drag_restores_the_start_pose(designer):
    d = designer(FOURBAR)
    toml0 = d.state("result.toml")
    sketch0 = d.array("sketch")
    start = [float(d.testid("point-O1").get_attribute(a)) for a in ("data-x", "data-y")]
    d.drag("O1", sketch_of(d, "O1") + [0.08, 0.05], steps=6, release=False)
    assert d.state("result.committed") is False, "the drag previews"
    d.page.keyboard.press("Escape")
    d.page.mouse.up()
    settle(d.page)
    assert d.state("result.toml") == toml0
    assert d.state("history.undo") == 0
    np.testing.assert_array_equal(d.array("sketch"), sketch0)
    now = [float(d.testid("point-O1").get_attribute(a)) for a in ("data-x", "data-y")]
    assert now == start
    assert "cancel" in d.wire()["ops"] and "commit" not in d.wire()["ops"]


def test_a_drag_never_flips_a_branch_and_a_flip_needs_the_button(designer):
    d = designer(FOURBAR)
    toml0 = d.state("result.toml")
    groups0 = d.state("result.model.groups")
    (group,) = [g for g in groups0 if g["point"] == "L"]
    k, o1, l = (sketch_of(d, n) for n in ("K", "O1", "L"))
    across = mirror(l, k, o1)
    branches = []
    d.drag("L", across, steps=14, release=False,
           on_step=lambda i: branches.append([g["branch"] for g in d.state("result.model.groups")]))
    d.page.mouse.up()
    settle(d.page)
    assert all(b == [g["branch"] for g in groups0] for b in branches)
    refusal = d.state("refusal")
    assert refusal and "flip" in refusal.lower()
    assert d.text("refusal").strip() == refusal
    assert d.state("result.toml") == toml0 and d.state("history.undo") == 0
    # the dragged point snapped back to the last good result
    np.testing.assert_allclose(sketch_of(d, "L"), l, atol=1e-12)
    # Flip: one undo entry, the group on its other branch
    before = d.seq()
    d.testid(f"flip-{group['index']}").click()
    r = d.wait_result(before, "r.committed && r.history.undo === 1")
    (flipped,) = [g for g in r["model"]["groups"] if g["point"] == "L"]
    assert flipped["branch"] == -group["branch"]
    assert d.state("refusal") == ""
    d.testid("undo").click()
    settle(d.page)
    assert d.state("result.toml") == toml0


def test_moving_the_frame_pivot_far_away_makes_gaps(designer):
    d = designer(FOURBAR)
    n = d.state("result.cycle.n")
    assert int(d.text("assembled-count")) == n
    o1 = sketch_of(d, "O1")
    before = d.seq()
    d.drag("O1", o1 + [0.63, 0.0], steps=10)
    r = d.wait_result(before, "r.committed")
    settle(d.page)
    assembled = int(d.text("assembled-count"))
    valid = d.array("valid") > 0.5
    assert assembled == r["cycle"]["assembled"] == int(valid.sum())
    assert 0 < assembled < n
    plan, q, state = engine_state(d)
    assert assembled == int(np.asarray(state.valid).sum())
    path = d.testid("path-H")
    drawn = len([c for c in path.get_attribute("d") if c in "ML"])
    assert int(path.get_attribute("data-runs")) > 1 or drawn < n
    assert drawn == assembled


# -- editing tools ----------------------------------------------------------------------------------------------

def test_add_point_add_link_delete_point(designer):
    d = designer(FOURBAR)
    points0 = set(d.state("result.model.points"))
    o = sketch_of(d, "O")
    d.testid("tool-add-point").click()
    before = d.seq()
    at = o + [0.0, 0.25]
    d.click_world(at)
    r = d.wait_result(before, "r.committed && r.history.undo === 1")
    (new,) = set(r["model"]["points"]) - points0
    assert new in r["model"]["frame_points"]
    px = 1 / d.world_to_screen().scale
    np.testing.assert_allclose(sketch_of(d, new), at, atol=2 * px)
    # a link between two clicks on empty space: two new points and the link
    d.testid("tool-add-link").click()
    links0 = {lk["name"] for lk in r["model"]["links"]}
    before = d.seq()
    d.click_world(o + [-0.2, 0.3])
    d.click_world(o + [-0.1, 0.45])
    r = d.wait_result(before, "r.committed && r.history.undo === 2")
    (link,) = [lk for lk in r["model"]["links"] if lk["name"] not in links0]
    assert len(link["points"]) == 2 and not set(link["points"]) & points0
    # delete H
    d.testid("tool-delete").click()
    before = d.seq()
    sx, sy = d.screen_of("H")
    d.page.mouse.click(sx, sy)
    r = d.wait_result(before, "r.committed && r.history.undo === 3")
    assert "H" not in r["model"]["points"]
    assert d.testid("point-H").count() == 0
    d.testid("undo").click()
    settle(d.page)
    assert "H" in d.state("result.model.points")


def test_a_locked_point_does_not_move(designer):
    d = designer(FOURBAR)
    sx, sy = d.screen_of("O1")
    d.page.mouse.click(sx, sy)                        # select O1
    before = d.seq()
    d.testid("lock-point").check()
    r = d.wait_result(before, "r.committed && r.history.undo === 1")
    assert "O1" in r["model"]["locks"]["points"]
    toml_locked = r["toml"]
    o1 = sketch_of(d, "O1")
    d.drag("O1", o1 + [0.1, 0.1], steps=6)
    settle(d.page)
    assert d.state("refusal") or d.state("result.toml") == toml_locked
    np.testing.assert_allclose(sketch_of(d, "O1"), o1, atol=1e-12)


def test_save_writes_the_document(designer):
    d = designer(FOURBAR)
    d.drag("O1", sketch_of(d, "O1") + [0.02, 0.02], steps=4)
    settle(d.page)
    assert d.state("history.dirty")
    d.testid("save").click()
    d.page.wait_for_function("() => document.querySelector('[data-testid=status]').textContent.includes('saved')")
    toml = d.state("result.toml")
    text = d.file.read_text(encoding="utf-8")
    assert "# l2" in text and 'mass = "0.6358 kg"' in text       # the file's comments and units stay
    saved = assur.load(d.file)
    assert assur.dumps(saved) == assur.dumps(assur.loads(toml))
    np.testing.assert_allclose(saved.sketch("O1"), sketch_of(d, "O1"), atol=1e-12)
    assert str(d.file) in d.text("status")


# -- units and sharing ----------------------------------------------------------------------------------------------

def readouts(d) -> dict:
    return d.page.evaluate("""() => {
        const out = {};
        for (const e of document.querySelectorAll('[data-testid]')) {
          const id = e.dataset.testid;
          if (/^(readout-|transmission-|gait-|torque-peak|power-peak|assembled-count|sample-index)/.test(id))
            out[id] = e.textContent;
          if (/^speed-/.test(id)) out[id] = e.value;
          if (/^point-/.test(id)) out[id] = [e.dataset.x, e.dataset.y];
        }
        return out; }""")


def test_a_unit_round_trip_is_the_identity(designer):
    d = designer(FOURBAR)
    d.set_sample(77)
    d.testid("plot-point").select_option("H")
    toml0 = d.state("result.toml")
    before = readouts(d)
    assert d.state("units") == {"length": "m", "angle": "deg", "speed": "rpm"}
    v_si = number(before["readout-vel-H"])
    d.testid("unit-length").select_option("mm")
    d.testid("unit-angle").select_option("rad")
    d.testid("unit-speed").select_option("rad/s")
    changed = readouts(d)
    assert close_printed(changed["readout-vel-H"], 1000 * v_si, rel=2e-5)
    assert close_printed(changed["readout-input"], math.radians(number(before["readout-input"])), rel=2e-5)
    speed = d.state("result.cycle.input.speed")
    assert close_printed(changed["speed-crank"], speed, rel=2e-5)
    assert close_printed(before["speed-crank"], speed * 60 / (2 * math.pi), rel=2e-5)
    for key, value in before.items():
        if key.startswith("transmission-"):
            assert close_printed(changed[key], math.radians(number(value)), rel=2e-5)
    d.testid("unit-length").select_option("m")
    d.testid("unit-angle").select_option("deg")
    d.testid("unit-speed").select_option("rpm")
    assert readouts(d) == before
    settle(d.page)
    assert d.state("result.toml") == toml0 and d.state("history.undo") == 0
    assert "set_speed" not in str(d.wire()["ops"]) and d.wire()["ops"].count("commit") == 0


def test_share_link_round_trips_in_a_new_page(designer):
    a = designer(FOURBAR)
    a.drag("O1", sketch_of(a, "O1") + [0.03, 0.0], steps=4)
    settle(a.page)
    toml = a.state("result.toml")
    codec = a.page.evaluate("async (t) => window.__assur.share.decode(await window.__assur.share.encode(t))", toml)
    assert codec == toml
    a.testid("share").click()
    a.page.wait_for_function("() => document.querySelector('[data-testid=share-url]').value.includes('#m=1.')")
    url = a.testid("share-url").input_value()
    fragment = url[url.index("#"):]
    # another designer, on another file: the link loads the shared document as one history entry
    b = designer("crank_rocker.toml")
    assert b.state("result.toml") != toml
    page = b.open(fragment)
    b.page = page
    page.wait_for_function("(t) => window.__assur.result && window.__assur.result.toml === t", arg=toml)
    assert b.state("history.undo", page) == 1
    assert b.state("refusal", page) == ""


def test_a_newer_share_format_is_refused(designer):
    a = designer(FOURBAR)
    payload = a.page.evaluate("async (t) => window.__assur.share.encode(t)", a.state("result.toml"))
    assert payload.startswith("1.")
    b = designer("crank_rocker.toml")
    toml_b = b.state("result.toml")
    page = b.open("#m=2." + payload[2:])
    b.page = page
    refusal = b.wait_refusal(page)
    assert "newer" in refusal and "2" in refusal
    assert page.locator('[data-testid="refusal"]').text_content().strip() == refusal
    settle(page)
    assert "load" not in b.wire(page)["ops"]
    assert b.state("result.toml", page) == toml_b and b.state("history.undo", page) == 0


# -- synthesis from the page ---------------------------------------------------------------------------------------

def test_synthesis_progress_cancel_and_insert(designer):
    d = designer(FOURBAR)
    toml0 = d.state("result.toml")
    pos = d.array("pos")
    foot = d.point_order().index("H")
    targets = pos[::60, foot] + [0.01, -0.01]                 # six targets near the foot's path
    d.testid("synth-point").select_option("H")
    d.testid("synth-add-targets").check()
    for t in targets:
        d.click_world(t)
    d.testid("synth-add-targets").uncheck()
    drawn = d.page.evaluate("""() => [...document.querySelectorAll('[data-testid^="synth-target-"]')]
        .filter((e) => /^synth-target-\\d+$/.test(e.dataset.testid)).map((e) => [Number(e.dataset.x), Number(e.dataset.y)])""")
    px = 1 / d.world_to_screen().scale
    np.testing.assert_allclose(drawn, targets, atol=2 * px)
    d.testid("synth-budget").fill("100000")
    d.testid("synth-run").click()
    d.page.wait_for_function("() => Number(document.querySelector('[data-testid=synth-progress]').textContent) > 0",
                             timeout=60_000)
    # drags keep working while it runs
    before = d.seq()
    d.drag("O1", sketch_of(d, "O1") + [0.01, 0.01], steps=3)
    d.wait_result(before, "r.committed && r.history.undo === 1")
    d.testid("synth-cancel").click()
    d.page.wait_for_function("() => window.__assur.synth.running === false", timeout=30_000)
    synth = d.state("synth")
    assert synth["status"] == "cancelled"
    assert synth["best"] is not None and math.isfinite(synth["best"])
    assert math.isfinite(number(d.text("synth-best")))
    d.page.wait_for_function("() => !document.querySelector('[data-testid=synth-insert]').disabled")
    before = d.seq()
    d.testid("synth-insert").click()
    r = d.wait_result(before, "r.committed && r.history.undo === 2")
    assert r["toml"] != toml0
    assert "H" in r["model"]["points"]
    d.testid("undo").click()
    settle(d.page)
    assert d.state("history.undo") == 1


# -- safety ---------------------------------------------------------------------------------------------------------

def http_status(url: str, headers=None) -> int:
    try:
        with urllib.request.urlopen(urllib.request.Request(url, headers=headers or {}), timeout=10) as r:
            return r.status
    except urllib.error.HTTPError as exc:
        return exc.code


def non_loopback_address() -> str | None:
    s = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
    try:
        s.connect(("192.0.2.1", 9))                # no packet is sent: only the route is looked up
        ip = s.getsockname()[0]
    except OSError:
        return None
    finally:
        s.close()
    return None if ip.startswith("127.") else ip


def test_safety_token_host_origin_and_interface(designer):
    from websockets.exceptions import InvalidStatus
    from websockets.sync.client import connect
    d = designer(FOURBAR)
    srv = d.server
    base = f"http://127.0.0.1:{srv.port}"
    assert http_status(srv.url) == 200
    assert http_status(base + "/") == 403
    assert http_status(base + "/?token=wrong") == 403
    assert http_status(base + "/static/designer.js") == 403
    assert http_status(srv.url, headers={"Host": "evil.com"}) in (400, 403)
    assert http_status(srv.url, headers={"Host": f"evil.com:{srv.port}"}) in (400, 403)
    ws = f"ws://127.0.0.1:{srv.port}/ws?token={srv.token}"
    with connect(ws, origin=f"http://127.0.0.1:{srv.port}") as c:     # the page's own origin is served
        c.send('{"op": "hello", "seq": 1}')
        assert '"result"' in c.recv(timeout=30)
    with pytest.raises(InvalidStatus) as refused:
        with connect(ws, origin="http://evil.com"):
            pass
    assert refused.value.response.status_code == 403
    with pytest.raises(InvalidStatus):
        with connect(f"ws://127.0.0.1:{srv.port}/ws", origin=f"http://127.0.0.1:{srv.port}"):
            pass
    ip = non_loopback_address()
    if ip is not None:
        with pytest.raises(OSError):
            socket.create_connection((ip, srv.port), timeout=3).close()


# -- every example file -----------------------------------------------------------------------------------------------

def mechanism_examples():
    out = []
    for path in sorted(EXAMPLES.glob("*.toml")):
        with open(path, "rb") as f:
            if tomllib.load(f).get("format") == "assur/1":
                out.append(path.name)
    return out


@pytest.mark.parametrize("example", mechanism_examples())
def test_every_example_opens(designer, example):
    d = designer(example)
    mech = assur.load(EXAMPLES / example)
    plan = assur.compile(mech)
    r = d.state("result")
    if plan.dimension == 3:
        assert d.testid("view3d").is_visible()
        assert not d.testid("canvas").is_visible()
        params = r["model"]["params"]
        assert params and all(d.testid(f"param-{p['name']}").count() == 1 for p in params)
        assert d.page.locator("[data-testid=view3d] .main-svg").count() > 0     # plotly drew
        return
    from assur.analysis.sampling import sweep_inputs
    q_all, _, _ = sweep_inputs(plan, r["cycle"]["n"])
    np.testing.assert_allclose(d.array("q"), q_all[:, r["cycle"]["input"]["index"]], rtol=0, atol=1e-15)
    state = assur.solve(plan, None, q_all, order=0)
    k = 0
    scale = max(1.0, float(np.nanmax(np.abs(state.pos))))
    for i, name in enumerate(plan.point_names):
        c = d.testid(f"point-{name}")
        assert c.count() == 1, name
        xy = [float(c.get_attribute("data-x")), float(c.get_attribute("data-y"))]
        ref = state.pos[k, i] if bool(state.valid[k]) else np.asarray(mech.sketch(name), dtype=float)
        np.testing.assert_allclose(xy, ref, atol=1e-12 * scale, err_msg=name)


def test_spatial_parameter_sliders(designer):
    d = designer("rssr.toml")
    toml0 = d.state("result.toml")
    params = d.state("result.model.params")
    assert params
    for p in params:
        assert p["min"] <= p["value"] <= p["max"], f"the range of the slider {p['name']} excludes its value: {p}"
        slider = d.testid(f"param-{p['name']}")
        step = (p["max"] - p["min"]) / 400
        assert abs(float(slider.input_value()) - p["value"]) <= step, p["name"]
    plan = plan_of_toml(d.state("result.toml"))
    (p,) = [p for p in params if p["name"] == "crank.length"]
    new = p["value"] + 0.8 * (p["max"] - p["value"])
    before = d.seq()
    d.page.evaluate("""([name, v]) => { const s = document.querySelector(`[data-testid="param-${name}"]`);
                                       s.value = String(v); s.dispatchEvent(new Event('input', {bubbles: true})); }""",
                    [p["name"], new])
    r = d.wait_result(before)
    settle(d.page)
    (shown,) = [x for x in d.state("result.model.params") if x["name"] == p["name"]]
    assert math.isclose(shown["value"], new, rel_tol=1e-3)
    values = plan.defaults.copy()
    values[plan.param_index(p["name"])] = shown["value"]
    q = d.array("q")
    state = assur.solve(plan, values, q, order=0)
    valid = np.asarray(state.valid, dtype=bool)
    assert valid.any() and int(r["cycle"]["assembled"]) == int(valid.sum())
    pos = by_name(d, d.array("pos"), plan)
    for i, name in enumerate(plan.point_names):
        np.testing.assert_allclose(pos[name][valid], state.pos[valid, i], atol=1e-12, rtol=1e-9)
    assert d.state("result.toml") == toml0 and d.state("history.undo") == 0     # the sliders do not edit the file


def test_a_geared_leg_draws_its_pitch_curves_turning_and_touching(designer):
    """walker_fourbar_geared: at a cycle sample both pitch curves are drawn where the solved links put them (the
    gear module's curves turned by each link's turn, computed here from the page's own positions), and they touch
    (roll) at one point, within a drawing tolerance."""
    from assur.model.gearing import pitch_points
    d = designer("walker_fourbar_geared.toml")
    mech = assur.load(EXAMPLES / "walker_fourbar_geared.toml")
    k = 40
    d.set_sample(k)
    settle(d.page)
    pos = d.array("pos")[k]
    order = d.point_order()
    at = {name: complex(*pos[i][:2]) for i, name in enumerate(order)}
    sketch = {name: complex(*mech.sketch(name)[:2]) for name in order}
    curves = pitch_points(mech.gears[0], sketch["M"], sketch["O"], samples=180)
    to_screen = d.world_to_screen()
    drawn = {}
    for tag, curve, pivot, arm in (("a", curves[0], "M", "M1"), ("b", curves[1], "O", "K")):
        turn = (at[arm] - at[pivot]) / (sketch[arm] - sketch[pivot])
        world = at[pivot] + turn / abs(turn) * curve
        want = np.array([to_screen((z.real, z.imag)) for z in world])
        text = d.testid(f"gear-drive-{tag}").get_attribute("points")
        got = np.array([[float(v) for v in pair.split(",")] for pair in text.split()])
        box = d.page.locator('[data-testid="canvas"]').bounding_box()
        got = got + np.array([box["x"], box["y"]])              # SVG user units → page pixels (no viewBox scaling)
        np.testing.assert_allclose(got, want, atol=0.6)
        drawn[tag] = world
    gap = np.min(np.abs(drawn["a"][:, None] - drawn["b"][None, :]))
    assert gap < 0.01 * abs(sketch["M"] - sketch["O"])        # the two curves meet (sampled every 2°)
