"""Time laws of the inputs (assur.analysis.timelaw) and solving along them.

Constant speed and table laws (cubic spline, PCHIP) against independent computations; the engine's
chain rule along a time law against central differences in time; the file fields ``range`` and
``law`` of a linear driver (load, errors with their location, round trip).
"""
from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest
from hypothesis import given, settings, strategies as st

import assur
from assur.analysis.timelaw import ConstantSpeed, TableLaw, driver_law, solve_in_time

EXAMPLE = Path(__file__).resolve().parents[1] / "examples" / "lever_manipulator.toml"


def test_constant_speed():
    law = ConstantSpeed.over(0.5, 0.1, (0.5, 1.0))
    assert (law.t_start, law.t_end) == (0.0, 5.0)      # (1.0 − 0.5) / 0.1
    q, v, a = law(np.array([0.0, 2.5]))
    np.testing.assert_allclose(q, [0.5, 0.75])
    assert np.all(v == 0.1) and np.all(a == 0)
    back = ConstantSpeed.over(0.5, -0.05, (0.5, 0.4))   # retracting: t runs forward all the same
    assert (back.t_start, back.t_end) == (0.0, pytest.approx(2.0))
    with pytest.raises(assur.SpecError, match="speed: a time axis needs a nonzero"):
        ConstantSpeed.over(0.5, 0.0, (0.5, 1.0))


def test_cubic_table_reproduces_a_cubic_exactly():
    """A not-a-knot cubic spline through ≥ 4 samples of a cubic polynomial is that polynomial."""
    c = np.array([0.5, 0.02, 0.03, -0.004])             # q = c0 + c1 t + c2 t² + c3 t³
    t_knots = np.array([0.0, 0.7, 1.5, 2.2, 3.0])
    q_knots = np.polyval(c[::-1], t_knots)
    law = TableLaw(tuple(t_knots), tuple(q_knots))
    t = np.linspace(0, 3, 13)
    q, v, a = law(t)
    np.testing.assert_allclose(q, np.polyval(c[::-1], t), rtol=1e-13)
    np.testing.assert_allclose(v, c[1] + 2 * c[2] * t + 3 * c[3] * t ** 2, rtol=1e-12, atol=1e-14)
    np.testing.assert_allclose(a, 2 * c[2] + 6 * c[3] * t, rtol=1e-11, atol=1e-14)


@settings(max_examples=40, deadline=None)
@given(st.lists(st.floats(min_value=1e-3, max_value=0.2), min_size=3, max_size=8),
       st.lists(st.floats(min_value=0.2, max_value=2.0), min_size=8, max_size=8))
def test_pchip_table_is_monotone_between_monotone_values(steps, dts):
    """PCHIP keeps a monotone table monotone (no overshoot), unlike a cubic spline in general."""
    q_knots = 0.5 + np.cumsum([0.0] + steps)
    t_knots = np.cumsum([0.0] + dts[: len(steps)])
    law = TableLaw(tuple(t_knots), tuple(q_knots), "pchip")
    t = np.linspace(t_knots[0], t_knots[-1], 400)
    q, v, _ = law(t)
    assert np.all(np.diff(q) >= -1e-15) and np.all(v >= -1e-12)
    np.testing.assert_allclose(law(t_knots)[0], q_knots, rtol=1e-14)


def test_table_law_is_nan_outside_its_times():
    law = TableLaw((0.0, 1.0, 2.0), (0.5, 0.6, 0.8))
    q, v, a = law(np.array([-0.1, 2.1]))
    assert np.all(np.isnan(q)) and np.all(np.isnan(v)) and np.all(np.isnan(a))


@pytest.mark.parametrize("times, values, kind, where", [
    ((0.0,), (0.5,), "cubic", "law.time"),
    ((0.0, 1.0, 1.0), (0.5, 0.6, 0.7), "cubic", "law.time[2]"),
    ((0.0, 1.0), (0.5,), "cubic", "law.length"),
    ((0.0, 1.0), (0.5, 0.6), "linear", "law.interpolation"),
])
def test_bad_tables_name_the_field(times, values, kind, where):
    with pytest.raises(assur.SpecError) as info:
        TableLaw(times, values, kind)
    assert [p for p, _ in info.value.problems] == [where]


