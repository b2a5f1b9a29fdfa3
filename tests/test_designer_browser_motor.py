"""The designer's "Run on the motor" panel in a real headless Chromium: the page's numbers are those of `assur simulate
--json` (run by the command line in its own process: the reference), the plot marks the start-up time and the
steady mean speed, a run that cannot start says where and moves the mechanism there, a run is cancelled, and a file
without a motor shows where to add one.
"""
from __future__ import annotations

import json
import math
import subprocess
import sys
from pathlib import Path

import pytest

from designer_browser import browser, designer, needs_designer_browser, settle  # noqa: F401

pytestmark = [pytest.mark.slow, needs_designer_browser]

ROOT = Path(__file__).resolve().parents[1]
RPM = 60 / (2 * math.pi)


def cli_simulate(path) -> dict:
    out = subprocess.run([sys.executable, "-m", "assur", "simulate", str(path), "--json"], capture_output=True,
                         encoding="utf-8", check=True, cwd=ROOT)
    return json.loads(out.stdout)


def shown(d, testid) -> float:
    return float(d.text(testid).strip().replace("−", "-"))


def wait_run(d, status="finished"):
    d.page.wait_for_function("(s) => window.__assur.motor && window.__assur.motor.status === s", arg=status,
                             timeout=120_000)
    return d.state("motor")


def test_the_panel_shows_assur_simulates_numbers_and_says_when_the_design_changed(designer):
    d = designer("slider_crank_motor.toml")
    assert d.testid("motor-hint").is_hidden()
    assert d.text("motor-description").startswith("dc on crank: ")
    d.testid("motor-run").click()
    run = wait_run(d)
    reference = cli_simulate(d.file)
    s = run["summary"]
    for key in ("startup_time", "mean_speed", "delta", "time", "motor_torque_peak", "current_peak", "power_peak"):
        assert s[key] == pytest.approx(reference[key], rel=1e-12), key
    for key in ("delta_estimate", "difference", "energy_fluctuation", "inertia"):
        assert s["kinetostatic"][key] == pytest.approx(reference["kinetostatic"][key], rel=1e-12, abs=1e-15), key
    assert s["turns"] == reference["turns"] and s["stop"] == reference["stop"] == "steady"
    # on the panel, rounded to the 6 digits the page shows; the speed in rpm (the page's speed unit)
    assert shown(d, "motor-startup") == pytest.approx(reference["startup_time"], rel=1e-5)
    assert shown(d, "motor-mean-speed") == pytest.approx(reference["mean_speed"] * RPM, rel=1e-5)
    assert shown(d, "motor-delta") == pytest.approx(reference["delta"], rel=1e-5)
    assert shown(d, "motor-delta-estimate") == pytest.approx(reference["kinetostatic"]["delta_estimate"], rel=1e-5)
    assert shown(d, "motor-torque-peak") == pytest.approx(reference["motor_torque_peak"], rel=1e-5)
    assert shown(d, "motor-current-peak") == pytest.approx(reference["current_peak"], rel=1e-5)
    # the speed plot: its line, the steady mean speed and 95 % of it, the start-up time
    assert len(d.testid("motor-speed-line").get_attribute("d")) > 100
    assert float(d.testid("motor-mean-line").get_attribute("data-value")) == pytest.approx(
        reference["mean_speed"] * RPM, rel=1e-12)
    assert float(d.testid("motor-share-line").get_attribute("data-value")) == pytest.approx(
        0.95 * reference["mean_speed"] * RPM, rel=1e-12)
    assert float(d.testid("motor-startup-line").get_attribute("data-value")) == pytest.approx(
        reference["startup_time"], rel=1e-12)
    assert d.testid("motor-torque-line").count() == 1 and d.testid("motor-current-line").count() == 1
    assert d.testid("motor-stale").is_hidden() and d.testid("motor-stop").is_hidden()
    # the speed unit on display changes the shown speed only
    d.page.select_option('[data-testid="unit-speed"]', "rad/s")
    assert shown(d, "motor-mean-speed") == pytest.approx(reference["mean_speed"], rel=1e-5)
    # a committed edit makes the run stale
    seq = d.seq()
    d.drag("A", [0.026, 0.0433], steps=3)
    d.wait_result(seq, "r.committed")
    settle(d.page)
    assert d.state("motor.stale") is True and d.testid("motor-stale").is_visible()


def test_a_crank_that_cannot_turn_runs_for_a_time_stops_where_it_must_and_a_run_is_cancelled(designer, tmp_path):
    from test_designer_motor import NON_GRASHOF
    path = tmp_path / "non_grashof.toml"
    path.write_text(NON_GRASHOF)
    d = designer(str(path))
    # no steady state to run to: the page offers a time and says why
    assert d.testid("motor-time").input_value() == "5" and d.testid("motor-time-note").is_visible()
    d.set_sample(300)
    d.testid("motor-run").click()
    run = wait_run(d)
    out = subprocess.run([sys.executable, "-m", "assur", "simulate", str(path), "--time", "5", "--json"],
                         capture_output=True, encoding="utf-8", check=True, cwd=ROOT)
    reference = json.loads(out.stdout)
    assert run["stop"]["kind"] == reference["stop"] == "limit" and run["stop"]["message"] == reference["message"]
    assert run["summary"]["time"] == pytest.approx(reference["time"], rel=1e-12)
    stop = d.text("motor-stop")
    q = run["stop"]["q"]
    assert stop.startswith("stopped (limit) at t = ") and f"{math.degrees(q):.4g}"[:4] in stop
    assert float(d.testid("motor-stop-line").get_attribute("data-value")) == pytest.approx(run["stop"]["t"], rel=1e-12)
    # Show where: the mechanism at the sample nearest the input where it stopped (one sample per degree)
    d.testid("motor-show-stop").click()
    assert d.state("sample") == round(math.degrees(q)) % 360
    # a second run, cancelled at once
    d.testid("motor-run").click()
    d.page.wait_for_function("() => window.__assur.motor.running === true")
    d.testid("motor-cancel").click()
    run = wait_run(d, "cancelled")
    assert run["summary"] is None and run["running"] is False
    assert d.testid("motor-run").is_enabled()


def test_a_file_without_a_motor_shows_where_to_add_one(designer):
    d = designer("triad_sixbar.toml")
    assert d.testid("motor-hint").is_visible() and d.testid("motor-run").is_disabled()
    message = d.text("motor-hint-message")
    assert "no [motor]" in message and "triad_sixbar.toml, after line 39" in message
    assert d.text("motor-hint-example").startswith('[motor]\ndriver = "crank"\nkind = "dc"')
    assert d.state("refusal") == ""
