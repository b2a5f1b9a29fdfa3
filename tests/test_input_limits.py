"""Bad input gets a located SpecError (never a traceback, never accepted nonsense): endless or huge files, deep
nesting, [units] of the wrong type, infinite speeds, absurd magnitudes; a missing [units] says what it assumed."""
import warnings
from pathlib import Path

import pytest

import assur
from assur.errors import AssumedUnitsWarning, SpecError

BASE = (Path(__file__).resolve().parents[1] / "examples" / "crank_rocker.toml").read_text(encoding="utf-8")


@pytest.mark.parametrize("path, message", [
    ("/dev/zero", "larger than 16 MiB"),          # an endless stream is not read until memory runs out
    ("/", "Is a directory"),
    ("/no/such/file.toml", "no such file"),
])
def test_unreadable_paths_are_refused_with_the_path(path, message):
    with pytest.raises(SpecError, match=message):
        assur.load(path)


@pytest.mark.parametrize("depth", [40, 5000])     # 5000 made the TOML parser itself recurse too deep
def test_deep_nesting_is_refused(depth):
    with pytest.raises(SpecError, match="nested deeper than 32 levels"):
        assur.loads("a = " + "[" * depth + "]" * depth)


@pytest.mark.parametrize("value", ['["mm"]', "{ a = 1 }", "3"])
def test_units_of_the_wrong_type_are_a_located_error(value):
    with pytest.raises(SpecError, match=r"units\.length: must be one of m, mm"):
        assur.loads(BASE.replace('length = "mm"', f"length = {value}", 1))


@pytest.mark.parametrize("speed", ['"1e400 rpm"', "1e400", '"1e12 rad/s"'])
def test_an_infinite_or_absurd_speed_is_refused(speed):
    with pytest.raises(SpecError, match=r"drivers\[0\]\.speed: must be a finite speed"):
        assur.loads(BASE.replace('speed = "60 rpm"', f"speed = {speed}"))


@pytest.mark.parametrize("old, new, where", [
    ("angle = 30", "angle = 1e308", r"links\.coupler\.place\.P\.angle"),
    ("length = 40", "length = 1e300", r"links\.crank\.length"),
    ("O4 = [100, 0]", "O4 = [1e300, 0]", r"points\.O4"),
])
def test_absurd_magnitudes_are_refused_where_they_are(old, new, where):
    assert old in BASE
    with pytest.raises(SpecError, match=where):
        assur.loads(BASE.replace(old, new, 1))


def test_a_missing_units_table_says_what_it_assumed():
    text = BASE.replace('[units]\nlength = "mm"\nangle = "deg"\n', "")
    assert "[units]" not in text
    with pytest.warns(AssumedUnitsWarning, match="lengths are read in m and angles in degrees"):
        assur.loads(text)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        assur.loads(BASE)                              # with [units]: no warning


# -- synthesis problems ---------------------------------------------------------------------------------------------
PROBLEM = (Path(__file__).resolve().parents[1] / "examples" / "synthesis" / "paper000_six_points.toml")


def _problem(tmp_path, old, new):
    from assur.synthesis.problem import load_problem
    text = PROBLEM.read_text(encoding="utf-8")
    assert old in text
    text = text.replace(old, new).replace('mechanism = "../', f'mechanism = "{PROBLEM.parent.parent}/')
    f = tmp_path / "problem.toml"
    f.write_text(text, encoding="utf-8")
    return load_problem(f)


def test_a_link_length_bound_below_zero_is_refused(tmp_path):
    """A negative crank length would be a mirrored design that `assur validate` then rejects."""
    with pytest.raises(SpecError, match=r"variables\.crank\.length: a link length must stay positive"):
        _problem(tmp_path, '"crank.length" = [1, 1000]', '"crank.length" = [-100, 1000]')


def test_an_absurd_cycle_sample_count_is_refused(tmp_path):
    """2e8 samples per design once asked for terabytes."""
    with pytest.raises(SpecError, match=r"options\.cycle_samples: must be an integer from 16 to 100000"):
        _problem(tmp_path, "[constraints]", "[options]\ncycle_samples = 200000000\n\n[constraints]")


def test_a_typo_in_a_parameter_name_gets_a_suggestion(tmp_path):
    with pytest.raises(SpecError, match=r"parameters\.crank\.lenght: not a parameter of the mechanism "
                                        r"\(did you mean 'crank\.length'\?\)"):
        _problem(tmp_path, "[targets]", '[parameters]\n"crank.lenght" = "100"\n\n[targets]')


@pytest.mark.parametrize("old, new, where", [
    ('use = ["buildable"]', 'use = [["buildable"]]', "constraints.use[0]"),
    ('use = ["buildable"]', 'use = [{ name = "buildable" }]', "constraints.use[0]"),
    ("[objective]", "[objective]\nterms = 5", "objective.terms"),
    ('[[constraints.limits]]\nexpression = "rod.length - crank.length"\nmin = 0', "limits = 3", "constraints.limits"),
])
def test_a_value_of_the_wrong_shape_in_a_problem_is_a_located_error(tmp_path, old, new, where):
    """A list where a constraint name belongs, a number where an array of terms or limits belongs: each once ended
    in a TypeError from the reader; each is one located problem."""
    with pytest.raises(SpecError) as info:
        _problem(tmp_path, old, new)
    assert [p for p, _ in info.value.problems] == [where]


def test_a_length_that_disagrees_with_the_sketch_is_reported_with_both_numbers():
    """crank_rocker.toml draws O4–B exactly 80 mm (|(133.880965996, 72.471236661) − (100, 0)| = 80.000 mm)."""
    from assur.errors import SketchWarning
    with pytest.warns(SketchWarning, match=r"links\.rocker\.length: 90 mm is used, but the sketch draws O4–B 80 mm long"):
        assur.loads(BASE.replace("length = 80", "length = 90"))
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        assur.loads(BASE)
