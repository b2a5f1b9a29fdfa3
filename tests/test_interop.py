"""assur.interop: reading and writing pylinkage, PMKS+, Pyslvs and four-bar-rs designs (docs/interop.md).

Round trips assur → format → assur must give the same description (assur.interop.compare) on every shipped example
the format can represent; every other example is refused with a located error. The peers' own files (fixtures in
tests/crosscheck/data, each naming its source) are read; bad and foreign input gets one located SpecError.
"""
import json
import math
import os
import warnings
from pathlib import Path

import pytest

import assur
from assur.errors import AssurError, SpecError
from assur.interop import EXPORTERS, detect_format, draft_of, export_mechanism, import_mechanism
from assur.interop import pmks_codec as codec
from assur.interop.compare import differences
from assur.interop.draft import InteropWarning

ROOT = Path(__file__).resolve().parents[1]
DATA = ROOT / "tests" / "crosscheck" / "data"
EXAMPLES = sorted(p for p in (ROOT / "examples").glob("*.toml") if 'format = "assur/1"' in p.read_text(encoding="utf-8"))

#: what each format cannot hold, by example: the located error expected instead of a round trip
REFUSED = {
    "lever_manipulator.toml": "actuators.drive_rod",
    "rssr.toml": "dimension", "rssr_tilted.toml": "dimension",
    "walker_fourbar_geared.toml": "gears",
    "cam_press.toml": "cams",
}
REFUSED_BY = {
    "pylinkage": {"walker_sixbar_beta1_60.toml": "links.crank"},
    "pmks": {"walker_fourbar_adjustable.toml": "drivers"},
    "pyslvs": {},
    "fourbar": {n: "links" for n in ("classiv_sixbar.toml", "jansen.toml", "klann.toml", "stephenson3.toml", "triad_sixbar.toml",
                                      "walker_sixbar.toml", "walker_sixbar_beta1_60.toml", "watt2.toml")}
               | {"slider_crank.toml": "prismatic", "slider_crank_motor.toml": "prismatic",
                  "walker_crank_slider.toml": "prismatic",
                  "walker_fourbar_adjustable.toml": "drivers"},
}


def quiet(fn, *args, **kw):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return fn(*args, **kw)


@pytest.mark.parametrize("fmt", list(EXPORTERS))
@pytest.mark.parametrize("path", EXAMPLES, ids=lambda p: p.name)
def test_round_trip_gives_the_same_description(path, fmt, tmp_path):
    m = quiet(assur.load, path)
    out = tmp_path / f"out{EXPORTERS[fmt][1]}"
    expected = REFUSED.get(path.name) or REFUSED_BY[fmt].get(path.name)
    if expected:
        with pytest.raises(SpecError) as err:
            quiet(export_mechanism, m, fmt, out)
        assert err.value.problems[0][0] == expected
        assert not out.exists()                       # nothing half written
        return
    quiet(export_mechanism, m, fmt, out)
    back = quiet(import_mechanism, out)               # the format told from the file
    if fmt == "pmks":
        # a PMKS+ link holds thousandths of its length unit (cm or inch) and whole rpm: every point within half a
        # step of its assembled place, and so the same mechanism to that resolution (amplified by the linkage)
        from assur.interop.common import assembled
        from assur.io.units import LENGTH
        step = 0.001 * (0.0254 if back.units.length == "in" else 0.01)
        a, b = assembled(m), assembled(back)
        for n in m.point_names:
            assert max(abs(u * LENGTH[m.units.length] - v * LENGTH[back.units.length])
                       for u, v in zip(a[n], b[n])) <= step / 2 * (1 + 1e-9)
        assert differences(m, back, tol=1e-3, speeds=False, samples=24) == []
        rpm = m.drivers[0].speed / (2 * math.pi / 60)
        assert back.drivers[0].speed == pytest.approx(max(round(rpm), 0) * 2 * math.pi / 60, rel=1e-12)
        # no name in a link; its length units are inch, cm and m
        assert back.units.length == ("in" if m.units.length in ("in", "ft") else "cm")
    else:
        assert differences(m, back, samples=24) == []
        assert back.name == m.name and back.units.length == m.units.length


