"""The designer's run on the motor without a browser: the located hint of a file without a motor, the refusals, the
run in its worker process (the numbers of `assur simulate --json`, run as a separate process of the command line in
the test: the reference), a stall that says where, a cancel, and a drag answered while a run goes.

The Chromium side is tests/test_designer_browser_motor.py.
"""
import json
import math
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest

import assur
from assur.designer.motor_job import MotorJob, drivers_end_line, motor_hint, run_document
from assur.designer.session import Session

ROOT = Path(__file__).resolve().parents[1]
EX = ROOT / "examples"
MOTOR = EX / "slider_crank_motor.toml"


def reply(s, **request):
    (r,) = s.handle({"seq": 1, **request})
    return r.message


def wait_done(s: Session, timeout: float = 120.0):
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline:
        out = s.poll_jobs()
        if out:
            (r,) = out
            return r
        time.sleep(0.05)
    raise AssertionError("the run on the motor did not end")


def cli_simulate(path) -> dict:
    """`assur simulate FILE --json`, run by the command line in its own process."""
    out = subprocess.run([sys.executable, "-m", "assur", "simulate", str(path), "--json"], capture_output=True,
                         encoding="utf-8", check=True, cwd=ROOT)
    return json.loads(out.stdout)


def same_numbers(a, b, path="summary"):
    """Every number of ``b`` (the command line's JSON) equal in ``a`` to round-off, every other value equal."""
    if isinstance(b, dict):
        assert set(a) == set(b), (path, sorted(set(a) ^ set(b)))
        for k in b:
            same_numbers(a[k], b[k], f"{path}.{k}")
    elif isinstance(b, list):
        assert len(a) == len(b), path
        for i, (x, y) in enumerate(zip(a, b)):
            same_numbers(x, y, f"{path}[{i}]")
    elif isinstance(b, float) and not isinstance(b, bool):
        assert a == pytest.approx(b, rel=1e-12, abs=1e-12), path
    else:
        assert a == b, path


def weak_motor(tmp_path) -> Path:
    """The pump on a motor of 0.002 N·m at stall: 0.01 N·m at the crank through the 5:1 gearbox, far below the 60 N
    pumping force on the piston times its lever arm about the crank (some 50 mm at most)."""
    text = MOTOR.read_text().replace('stall_torque = "1 N*m"', 'stall_torque = "0.002 N*m"')
    path = tmp_path / "weak_pump.toml"
    path.write_text(text)
    return path


#: a non-Grashof four-bar (ground 100, crank 40, coupler 50, rocker 80 mm: s + l = 140 > p + q = 130, so the crank
#: cannot turn fully) with masses, on a constant torque: it has no steady state and its run stops where the crank
#: can go no further. B is the coupler–rocker joint above the ground line, drawn at the crank's 60°.
NON_GRASHOF = """format = "assur/1"
name = "A four-bar whose crank cannot turn"
[units]
length = "mm"
angle = "deg"
[points]
O2 = [0, 0]
O4 = [100, 0]
A = [20.000000000000004, 34.64101615137754]
B = [57.46346662911449, 67.7542864237204]
[links]
frame = ["O2", "O4"]
crank = { points = ["O2", "A"], mass = "0.2 kg", com = "mid", inertia = "1 kg*cm^2" }
coupler = { points = ["A", "B"], mass = "0.3 kg", com = "mid", inertia = "2 kg*cm^2" }
rocker = { points = ["O4", "B"], mass = "0.3 kg", com = "mid", inertia = "2 kg*cm^2" }
[[drivers]]
name = "crank"
link = "crank"
pivot = "O2"
arm = "A"
speed = "60 rpm"
[motor]
kind = "torque"
torque = "0.5 N*m"
"""


def non_grashof(tmp_path) -> Path:
    path = tmp_path / "non_grashof.toml"
    path.write_text(NON_GRASHOF)
    return path


# ---------------------------------------------------------------------------------------------------------------
# a file without a motor

