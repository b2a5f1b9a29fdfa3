"""The force analysis' keys of a mechanism file: masses, loads, friction, gravity, the gait's foot load.

Reference values are unit conversions by the SI definitions (1 g = 1e-3 kg, 1 mm = 1e-3 m, 1 kN = 1e3 N,
1 lbf = 4.4482216152605 N exactly by its definition 0.45359237 kg × 9.80665 m/s²), written out in each test.
"""
from __future__ import annotations

import math
import re
import pathlib

import pytest

import assur
from assur.errors import SpecError
from assur.io import units as U
from assur.model.dynamics import Dynamics, Friction, Load, LoadLaw, MassProperties
from assur.model.mechanism import Units

EXAMPLES = pathlib.Path(__file__).resolve().parents[1] / "examples"


def bare(name: str) -> str:
    """An example file's text without its force data (the masses, loads, body weight and [dynamics] that the
    examples carry), so the tests below add their own."""
    text = (EXAMPLES / name).read_text()
    text = text.split("\n# -- forces")[0] + "\n"
    keep = [line for line in text.splitlines()
            if not re.match(r"\s*(mass|com|inertia|weight|cylinder|rod) = ", line)]
    return "\n".join(keep) + "\n"

# an offset slider-crank in mm (examples/slider_crank.toml's geometry), the force keys added by the tests
BASE = """
format = "assur/1"
[units]
length = "mm"
angle = "deg"
[points]
O = [0, 0]
A = [25, 43.3012701892]
B = [173.179117313, 20]
[links]
frame = ["O"]
[links.crank]
points = ["O", "A"]
{crank}
[links.rod]
points = ["A", "B"]
{rod}
[[prismatic]]
name = "slot"
point = "B"
guide = "frame"
through = "O"
offset = 20
{slot}
[[drivers]]
name = "crank"
kind = "rotary"
link = "crank"
pivot = "O"
arm = "A"
{rest}
"""


def mech(crank="", rod="", slot="", rest=""):
    return assur.loads(BASE.format(crank=crank, rod=rod, slot=slot, rest=rest))


def problems(**kw):
    with pytest.raises(SpecError) as e:
        mech(**kw)
    return dict(e.value.problems)


# -- units ----------------------------------------------------------------------------------------------------
@pytest.mark.parametrize("text, kind, si", [
    ("1 kg", "mass", 1.0), ("500 g", "mass", 500 * 1e-3), ("0.2 t", "mass", 0.2 * 1e3), (3, "mass", 3.0),
    ("0.0833 kg*m^2", "inertia", 0.0833), ("2 kg m^2", "inertia", 2.0), ("2 kg·m²", "inertia", 2.0),
    ("83 g*cm^2", "inertia", 83 * 1e-3 * (1e-2) ** 2), ("5 g*mm^2", "inertia", 5 * 1e-3 * (1e-3) ** 2),
    ("7 kg*mm^2", "inertia", 7 * (1e-3) ** 2), (0.5, "inertia", 0.5),
    ("100 N", "force", 100.0), ("3 kN", "force", 3e3), ("20 mN", "force", 20e-3),
    ("1 lbf", "force", 0.45359237 * 9.80665),
    ("5 N*m", "torque", 5.0), ("5 N·m", "torque", 5.0), ("5 N m", "torque", 5.0), ("40 N*mm", "torque", 40e-3),
    ("2 kN*m", "torque", 2e3), (1.5, "torque", 1.5),
])
def test_quantities_in_si(text, kind, si):
    assert U.parse_quantity(text, kind) == pytest.approx(si, rel=1e-12)


def test_a_bare_length_is_in_the_file_unit():
    assert U.parse_quantity(2, "length", Units("mm", "deg")) == pytest.approx(2e-3)
    assert U.parse_quantity("2 cm", "length", Units("mm", "deg")) == pytest.approx(2e-2)