def test_differences_notices_a_changed_mechanism():
    """The round-trip check can fail: a longer crank, another assembly, another speed are each reported."""
    m = quiet(assur.load, ROOT / "examples" / "crank_rocker.toml")
    text = assur.dumps(m)
    assert differences(m, assur.loads(text.replace("length = 40", "length = 41"))) != []
    assert differences(m, assur.loads(text + '\n[branches.B]\nside = "right"\nof = ["A", "O4"]\n')) != []
    assert differences(m, assur.loads(text.replace('speed = "60 rpm"', 'speed = "61 rpm"'))) != []
    assert differences(m, assur.loads(text)) == []


# -- pylinkage -----------------------------------------------------------------------------------------------------
def test_pylinkage_json_joint_kinds():
    """A Mechanism JSON with every joint kind (ground, revolute, prismatic, tracker) and link kind."""
    doc = {"name": "kinds", "joints": [
        {"id": "O", "type": "ground", "position": [0, 0]},
        {"id": "A", "type": "revolute", "position": [1, 0]},
        {"id": "S", "type": "prismatic", "position": [3.0, 0.0], "axis": [1, 0], "line_point": [0, 0]},
        {"id": "T", "type": "tracker", "position": [0, 0], "ref_joint1_id": "A", "ref_joint2_id": "S",
         "distance": 1.0, "angle": math.pi / 2}],
        "links": [{"id": "ground", "type": "ground", "joints": ["O"]},
                  {"id": "crank", "type": "arc_driver", "joints": ["O", "A"], "motor_joint": "O",
                   "angular_velocity": 0.5, "arc_start": 0.0, "arc_end": 1.0, "initial_angle": 0.0},
                  {"id": "rod", "type": "link", "joints": ["A", "S"]}]}
    with pytest.warns(InteropWarning, match="arc_driver 'crank' oscillates"):
        m = import_mechanism(doc)
    assert m.sketch("T") == pytest.approx((1.0, 1.0))             # 1 from A, 90° from A → S
    assert m.link("rod").points == ("A", "S", "T")                 # the tracker rides the rod
    assert m.prismatic[0].point == "S" and m.drivers[0].speed == pytest.approx(0.5)


def test_pylinkage_legacy_joints_are_assembled_as_pylinkage_builds_them():
    """pylinkage < 1.0 ``Linkage.to_dict``: x, y only guess the assembly (nearest intersection)."""
    doc = {"name": "legacy four-bar", "joints": [
        {"type": "Static", "name": "A", "x": 0, "y": 0},
        {"type": "Crank", "name": "B", "x": 0, "y": 1, "joint0": {"ref": "A"}, "distance": 1, "angle": 0.31},
        {"type": "Revolute", "name": "C", "x": 3, "y": 2, "joint0": {"ref": "B"},
         "joint1": {"inline": True, "type": "Static", "x": 3, "y": 0, "name": "D"}, "distance0": 3, "distance1": 1},
        {"type": "Fixed", "name": "P", "joint0": {"ref": "B"}, "joint1": {"ref": "C"}, "distance": 1, "angle": 0.5},
        {"type": "Linear", "name": "S", "x": 5, "y": 0, "joint0": {"ref": "C"},
         "joint1": {"ref": "A"}, "joint2": {"inline": True, "type": "Static", "x": 1, "y": 0, "name": "E"},
         "revolute_radius": 2.5}]}
    m = quiet(import_mechanism, doc)
    B, C, P = (complex(*m.sketch(n)) for n in "BCP")
    assert B == pytest.approx(1j)                                   # the crank keeps its drawn direction
    assert abs(C - B) == pytest.approx(3) and abs(C - 3) == pytest.approx(1) and C.imag > 0
    assert P == pytest.approx(B + (C - B) / abs(C - B) * complex(math.cos(0.5), math.sin(0.5)))
    assert m.link("B_C").points == ("B", "C", "P")
    assert m.drivers[0].speed == pytest.approx(0.31)
    S = complex(*m.sketch("S"))
    assert S.imag == pytest.approx(0) and abs(S - C) == pytest.approx(2.5) and S.real > C.real   # nearest (5, 0)
    assert m.prismatic[0].point == "S" and m.prismatic[0].guide == "frame"


