"""Layer L3: mechanism files — round-trips and the exact text of load errors.

Round-trip: ``assur.loads(assur.dumps(m)) == m`` for files in mm/deg, m/rad, cm, in, and for every
example; numbers are written back in the file's units. Errors: one SpecError lists every problem,
each as ``<location>: <message>`` (docs/format.md, "Errors"), and is a picklable ValueError.
"""
from __future__ import annotations

import glob
import math
import os
import pickle
import tomllib

import pytest
from hypothesis import given, settings, strategies as st

import assur
from conftest import rssr

EXAMPLES = sorted(f for f in glob.glob(os.path.join(os.path.dirname(__file__), "..", "examples", "*.toml"))
                  if tomllib.loads(open(f, encoding="utf-8").read()).get("format") == "assur/1")   # mechanisms only

# A complete file touching every section: points, plain and table links with a placed point, a pin in a
# slot and a translating link, an actuator, two drivers, a branch hint and a gait.
FULL = """
format = "assur/1"
name = "round-trip fixture"
description = "every section once"

[units]
length = "{length}"
angle = "{angle}"

[points]
O = [0, 0]
O1 = [{o1x}, 0]
A = [{ax}, {ay}]
B = [{bx}, {by}]
P = [{px}, {py}]
F = [0, {fy}]

[links]
frame = ["O", "O1", "F"]
crank = ["O", "A"]
rocker = ["O1", "B"]

[links.coupler]
points = ["A", "B", "P"]
length = {coupler}

[links.coupler.place.P]
from = "A"
toward = "B"
distance = {dist}
angle = {ang}

[[prismatic]]
name = "slot"
point = "P"
guide = "frame"
through = "F"
angle = {slot_angle}
offset = {offset}

[actuators.cyl]
between = ["F", "B"]

[[drivers]]
name = "crank"
kind = "rotary"
link = "crank"
pivot = "O"
arm = "A"
zero = {zero}
sense = "cw"
speed = "{speed}"

[branches]
B = {{ side = "left", of = ["A", "O1"] }}

[gait]
foot = "P"
ground = [1, 0]
phases = [0, {phase}]
"""

MM_DEG = dict(length="mm", angle="deg", o1x=1000, ax=300, ay=0, bx=900.5, by=800.25, px=600, py=-100.125,
              fy=-400, coupler=1000.0, dist=333.3, ang=70.8, slot_angle=12.5, offset=-7.25, zero=90,
              speed="27 rpm", phase=180)
M_RAD = dict(length="m", angle="rad", o1x=1.0, ax=0.3, ay=0.0, bx=0.9005, by=0.80025, px=0.6, py=-0.100125,
             fy=-0.4, coupler=1.0, dist=0.3333, ang=1.2356931104, slot_angle=0.2181661565, offset=-0.00725,
             zero=1.5707963267948966, speed="2.8274 rad/s", phase=3.141592653589793)


@pytest.mark.parametrize("values", [MM_DEG, M_RAD, dict(MM_DEG, length="cm"), dict(MM_DEG, length="in")],
                         ids=["mm-deg", "m-rad", "cm-deg", "in-deg"])
def test_round_trip_of_a_complete_file(values):
    m = assur.loads(FULL.format(**values))
    text = assur.dumps(m)
    assert assur.loads(text) == m
    assert assur.dumps(assur.loads(text)) == text                  # the writer is a fixed point
    # numbers come back in the file's units, equal to what the file said
    d = tomllib.loads(text)
    assert d["units"] == {"length": values["length"], "angle": values["angle"]}
    assert d["points"]["B"] == [values["bx"], values["by"]]
    assert d["links"]["coupler"]["length"] == values["coupler"]
    assert d["links"]["coupler"]["place"]["P"]["angle"] == values["ang"]
    assert d["prismatic"][0]["offset"] == values["offset"]
    assert d["gait"]["phases"] == [0, values["phase"]]


