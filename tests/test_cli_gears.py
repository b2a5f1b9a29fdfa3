"""`assur gears` and `assur wheelstep` end to end on the paper-001 design files and on a small envelope design.

References, sections of docs/papers/001.md: §A4 (printed shoe numbers), §E Table 1 (printed radii; tolerance
0.006 from §B5), §B6.9 (the printed sector scheme interferes near the step boundary, driving angle |θ| ≈ 72–79° at
L_p, ±0.5°), the closure of rolling pitch curves (perimeter ratio = driving turns, §B2).
"""
import csv
import json
import math
from pathlib import Path

import numpy as np
import pytest

from assur.cli.main import main

ROOT = Path(__file__).resolve().parents[1]
GEARS = ROOT / "examples" / "gears_001.toml"
WHEELSTEP = ROOT / "examples" / "wheelstep_001.toml"

ENVELOPE = """format = "assur-gears/1"
name = "oval pair"
[units]
length = "mm"
angle = "deg"
[law]
kind = "ratio"
ratio = "1 + 0.2*cos(phi)"
[teeth]
method = "envelope"
module = 2
pressure_angle = 20
backlash = 0.1
driving_teeth = 30
driven_teeth = 30
"""


@pytest.fixture(scope="module")
def paper_gears(tmp_path_factory):
    out = tmp_path_factory.mktemp("gears") / "out"
    import contextlib
    import io
    buf = io.StringIO()
    with contextlib.redirect_stdout(buf):
        code = main(["gears", str(GEARS), "-o", str(out), "--mesh-steps", "24", "--json", "--frames", "0"])
    assert code == 0
    return out, json.loads(buf.getvalue())


def read_csv(path):
    with open(path, encoding="utf-8") as fh:
        rows = [r for r in csv.reader(fh) if r and not r[0].startswith("#")]
    return rows[0], np.array(rows[1:], dtype=float)


@pytest.mark.slow
def test_paper_gears_summary_and_tables(paper_gears):
    out, s = paper_gears
    assert s["closure"]["perimeter_ratio"] == pytest.approx(2.0, abs=1e-6)
    assert s["teeth"] == [48, 96] and s["envelope"]["teeth"] == [48, 96]
    # Table 1 as printed (§E), rows 1 and 12: θ_i, r_i, φ_i, r_Hi within 0.006 (§B5)
    head, t1 = read_csv(out / "table1.csv")
    assert head[:3] == ["i", "theta [deg]", "r [mm]"]
    assert t1[0, [1, 2, 6, 7]] == pytest.approx([-90.00, 61.30, -45.00, 82.20], abs=0.006)
    assert t1[11, [1, 2, 6, 7]] == pytest.approx([-8.49, 41.91, -3.50, 101.59], abs=0.006)
    data = json.loads((out / "table2.json").read_text(encoding="utf-8"))
    assert data["rows"][4][2:] == pytest.approx([-87.84, -86.36, 63.30], abs=0.006)   # Table 2, i = 1, j = 5


@pytest.mark.slow
def test_paper_sector_scheme_interferes_near_the_step_boundary(paper_gears):
    _, s = paper_gears
    m = s["sectors"]["mesh"]["143.5 mm"]
    assert m["interference"]
    ranges = m["fine_scan"]["interference_driving_ranges"]
    first = [float(x) for x in ranges.split("]")[0].strip("[").replace("°", "").split(",")]
    # inside the band 72–79° of B6.9 (±0.5°)
    assert 71.5 <= first[0] <= first[1] <= 79.5
    assert m["fine_scan"]["max_penetration"] > 0.01e-3
    # the envelope teeth (corners rounded) run without interference and follow their law within 3 %
    e = s["envelope"]["mesh"]
    assert not e["interference"] and e["max_ratio_deviation"] < 0.03
    assert s["envelope_rounding"]["max_speed_deviation"] > 0          # the rounding's price is reported


def crossings(xy, chunk=256):
    """Number of proper crossings between non-adjacent edges of the closed polygon xy (M, 2)."""
    a, b = xy, np.roll(xy, -1, axis=0)
    n, count = len(xy), 0

    def cross(p, q, r):
        return (q[..., 0] - p[..., 0]) * (r[..., 1] - p[..., 1]) - (q[..., 1] - p[..., 1]) * (r[..., 0] - p[..., 0])
    for i0 in range(0, n, chunk):
        A, B = a[i0:i0 + chunk, None], b[i0:i0 + chunk, None]
        hit = (cross(A, B, a[None]) * cross(A, B, b[None]) < 0) & (cross(a[None], b[None], A) * cross(a[None], b[None], B) < 0)
        i, j = np.nonzero(hit)
        d = np.abs(i + i0 - j)
        count += int(np.sum((d > 1) & (d < n - 1)))
    return count