def test_a_file_without_a_motor_gets_a_located_hint_whose_table_loads(tmp_path):
    s = Session.of_file(str(EX / "triad_sixbar.toml"))
    m = reply(s, op="hello")
    assert m["model"]["motor"] is None
    hint = m["model"]["motor_hint"]
    text = (EX / "triad_sixbar.toml").read_text()
    lines = text.splitlines()
    # after the last line of the [[drivers]] table: its speed
    assert hint["where"] == "motor" and hint["line"] == drivers_end_line(text) == len(lines) \
        and lines[hint["line"] - 1] == 'speed = "60 rpm"'
    assert "triad_sixbar.toml, after line" in hint["message"] and "driver 'crank'" in hint["message"]
    # the example is a [motor] the file reader takes, on the file's driver
    patched = tmp_path / "with_motor.toml"
    patched.write_text("\n".join(lines[:hint["line"]] + ["", hint["example"]] + lines[hint["line"]:]) + "\n")
    motor = assur.load(patched).motor
    assert motor.kind == "dc" and motor.driver == "crank" and motor.stall_torque == 1.0
    assert motor.no_load_speed == pytest.approx(3000 * 2 * math.pi / 60, rel=1e-15)
    # Run is refused with the same located sentence, never an error page
    r = reply(s, op="motor_start")
    assert r["type"] == "refused" and r["message"] == hint["message"] and r["where"] == "motor"
    assert s.motor_job is None


def test_a_linear_driver_gets_a_force_and_a_document_without_drivers_no_hint():
    doc = {"drivers": [{"name": "push", "kind": "linear", "actuator": "a"}]}
    assert 'kind = "force"' in motor_hint(doc)["example"]
    assert motor_hint({"links": {}}) is None
    assert motor_hint({"drivers": [{"name": "c"}], "motor": {"kind": "dc"}}) is None


def test_refusals_name_what_is_missing():
    s = Session.of_file(str(MOTOR))
    # deleting the motor's driver takes the motor with it (a [motor] without its driver would not load)
    r = reply(s, op="commit", edits=[{"kind": "delete_driver", "name": "crank"}])
    assert r["type"] == "result" and "motor" not in r["doc"] and r["model"]["motor_hint"] is None
    r = reply(s, op="motor_start")
    assert r["type"] == "refused" and r["where"] == "motor" and "not a mechanism yet" in r["message"]
    r = reply(s, op="motor_cancel")
    assert r["type"] == "refused" and r["message"] == "no run on the motor is going"


# ---------------------------------------------------------------------------------------------------------------
# runs

@pytest.mark.slow
def test_the_run_gives_assur_simulates_numbers_and_a_drag_is_answered_meanwhile(tmp_path):
    path = Path(tmp_path / MOTOR.name)
    path.write_text(MOTOR.read_text())
    s = Session.of_file(str(path))
    r = reply(s, op="motor_start")
    assert r["type"] == "motor_started" and s.motor_job.running
    # a drag is answered at once: the run is another process's, and its end is only polled
    preview = reply(s, op="preview", edits=[{"kind": "move_point", "point": "O", "to": [0.001, 0.0]}])
    assert preview["type"] == "result" and preview["committed"] is False
    assert s.motor_job.running, "the run ended before the drag was answered"
    assert reply(s, op="motor_start")["message"] == "a run on the motor is going; cancel it first"
    done = wait_done(s)
    m = done.message
    assert m["type"] == "motor_done" and m["status"] == "finished" and m["stop"]["kind"] == "steady"
    reference = cli_simulate(path)
    reference.pop("file")
    same_numbers(m["summary"], reference)
    # the samples: t increasing from 0, the speed from rest, the motor's torque the DC line τ = τs (1 − ω/ω0)
    arrays = {k: np.frombuffer(done.blob, "<f8", n, 8 * o).reshape(shape) for k, (o, n, shape) in m["arrays"].items()}
    t, w = arrays["t"], arrays["speed"]
    assert t[0] == 0 and np.all(np.diff(t) > 0) and t[-1] == pytest.approx(reference["time"], rel=1e-15)
    assert w[0] == 0
    motor = assur.load(path).motor
    wm = arrays["motor_speed"]
    np.testing.assert_allclose(arrays["motor_torque"], motor.stall_torque * (1 - wm / motor.no_load_speed),
                               rtol=1e-12, atol=1e-12)
    assert not s.jobs_running