def test_values_are_si_inside():
    # independent: the file's numbers times the unit factors (mm = 1e-3 m, deg = π/180 rad, rpm = 2π/60 rad/s)
    m = assur.loads(FULL.format(**MM_DEG))
    assert m.sketch("B") == (900.5 * 1e-3, 800.25 * 1e-3)
    assert m.link("coupler").length == 1000.0 * 1e-3
    pl = m.link("coupler").placement("P")
    assert pl.distance == 333.3 * 1e-3 and pl.angle == 70.8 * (math.pi / 180)
    assert m.prismatic[0].offset == -7.25 * 1e-3
    assert m.drivers[0].speed == 27 * (2 * math.pi / 60) and m.drivers[0].sense == -1
    assert m.drivers[0].zero == 90 * (math.pi / 180)


@pytest.mark.parametrize("path", EXAMPLES, ids=[os.path.basename(p) for p in EXAMPLES])
def test_round_trip_of_every_example(path, tmp_path):
    m = assur.load(path)
    assert assur.loads(assur.dumps(m)) == m
    out = tmp_path / "copy.toml"
    assur.dump(m, out)
    assert assur.load(out) == m
    assert tomllib.loads(out.read_text())["units"] == {"length": m.units.length, "angle": m.units.angle}


def test_examples_exist():
    assert len(EXAMPLES) >= 5


_num = st.floats(-1e4, 1e4, allow_nan=False, allow_infinity=False)


@settings(max_examples=40, deadline=None)
@given(st.sampled_from([("mm", "deg"), ("m", "rad"), ("in", "deg"), ("cm", "rad"), ("ft", "deg")]),
       st.lists(_num, min_size=6, max_size=6), st.floats(0.001, 1e4), _num, _num)
def test_round_trip_of_random_numbers(units, xs, length, angle, offset):
    values = dict(MM_DEG, length=units[0], angle=units[1], ax=xs[0], ay=xs[1], bx=xs[2], by=xs[3],
                  px=xs[4], py=xs[5], coupler=length, ang=angle, slot_angle=angle / 3, offset=offset, zero=angle)
    m = assur.loads(FULL.format(**{k: (repr(v) if isinstance(v, float) else v) for k, v in values.items()}))
    assert assur.loads(assur.dumps(m)) == m


SPATIAL = rssr("mm", 100.0, driver=False)


def test_round_trip_of_a_spatial_description():
    m = assur.loads(SPATIAL)
    assert m.dimension == 3 and m.sketch("D0") == (100 * 1e-3, 0.0, 30 * 1e-3)
    text = assur.dumps(m)
    assert assur.loads(text) == m
    assert tomllib.loads(text)["joints"] == {"A": "spherical", "B": "spherical"}


def test_style_table_is_ignored():
    plain = FULL.format(**MM_DEG)
    styled = plain + '\n[style]\ncolor = "red"\n[style.points]\nA = { marker = "o" }\n'
    m = assur.loads(styled)
    assert m == assur.loads(plain)
    assert "style" not in tomllib.loads(assur.dumps(m))


# -- error messages ------------------------------------------------------------------------------------------------
BASE = """
format = "assur/1"
[units]
length = "{length}"
angle = "deg"
[points]
O1 = [0, 0]
A = [1, 0]
B = [2, 1]
[links]
{frame}
crank = ["O1", "A"]
coupler = {coupler}
rocker = ["O1", "B"]
[[drivers]]
name = "crank"
link = "crank"
pivot = "{pivot}"
arm = "{arm}"
sense = "{sense}"
speed = "{speed}"
"""
GOOD = dict(length="m", frame='frame = ["O1"]', coupler='["A", "B"]', pivot="O1", arm="A", sense="ccw",
            speed="27 rpm")


def problems(**changes):
    with pytest.raises(assur.SpecError) as info:
        assur.loads(BASE.format(**dict(GOOD, **changes)), source="mech.toml")
    return info.value


def test_the_fixture_is_valid():
    m = assur.loads(BASE.format(**GOOD))
    assert assur.compile(m).structure.mobility == 1


def test_documented_two_problem_message():
    # the example of docs/format.md, "Errors", verbatim
    e = problems(coupler='["A", "B", "Q"]', sense="clockwise")
    assert str(e) == ("mech.toml: 2 problems\n"
                      "  links.coupler[2]: unknown point 'Q' (known: A, B, O1)\n"
                      "  drivers[0].sense: must be 'ccw' or 'cw': 'clockwise'")
    assert e.problems == [("links.coupler[2]", "unknown point 'Q' (known: A, B, O1)"),
                          ("drivers[0].sense", "must be 'ccw' or 'cw': 'clockwise'")]
    assert e.source == "mech.toml"


