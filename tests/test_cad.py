"""CAD and table outputs (assur.io.cad): DXF re-opened with ezdxf, SVG parsed with xml.etree, CSV/JSON read back."""
import csv
import json
import math
import xml.etree.ElementTree as ET

import numpy as np
import pytest

from assur.io.cad import Shape, write_dxf, write_svg, write_table

ezdxf = pytest.importorskip("ezdxf")


def star(n=40, r=0.03, c=(0.0, 0.0)):
    a = np.arange(n) * 2 * math.pi / n
    rr = r * (1 + 0.1 * np.cos(7 * a))
    return np.stack([c[0] + rr * np.cos(a), c[1] + rr * np.sin(a)], axis=-1)


def test_dxf_round_trip_closed_polylines_in_mm(tmp_path):
    a, b = star(), star(60, 0.05, (0.08, 0.0))
    path = write_dxf(tmp_path / "pair.dxf", [Shape("driving", a), Shape("driven", b, centre=(0.08, 0.0),
                                                                        references=(star(30, 0.05, (0.08, 0)),))],
                     metadata={"module_mm": 2.0, "teeth": 48})
    doc = ezdxf.readfile(path)
    assert doc.header["$INSUNITS"] == 4
    msp = doc.modelspace()
    polys = {e.dxf.layer: e for e in msp.query("LWPOLYLINE") if e.dxf.layer != "PITCH"}
    assert set(polys) == {"DRIVING", "DRIVEN"}
    for name, xy in (("DRIVING", a), ("DRIVEN", b)):
        e = polys[name]
        assert e.closed
        pts = np.array([(p[0], p[1]) for p in e.get_points("xy")])
        assert np.max(np.abs(pts - xy * 1e3)) < 1e-6                   # mm, to 1e-6 mm
    assert len(msp.query('LWPOLYLINE[layer=="PITCH"]')) == 1
    assert len(msp.query('LINE[layer=="CENTRE"]')) == 4                 # a cross per outline
    props = dict(doc.header.custom_vars)
    assert props["module_mm"] == "2.0" and props["teeth"] == "48"


def test_svg_is_xml_in_mm_with_closed_paths(tmp_path):
    a = star()
    path = write_svg(tmp_path / "g.svg", [Shape("driving", a)], metadata={"module_mm": 2.0})
    root = ET.parse(path).getroot()
    ns = {"s": "http://www.w3.org/2000/svg"}
    assert root.get("width").endswith("mm")
    vb = [float(v) for v in root.get("viewBox").split()]
    # view box = outline extent + 2·5 mm margin
    assert vb[2] == pytest.approx((a[:, 0].max() - a[:, 0].min()) * 1e3 + 10, abs=1e-4)
    (p,) = root.findall("s:path", ns)
    d = p.get("d")
    assert d.startswith("M ") and d.endswith(" Z")
    xs = [tuple(map(float, t.split(","))) for t in d[2:-2].split(" L ")]
    assert len(xs) == a.shape[0]
    # y is flipped: SVG y = top − y_mm
    x0, y0 = xs[0]
    assert x0 == pytest.approx(a[0, 0] * 1e3 - (a[:, 0].min() * 1e3 - 5), abs=1e-5)
    assert y0 == pytest.approx((a[:, 1].max() * 1e3 + 5) - a[0, 1] * 1e3, abs=1e-5)
    assert json.loads(root.find("s:metadata", ns).text) == {"module_mm": 2.0}


def test_tables_csv_and_json(tmp_path):
    head = ["i", "theta [deg]", "r [mm]"]
    rows = [[1, -90.0, 61.3], [2, -84.19, float("nan")]]
    c, j = write_table(tmp_path / "t", head, rows, meta={"title": "Table 1"})
    with open(c, encoding="utf-8") as fh:
        got = list(csv.reader(fh))
    assert got[0] == head and got[1] == ["1", "-90.0", "61.3"] and got[2][2] == "nan"
    data = json.loads(j.read_text(encoding="utf-8"))
    assert data["title"] == "Table 1" and data["columns"] == head and data["rows"][1] == [2, -84.19, None]


def test_bad_outline_writes_nothing(tmp_path):
    with pytest.raises(ValueError, match="outline 'x' must be a finite"):
        write_dxf(tmp_path / "bad.dxf", [Shape("x", np.array([[0.0, 0.0], [np.nan, 1.0], [1.0, 1.0]]))])
    assert list(tmp_path.iterdir()) == []


def test_bore_circle_on_its_own_layer_and_the_headers(tmp_path):
    from assur.io.cad import write_outline_csv
    a = star()
    path = write_dxf(tmp_path / "g.dxf", [Shape("driving", a, bore=8e-3)], metadata={"face_width_mm": 10.0})
    doc = ezdxf.readfile(path)
    (c,) = doc.modelspace().query('CIRCLE[layer=="BORE"]')
    assert c.dxf.radius == pytest.approx(4.0) and tuple(c.dxf.center)[:2] == (0.0, 0.0)     # 8 mm bore, mm
    assert dict(doc.header.custom_vars)["face_width_mm"] == "10.0"
    root = ET.parse(write_svg(tmp_path / "g.svg", [Shape("driving", a, bore=8e-3)])).getroot()
    (circle,) = [e for e in root.iter("{http://www.w3.org/2000/svg}circle") if e.get("class") == "bore"]
    assert float(circle.get("r")) == pytest.approx(4.0)
    csv_path = write_outline_csv(tmp_path / "g.csv", a, comments={"face width [mm]": 10.0, "bore [mm]": 8.0})
    lines = csv_path.read_text(encoding="utf-8").splitlines()
    assert lines[:3] == ["# face width [mm]: 10.0", "# bore [mm]: 8.0", "x [mm],y [mm]"]
    xy = np.array([[float(v) for v in ln.split(",")] for ln in lines[3:]])
    assert np.max(np.abs(xy - a * 1e3)) < 1e-9