@pytest.mark.parametrize("text, kind", [("1 lb", "mass"), ("1 kg*m", "inertia"), ("five N", "force"),
                                        (True, "torque"), ([1], "mass"), ("1e400 kg", "mass")])
def test_bad_quantities_are_spec_errors(text, kind):
    with pytest.raises(SpecError):
        U.parse_quantity(text, kind)


def test_speeds_still_parse_as_before():
    # 27 rpm = 27 · 2π / 60 rad/s; a bad unit keeps its message
    assert U.parse_speed("27 rpm", "rotary", Units()) == pytest.approx(27 * 2 * math.pi / 60)
    assert U.parse_speed("100 mm/s", "linear", Units("mm", "deg")) == pytest.approx(0.1)
    with pytest.raises(SpecError, match="with unit one of rad/s, deg/s, rpm"):
        U.parse_speed("fast", "rotary", Units())


# -- loading ----------------------------------------------------------------------------------------------------
def test_no_force_keys_no_dynamics():
    assert mech().dynamics is None
    assert assur.load(EXAMPLES / "slider_crank.toml").dynamics is None


def test_link_masses_in_si_and_defaults_stored_as_none():
    m = mech(crank='mass = "500 g"', rod='mass = "1 kg"\ninertia = "0.0833 kg*m^2"\ncom = "mid"')
    d = m.dynamics
    assert isinstance(d, Dynamics)
    assert d.gravity == (0.0, 0.0)                                  # default: no gravity
    assert d.mass_of("crank") == MassProperties(0.5, None, None)    # inertia and com left to the solver
    assert d.mass_of("rod") == MassProperties(1.0, 0.0833, "mid")
    assert d.mass_of("slot.block") == MassProperties()              # no mass given: none stored
    assert [b for b, _ in d.bodies] == ["crank", "rod"]
    assert d.loads == () and d.friction == Friction()


def test_com_forms():
    m = mech(crank='mass = 1\ncom = "A"', rod="mass = 1\ncom = [100, 25]")
    assert m.dynamics.mass_of("crank").com == "A"
    assert m.dynamics.mass_of("rod").com == pytest.approx((0.1, 0.025))       # mm → m
    far = mech(rod="mass = 1\ncom = [100000, 0]")                                # far off the link: allowed
    assert far.dynamics.mass_of("rod").com == pytest.approx((100.0, 0.0))


def test_inertia_without_mass_gives_zero_mass():
    assert mech(rod='inertia = "10 g*cm^2"').dynamics.mass_of("rod") == MassProperties(0.0, 10e-3 * 1e-4, None)


def test_slider_block_mass():
    m = mech(slot='mass = "2 kg"\ninertia = 0.001')
    assert m.dynamics.bodies == (("slot.block", MassProperties(2.0, 0.001, None)),)


def test_dynamics_table_and_friction():
    m = mech(rest='[dynamics]\ngravity = [0, -9.81]\njoint_friction_radius = "1 mm"\nslide_friction = 0.1\n'
                  '[dynamics.joints]\nA = 2\n[dynamics.slides]\nslot = 0.2\n')
    d = m.dynamics
    assert d.gravity == (0.0, -9.81)
    assert d.bodies == ()
    f = d.friction
    assert f.joint_radius == pytest.approx(1e-3) and f.slide == 0.1
    assert f.radius_at("A") == pytest.approx(2e-3) and f.radius_at("O") == pytest.approx(1e-3)   # bare: mm
    assert f.mu_of("slot") == 0.2


def test_an_empty_dynamics_table_is_a_dynamics():
    assert mech(rest="[dynamics]\n").dynamics == Dynamics()


