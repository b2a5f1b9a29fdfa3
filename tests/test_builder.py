"""assur.Builder: a mechanism described in Python gives the same plan as the equivalent mechanism file."""
import dataclasses

import numpy as np
import pytest

import assur


def walker_fourbar():
    """examples/walker_fourbar.toml, call by call (its tables in the same order)."""
    return (assur.Builder(units="m", angle="deg")
            .point("O", 0.0, 0.0).point("O1", 0.567, 0.615).point("K", 0.27, 0.0)
            .point("L", 0.915023163371, 0.0802814967134).point("H", 0.77787367222, -0.559176099283)
            .frame("O", "O1")
            .link("crank", "O", "K", length=0.27)
            .link("rocker", "O1", "L", length=0.638)
            .link("coupler", "K", "L", "H", length=0.65)
            .place("coupler", "H", origin="L", toward="K", distance=0.654, angle=70.8)
            .crank("crank", pivot="O", arm="K", zero=0, sense="ccw", speed="27 rpm", name="crank")
            .branch("L", "right", of=("K", "O1"))
            .gait("H", ground=[1, 0], up=[0, 1], phases=[0, 180], weight="300 N")
            .mass("crank", "0.6358 kg", com="mid").mass("rocker", "1.5025 kg", com="mid")
            .mass("coupler", "3.0709 kg", com=[0.719869, -0.100082], inertia="0.21831 kg*m^2")
            .dynamics(gravity=(0, -9.81)))


def slider_crank():
    """examples/slider_crank.toml (mm, a pin in a slot), with numpy numbers for the coordinates."""
    return (assur.Builder(units="mm")
            .point("O", 0, 0).point("A", np.float64(25), 43.3012701892).point("B", 173.179117313, np.int64(20))
            .frame("O").link("crank", "O", "A", length=50).link("rod", "A", "B", length=150)
            .slider(name="slot", point="B", guide="frame", through="O", angle=0, offset=20)
            .crank("crank", name="crank", pivot="O", arm="A", zero=0, sense="ccw", speed="3000 rpm"))


@pytest.mark.parametrize("build, path", [(walker_fourbar, "examples/walker_fourbar.toml"),
                                         (slider_crank, "examples/slider_crank.toml")])
def test_builder_gives_the_file_plan(build, path):
    from_file = assur.load(path)
    built = build().build()
    # the same description (the file adds only its name and description)
    assert built == dataclasses.replace(from_file, name="", description="")
    p_file, p_built = assur.compile(from_file), assur.compile(built)
    assert p_built.param_names == p_file.param_names
    np.testing.assert_array_equal(p_built.defaults, p_file.defaults)
    q = np.linspace(0, 2 * np.pi, 73)
    s_file, s_built = assur.solve(p_file, inputs=q), assur.solve(p_built, inputs=q)
    np.testing.assert_array_equal(s_built.pos, s_file.pos)
    np.testing.assert_array_equal(s_built.acc, s_file.acc)


def test_builder_dict_is_the_toml_document():
    from assur.io.toml_reader import parse_toml
    text = open("examples/slider_crank.toml", encoding="utf-8").read()
    doc = parse_toml(text, "slider_crank.toml")
    doc.pop("name"), doc.pop("description")
    assert slider_crank().to_dict() == doc


def test_builder_reports_problems_like_a_file():
    bad_toml = """
format = "assur/1"
[units]
length = "mm"
angle = "deg"
[points]
O = [0, 0]
A = [30, 0]
[links]
frame = ["O"]
crank = ["O", "Q"]
[[drivers]]
link = "crank"
pivot = "O"
sense = "clockwise"
"""
    with pytest.raises(assur.SpecError) as from_file:
        assur.loads(bad_toml)
    with pytest.raises(assur.SpecError) as from_builder:
        (assur.Builder(units="mm").point("O", 0, 0).point("A", 30, 0).frame("O").link("crank", "O", "Q")
         .crank("crank", pivot="O", sense="clockwise").build())
    assert from_builder.value.problems == from_file.value.problems
    assert "links.crank[1]: unknown point 'Q'" in str(from_builder.value)
    assert str(from_builder.value).startswith("builder: ")


def test_builder_refuses_a_name_defined_twice():
    b = (assur.Builder().point("O", 0, 0).point("O", 1, 0).point("A", 1, 0).frame("O")
         .link("crank", "O", "A").link("crank", "A", "O").place("nolink", "A", distance=1)
         .crank("crank", pivot="O"))
    with pytest.raises(assur.SpecError) as err:
        b.build()
    paths = [p for p, _ in err.value.problems]
    assert paths == ["points.O", "links.crank", "links.nolink.place.A"]


def test_builder_spatial_dimension_from_the_points():
    """examples/rssr.toml's points are three-dimensional: the builder infers dimension = 3."""
    from assur.io.toml_reader import parse_toml
    doc = parse_toml(open("examples/rssr.toml", encoding="utf-8").read(), "rssr.toml")
    b = assur.Builder(units=doc["units"]["length"], angle=doc["units"]["angle"])
    for name, xyz in doc["points"].items():
        b.point(name, *xyz)
    for name, pts in doc["links"].items():
        if isinstance(pts, dict):
            b.link(name, *pts["points"], length=pts.get("length"))
        else:
            b.link(name, *pts)
    for point, kind in doc["joints"].items():
        b.joint(point, kind["kind"], kind.get("axis")) if isinstance(kind, dict) else b.joint(point, kind)
    for d in doc["drivers"]:
        b.crank(d["link"], pivot=d["pivot"], arm=d.get("arm"), speed=d.get("speed"), zero=d.get("zero"),
                sense=d.get("sense"), name=d.get("name"))
    for load in doc["loads"]:
        b.load(link=load["link"], torque=load["torque"])
    m = b.build()
    assert m.dimension == 3
    ref = assur.load("examples/rssr.toml")
    assert m == dataclasses.replace(ref, name="", description="")
