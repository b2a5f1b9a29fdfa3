"""``assur codesign``: a walking leg and its non-circular gear drive designed together, end to end.

The targets are measured on the written files by independent routes: ``assur analyze --json`` on the geared
mechanism (the engine through the gear pair read back from the gear design file, gait in motor time) for the
foot-speed spread, ezdxf for the DXF outlines, the gear module's own mesh check for the teeth."""
import json
from pathlib import Path

import numpy as np
import pytest

import assur
from assur.cli.main import main

EXAMPLES = Path(__file__).resolve().parents[1] / "examples"


def _run(capsys, *argv):
    code = main(list(map(str, argv)))
    out, err = capsys.readouterr()
    return code, out, err


@pytest.fixture(scope="module")
def bundle(tmp_path_factory):
    out = tmp_path_factory.mktemp("codesign") / "out"
    code = main(["codesign", str(EXAMPLES / "walker_fourbar.toml"), "-o", str(out), "--frames", "3",
                 "--mesh-steps", "90", "--json"])
    assert code == 0
    return out


@pytest.mark.slow
def test_the_geared_leg_moves_its_foot_at_constant_speed(bundle, capsys):
    summary = json.loads((bundle / "codesign.json").read_text())
    code, out, _ = _run(capsys, "analyze", bundle / summary["files"]["mechanism"], "--json")
    assert code == 0
    gait = json.loads(out)["gait"]
    assert gait["vx_spread"]["0.8"] <= 1e-6                 # the window: exact in motor time
    before = json.loads(_run(capsys, "analyze", EXAMPLES / "walker_fourbar.toml", "--json")[1])["gait"]
    assert before["vx_spread"]["0.8"] > 0.3                 # the plain leg (issue 15: 37 %)
    assert gait["vx_spread"]["0.9"] < before["vx_spread"]["0.9"] / 5


@pytest.mark.slow
def test_the_gears_pass_their_checks_and_the_outlines_open_in_cad(bundle):
    import ezdxf
    summary = json.loads((bundle / "codesign.json").read_text())
    assert summary["checks"]["ok"], summary["checks"]["violations"]
    assert min(summary["checks"]["convexity"].values()) >= 0
    assert summary["outlines"]["valid"] and not summary["outlines"]["interference"]
    for name in ("envelope_driving.dxf", "envelope_driven.dxf"):
        doc = ezdxf.readfile(bundle / "gears" / name)
        polylines = [e for e in doc.modelspace() if e.dxftype() in ("LWPOLYLINE", "POLYLINE")]
        assert polylines and all(p.closed or p.is_closed for p in polylines)
    for name in ("foot_speed.png", "animation.gif", "walker_fourbar_geared_gears.toml"):
        assert (bundle / name).stat().st_size > 0


@pytest.mark.slow
def test_the_written_mechanism_is_the_leg_with_a_motor_and_the_pair(bundle):
    m = assur.load(bundle / "walker_fourbar_geared.toml")
    plan = assur.compile(m)
    assert dict(plan.structure.pair_counts) == {"p5": 5, "p4": 1} and plan.structure.mobility == 1
    assert m.gears[0].b == "crank" and m.gears[0].mesh == "external"
    # the crank turns once per motor turn, in its own (counter-clockwise) sense
    s = assur.solve(plan, inputs=np.linspace(0, 2 * np.pi, 5))
    k = s.pos[:, plan.point_index("K")]
    np.testing.assert_allclose(k[0], k[-1], atol=1e-9)


def test_a_window_outside_the_stride_is_a_one_line_error(tmp_path, capsys):
    code, out, err = _run(capsys, "codesign", EXAMPLES / "walker_fourbar.toml", "-o", tmp_path / "o",
                          "--window", "1.5")
    assert code == 1 and "--window" in err and "Traceback" not in err
    assert not (tmp_path / "o").exists()


@pytest.mark.slow
def test_a_window_no_gear_pair_can_serve_writes_nothing(tmp_path, capsys):
    """At f = 0.99 the window's own pressure angle is far above 30° (window_pressure_bound), so no transfer helps."""
    code, out, err = _run(capsys, "codesign", EXAMPLES / "walker_fourbar.toml", "-o", tmp_path / "o",
                          "--window", "0.99", "--optimize", "none")
    assert code == 3 and "no feasible gear pair" in err and "pressure angle" in err
    assert not (tmp_path / "o").exists()


def test_a_mechanism_without_a_gait_is_refused(tmp_path, capsys):
    code, _, err = _run(capsys, "codesign", EXAMPLES / "crank_rocker.toml", "-o", tmp_path / "o")
    assert code == 1 and "gait" in err and not (tmp_path / "o").exists()


def _forces_peaks(plan, joint):
    """(peak |driver torque|, peak |reaction| at the pair named ``joint``) over one turn of the input (720
    samples), by assur.forces: independent of the summary's Study."""
    f = assur.forces(plan, inputs=np.linspace(0, 2 * np.pi, 720, endpoint=False))
    k = f.pair_names.index(joint)
    return np.max(np.abs(f.driver)), np.max(np.hypot(f.reactions[:, k, 0], f.reactions[:, k, 1]))


@pytest.mark.slow
def test_the_summary_gives_the_drives_cost_before_and_after(bundle):
    """Issue 25 C2: the peak and RMS motor torque and the peak bearing loads, the plain leg (a uniform crank) against
    the geared leg (a uniform motor), in codesign.json and on the summary page."""
    summary = json.loads((bundle / "codesign.json").read_text())
    drive = summary["drive"]
    plain = assur.compile(assur.load(EXAMPLES / "walker_fourbar.toml"))
    geared = assur.compile(assur.load(bundle / summary["files"]["mechanism"]))
    for key, plan in (("before", plain), ("after", geared)):
        torque, at_o = _forces_peaks(plan, "O")
        assert drive[key]["peak"] == pytest.approx(torque, rel=1e-9)
        assert drive[key]["joint_peaks"]["O (frame–crank)"] == pytest.approx(at_o, rel=1e-9)
        assert 0 < drive[key]["rms"] < drive[key]["peak"]
    assert drive["after"]["peak"] > 3 * drive["before"]["peak"]        # the cost issue 25 C2 measured
    assert "M (frame–motor)" in drive["after"]["joint_peaks"] and "M (frame–motor)" not in drive["before"]["joint_peaks"]
    page = (bundle / "index.html").read_text(encoding="utf-8")
    assert "peak motor torque" in page and f"{drive['after']['peak']:.4g}" in page
    assert 'alt="foot speed before and after" src="data:image/png;base64,' in page


def test_a_torque_limit_on_a_leg_without_masses_is_a_one_line_error(tmp_path, capsys):
    code, _, err = _run(capsys, "codesign", EXAMPLES / "klann.toml", "-o", tmp_path / "o", "--max-torque", "5")
    assert code == 1 and "--max-torque" in err and "no masses" in err and "Traceback" not in err
    assert not (tmp_path / "o").exists()


def test_a_torque_limit_nothing_meets_writes_nothing(tmp_path, capsys):
    code, _, err = _run(capsys, "codesign", EXAMPLES / "walker_fourbar.toml", "-o", tmp_path / "o",
                        "--optimize", "none", "--max-torque", "1")
    assert code == 3 and "motor torque reaches" in err and "> the limit 1 N·m" in err and "--max-torque" in err
    assert not (tmp_path / "o").exists()