def test_solving_along_a_table_law_uses_the_chain_rule():
    """ω = q̇·dθ/dq and ε = q̇²·d²θ/dq² + q̈·dθ/dq along a non-constant speed, checked against central
    differences in time of the solved angles and positions."""
    plan = assur.compile(assur.load(EXAMPLE))
    law = TableLaw((0.0, 1.0, 2.0, 3.0, 4.0), (0.5, 0.52, 0.6, 0.75, 0.8))
    t = np.linspace(0.3, 3.7, 9)
    h = 1e-4
    st_ = solve_in_time(plan, law, t)
    lo, hi = solve_in_time(plan, law, t - h, order=0), solve_in_time(plan, law, t + h, order=0)
    b = st_.body("driven_rod.cylinder")
    unwrap = lambda x: (x + math.pi) % (2 * math.pi) - math.pi  # noqa: E731
    d_ang = unwrap(hi.body_angle[:, b] - lo.body_angle[:, b])
    d2_ang = unwrap(hi.body_angle[:, b] - st_.body_angle[:, b]) - unwrap(st_.body_angle[:, b] - lo.body_angle[:, b])
    np.testing.assert_allclose(st_.body_omega[:, b], d_ang / (2 * h), rtol=1e-6, atol=1e-9)
    np.testing.assert_allclose(st_.body_alpha[:, b], d2_ang / h ** 2, rtol=1e-4, atol=1e-5)
    iB = plan.point_index("B")
    np.testing.assert_allclose(st_.vel[:, iB], (hi.pos[:, iB] - lo.pos[:, iB]) / (2 * h), rtol=1e-6, atol=1e-10)
    np.testing.assert_allclose(st_.acc[:, iB], (hi.pos[:, iB] - 2 * st_.pos[:, iB] + lo.pos[:, iB]) / h ** 2,
                               rtol=1e-4, atol=1e-6)


def test_one_law_per_input():
    plan = assur.compile(assur.load(EXAMPLE))
    law = ConstantSpeed(0.5, 0.1)
    with pytest.raises(assur.SpecError, match="one time law per input"):
        solve_in_time(plan, [law, law], np.array([0.0]))


# -- the file fields ``range`` and ``law`` -------------------------------------------------------------------
LINEAR = EXAMPLE.read_text(encoding="utf-8")


def with_driver_extra(extra: str) -> str:
    return LINEAR.replace('range = [500, 1000]    # the driving rod\'s length over the working stroke', extra)


def test_example_range_gives_the_driver_law():
    plan = assur.compile(assur.load(EXAMPLE))
    law = driver_law(plan)
    assert isinstance(law, ConstantSpeed)
    assert (law.start, law.speed, law.t_start, law.t_end) == (0.5, 0.1, 0.0, pytest.approx(5.0))


def test_table_law_in_the_file_round_trips():
    text = with_driver_extra('range = [500, 800]\nlaw = { time = [0, 1, 2, 3], length = [500, 560, 680, 740], '
                             'interpolation = "pchip" }')
    m = assur.loads(text)
    d = m.drivers[0]
    assert d.range == pytest.approx((0.5, 0.8)) and d.law.interpolation == "pchip"
    assert d.law.values == pytest.approx((0.5, 0.56, 0.68, 0.74))
    assert assur.loads(assur.dumps(m)) == m
    law = driver_law(assur.compile(m))
    assert isinstance(law, TableLaw)
    np.testing.assert_allclose(law(np.array([0.0, 1.0, 2.0, 3.0]))[0], [0.5, 0.56, 0.68, 0.74], rtol=1e-14)


@pytest.mark.parametrize("extra, where", [
    ("range = [500]", "drivers[0].range"),
    ("range = [500, 500]", "drivers[0].range"),
    ("range = [-1, 500]", "drivers[0].range"),
    ("law = { time = [0, 2, 1], length = [500, 600, 700] }", "drivers[0].law.time[2]"),
    ("law = { time = [0, 1], length = [500, 600, 700] }", "drivers[0].law.length"),
    ("law = { time = [0, 1], length = [500, 600], interpolation = \"spline\" }", "drivers[0].law.interpolation"),
    ("law = { time = [0, 1], length = [500, 600], speed = 3 }", "drivers[0].law.speed"),
])
def test_bad_range_or_law_is_located(extra, where):
    with pytest.raises(assur.SpecError) as info:
        assur.loads(with_driver_extra(extra))
    assert where in [p for p, _ in info.value.problems], info.value.problems


def test_a_linear_driver_without_a_stroke_is_named():
    plan = assur.compile(assur.loads(with_driver_extra("")))
    with pytest.raises(assur.SpecError, match=r"drivers\[0\].range: the linear input 'drive' has no stroke"):
        driver_law(plan)