@pytest.mark.slow
def test_paper_dxf_outlines_are_closed_and_match_the_csv(paper_gears):
    ezdxf = pytest.importorskip("ezdxf")
    out, _ = paper_gears
    for prefix in ("envelope", "sectors"):
        for gear in ("driving", "driven"):
            doc = ezdxf.readfile(out / f"{prefix}_{gear}.dxf")
            (poly,) = [e for e in doc.modelspace().query("LWPOLYLINE") if e.dxf.layer != "PITCH"]
            assert poly.closed
            pts = np.array([(p[0], p[1]) for p in poly.get_points("xy")])
            _, xy = read_csv(out / f"{prefix}_{gear}_outline.csv")
            assert pts.shape == xy.shape and np.max(np.abs(pts - xy)) < 1e-6
            # a whole gear in mm: the driving gear spans about ±63 mm, the driven about ±104 mm
            assert 40 < np.abs(pts).max() < 110
            if gear == "driving":          # one closed, non-self-intersecting polyline (B7.9)
                assert crossings(pts) == 0
        assert (out / f"teeth_{prefix}.png").stat().st_size > 20_000 and (out / f"speed_{prefix}.png").exists()
        svg = (out / f"{prefix}_pair.svg").read_text(encoding="utf-8")
        import xml.etree.ElementTree as ET
        assert len(ET.fromstring(svg).findall("{http://www.w3.org/2000/svg}path")) >= 2


@pytest.mark.slow
def test_wheelstep_budget_and_drive(tmp_path, capsys):
    out = tmp_path / "ws"
    assert main(["wheelstep", str(WHEELSTEP), "-o", str(out), "--mesh-steps", "12", "--frames", "3"]) == 0
    text = capsys.readouterr().out
    assert "X_01 = 0.8027 m" in text and "rolling share 25.25 %" in text
    b = json.loads((out / "budget.json").read_text(encoding="utf-8"))
    # §A4 printed values, half a unit of the last printed digit
    assert b["c"] == pytest.approx(0.36, abs=0.005)
    assert b["X_I"] == pytest.approx(0.6, abs=0.05)
    assert b["X_II"] == pytest.approx(0.2027, abs=0.00005)
    assert b["X_01"] == pytest.approx(0.8027, abs=0.00005)
    assert 100 * b["rolling_share"] == pytest.approx(25.25, abs=0.005)
    head, prof = read_csv(out / "shoe_profile.csv")
    i0 = np.argmin(np.abs(prof[:, 0]))
    assert prof[i0, 2] == pytest.approx(0.36)            # the profile passes (0, c) at φ = 0 (§A2)
    assert (out / "shoe.png").stat().st_size > 10_000
    assert (out / "gears" / "envelope_driving.dxf").exists() and (out / "gears" / "table1.csv").exists()
    page = (out / "gears" / "envelope_mesh.html").read_text(encoding="utf-8")     # the meshing animation
    assert page.count("data:image/png;base64,") >= 2


@pytest.mark.slow
def test_envelope_design(tmp_path, capsys):
    f = tmp_path / "oval.toml"
    f.write_text(ENVELOPE, encoding="utf-8")
    out = tmp_path / "oval"
    assert main(["gears", str(f), "-o", str(out), "--mesh-steps", "24", "--json", "--frames", "0"]) == 0
    s = json.loads(capsys.readouterr().out)
    assert "sectors" not in s and "envelope_rounding" not in s
    # module 2 mm and 30 teeth: the centre distance is chosen so the driving perimeter is π·m·z
    assert s["closure"]["driving_perimeter"] == pytest.approx(math.pi * 2e-3 * 30, rel=1e-3)
    assert s["envelope"]["module"] == pytest.approx(2e-3)
    e = s["envelope"]["mesh"]
    assert not e["interference"] and e["max_ratio_deviation"] < 0.01
    assert 0 < e["backlash_min"] < 0.3e-3


@pytest.mark.parametrize("change, message", [
    (('ratio = "1 + 0.2*cos(phi)"', 'ratio = "1.2*cos(phi)"'), r"law\.ratio.*> 0.*φ ∈ \["),
    (("[teeth]", "[pair]\ncentre_distance = 50\n[teeth]"), r"pair\.centre_distance.*cannot close the teeth"),
    (("driving_teeth = 30\ndriven_teeth = 30", "driving_teeth = 30\ndriven_teeth = 31"), r"teeth\.driven_teeth"),
    (("driving_teeth = 30\ndriven_teeth = 30", "driving_teeth = 8\ndriven_teeth = 8"),
     r"teeth\.module.*too large for the curvature.*body angle ∈ \["),
])
def test_bad_input_exits_1_and_writes_nothing(tmp_path, capsys, change, message):
    import re
    f = tmp_path / "bad.toml"
    f.write_text(ENVELOPE.replace(*change), encoding="utf-8")
    out = tmp_path / "sub" / "out"
    assert main(["gears", str(f), "-o", str(out)]) == 1
    err = capsys.readouterr().err
    assert err.startswith("error: ") and re.search(message, err), err
    assert not (tmp_path / "sub").exists()


def test_a_failure_midway_leaves_nothing(tmp_path, capsys, monkeypatch):
    f = tmp_path / "oval.toml"
    f.write_text(ENVELOPE, encoding="utf-8")
    import assur.gears.mesh as mesh
    from assur.gears.errors import GearError

    def broken(*a, **k):
        raise GearError("mesh check failed (test)")
    monkeypatch.setattr(mesh, "mesh_check", broken)
    out = tmp_path / "out"
    assert main(["gears", str(f), "-o", str(out)]) == 1
    assert "error: mesh check failed (test)" in capsys.readouterr().err
    assert list(tmp_path.iterdir()) == [f]                       # pitch tables and DXFs were written, then removed


def test_wrong_document_kind(tmp_path, capsys):
    assert main(["wheelstep", str(GEARS), "-o", str(tmp_path / "x")]) == 1
    assert "needs a assur-wheelstep/1 file" in capsys.readouterr().err