def test_loads():
    m = mech(rest="""
[[loads]]
point = "B"
force = [-100, "0.5 kN"]
opposes = "velocity"
[[loads]]
link = "crank"
torque = "5 N*m"
[[loads]]
point = "B"
link = "rod"
law = { input = [0, 180, 360], force = [[0, 1], [2, 3], [4, 5]] }
[[loads]]
link = "slot.block"
law = { input = [0, 90], torque = ["1 N*m", 2] }
""")
    f, t, lf, lt = m.dynamics.loads
    assert f == Load(point="B", force=(-100.0, 500.0), opposes="velocity")
    assert t == Load(link="crank", torque=5.0)
    # the input of a law is in the first driver's unit: a crank in degrees → rad
    assert lf == Load(point="B", link="rod", law=LoadLaw((0.0, math.pi, 2 * math.pi), ((0, 1), (2, 3), (4, 5))))
    assert lt.law == LoadLaw((0.0, math.pi / 2), ((1.0,), (2.0,)))
    assert m.dynamics.bodies == ()


def test_loads_on_a_linear_driver_and_actuator_bodies():
    text = bare("lever_manipulator.toml")
    text = text.replace('[actuators.drive_rod]\nbetween = ["A", "B"]',
                        '[actuators.drive_rod]\nbetween = ["A", "B"]\n'
                        'cylinder = { mass = "8 kg", inertia = 0.5, com = 300 }\nrod = { mass = 3, com = "0.1 m" }')
    text += ('\n[[loads]]\nlink = "drive_rod.rod"\npoint = "B"\n'
             'law = { input = [500, 1000], force = [[0, -10], [0, -20]] }\n')
    m = assur.loads(text)
    d = m.dynamics
    assert d.mass_of("drive_rod.cylinder") == MassProperties(8.0, 0.5, pytest.approx(0.3))
    assert d.mass_of("drive_rod.rod") == MassProperties(3.0, None, pytest.approx(0.1))
    assert d.loads[0].law.inputs == pytest.approx((0.5, 1.0))       # the linear driver's mm → m


def test_gait_weight_and_friction():
    text = bare("walker_fourbar.toml")
    assert "[gait]" in text
    m = assur.loads(text.replace("[gait]", '[gait]\nweight = "0.2 kN"\nfriction = 0.6'))
    assert m.gait.weight == pytest.approx(200.0) and m.gait.friction == 0.6
    assert m.dynamics is None                                        # a foot load alone gives no Dynamics
    plain = assur.loads(bare("walker_fourbar.toml"))
    assert plain.gait.weight is None and plain.gait.friction is None


def test_spatial_masses_and_gravity():
    text = bare("rssr.toml")
    text = text.replace('rocker = { points = ["P4", "P3"], length = 50 }',
                        'rocker = { points = ["P4", "P3"], length = 50, mass = 0.2, com = "mid" }\n'
                        'crank = { points = ["P1", "P2"], mass = 0.1, inertia = 1e-5, com = [0, -10, 0] }')
    text = text.replace('crank = ["P1", "P2"]\n', "")
    text += "\n[dynamics]\ngravity = [0, -9.81, 0]\n[[loads]]\npoint = \"C\"\nforce = [1, 2, 3]\n"
    m = assur.loads(text)
    d = m.dynamics
    assert d.gravity == (0.0, -9.81, 0.0)
    assert d.mass_of("crank") == MassProperties(0.1, 1e-5, pytest.approx((0.0, -0.01, 0.0)))
    assert d.mass_of("rocker").com == "mid"
    assert d.loads[0].force == (1.0, 2.0, 3.0)
    assert assur.loads(assur.dumps(m)) == m


