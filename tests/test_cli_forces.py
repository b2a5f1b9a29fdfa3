"""``assur forces``, and the forces sections of ``assur analyze`` and ``assur report``, end to end.

Files are the examples' slider-crank, crank-rocker, linear-driver lever and RSSR with masses, gravity and
loads added in TOML (docs/format.md, "Forces"). Reference values come from an independent computation in
the tests themselves: the principle of virtual work, T·ω + F·v_B = 0 for a load F at B and no masses, with
v_B/ω the finite-difference derivative of B's solved position (the kinematics only, no force code).
"""
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
LOAD = -100.0   # N, along x at the slider's pin B


def _slider_crank(tmp_path, masses=True, load=True, friction=False, name="sc.toml"):
    s = (EXAMPLES / "slider_crank.toml").read_text(encoding="utf-8")
    if masses:
        s = s.replace('length = 50\n', 'length = 50\nmass = "0.5 kg"\n', 1)
        s = s.replace('length = 150\n', 'length = 150\nmass = "1 kg"\n', 1)
        s += '\n[dynamics]\ngravity = [0, -9.81]\n'
        if friction:
            s += 'joint_friction_radius = "2 mm"\nslide_friction = 0.1\n'
    if load:
        s += f'\n[[loads]]\npoint = "B"\nforce = [{LOAD}, 0]\n'
    p = tmp_path / name
    p.write_text(s, encoding="utf-8")
    return p


def _virtual_work_torque(path, q):
    """T(q) = −F·dx_B/dq for the load F = (LOAD, 0) at B alone (central differences of B's position)."""
    plan = assur.compile(assur.load(path))
    h = 1e-6
    xp = assur.solve(plan, None, np.asarray(q) + h).point("B").pos[..., 0]
    xm = assur.solve(plan, None, np.asarray(q) - h).point("B").pos[..., 0]
    return -LOAD * (xp - xm) / (2 * h)


def _run(capsys, *argv):
    code = main(list(map(str, argv)))
    out, err = capsys.readouterr()
    return code, out, err


def _strict(text):
    def bad(token):
        raise ValueError(f"non-strict JSON token {token}")
    return json.loads(text, parse_constant=bad)


def _one_error(code, out, err):
    assert code == 1, (out, err)
    lines = err.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("error: "), err
    return lines[0]


def test_summary_text_and_json(tmp_path, capsys):
    f = _slider_crank(tmp_path, masses=False)
    code, out, _ = _run(capsys, "forces", f, "--steps", 360)
    assert code == 0
    for label in ("peak driving torque", "RMS driving torque", "mean driving torque", "peak motor power",
                  "mean motor power", "energy per cycle", "kinetic-energy fluctuation", "flywheel inertia for δ = 0.05",
                  "peak shaking force", "peak shaking moment", "peak load at O", "singular samples"):
        assert label in out
    assert "N·m" in out and " W" in out and " J" in out and "kg·m²" in out
    code, out, _ = _run(capsys, "forces", f, "--steps", 360, "--json")
    s = _strict(out)
    q = np.linspace(0, 2 * math.pi, 360, endpoint=False)
    T = _virtual_work_torque(f, q)
    assert s["peak"] == pytest.approx(np.max(np.abs(T)), rel=1e-6)
    assert s["rms"] == pytest.approx(math.sqrt(np.mean(T ** 2)), rel=1e-6)
    # a constant force does no net work over a closed turn
    assert abs(s["energy"]) < 1e-9 * s["peak"]
    omega = 3000 * 2 * math.pi / 60   # speed = "3000 rpm" in the file
    assert s["power_peak"] == pytest.approx(s["peak"] * omega, rel=1e-12)
    assert s["flywheel_delta"] == 0.05
    assert s["flywheel_inertia"] == pytest.approx(s["energy_fluctuation"] / (0.05 * omega ** 2), rel=1e-12)
    assert s["singular"] == 0 and s["samples"] == 360


def test_at_table_json_and_several_values(tmp_path, capsys):
    f = _slider_crank(tmp_path, masses=False)
    code, out, _ = _run(capsys, "forces", f, "--at", 30, "--at", "90.0")
    assert code == 0
    assert "crank = 30 °" in out and "crank = 90 °" in out
    assert "Rx [N]" in out and "normal [N]" in out and "couple [N·m]" in out and "driving torque" in out
    code, out, _ = _run(capsys, "forces", f, "--at", 30, "--at", 90, "--json")
    d = _strict(out)
    assert [round(x["input"], 9) for x in d["samples"]] == [30, 90]
    T = _virtual_work_torque(f, np.radians([30.0, 90.0]))
    for smp, t in zip(d["samples"], T):
        assert smp["driver"] == pytest.approx(t, rel=1e-6)
        slot = next(j for j in smp["joints"] if j["pair"] == "slot")
        assert "normal" in slot and "couple" in slot
        # the guide is horizontal and the load horizontal: with no masses the slide's normal force balances the
        # rod's vertical component, so the frame's reaction at O balances the load (−F) plus the slide's normal
        O = next(j for j in smp["joints"] if j["pair"] == "O")
        assert O["reaction"][0] == pytest.approx(-LOAD, rel=1e-9)