def test_one_problem_is_one_line():
    e = problems(coupler='["A", "B", "Q"]')
    assert str(e) == "mech.toml: links.coupler[2]: unknown point 'Q' (known: A, B, O1)"


def test_bad_length_unit():
    e = problems(length="furlong")
    assert str(e) == "mech.toml: units.length: must be one of m, mm, cm, dm, km, in, ft: 'furlong'"


def test_missing_frame():
    e = problems(frame='base = ["O1"]')
    assert str(e) == "mech.toml: links: must include the ground link 'frame' (links: base, crank, coupler, rocker)"


def test_bad_speed_string():
    e = problems(speed="27 rpmm")
    assert str(e) == ("mech.toml: drivers[0].speed: must be '<number> <unit>' with unit one of "
                      "rad/s, deg/s, rpm, rev/s, 1/s, rev/min: '27 rpmm'")


def test_driver_pivot_not_on_the_frame():
    e = problems(pivot="A", arm="O1")
    assert str(e) == "mech.toml: drivers[0].pivot: must be a point of the frame (a crank turns about a fixed pivot): 'A'"


def test_every_problem_is_reported_in_file_order():
    e = problems(length="furlong", coupler='["A", "Q"]', speed="fast")
    assert str(e).splitlines() == [
        "mech.toml: 3 problems",
        "  units.length: must be one of m, mm, cm, dm, km, in, ft: 'furlong'",
        "  links.coupler[1]: unknown point 'Q' (known: A, B, O1)",
        "  drivers[0].speed: must be '<number> <unit>' with unit one of rad/s, deg/s, rpm, rev/s, 1/s, rev/min: 'fast'",
    ]


def test_invalid_toml():
    with pytest.raises(assur.SpecError) as info:
        assur.loads('format = "assur/1"\n[points\nA = [0, 0]\n', source="mech.toml")
    e = info.value
    # the message wraps tomllib's, which names the line and column
    assert str(e).startswith("mech.toml: not valid TOML: ")
    assert "line 2" in str(e)
    assert len(e.problems) == 1 and e.problems[0][0] == ""


def test_missing_file(tmp_path):
    path = tmp_path / "nope.toml"
    with pytest.raises(assur.SpecError) as info:
        assur.load(path)
    assert str(info.value) == f"no such file: {path}"


def test_load_names_the_file(tmp_path):
    path = tmp_path / "mech.toml"
    path.write_text(BASE.format(**dict(GOOD, sense="clockwise")), encoding="utf-8")
    with pytest.raises(assur.SpecError) as info:
        assur.load(path)
    assert str(info.value) == f"{path}: drivers[0].sense: must be 'ccw' or 'cw': 'clockwise'"


def test_spec_error_is_a_picklable_value_error():
    e = problems(coupler='["A", "B", "Q"]', sense="clockwise")
    assert isinstance(e, ValueError) and isinstance(e, assur.AssurError)
    e2 = pickle.loads(pickle.dumps(e))
    assert type(e2) is assur.SpecError
    assert str(e2) == str(e) and e2.problems == e.problems and e2.source == e.source
    # also a SpecError built from a single message
    s = assur.SpecError("plain message")
    assert str(pickle.loads(pickle.dumps(s))) == "plain message"


def test_a_wrong_format_version_is_reported():
    with pytest.raises(assur.SpecError) as info:
        assur.loads(BASE.format(**GOOD).replace('format = "assur/1"', 'format = "assur/2"'), source="mech.toml")
    assert str(info.value) == "mech.toml: format: must be 'assur/1': 'assur/2'"


def test_an_unknown_point_does_not_cascade():
    text = ('format = "assur/1"\n[points]\nO = [0, 0]\nA = [1, 0]\nB = [2, 0]\n'
            '[links]\nframe = ["O"]\ncrank = ["O", "A"]\ncoupler = ["A", "B", "Q"]\n')
    with pytest.raises(assur.SpecError) as info:
        assur.loads(text, source="mech.toml")
    # B is listed by the coupler; the only problem is the unknown Q
    assert str(info.value) == "mech.toml: links.coupler[2]: unknown point 'Q' (known: A, B, O)"