# -- errors -----------------------------------------------------------------------------------------------------
def test_every_problem_at_once_with_its_location():
    p = problems(crank='mass = "-1 kg"\ncom = "B"', rod='inertia = -2\ncolour = "red"',
                 slot='mass = 1\ncom = [0, 0]',
                 rest="""
[dynamics]
gravity = [0, "down"]
joint_friction_radius = -1
slide_friction = -0.1
wind = 3
[dynamics.joints]
Q = 1
[dynamics.slides]
nope = 0.1
[gait]
foot = "B"
weight = "-5 N"
friction = -1
[[loads]]
point = "Q"
force = [1, 0]
[[loads]]
link = "nothing"
torque = 1
[[loads]]
point = "B"
[[loads]]
point = "O"
link = "rod"
force = [1, 0]
torque = 2
[[loads]]
torque = "5 lb"
[[loads]]
link = "crank"
force = [1, 0]
opposes = "position"
[[loads]]
link = "crank"
law = { input = [0, 90, 90], torque = [1, 2] }
""")
    assert p["links.crank.mass"].startswith("must not be negative")
    assert "is not a point of link 'crank'" in p["links.crank.com"]
    assert p["links.rod.inertia"].startswith("must not be negative")
    assert p["links.rod.colour"].startswith("unknown key")
    assert "no com" in p["prismatic[0].com"]
    assert "gravity" not in p.get("dynamics", "") and "dynamics.gravity" in p
    assert p["dynamics.joint_friction_radius"].startswith("must not be negative")
    assert "non-negative" in p["dynamics.slide_friction"]
    assert p["dynamics.wind"].startswith("unknown key")
    assert "unknown point 'Q'" in p["dynamics.joints.Q"]
    assert "unknown prismatic pair or actuator 'nope'" in p["dynamics.slides.nope"]
    assert p["gait.weight"].startswith("must not be negative")
    assert "non-negative" in p["gait.friction"]
    assert "unknown point 'Q'" in p["loads[0].point"]
    assert "unknown link 'nothing'" in p["loads[1].link"]
    assert p["loads[2]"].startswith("a load on nothing")
    assert "takes one of force, torque or law" in p["loads[3]"]
    assert "is not a point of 'rod'" in p["loads[3].point"]
    assert "with unit one of N*m" in p["loads[4].torque"]
    assert p["loads[4].link"] == "a torque needs the link it acts on"
    assert p["loads[5].point"] == "a force needs the point it acts at"
    assert p["loads[5].opposes"] == "must be 'velocity': 'position'"
    assert "must increase strictly" in p["loads[6].law.input[2]"]
    assert "one value per input" in p["loads[6].law.torque"]


def test_mid_needs_a_binary_link():
    with pytest.raises(SpecError) as e:
        assur.loads(BASE.format(crank="", rod="", slot="", rest="")
                    .replace('[links.rod]\npoints = ["A", "B"]', '[links.rod]\npoints = ["A", "B", "O"]\ncom = "mid"'))
    assert any(path == "links.rod.com" and "'mid' needs a binary link" in msg for path, msg in e.value.problems)


def test_mass_on_a_translating_link_is_an_error():
    doc = assur.Builder(units="mm").point("O", 0, 0).point("A", 10, 0).point("B", 50, 0).to_dict()
    doc["links"] = {"frame": ["O"], "crank": ["O", "A"], "yoke": ["A", "B"]}
    doc["prismatic"] = [{"name": "p", "link": "yoke", "through": "O", "mass": 1}]
    with pytest.raises(SpecError) as e:
        assur.io.mechanism_file.from_dict(doc)
    msgs = dict(e.value.problems)
    assert "give its mass in [links.yoke]" in msgs["prismatic[0].mass"]


def test_non_finite_numbers_are_errors():
    p = problems(rod="mass = nan\ninertia = inf", rest="[dynamics]\ngravity = [0, inf]\n")
    assert {"links.rod.mass", "links.rod.inertia", "dynamics.gravity"} <= set(p)


def test_a_law_needs_a_driver_and_matching_rows():
    p = problems(rest='[[loads]]\npoint = "B"\nlaw = { input = [0, 90], force = [[1, 2], [3]] }\n'
                      '[[loads]]\npoint = "B"\nlaw = { input = [0, 90] }\n')
    assert "must be [x, y]" in p["loads[0].law.force[1]"]
    assert "exactly one of force" in p["loads[1].law"]