def test_csv_rows(tmp_path, capsys):
    f = _slider_crank(tmp_path)
    out_csv = tmp_path / "f.csv"
    code, out, _ = _run(capsys, "forces", f, "--steps", 24, "--csv", out_csv)
    assert code == 0 and "wrote" in out
    rows = list(csv.reader(out_csv.open(encoding="utf-8")))
    head, body = rows[0], rows[1:]
    assert head[:3] == ["crank [°]", "driver [N·m]", "power [W]"]
    assert "O Rx [N]" in head and "A Ry [N]" in head and "slot Ry [N]" in head
    assert len(body) == 24 and all(len(r) == len(head) for r in body)
    assert [float(r[0]) for r in body] == pytest.approx(np.arange(24) * 15.0)
    omega = 3000 * 2 * math.pi / 60
    assert all(float(r[2]) == pytest.approx(float(r[1]) * omega, rel=1e-12) for r in body)


@pytest.mark.parametrize("at", [[], ["--at", "30", "--at", "90"]])
def test_no_masses_is_said_first(capsys, at):
    """A file without masses or loads: its forces are all zero, and the command says so before any number (once the
    note came second, and --at said nothing at all before its tables of zeros)."""
    code, out, _ = _run(capsys, "forces", EXAMPLES / "crank_rocker.toml", "--steps", 36, *at)
    assert code == 0
    assert out.splitlines()[0].startswith("note: the file has no masses or loads: every force is zero")
    assert out.count("no masses or loads") == 1
    code, out, _ = _run(capsys, "forces", EXAMPLES / "crank_rocker.toml", "--steps", 36, "--json", *at)
    s = _strict(out)
    assert next(iter(s)) == "note" and s["note"].startswith("the file has no masses or loads")
    if not at:
        assert s["peak"] == 0


def test_plot_forces_of_a_file_without_loads_draws_nothing(tmp_path, capsys):
    out = tmp_path / "forces.png"
    msg = _one_error(*_run(capsys, "plot", EXAMPLES / "slider_crank.toml", "--forces", "-o", out))
    assert "no masses or loads" in msg and "nothing was drawn" in msg
    assert not out.exists()


def test_friction_reports_iterations(tmp_path, capsys):
    f = _slider_crank(tmp_path, friction=True)
    code, out, _ = _run(capsys, "forces", f, "--steps", 36, "--friction")
    assert code == 0 and "friction iterations" in out and "converged" in out
    code, out, _ = _run(capsys, "forces", f, "--steps", 36, "--friction", "--json")
    s = _strict(out)
    assert s["friction"]["iterations"] >= 1 and s["friction"]["converged"] is True
    code, out, _ = _run(capsys, "forces", f, "--steps", 36, "--json")
    plain = _strict(out)
    # Coulomb friction only takes energy out: the motor's work per turn becomes positive
    assert plain["energy"] == pytest.approx(0.0, abs=1e-9 * plain["peak"]) and s["energy"] > 0


def test_linear_driver_stroke_and_at_outside(tmp_path, capsys):
    text = (EXAMPLES / "lever_manipulator.toml").read_text(encoding="utf-8")
    text += '\n[[loads]]\npoint = "B"\nforce = [0, -100]\n'
    p = tmp_path / "lever.toml"
    p.write_text(text, encoding="utf-8")
    code, out, err = _run(capsys, "forces", p, "--steps", 20, "--json")
    assert code == 0, err
    s = _strict(out)
    assert s["cycle"] == "stroke" and s["effort_unit"] == "N"
    assert s["start"] == pytest.approx(0.5) and s["stop"] == pytest.approx(1.0)   # range = [500, 1000] mm
    msg = _one_error(*_run(capsys, "forces", p, "--at", 1200))
    assert "--at" in msg and "outside the working stroke" in msg


