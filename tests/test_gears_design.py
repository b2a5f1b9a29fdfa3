"""Design files assur-gears/1 and assur-wheelstep/1 (read by assur.io.gear_file into assur.gears.design): the paper's examples and located errors."""
import math
from pathlib import Path

import numpy as np
import pytest

from assur.errors import SpecError
from assur.gears import WheelStepLaw
from assur.gears.design import GearDesign, WheelStepDesign
from assur.io.gear_file import compile_expression, load_design

EX = Path(__file__).resolve().parents[1] / "examples"

ENVELOPE = """
format = "assur-gears/1"
[units]
length = "mm"
[law]
kind = "ratio"
ratio = "1 + 0.3*cos(phi)"
[teeth]
method = "envelope"
module = 2
driving_teeth = 40
driven_teeth = 40
"""


def write(tmp_path, text, name="design.toml"):
    p = tmp_path / name
    p.write_text(text, encoding="utf-8")
    return p


def problems(path):
    with pytest.raises(SpecError) as exc:
        load_design(path)
    return dict(exc.value.problems)


def test_paper_gear_design_loads_in_si():
    """examples/gears_001.toml holds docs/papers/001.md B1: L_p = 143.5 mm, L_ust = 144 mm, a, b, c,
    z = 48/96, m = 2 mm, j_n = 0.25 m, 24 sectors per step; the wheelstep law with 2 driving turns."""
    d = load_design(EX / "gears_001.toml")
    assert isinstance(d, GearDesign) and isinstance(d.law, WheelStepLaw)
    assert d.centre_distance == 0.1435 and d.installation_distance == 0.144
    assert (d.law.shoe.a, d.law.shoe.b, d.law.shoe.c) == (0.06, 0.1, 0.36)
    assert (d.driving_teeth, d.driven_teeth, d.sectors, d.driving_turns) == (48, 96, 24, 2)
    assert d.module == 0.002 and d.backlash == 0.0005 and d.method == "sectors"
    assert d.pressure_angle == pytest.approx(math.radians(20))
    assert d.sector_model().arc * 1e3 == pytest.approx(6.212273, abs=1e-6)   # docs/papers/001.md B3 regression value
    pair = d.pair()
    assert pair.centre_distance == 0.1435 and pair.driving_turns == 2


def test_paper_wheelstep_design_links_its_gears():
    """examples/wheelstep_001.toml: a = 0.06, b = 0.1, R_min = 0.02 → c = 0.36 m (eq. 9); drive = gears_001.toml."""
    w = load_design(EX / "wheelstep_001.toml")
    assert isinstance(w, WheelStepDesign)
    assert w.shoe.c == pytest.approx(0.36, rel=1e-15)
    assert w.gears is not None and w.gears.driving_teeth == 48
    assert w.pair().driving_turns == 2


def test_envelope_design_derives_the_centre_distance(tmp_path):
    """Without a centre distance, L follows from perimeter = z·π·m (docs/papers/001.md B7.8)."""
    d = load_design(write(tmp_path, ENVELOPE))
    pair = d.pair()
    assert pair.driving.perimeter == pytest.approx(40 * math.pi * 0.002, rel=1e-6)
    assert pair.driven.perimeter == pytest.approx(40 * math.pi * 0.002, rel=1e-6)


def test_envelope_centre_distance_that_cannot_close(tmp_path):
    text = ENVELOPE.replace("[teeth]", "[pair]\ncentre_distance = 50\n[teeth]")
    p = problems(write(tmp_path, text))
    msg = p["pair.centre_distance"]
    assert "cannot close the teeth" in msg and "z·π·m = 40·π·2" in msg and "use centre_distance =" in msg


def test_tooth_count_that_does_not_divide_the_perimeter(tmp_path):
    text = ENVELOPE.replace("driven_teeth = 40", "driven_teeth = 41")
    assert "must be driving_turns · driving_teeth = 1·40 = 40" in problems(write(tmp_path, text))["teeth.driven_teeth"]
    paper = (EX / "gears_001.toml").read_text(encoding="utf-8").replace("driving_teeth = 48", "driving_teeth = 50")
    p = problems(write(tmp_path, paper))
    assert "sectors · (hub steps per driving turn) = 24·2 = 48" in p["teeth.driving_teeth"]
    assert "2·50 = 100" in p["teeth.driven_teeth"]


def test_module_too_large_for_the_curvature(tmp_path):
    """k = 1 + 0.6 cos φ gives a pitch curve with small radii of curvature; 8 mm teeth do not fit."""
    text = ENVELOPE.replace("0.3*cos(phi)", "0.6*cos(phi)").replace("module = 2", "module = 8")
    msg = problems(write(tmp_path, text))["teeth.module"]
    assert "module 8 mm is too large for the curvature" in msg and "body angle ∈ [" in msg


def test_negative_radius_from_a_ratio_expression(tmp_path):
    text = ENVELOPE.replace("0.3*cos(phi)", "1.5*cos(phi)")
    msg = problems(write(tmp_path, text))["law.ratio"]
    assert "must be finite and > 0" in msg and "for φ ∈ [" in msg


def test_table_law_that_does_not_close(tmp_path):
    text = ENVELOPE.replace('kind = "ratio"\nratio = "1 + 0.3*cos(phi)"',
                            'kind = "table"\nphi = [0, 90, 180, 270, 360]\ntheta = [0, 80, 170, 260, 350]')
    msg = problems(write(tmp_path, text))["law"]
    assert "the law does not close: θ after one driving turn = 350.0000°, must be 360°/1" in msg