def test_actuator_body_errors():
    text = bare("lever_manipulator.toml").replace(
        '[actuators.drive_rod]\nbetween = ["A", "B"]',
        '[actuators.drive_rod]\nbetween = ["A", "B"]\ncylinder = { mass = -8, colour = 1 }\nrod = 3')
    with pytest.raises(SpecError) as e:
        assur.loads(text)
    p = dict(e.value.problems)
    assert p["actuators.drive_rod.cylinder.mass"].startswith("must not be negative")
    assert p["actuators.drive_rod.cylinder.colour"].startswith("unknown key")
    assert "must be a table" in p["actuators.drive_rod.rod"]


# -- writing and building -------------------------------------------------------------------------------------
FULL = dict(crank='mass = "500 g"\ncom = [10, 5]', rod='mass = "1 kg"\ninertia = "833 kg*cm^2"\ncom = "mid"',
            slot="mass = 2", rest="""
[dynamics]
gravity = [0, -9.81]
joint_friction_radius = "1 mm"
slide_friction = 0.1
[dynamics.joints]
A = "2 mm"
[dynamics.slides]
slot = 0.2
[[loads]]
point = "B"
force = [-100, 0]
opposes = "velocity"
[[loads]]
link = "crank"
torque = "5 N*m"
[[loads]]
point = "B"
link = "rod"
law = { input = [0, 180, 360], force = [[0, 1], [2, 3], [4, "5 kN"]] }
[[loads]]
link = "slot.block"
law = { input = [0, 90], torque = [1, 2] }
""")


def test_round_trip_in_the_files_units():
    m = mech(**FULL)
    text = assur.dumps(m)
    assert assur.loads(text) == m
    assert "joint_friction_radius = 1\n" in text                  # mm, the file's length unit
    assert "input = [0, 180, 360]" in text                         # degrees, the crank's unit
    assert "com = [10, 5]" in text


def test_round_trip_of_actuator_bodies_and_gait_load():
    text = bare("lever_manipulator.toml").replace(
        '[actuators.drive_rod]\nbetween = ["A", "B"]',
        '[actuators.drive_rod]\nbetween = ["A", "B"]\ncylinder = { mass = "8 kg", com = 300 }\nrod = { mass = 3 }')
    m = assur.loads(text)
    assert assur.loads(assur.dumps(m)) == m
    w = assur.loads(bare("walker_fourbar.toml").replace("[gait]", '[gait]\nweight = "200 N"\n'
                                                                                      "friction = 0.6"))
    assert assur.loads(assur.dumps(w)) == w


def test_builder_equals_the_file():
    m = mech(**FULL)
    b = (assur.Builder(units="mm")
         .point("O", 0, 0).point("A", 25, 43.3012701892).point("B", 173.179117313, 20)
         .frame("O").link("crank", "O", "A").link("rod", "A", "B")
         .slider(point="B", through="O", offset=20, name="slot")
         .crank("crank", pivot="O", arm="A", name="crank")
         .mass("crank", "500 g", com=(10, 5)).mass("rod", "1 kg", inertia="833 kg*cm^2", com="mid")
         .mass("slot.block", 2)
         .dynamics(gravity=(0, -9.81), joint_friction_radius="1 mm", slide_friction=0.1,
                   joints={"A": "2 mm"}, slides={"slot": 0.2})
         .load(point="B", force=(-100, 0), opposes="velocity")
         .load(link="crank", torque="5 N*m")
         .load(point="B", link="rod", law={"input": [0, 180, 360], "force": [[0, 1], [2, 3], [4, "5 kN"]]})
         .load(link="slot.block", law={"input": [0, 90], "torque": [1, 2]}))
    import warnings
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        built = b.build()
    assert built.dynamics == m.dynamics
    assert built.links == m.links and built.prismatic == m.prismatic