@pytest.mark.slow
def test_a_motor_that_cannot_start_says_where(tmp_path):
    path = weak_motor(tmp_path)
    summary, stop, arrays, message = run_document(Session.of_file(str(path)).doc, 360)
    reference = cli_simulate(path)
    reference.pop("file")
    same_numbers(summary, reference)
    assert stop["kind"] == "cannot start" and summary["starts"] is False
    # it stalls where it starts: the sketch's crank angle (60°), at once
    assert stop["q"] == pytest.approx(math.radians(60), abs=1e-6) and stop["t"] < 1e-3
    assert f"q = {stop['q']:.6g}" in stop["message"] and message.startswith("The motor cannot start")


@pytest.mark.slow
def test_a_crank_that_cannot_turn_runs_for_a_time_and_stops_where_it_can_go_no_further(tmp_path):
    path = non_grashof(tmp_path)
    doc = Session.of_file(str(path)).doc
    with pytest.raises(assur.SpecError, match="does not turn fully"):
        run_document(doc, 360)
    summary, stop, arrays, message = run_document(doc, 360, 5.0)
    out = subprocess.run([sys.executable, "-m", "assur", "simulate", str(path), "--time", "5", "--json"],
                         capture_output=True, encoding="utf-8", check=True, cwd=ROOT)
    reference = json.loads(out.stdout)
    reference.pop("file")
    same_numbers(summary, reference)
    assert stop["kind"] == "limit" and "t = " in stop["message"] and f"q = {stop['q']:.6g}" in stop["message"]
    # where: the end of the crank's range, where the coupler and the rocker stretch out (B on the line O4–A):
    # |A − O4| = 50 + 80 at the crank angle of the law of cosines, 40² + 100² − 2·40·100·cos q = 130²
    limit = math.acos((40 ** 2 + 100 ** 2 - 130 ** 2) / (2 * 40 * 100))
    assert stop["q"] == pytest.approx(limit, abs=1e-3) and 0 < stop["t"] < 5
    assert arrays["t"][-1] == pytest.approx(stop["t"], rel=1e-12)
    r = reply(Session.of_file(str(path)), op="motor_start", time=-1)
    assert r["type"] == "refused" and r["where"] == "time"


@pytest.mark.slow
def test_cancel_stops_the_worker_at_once():
    s = Session.of_file(str(MOTOR))
    assert reply(s, op="motor_start")["type"] == "motor_started"
    job = s.motor_job
    (r,) = s.handle({"seq": 2, "op": "motor_cancel"})
    assert r.message["type"] == "motor_done" and r.message["status"] == "cancelled" and r.message["summary"] is None
    assert not job._process.is_alive() and not s.jobs_running
    assert reply(s, op="motor_cancel")["message"] == "no run on the motor is going"


def test_a_job_whose_process_dies_says_so(monkeypatch):
    """A worker that ends without its message (killed from outside) is reported, not waited for."""
    job = MotorJob.__new__(MotorJob)

    class Dead:
        exitcode = -9

        def is_alive(self):
            return False

        def join(self, timeout=None):
            pass

    import queue
    job.id, job.created, job._finished, job._cancelled = "x", time.time(), False, False
    job._queue, job._process = queue.Queue(), Dead()
    monkeypatch.setattr("assur.designer.motor_job.LAST_MESSAGE_WAIT", 0.01)
    (message, arrays), = job.poll()
    assert message["status"] == "failed" and "exit code -9" in message["message"] and arrays == {}
    assert job.poll() == [] and not job.running