def test_pylinkage_hypergraph_document_goes_through_pylinkage():
    pytest.importorskip("pylinkage")
    from pylinkage.actuators import Crank
    from pylinkage.components import Ground
    from pylinkage.dyads import RRRDyad
    from pylinkage.hypergraph.serialization import graph_to_dict
    from pylinkage.simulation import Linkage
    a, d = Ground(0.0, 0.0, name="A"), Ground(4.0, 0.0, name="D")
    crank = Crank(anchor=a, radius=1.0, angular_velocity=0.1, initial_angle=1.0, name="B")
    lk = Linkage([a, d, crank, RRRDyad(crank.output, d, 3.0, 3.0, name="C")], name="hg")
    graph, dims = lk.to_hypergraph()
    m = quiet(import_mechanism, json.loads(json.dumps({"graph": graph_to_dict(graph), "dimensions": dims.to_dict()})))
    assert sorted(m.point_names) == ["A", "B", "C", "D"]
    assert math.dist(m.sketch("B"), m.sketch("C")) == pytest.approx(3.0)


def test_reading_a_hypergraph_file_leaves_the_compiled_kernels_usable(tmp_path):
    """Reading it imports pylinkage, whose numba code fixes numba's target: assur sets its own first
    (kernels/numba_target.py), so the compiled kernels stay in use in that process, on any host."""
    pytest.importorskip("pylinkage")
    pytest.importorskip("numba")
    import subprocess
    import sys
    from pylinkage.actuators import Crank
    from pylinkage.components import Ground
    from pylinkage.dyads import RRRDyad
    from pylinkage.hypergraph.serialization import graph_to_dict
    from pylinkage.simulation import Linkage
    a, d = Ground(0.0, 0.0, name="A"), Ground(4.0, 0.0, name="D")
    crank = Crank(anchor=a, radius=1.0, angular_velocity=0.1, initial_angle=1.0, name="B")
    graph, dims = Linkage([a, d, crank, RRRDyad(crank.output, d, 3.0, 3.0, name="C")], name="hg").to_hypergraph()
    path = tmp_path / "hg.json"
    path.write_text(json.dumps({"graph": graph_to_dict(graph), "dimensions": dims.to_dict()}), encoding="utf-8")
    code = ("import sys, warnings; warnings.simplefilter('ignore'); from assur.interop import import_mechanism; "
            "m = import_mechanism(sys.argv[1]); from assur.kernels import codegen; "
            "print(sorted(m.point_names), 'pylinkage' in sys.modules, codegen.available())")
    env = {k: v for k, v in os.environ.items() if not k.startswith("NUMBA_CPU")}    # as a user's process starts
    out = subprocess.run([sys.executable, "-c", code, str(path)], capture_output=True, encoding="utf-8", check=True,
                         env=env)
    assert out.stdout.split("] ")[1].split() == ["True", "True"]


def test_pylinkage_refuses_what_it_cannot_place():
    pytest.importorskip("pylinkage")
    from pylinkage.actuators import Crank, LinearActuator
    from pylinkage.components import Ground
    from pylinkage.simulation import Linkage
    a = Ground(0.0, 0.0, name="A")
    lk = Linkage([a, Crank(anchor=a, radius=1.0, name="B"),
                  LinearActuator(anchor=Ground(2.0, 0.0, name="G"), angle=0.0, stroke=1.0, name="L")])
    with pytest.raises(SpecError, match="LinearActuator 'L'.*not representable"):
        import_mechanism(lk)
    bad = {"joints": [{"id": "O", "type": "hinge", "position": [0, 0]}], "links": []}
    with pytest.raises(SpecError, match=r"joints\[0\].type: unknown joint kind 'hinge'"):
        import_mechanism(bad)


# -- PMKS+ ---------------------------------------------------------------------------------------------------------
def fixture_links():
    out = []
    for line in (DATA / "pmks_fixture_urls.tsv").read_text(encoding="utf-8").splitlines():
        if line.strip() and not line.startswith("#"):
            out.append(line.split("\t"))
    return out


#: the gallery links that assur refuses, with why (a located error each)
PMKS_REFUSED = {"Elliptical trammel": "no point fixed to the ground", "Elliptical trammel, driven": "driven slider",
                "Screw jack": "driven slider"}


def _gallery_params():
    return [pytest.param(name, gallery, link, id=f"{name}-{gallery}") for name, gallery, link in fixture_links()]


@pytest.mark.parametrize("name,gallery,link", _gallery_params())
def test_pmks_gallery_links_are_read(name, gallery, link):
    """Every link of PMKS+'s verification galleries (production and current encodings) is read, or refused for a
    stated reason; a read one compiles and solves a turn."""
    if name in PMKS_REFUSED:
        with pytest.raises(SpecError, match=PMKS_REFUSED[name]):
            quiet(import_mechanism, link)
        return
    m = quiet(import_mechanism, link)
    plan = assur.compile(m)
    st = assur.solve(plan, inputs=plan.sketch_inputs, order=0)
    assert st.valid.all()