def test_bad_input(tmp_path, capsys):
    f = _slider_crank(tmp_path)
    msg = _one_error(*_run(capsys, "forces", f, "--at", "thirty"))
    assert "--at" in msg and "thirty" in msg
    # a two-input plan: a five-bar with two cranks
    five = tmp_path / "five.toml"
    five.write_text("""format = "assur/1"
[units]
length = "mm"
angle = "deg"
[points]
O1 = [0, 0]
O2 = [60, 0]
A = [0, 30]
B = [60, 30]
C = [30, 70]
[links]
frame = ["O1", "O2"]
c1 = ["O1", "A"]
c2 = ["O2", "B"]
l1 = ["A", "C"]
l2 = ["B", "C"]
[[drivers]]
name = "m1"
kind = "rotary"
link = "c1"
pivot = "O1"
arm = "A"
[[drivers]]
name = "m2"
kind = "rotary"
link = "c2"
pivot = "O2"
arm = "B"
""", encoding="utf-8")
    msg = _one_error(*_run(capsys, "forces", five))
    assert "one driver" in msg and "m1" in msg
    # unwritable CSV paths: nothing is computed or written
    missing = tmp_path / "nope" / "f.csv"
    msg = _one_error(*_run(capsys, "forces", f, "--csv", missing))
    assert "nope" in msg and not missing.exists()
    msg = _one_error(*_run(capsys, "forces", f, "--csv", tmp_path))
    assert "directory" in msg


def test_analyze_forces_section_only_with_loads(tmp_path, capsys):
    f = _slider_crank(tmp_path)
    code, out, _ = _run(capsys, "analyze", f, "--steps", 72)
    assert code == 0 and "Forces (N, N·m, W, J):" in out and "peak driving torque" in out
    code, out, _ = _run(capsys, "analyze", f, "--steps", 72, "--json")
    assert "forces" in _strict(out)
    code, out, _ = _run(capsys, "analyze", EXAMPLES / "crank_rocker.toml", "--steps", 72)
    assert code == 0 and "Forces" not in out
    code, out, _ = _run(capsys, "analyze", EXAMPLES / "crank_rocker.toml", "--steps", 72, "--json")
    assert "forces" not in _strict(out)


def test_report_forces_section_only_with_loads(tmp_path, capsys):
    f = _slider_crank(tmp_path)
    code, _, err = _run(capsys, "report", f, "-o", tmp_path / "r1", "--steps", 72, "--frames", 2)
    assert code == 0, err
    html = (tmp_path / "r1" / "index.html").read_text(encoding="utf-8")
    assert ">Forces</h2>" in html and "Zhukovsky" in html and "peak driving torque" in html
    bare = _slider_crank(tmp_path, masses=False, load=False, name="bare.toml")
    code, _, err = _run(capsys, "report", bare, "-o", tmp_path / "r2", "--steps", 72, "--frames", 2)
    assert code == 0, err
    html = (tmp_path / "r2" / "index.html").read_text(encoding="utf-8")
    assert ">Forces</h2>" not in html


def test_spatial_file(tmp_path, capsys):
    s = (EXAMPLES / "rssr.toml").read_text(encoding="utf-8")
    s = s.replace('length = 70 }', 'length = 70, mass = "0.3 kg" }').replace('length = 50 }', 'length = 50, mass = "0.2 kg" }')
    s += '\n[dynamics]\ngravity = [0, 0, -9.81]\n'
    p = tmp_path / "rssr.toml"
    p.write_text(s, encoding="utf-8")
    code, out, err = _run(capsys, "forces", p, "--at", 30, "--csv", tmp_path / "r.csv", "--json")
    assert code == 0, err
    smp = _strict(out)["samples"][0]
    assert smp["dimension"] == 3 and all(len(j["reaction"]) == 3 for j in smp["joints"])
    head = next(csv.reader((tmp_path / "r.csv").open(encoding="utf-8")))
    assert "P1 Rz [N]" in head
    code, out, err = _run(capsys, "forces", p, "--steps", 36, "--json")
    s = _strict(out)
    # gravity alone is conservative: no net work over a turn
    assert code == 0 and s["mean"] == pytest.approx(0.0, abs=1e-9 * s["peak"])
    # the peak load of a joint is the largest reaction magnitude (3-vectors) over the turn
    plan = assur.compile(assur.load(p))
    fr = assur.forces(plan, None, np.linspace(0, 2 * math.pi, 36, endpoint=False)[:, None])
    k = fr.pair("P1")
    assert s["joint_peaks"][f"P1 ({fr.pair_bodies[k][0]}–{fr.pair_bodies[k][1]})"] == pytest.approx(
        np.max(np.linalg.norm(fr.reactions[:, k], axis=-1)), rel=1e-12)
