"""``assur simulate`` and ``assur export --to mjcf`` end to end: the summary, JSON, CSV (every joint's reaction over
time), the figure, the motor option, and bad input (one error line, nothing written). The numbers are checked
against the Python API and, for the reactions, against the force analysis at the simulated motion."""
from __future__ import annotations

import csv
import json
import math
from pathlib import Path

import numpy as np
import pytest

import assur
from assur.cli.main import main

EXAMPLES = Path(__file__).resolve().parents[1] / "examples"
PUMP = EXAMPLES / "slider_crank_motor.toml"


def _run(capsys, *argv):
    code = main(list(map(str, argv)))
    out, err = capsys.readouterr()
    return code, out, err


@pytest.fixture(scope="module")
def pump():
    return assur.compile(assur.load(PUMP))


@pytest.mark.slow
def test_the_summary_and_json_agree_with_the_api(capsys, pump):
    s = assur.simulate(pump)
    code, out, err = _run(capsys, "simulate", PUMP, "--json")
    assert code == 0, err
    data = json.loads(out)
    assert data["stop"] == "steady" and data["starts"] is True
    assert data["mean_speed"] == pytest.approx(s.mean_speed, rel=1e-9)
    assert data["delta"] == pytest.approx(s.delta, rel=1e-9)
    assert data["startup_time"] == pytest.approx(s.startup_time, rel=1e-9)
    k = data["kinetostatic"]
    assert k["difference"] == pytest.approx(data["delta"] - k["delta_estimate"])
    assert set(data["joint_peaks"]) == {"O (frame–crank)", "A (crank–rod)", "B (rod–slot.block)",
                                        "slot (frame–slot.block)"}
    code, out, err = _run(capsys, "simulate", PUMP)
    assert code == 0
    assert "start-up time (to 95 % of the steady speed)" in out and "kinetostatic estimate of δ" in out
    assert f"{s.mean_speed * 30 / math.pi:.5g} rpm" in out


def test_the_csv_holds_every_joints_reaction_over_time(capsys, tmp_path, pump):
    plan = pump
    out = tmp_path / "run.csv"
    code, _, err = _run(capsys, "simulate", PUMP, "--csv", out, "--samples", 200, "--time", "0.5")
    assert code == 0, err
    rows = list(csv.reader(out.open(encoding="utf-8")))
    head, data = rows[0], np.array(rows[1:], dtype=float)
    assert head[:4] == ["t [s]", "crank [°]", "speed [rad/s]", "acceleration [rad/s²]"]
    assert data.shape == (200, len(head))
    # the reactions are the force analysis at the simulated motion, sample by sample
    q = np.radians(data[:, 1])
    f = assur.forces(plan, None, q[:, None], speeds=data[:, 2:3], accels=data[:, 3:4])
    col = head.index("A Rx [N]")
    k = f.pair_names.index("A")
    assert np.allclose(data[:, col], f.reactions[:, k, 0], rtol=1e-9, atol=1e-9)
    torque = data[:, head.index("motor effort at the input [N·m]")]
    assert np.allclose(f.driver[:, 0], torque - 0.031 * data[:, 3], rtol=1e-7, atol=1e-9)


def test_the_plot_is_written(capsys, tmp_path):
    out = tmp_path / "startup.png"
    code, _, err = _run(capsys, "simulate", PUMP, "--plot", out, "--time", "0.5")
    assert code == 0, err
    assert out.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


def test_a_motor_given_on_the_command_line(capsys):
    code, out, err = _run(capsys, "simulate", EXAMPLES / "walker_fourbar.toml", "--json", "--motor",
                          'kind = "dc", stall_torque = "0.2 N*m", no_load_speed = "3000 rpm", gear_ratio = 100')
    assert code == 0, err
    data = json.loads(out)
    assert data["stop"] == "steady" and 0 < data["mean_speed"] < 3000 * math.pi / 30 / 100
    code, out, err = _run(capsys, "simulate", EXAMPLES / "walker_fourbar.toml", "--json", "--motor",
                          'kind = "dc", stall_torque = "0.01 N*m", no_load_speed = "3000 rpm", gear_ratio = 100')
    assert code == 0 and json.loads(out)["stop"] == "cannot start" and json.loads(out)["starts"] is False


def test_a_free_motion(capsys):
    code, out, err = _run(capsys, "simulate", EXAMPLES / "walker_fourbar.toml", "--motor", "none", "--time", "1",
                          "--speed", "60 rpm", "--json")
    assert code == 0, err
    data = json.loads(out)
    assert data["stop"] == "time" and data["time"] == pytest.approx(1.0)


@pytest.mark.parametrize("argv, words", [
    (["simulate", EXAMPLES / "crank_rocker.toml"], "error: --motor: the file has no [motor]"),
    (["simulate", PUMP, "--motor", 'kind = "dc", stall_torque = -2, no_load_speed = 5'], "error: --motor.stall_torque"),
    (["simulate", PUMP, "--speed", "fast"], "error: --speed"),
    (["simulate", EXAMPLES / "nonexistent.toml"], "error:"),
    # 1e308° was a division by zero: the run's turns took no time at that angle's round-off
    (["simulate", PUMP, "--start", "1e308"], "error: --start: must be a finite angle within 1000 turns of the sketch's angle: 1e+308"),
])
def test_bad_input_is_one_error_line(capsys, argv, words):
    code, out, err = _run(capsys, *argv)
    assert code == 1 and err.startswith(words) and "Traceback" not in err


@pytest.mark.parametrize("q0", [1e308, float("nan"), "x"])
def test_the_api_refuses_a_start_out_of_reach(q0, pump):
    from assur.dynamics.api import simulate
    from assur.errors import SpecError
    plan = assur.compile(assur.load(PUMP))
    with pytest.raises(SpecError, match="q0: must be a finite angle within 1000 turns of the sketch's angle"):
        simulate(plan, time=0.1, q0=q0)


@pytest.mark.parametrize("samples", [1, 200_001, 10 ** 20, 2.5, True])
def test_the_api_refuses_output_samples_out_of_range(samples, pump):
    from assur.dynamics.api import simulate
    from assur.errors import SpecError
    with pytest.raises(SpecError, match="samples: must be a whole number from 2 to 200000"):
        simulate(pump, time=0.1, samples=samples)


def test_a_refused_simulation_writes_nothing(capsys, tmp_path):
    out = tmp_path / "run.csv"
    out.write_text("keep")
    code, _, err = _run(capsys, "simulate", PUMP, "--csv", out, "--motor", 'kind = "force", force = 5')
    assert code == 1 and "motor.kind" in err
    assert out.read_text() == "keep"


def test_export_mjcf(capsys, tmp_path):
    out = tmp_path / "leg.xml"
    code, stdout, err = _run(capsys, "export", EXAMPLES / "walker_fourbar.toml", "--to", "mjcf", out)
    assert code == 0, err
    assert out.read_text().startswith("<mujoco")
    code, _, err = _run(capsys, "export", EXAMPLES / "walker_fourbar_geared.toml", "--to", "mjcf", tmp_path / "g.xml")
    assert code == 1 and err.startswith("error: gears.drive:") and not (tmp_path / "g.xml").exists()
