"""The ``[make]`` table of a mechanism file: reading (units, located errors), writing back, and the settings
``assur make`` resolves from it (docs/make.md)."""
import math
from pathlib import Path

import pytest

import assur
from assur.errors import SpecError
from assur.parts.settings import WASHERS, default_pin, resolve

EXAMPLES = Path(__file__).resolve().parents[1] / "examples"
JANSEN = (EXAMPLES / "jansen.toml").read_text(encoding="utf-8")      # a cm file


def with_make(text: str, table: str) -> str:
    return text + "\n[make]\n" + table


def test_lengths_are_in_the_files_unit_or_carry_their_own():
    m = assur.loads(with_make(JANSEN, 'pin = 0.4\nthickness = "4 mm"\nwidth = 1.2\nclearance = "0.5 mm"\n'
                                      'density = "1.24 g/cm3"\nprocess = "laser-cut"\nmaterial = "birch plywood"\n'))
    mk = m.make
    assert mk.pin == pytest.approx(0.004)          # 0.4 cm
    assert mk.thickness == pytest.approx(0.004)
    assert mk.width == pytest.approx(0.012)
    assert mk.clearance == pytest.approx(0.0005)
    assert mk.density == pytest.approx(1240.0)     # 1.24 g/cm³ = 1240 kg/m³
    assert (mk.process, mk.material) == ("laser-cut", "birch plywood")
    assert mk.washer is None and mk.hole_allowance is None


def test_the_table_round_trips_through_the_writer():
    m = assur.loads(with_make(JANSEN, 'pin = 0.5\nthickness = "3 mm"\nhole_allowance = -0.01\n'
                                      'density = 2700\nprocess = "machined"\n'))
    text = assur.dumps(m)
    assert "[make]" in text
    back = assur.loads(text)
    assert back == m
    assert back.make.given() == m.make.given()
    # only what the file gave is written back: the defaults stay defaults
    assert "washer" not in text.split("[make]")[1]


def test_a_file_without_the_table_has_none_and_writes_none():
    m = assur.loads(JANSEN)
    assert m.make is None
    assert "[make]" not in assur.dumps(m)


def test_an_empty_table_means_all_defaults():
    m = assur.loads(with_make(JANSEN, ""))
    assert m.make is not None and m.make.given() == {}
    assert "[make]" in assur.dumps(m)


@pytest.mark.parametrize("line, where, words", [
    ('pin = 0.33', "make.pin", "not a standard dowel"),
    ('process = "cnc"', "make.process", "fdm, laser-cut, machined"),
    ('thickness = -0.3', "make.thickness", "positive"),
    ('thickness = "3 furlongs"', "make.thickness", "unit"),
    ('density = "3 lb/in3"', "make.density", "unknown density unit"),
    ('density = 0.5', "make.density", "between"),
    ('material = 3', "make.material", "material's name"),
    ('hole_allowance = 1', "make.hole_allowance", "within"),
    ('colour = "red"', "make.colour", "unknown key"),
    ('width = 0.5\npin = 0.4', "make.width", "too little wall"),
    ('washer = 0.5\nthickness = 0.3', "make.washer", "thicker than"),
])
def test_every_bad_value_is_a_located_error(line, where, words):
    with pytest.raises(SpecError) as exc:
        assur.loads(with_make(JANSEN, line + "\n"), source="leg.toml")
    paths = [p for p, _ in exc.value.problems]
    assert where in paths, exc.value.problems
    message = dict(exc.value.problems)[where]
    assert words in message


def test_every_problem_of_the_table_is_reported_at_once():
    with pytest.raises(SpecError) as exc:
        assur.loads(with_make(JANSEN, 'pin = 0.33\nprocess = "cnc"\nthickness = 0\n'))
    assert {"make.pin", "make.process", "make.thickness"} <= {p for p, _ in exc.value.problems}


def test_a_spatial_file_takes_no_make_table():
    text = (EXAMPLES / "rssr.toml").read_text(encoding="utf-8")
    with pytest.raises(SpecError) as exc:
        assur.loads(with_make(text, "pin = 4\n"))
    assert "make" in [p for p, _ in exc.value.problems]


# -- settings ------------------------------------------------------------------------------------------------

def test_default_pin_follows_the_size_within_the_series():
    # S/60 of a 1.2 m leg is 20 mm: capped at 12 mm; a 112 mm leg gets the 3 mm floor, and a quarter of a
    # 17.5 mm crank (4.4 mm) allows it
    assert default_pin(1.2303, 0.15) == 0.012
    assert default_pin(0.1116, 0.0175) == 0.003
    assert default_pin(0.3, 0.010) == 0.0025          # a quarter of 10 mm between two joints of one link


def test_resolved_defaults_and_precedence_of_the_command_line():
    m = assur.loads(with_make(JANSEN, 'process = "machined"\npin = 0.8\n'))
    s = resolve(m.make, size=m.length_scale, shortest=0.15)
    assert (s.process, s.material, s.density) == ("machined", "aluminium 6061-T6", 2700.0)
    assert s.pin == 0.008 and s.width == pytest.approx(0.020)               # 2.5 × 8 mm
    assert (s.washer, s.washer_od) == WASHERS[0.008]                         # DIN 125-A of an 8 mm pin: 1.6 × ⌀16
    assert s.thickness == 0.004                                              # half the pin: the machined minimum
    cli = resolve(m.make, size=m.length_scale, shortest=0.15, clearance=0.002, process="fdm")
    assert (cli.clearance, cli.process, cli.material) == (0.002, "fdm", "PLA")
    assert set(cli.given) == {"clearance", "pin", "process"}


def test_command_line_values_are_checked():
    with pytest.raises(SpecError, match="--process"):
        resolve(None, size=1.0, shortest=0.1, process="waterjet")
    with pytest.raises(SpecError, match="--clearance"):
        resolve(None, size=1.0, shortest=0.1, clearance=-1.0)
    with pytest.raises(SpecError, match="make.clearance"):
        resolve(None, size=1.0, shortest=0.1, clearance=0.5)      # wider than the bars


def test_layer_pitch_is_a_plate_and_a_washer():
    s = resolve(None, size=0.2, shortest=0.05)
    assert s.pitch == pytest.approx(s.thickness + s.washer)
    assert s.boss == pytest.approx(0.5 * s.width)
    assert math.isclose(s.sleeve, 0.5 * s.washer_od)