def test_builder_actuator_bodies_and_gait():
    def base():
        return (assur.Builder(units="mm").point("O", 0, 0).point("A", 600, 0).point("G", 0, 400)
                .point("B", 300, 400).frame("O", "A", "G").slider(point="B", through="G", angle=180, name="guide")
                .actuator("drive_rod", "A", "B").actuator("driven_rod", "O", "B")
                .linear("drive_rod", speed="100 mm/s", name="drive"))
    m = base().mass("drive_rod.cylinder", "8 kg", com=300).mass("drive_rod.rod", 3).build()
    assert m.dynamics.mass_of("drive_rod.cylinder") == MassProperties(8.0, None, pytest.approx(0.3))
    assert m.dynamics.mass_of("drive_rod.rod") == MassProperties(3.0, None, None)
    with pytest.raises(SpecError) as e:
        base().mass("nothing", 1).mass("pump.rod", 1).mass("gone.block", 1).build()
    paths = [p for p, _ in e.value.problems]
    assert paths[:3] == ["links.nothing", "actuators.pump.rod", "prismatic (gone.block)"]
    with pytest.raises(SpecError, match="links.frame.mass: is defined twice"):
        base().mass("frame", 1).mass("frame", 2).build()


def test_builder_gait_weight():
    leg = (assur.Builder(units="m")
           .point("O", 0, 0).point("O1", 0.567, 0.615).point("K", 0.27, 0).point("L", 0.915, 0.080)
           .point("H", 0.778, -0.559).frame("O", "O1").link("crank", "O", "K").link("rocker", "O1", "L")
           .link("coupler", "K", "L", "H").crank("crank", pivot="O", arm="K")
           .gait("H", weight="200 N", friction=0.6).build())
    assert leg.gait.weight == 200.0 and leg.gait.friction == 0.6
    assert leg.dynamics is None



# -- physical bounds (docs/format.md, "Bounds"): a value no machine has is a typo or a unit slip, refused with the
# value and the bound named; values inside are kept
@pytest.mark.parametrize("gravity, ok", [("[0, -9.81]", True), ("[0, -999]", True), ("[2e8, -9.81]", False),
                                         ("[800, -800]", False)])
def test_gravity_beyond_a_hundred_g_is_refused_with_its_value(gravity, ok):
    rest = f"[dynamics]\ngravity = {gravity}\n"
    if ok:
        assert mech(rest=rest).dynamics.gravity == tuple(float(x) for x in gravity.strip("[]").split(","))
        return
    msg = problems(rest=rest)["dynamics.gravity"]
    assert "m/s²" in msg and "at most 1000" in msg and gravity.strip("[]").split(",")[0].strip() in msg.replace(
        "200000000.0", "2e8").replace("800.0", "800")


@pytest.mark.parametrize("load, path, ok", [
    ('point = "B"\nlink = "rod"\nforce = [-1e6, 0]', "loads[0].force[0]", True),
    ('point = "B"\nlink = "rod"\nforce = ["2000000 kN", 0]', "loads[0].force[0]", False),
    ('point = "B"\nlink = "rod"\nforce = [0, 1e10]', "loads[0].force[1]", False),
    ('link = "rod"\ntorque = "5e9 N*m"', "loads[0].torque", False),
    ('link = "rod"\ntorque = "2 kN*m"', "loads[0].torque", True)])
def test_absurd_loads_are_refused_with_their_value(load, path, ok):
    rest = f"[[loads]]\n{load}\n"
    if ok:
        assert len(mech(rest=rest).dynamics.loads) == 1
        return
    msg = problems(rest=rest)[path]
    assert "beyond any machine" in msg and "at most 1e+09" in msg
    given = {"loads[0].force[0]": "2000000 kN", "loads[0].force[1]": "10000000000.0", "loads[0].torque": "5e9 N*m"}
    assert given[path] in msg                       # the value as written
