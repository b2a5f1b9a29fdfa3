"""The commands of cams, instant centres and sensitivities end to end: ``assur cam`` (text, JSON, figure, and the
DXF/SVG profile read back), ``assur sensitivity`` (ranking, JSON, bands, Monte Carlo, clearance, figures, refusals),
``assur analyze --at`` and ``assur plot --centres / --centrodes``; and the cam plate outline for ``assur make``."""
from __future__ import annotations

import io
import json
import xml.etree.ElementTree as ET
from contextlib import redirect_stderr, redirect_stdout

import numpy as np
import pytest

import assur
from assur.cams.followers import from_plan
from assur.cams.outline import plate_outline
from assur.cli.main import main
from conftest import EXAMPLES

PRESS = str(EXAMPLES / "cam_press.toml")
LEG = str(EXAMPLES / "walker_fourbar.toml")


def run(*argv):
    out, err = io.StringIO(), io.StringIO()
    with redirect_stdout(out), redirect_stderr(err):
        code = main(list(argv))
    return code, out.getvalue(), err.getvalue()


@pytest.mark.slow
def test_cam_text_json_and_figure(tmp_path):
    code, out, _ = run("cam", PRESS)
    assert code == 0 and "fundamental law of cam design holds" in out and "largest pressure angle" in out
    code, out, _ = run("cam", PRESS, "--json")
    s = json.loads(out)
    assert s["follower"]["motion"] == "oscillating" and s["law"]["fundamental_law"]
    prime = float(np.hypot(30.5, 39.62)) * 1e-3                 # the sketch's roller centre at the law's base
    assert s["profile"]["base_radius"] == pytest.approx(prime - 0.01, rel=1e-9)   # the prime circle − the roller
    assert 0 < s["smallest_base_radius"] < s["profile"]["base_radius"]
    code, out, _ = run("cam", PRESS, "-o", str(tmp_path / "cam.png"))
    assert code == 0 and (tmp_path / "cam.png").stat().st_size > 10_000


def test_profile_dxf_and_svg_read_back(tmp_path):
    import ezdxf
    plan = assur.compile(assur.load(PRESS))
    xy = plate_outline(plan, "lift")
    from shapely.geometry import Point, Polygon
    poly = Polygon(xy)
    assert poly.is_valid and poly.exterior.is_ccw and poly.contains(Point(0, 0))
    g = from_plan(plan, "lift")
    assert np.allclose(np.hypot(*xy.T).min(), g.summary()["base_radius"] * 1e3, rtol=1e-6)
    assert run("cam", PRESS, "-o", str(tmp_path / "lift.dxf"))[0] == 0
    doc = ezdxf.readfile(tmp_path / "lift.dxf")
    lw = [e for e in doc.modelspace() if e.dxftype() == "LWPOLYLINE" and e.dxf.layer == "LIFT"]
    assert len(lw) == 1 and lw[0].closed
    pts = np.array([p[:2] for p in lw[0].get_points()])
    assert np.max(np.abs(pts - xy)) <= 1e-9
    assert doc.header["$INSUNITS"] == 4
    assert run("cam", PRESS, "-o", str(tmp_path / "lift.svg"))[0] == 0
    root = ET.parse(tmp_path / "lift.svg").getroot()
    paths = root.findall(".//{http://www.w3.org/2000/svg}path")
    assert len(paths) == 2                                                       # the profile and its pitch curve


def test_cam_refusals(tmp_path):
    code, _, err = run("cam", LEG)
    assert code == 1 and err.startswith("error:") and "no [[cams]]" in err
    code, _, err = run("cam", PRESS, "--name", "nope")
    assert code == 1 and "unknown cam pair" in err


def test_sensitivity_ranking_and_json(tmp_path):
    code, out, _ = run("sensitivity", LEG, "--steps", "90")
    assert code == 0 and "gait.step" in out and "crank.length" in out
    code, out, _ = run("sensitivity", LEG, "--steps", "90", "--of", "H.y", "--of", "crank.effort", "--json",
                       "--it", "IT7", "--tolerance", "crank.length=0.0001")
    d = json.loads(out)
    assert set(d["outputs"]) == {"H.y", "crank.effort"}
    plan = assur.compile(assur.load(LEG))
    from assur.analysis.study import Study
    sens = Study(plan, steps=90).sensitivity
    want = np.max(np.abs(sens["H.y"].derivative[:, plan.param_index("crank.length")])) * 1e-4
    assert d["outputs"]["H.y"]["influence"]["crank.length"] == pytest.approx(want, rel=1e-12)
    rows = {r["parameter"]: r for r in d["tolerances"]}
    assert rows["crank.length"]["source"] == "given" and "IT7" in rows["rocker.length"]["source"]


@pytest.mark.slow
def test_sensitivity_band_monte_carlo_clearance_and_figures(tmp_path):
    out_png = tmp_path / "s.png"
    code, out, _ = run("sensitivity", LEG, "--steps", "60", "--band", "H", "--monte-carlo", "500",
                       "--clearance", "0.0002", "-o", str(out_png))
    assert code == 0 and "Monte Carlo: 500 designs" in out and "clearance at" in out
    for name in ("s.png", "s_band.png", "s_clearance.png"):
        assert (tmp_path / name).stat().st_size > 10_000


@pytest.mark.parametrize("argv,message", [
    (["--of", "nothing.here"], "unknown output"),
    (["--monte-carlo", "10"], "needs --band"),
    (["--band", "ZZ"], "unknown point"),
    (["--tolerance", "crank.length=abc"], "--tolerance"),
    (["--clearance", "x=1"], "unknown joint"),
])
def test_sensitivity_refusals(argv, message):
    code, _, err = run("sensitivity", LEG, "--steps", "32", *argv)
    assert code == 1 and err.startswith("error:") and message in err and "Traceback" not in err


def test_analyze_at_lists_every_centre():
    code, out, _ = run("analyze", str(EXAMPLES / "crank_rocker.toml"), "--json", "--at", "30", "--at", "200")
    d = json.loads(out)
    assert code == 0 and len(d["instant_centres"]) == 2 and len(d["instant_centres"][0]["centres"]) == 6
    assert d["instant_centres"][0]["kennedy_residual"] <= 1e-12
    code, out, _ = run("analyze", str(EXAMPLES / "crank_rocker.toml"), "--json")
    assert "instant_centres" not in json.loads(out)
    code, out, _ = run("analyze", PRESS, "--at", "45")
    assert "Instant centres at motor = 45 deg (10 centres of 5 bodies" in out


def test_plot_centres_and_centrodes(tmp_path):
    six = str(EXAMPLES / "stephenson3.toml")
    assert run("plot", six, "--centres", "--at", "60", "-o", str(tmp_path / "ic.png"))[0] == 0
    assert run("plot", str(EXAMPLES / "crank_rocker.toml"), "--centrodes", "coupler", "--at", "60", "-o",
               str(tmp_path / "c.png"))[0] == 0
    code, _, err = run("plot", six, "--centrodes", "nobody", "-o", str(tmp_path / "x.png"))
    assert code == 1 and "unknown body" in err
    code, _, err = run("plot", six, "--at", "60", "-o", str(tmp_path / "x.png"))
    assert code == 1 and "--centres" in err


@pytest.mark.slow
def test_report_shows_cams_and_centres(tmp_path):
    code, out, _ = run("report", PRESS, "-o", str(tmp_path / "r"), "--steps", "72", "--frames", "4", "--at", "30")
    html = (tmp_path / "r" / "index.html").read_text()
    assert code == 0 and "Cam pair lift" in html and "Instant centres" in html and "Kennedy" in html