def test_pmks_numbers_and_checks():
    for v in (0, 1, 63, 64, 1520, -1000, -1, 10 ** 9):
        assert codec.to_int(codec.from_int(v), "x") == v
    assert codec.to_decimal("Nm", "x") == 1.52 and codec.to_decimal("0RF", "x") == -1.743
    assert codec.unpack_flags(codec.pack_flags([True, False, True, False, True, True]), 6, "x") == \
        [True, False, True, False, True, True]
    link = dict(((n, g), u) for n, g, u in fixture_links())[("Slider-crank whose rod comes square to the guide",
                                                              "current")]
    body = codec.unwrap(link)                                    # digest and length check both pass
    assert link.endswith("*" + codec.digest(body + codec.checksum(body)))


@pytest.mark.parametrize("damage,message", [
    (lambda u: u[:-20], "truncated or damaged"),                 # the digest's mark is cut: the length check fails
    (lambda u: u[:-7] + "N" + u[-7:], "damaged"),                # one more character before the digest
    (lambda u: u.replace("0.0B", "0.1B", 1), "digest does not match"),
    (lambda u: u.split("?")[0] + "?", "empty or truncated"),
    (lambda u: "pmks2:0000.abc", "native document"),
])
def test_pmks_damaged_links_are_refused(damage, message):
    link = fixture_links()[10][2]
    with pytest.raises(SpecError, match=message):
        import_mechanism(damage(link), format="pmks")


def test_pmks_share_link_opens_the_same_mechanism():
    m = quiet(assur.load, ROOT / "examples" / "jansen.toml")
    from assur.interop.pmks import share_link
    link = quiet(share_link, m)
    assert link.startswith("https://app.pmksplus.com/?")
    back = quiet(import_mechanism, link)
    assert differences(m, back, tol=2e-5, speeds=False) == []


# -- Pyslvs, four-bar-rs ------------------------------------------------------------------------------------------
def test_pyslvs_examples_are_read():
    import yaml
    examples = yaml.safe_load((DATA / "pyslvs" / "examples.yaml").read_text(encoding="utf-8"))
    for name, project in examples.items():
        text = yaml.safe_dump(project)
        if name == "Slider lifter":     # its input drives a slider along the ground
            with pytest.raises(SpecError, match="slider input"):
                import_mechanism(text, format="pyslvs")
            continue
        m = quiet(import_mechanism, text)
        plan = assur.compile(m)
        assert assur.solve(plan, inputs=plan.sketch_inputs, order=0).valid.all(), name


def test_pyslvs_expression_alone_takes_the_first_grounded_crank():
    expr = ("M[J[R, color[Green], P[0.0, 0.0], L[ground, L1]], J[R, P[12.92, 32.53], L[L1, L2]], "
            "J[R, P[73.28, 67.97], L[L2, L3]], J[R, P[90.0, 0.0], L[ground, L3]]]")
    assert detect_format(expr) == "pyslvs"
    with pytest.warns(InteropWarning, match="P0 → P1 is taken as the crank"):
        m = import_mechanism(expr)
    assert (m.drivers[0].pivot, m.drivers[0].arm) == ("P0", "P1")
    with pytest.raises(SpecError, match=r"unknown joint type 'Q'"):
        import_mechanism(expr.replace("J[R, P[90.0", "J[Q, P[90.0"))


def test_fourbar_files_are_read_and_spherical_ones_refused():
    for path in sorted((DATA / "fourbar").glob("*.ron")):
        text = path.read_text(encoding="utf-8")
        if path.name.startswith("sfb"):
            with pytest.raises(SpecError, match="spherical four-bar"):
                import_mechanism(text)
            continue
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            m = import_mechanism(text)
        if path.name.startswith("mfb"):
            assert any("motion four-bar" in str(w.message) for w in caught)
        assert sorted(m.point_names) == ["P1", "P2", "P3", "P4", "P5"]
    with pytest.raises(SpecError, match="stat: must be one of"):
        import_mechanism("(p1x: 0, p1y: 0, a: 0, l1: 9, l2: 3, l3: 7, l4: 7, l5: 4, g: 0.5, stat: c9b9)")