def test_an_invalid_link_does_not_cascade_into_its_driver():
    """A driver on a link that has its own problem reports only the link's problem."""
    text = """
format = "assur/1"
[points]
A = [0, 0]
B = [1, 0]
O1 = [0.5, 0.5]
[links]
frame = ["A", "O1"]
coupler = ["A", "B", "Q"]
[[drivers]]
name = "c"
link = "coupler"
pivot = "A"
"""
    with pytest.raises(assur.SpecError) as err:
        assur.loads(text)
    assert err.value.problems == [("links.coupler[2]", "unknown point 'Q' (known: A, B, O1)")]


def test_dump_writes_atomically_or_not_at_all(tmp_path):
    """dump() writes through a temporary file: no leftovers; an unusable location is an OutputError (an
    OSError) that leaves nothing behind."""
    from assur.errors import OutputError
    m = assur.load(EXAMPLES[0])
    out = tmp_path / "copy.toml"
    assur.dump(m, out)
    assert [p.name for p in tmp_path.iterdir()] == ["copy.toml"]
    with pytest.raises(OutputError):
        assur.dump(m, tmp_path / "missing" / "copy.toml")
    with pytest.raises(OSError):
        assur.dump(m, tmp_path)
    assert [p.name for p in tmp_path.iterdir()] == ["copy.toml"]


@pytest.mark.parametrize("value", ["[0, 0, 1]", "{ a = 1 }", "3"])
def test_a_joint_that_is_not_a_kind_is_a_located_error(value):
    """``[joints] A0 = [0, 0, 1]`` (an axis where a kind belongs) once ended in a TypeError (unhashable list)."""
    text = rssr().replace('A = "spherical"', f'A = "spherical"\nA0 = {value}')
    with pytest.raises(assur.SpecError) as info:
        assur.loads(text)
    msg = dict(info.value.problems)["joints.A0"]
    assert "must be one of" in msg and "revolute" in msg
    if value.startswith("[0"):
        assert 'axis = [x, y, z]' in msg        # where an axis goes


@pytest.mark.parametrize("points", ['[["O"], "A"]', '[{ a = 1 }, "A"]'])
def test_link_points_that_are_not_names_are_a_located_error(points):
    path = os.path.join(os.path.dirname(__file__), "..", "examples", "chebyshev_lambda.toml")
    with open(path, encoding="utf-8") as f:
        text = f.read()
    assert '[links.crank]\npoints = ["O", "B"]' in text
    text = text.replace('[links.crank]\npoints = ["O", "B"]', f"[links.crank]\npoints = {points}")
    with pytest.raises(assur.SpecError) as info:
        assur.loads(text)
    assert "links.crank.points[0]" in dict(info.value.problems)


@pytest.mark.parametrize("name, edit, where", [
    ("walker_fourbar.toml", lambda d: d["branches"]["L"].__setitem__("of", [["K"], "O1"]), "branches.L.of"),
    ("walker_fourbar.toml", lambda d: d["branches"]["L"].__setitem__("of", [{"a": 1}, "O1"]), "branches.L.of"),
    ("walker_fourbar.toml", lambda d: d["gait"].__setitem__("foot", ["H"]), "gait.foot"),
    ("walker_fourbar.toml", lambda d: d["gait"].__setitem__("foot", {"a": 1}), "gait.foot"),
    ("walker_fourbar_geared.toml", lambda d: d["gears"][0].__setitem__("mesh", ["external"]), "gears[0].mesh"),
    ("cam_press.toml", lambda d: d["cams"][0]["law"][1].__setitem__("motion", ["dwell"]), "cams[0].law[1].motion"),
])
def test_a_list_or_table_where_a_name_belongs_is_a_located_error(name, edit, where):
    """A list or a table where a point name or a keyword belongs once ended in a TypeError (unhashable) raised
    from the reader; it is one located problem like any other unknown name."""
    from assur.io.mechanism_file import from_dict
    from assur.io.toml_reader import read_toml
    path = os.path.join(os.path.dirname(__file__), "..", "examples", name)
    doc = read_toml(path)
    edit(doc)
    with pytest.raises(assur.SpecError) as info:
        from_dict(doc, source=path)
    assert [p for p, _ in info.value.problems] == [where]