def test_every_problem_is_reported_with_its_field(tmp_path):
    text = """
format = "assur-gears/1"
colour = "red"
[units]
length = "furlong"
[law]
kind = "wheelstep"
a = -60
b = 100
c = 360
driving_turns = 3
[pair]
centre_distance = 0
[teeth]
method = "sectors"
module = 2
driving_teeth = 48
driven_teeth = 96
sectors = 24
tip = 1
"""
    p = problems(write(tmp_path, text))
    assert "colour" in p and "units.length" in p and "teeth.tip" in p
    assert p["law.a"] == "must be > 0: -60"
    assert p["pair.centre_distance"] == "must be > 0: 0"


def test_shoe_r_min_and_c_must_agree(tmp_path):
    text = """
format = "assur-wheelstep/1"
[shoe]
a = 0.06
b = 0.1
c = 0.36
r_min = 0.03
"""
    assert "contradicts c" in problems(write(tmp_path, text))["shoe.r_min"]
    assert load_design(write(tmp_path, text.replace("0.03", "0.02"))).shoe.c == 0.36


def test_wheelstep_drive_must_match_the_shoe(tmp_path):
    (tmp_path / "g.toml").write_text((EX / "gears_001.toml").read_text(encoding="utf-8"), encoding="utf-8")
    text = """
format = "assur-wheelstep/1"
[shoe]
a = 0.07
b = 0.1
c = 0.36
[drive]
gears = "g.toml"
"""
    msg = problems(write(tmp_path, text))["drive.gears"]
    assert "law.a = 0.06 m differs from shoe.a = 0.07 m" in msg


def test_missing_file_bad_toml_and_format(tmp_path):
    with pytest.raises(SpecError):
        load_design(tmp_path / "nope.toml")
    with pytest.raises(SpecError, match="not valid TOML"):
        load_design(write(tmp_path, "format = = 1"))
    with pytest.raises(SpecError, match="must be 'assur-gears/1' or 'assur-wheelstep/1'"):
        load_design(write(tmp_path, 'format = "assur/1"'))


def test_expression_evaluator_is_arithmetic_only():
    f = compile_expression("1 + 0.5*cos(2*phi) - sin(phi)**2 / pi")
    x = np.linspace(0, 6, 7)
    np.testing.assert_allclose(f(x), 1 + 0.5 * np.cos(2 * x) - np.sin(x) ** 2 / np.pi)
    for bad in ("__import__('os')", "phi.real", "open('x')", "lambda: 1", "[1, 2]", "theta + 1"):
        with pytest.raises(ValueError, match="not allowed|not a valid"):
            compile_expression(bad)


def test_sector_module_too_large_for_the_sector_radii(tmp_path):
    """Sectors mode: with m = 40 mm the root radius r − 1.25m ≤ 0 wherever r ≤ 50 mm, i.e. in driver sectors 5–20
    (Table 1: r_4 = 50.97, r_5 = 48.70 mm, symmetric), whose angles run from θ_5 = −64.36° to θ_21 = 64.36°."""
    paper = (EX / "gears_001.toml").read_text(encoding="utf-8").replace("module = 2", "module = 40")
    msg = problems(write(tmp_path, paper))["teeth.module"]
    assert "module 40 mm is too large for the driving gear's sectors 5–20 (angles [-64.36°, 64.36°])" in msg


def test_rounding_key_reaches_the_law(tmp_path):
    text = (EX / "gears_001.toml").read_text(encoding="utf-8").replace("driving_turns = 2",
                                                                        "driving_turns = 2\nrounding = 10")
    d = load_design(write(tmp_path, text))
    assert d.law.rounding == pytest.approx(math.radians(10))
    bad = text.replace("rounding = 10", "rounding = 40")
    assert "corner rounding" in problems(write(tmp_path, bad))["law.rounding"]


def test_design_gives_the_paper_scheme_outline():
    o = load_design(EX / "gears_001.toml").sector_outline()
    assert o.teeth == (48, 96) and o.linking == "relieved"
    assert np.hypot(*o.driving.T).max() == pytest.approx(0.0613 + 0.002, abs=1e-4)   # Table 1: r_a1 = 63.30 mm


def test_expression_errors_are_located_spec_errors(tmp_path):
    """A bad ratio expression is an ExpressionError (a SpecError and a ValueError) and is reported at law.ratio;
    a function called with the wrong number of arguments is refused when the file is read."""
    from assur.errors import AssurError, ExpressionError
    with pytest.raises(ExpressionError) as exc:
        compile_expression("sin(phi, phi)")
    assert isinstance(exc.value, SpecError) and isinstance(exc.value, ValueError)
    assert isinstance(exc.value, AssurError) and "sin() takes 1 argument" in str(exc.value)
    msg = problems(write(tmp_path, ENVELOPE.replace("0.3*cos(phi)", "0.3*cosh(phi)")))["law.ratio"]
    assert "unknown function 'cosh'" in msg


def test_gear_and_wheelstep_names_stay_importable():
    import importlib
    import sys

    import assur.errors
    import assur.gears.errors
    import assur.gears.wheelstep
    assert assur.gears.errors.GearError is assur.errors.GearError
    assert issubclass(assur.errors.GearError, assur.errors.AssurError) and issubclass(assur.errors.GearError,
                                                                                      ValueError)
    sys.modules.pop("assur.wheelstep", None)        # the former module: still served, with a warning
    with pytest.warns(DeprecationWarning, match="assur.gears.wheelstep"):
        old = importlib.import_module("assur.wheelstep")
    assert old.Shoe is assur.gears.wheelstep.Shoe