# -- detection and foreign input ------------------------------------------------------------------------------------
@pytest.mark.parametrize("text,message", [
    ('{"type": "FeatureCollection", "features": []}', "JSON document that is not a pylinkage mechanism"),
    ('format = "assur/1"\n[points]\n', "already an assur/1 mechanism file"),
    ("hello world", "cannot tell the format"),
    ("M[J[R, P[0, 0], L[ground, L1]", "expected"),
    ("(p1x: 0, p1y: (1, 2))", "nested value"),
    ('{"joints": [{"id": "O", "type": "ground", "position": [0, "x"]}], "links": []}', r"position\[1\]"),
])
def test_foreign_or_broken_input_gets_one_located_error(text, message):
    with pytest.raises(SpecError, match=message):
        import_mechanism(text)


def test_a_huge_document_is_refused_before_it_is_parsed(tmp_path):
    big = tmp_path / "big.json"
    big.write_bytes(b'{"joints": [' + b" " * (17 * 2 ** 20) + b"]}")
    with pytest.raises(SpecError, match="larger than 16 MiB"):
        import_mechanism(big)
    many = {"joints": [{"id": f"J{i}", "type": "ground", "position": [i, 0]} for i in range(3000)], "links": []}
    with pytest.raises(SpecError, match="at most 2000"):
        import_mechanism(many)


def test_names_are_carried_over_or_renamed_with_a_warning():
    doc = {"name": "n", "joints": [{"id": "crank anchor", "type": "ground", "position": [0, 0]},
                                    {"id": "D", "type": "ground", "position": [4, 0]},
                                    {"id": "B", "type": "revolute", "position": [1, 0]},
                                    {"id": "C", "type": "revolute", "position": [2.5, 2.6]}],
           "links": [{"id": "ground", "type": "ground", "joints": ["crank anchor", "D"]},
                     {"id": "frame", "type": "driver", "joints": ["crank anchor", "B"], "motor_joint": "crank anchor",
                      "angular_velocity": -0.1},
                     {"id": "BC", "type": "link", "joints": ["B", "C"]}, {"id": "CD", "type": "link",
                                                                            "joints": ["C", "D"]}]}
    with pytest.warns(InteropWarning) as caught:
        m = import_mechanism(doc)
    messages = " ".join(str(w.message) for w in caught)
    assert "'crank anchor' is named 'crank_anchor'" in messages and "'frame' is named 'frame_'" in messages
    d = m.drivers[0]
    assert (d.link, d.pivot, d.sense, d.speed) == ("frame_", "crank_anchor", -1, pytest.approx(0.1))
    assert draft_of(doc).names()[0]["crank anchor"] == "crank_anchor"


def test_import_keeps_the_sources_assembly():
    """The sketch is the source's assembly and each dyad gets a [branches] hint from it: the other assembly of the
    same links imports to the other branch."""
    doc = {"name": "n", "joints": [{"id": "A", "type": "ground", "position": [0, 0]},
                                    {"id": "D", "type": "ground", "position": [4, 0]},
                                    {"id": "B", "type": "revolute", "position": [1, 0]},
                                    {"id": "C", "type": "revolute", "position": [2.5, 2.598076211353316]}],
           "links": [{"id": "ground", "type": "ground", "joints": ["A", "D"]},
                     {"id": "crank", "type": "driver", "joints": ["A", "B"], "motor_joint": "A"},
                     {"id": "BC", "type": "link", "joints": ["B", "C"]}, {"id": "CD", "type": "link",
                                                                            "joints": ["C", "D"]}]}
    up = quiet(import_mechanism, doc)
    doc["joints"][3]["position"] = [2.5, -2.598076211353316]
    down = quiet(import_mechanism, doc)
    assert [b.point for b in up.branches] == ["C"] and [b.point for b in down.branches] == ["C"]
    assert up.branches[0].of == down.branches[0].of and up.branches[0].side != down.branches[0].side
    assert differences(up, down) != []
    for m, sign in ((up, 1), (down, -1)):
        plan = assur.compile(m)
        st = assur.solve(plan, inputs=[0.3, 1.0, 2.0], order=0)
        assert (sign * st.pos[:, plan.point_index("C"), 1] > 0).all()


def test_errors_are_assur_errors():
    for bad in ("", "https://app.pmksplus.com/?", "(", "M[", "{}", b"\xff\xfe", 42):
        with pytest.raises(AssurError):
            import_mechanism(bad)
