"""Wheel-step mover of paper 001: shoe profile (eqs. 1–3), curvature (eqs. 7–9), displacements (eqs. 4–6, 10).

Printed values are from the paper's worked example as restated in docs/papers/001.md §A4; exact identities from
§A3 (section references below are to that page).
"""
import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from assur.errors import SpecError
from assur.gears.wheelstep import STEP_HALF_ANGLE, Shoe, bar_length_for

PAPER = Shoe.from_r_min(0.06, 0.1, 0.02)     # A1: a = 0.06 m, b = 0.1 m, R_min = 0.02 m
STEP = np.linspace(-math.pi / 4, math.pi / 4, 2001)

# shoes with R_min > 0: a, b, and R_min drawn; c from the design rule
shoes = st.builds(Shoe.from_r_min, st.floats(0.01, 0.2), st.floats(0.05, 0.5), st.floats(0.005, 0.5))


def half_unit(printed_digits):
    return 0.5 * 10.0 ** (-printed_digits)


def test_worked_numbers_match_the_printed_digits():
    """A4 table: c = 0.36 m, X_I = 0.6 m, X_II = 0.2027 m, X_01 = 0.8027 m, share 25.25 %."""
    b = PAPER.budget
    assert PAPER.c == pytest.approx(0.36, abs=half_unit(2))
    assert b.crank == pytest.approx(0.6, abs=half_unit(1))
    assert b.rolling == pytest.approx(0.2027, abs=half_unit(4))
    assert b.total == pytest.approx(0.8027, abs=half_unit(4))
    assert 100 * b.rolling_share == pytest.approx(25.25, abs=half_unit(2))
    assert PAPER.r_min == pytest.approx(0.02, abs=1e-15)


def test_budget_equals_the_closed_forms_to_round_off():
    """A4: X_II = (a − b + c)π/2 − 3b (corrected eq. 6) = eq. (10); X_01 = (a − b + c)π/2 + 3b (eq. 4)."""
    a, b, c = PAPER.a, PAPER.b, PAPER.c
    assert PAPER.budget.rolling == pytest.approx((a - b + c) * math.pi / 2 - 3 * b, rel=1e-15)
    assert PAPER.rolling_eq10() == pytest.approx(PAPER.budget.rolling, rel=1e-14)
    assert PAPER.budget.total == pytest.approx((a - b + c) * math.pi / 2 + 3 * b, rel=1e-15)
    # eq. (6) as printed (a copy of eq. 4) would double-count: X_I + (eq. 6 as printed) ≠ X_01 (erratum C.1)
    printed_eq6 = (a - b + c) * math.pi / 2 + 3 * b
    assert PAPER.budget.crank + printed_eq6 == pytest.approx(0.6 + 0.8027, abs=1e-4)


def test_design_rule_inverts_eq9():
    """Eq. (9) rearranged: c = R_min − a + 4b; the shoe built from R_min has R(0) = R_min."""
    assert bar_length_for(0.02, 0.06, 0.1) == pytest.approx(0.36, rel=1e-15)
    assert PAPER.curvature_radius(0.0) == pytest.approx(0.02, rel=1e-13)


def test_profile_at_zero_is_the_bar_end():
    """A2: at φ = 0 the profile point is (0, c), so ρ(0) = c and α(0) = 0."""
    xy = PAPER.profile(0.0)
    assert xy == pytest.approx([0.0, PAPER.c], abs=1e-15)
    rho, alpha = PAPER.profile_polar(0.0)
    assert rho == pytest.approx(PAPER.c) and alpha == 0.0


@settings(max_examples=50, deadline=None)
@given(shoes)
def test_polar_form_reconstructs_the_profile(shoe):
    """ρ·(sin α, cos α) = (X, Y), since α is measured from the OY axis (A2)."""
    rho, alpha = shoe.profile_polar(STEP)
    xy = shoe.profile(STEP)
    np.testing.assert_allclose(np.stack([rho * np.sin(alpha), rho * np.cos(alpha)], -1), xy, atol=1e-14)


@settings(max_examples=50, deadline=None)
@given(shoes)
def test_profile_symmetry(shoe):
    """X is odd and Y even in φ (A2)."""
    p, m = shoe.profile(STEP), shoe.profile(-STEP)
    np.testing.assert_allclose(p[:, 0], -m[:, 0], atol=1e-15)
    np.testing.assert_allclose(p[:, 1], m[:, 1], atol=1e-15)


@settings(max_examples=50, deadline=None)
@given(shoes)
def test_eq7_equals_eq8(shoe):
    """A3: eq. (7) = eq. (8) identically."""
    np.testing.assert_allclose(shoe.curvature_radius_eq7(STEP), shoe.curvature_radius(STEP), rtol=1e-12,
                               atol=1e-15)


@settings(max_examples=50, deadline=None)
@given(shoes)
def test_tangent_turns_with_phi(shoe):
    """A3: (dX/dφ, dY/dφ) = R·(cos φ, −sin φ); and the analytic tangent equals a central difference."""
    t = shoe.profile_tangent(STEP)
    R = shoe.curvature_radius(STEP)
    np.testing.assert_allclose(t, R[:, None] * np.stack([np.cos(STEP), -np.sin(STEP)], -1), atol=1e-13)
    h = 1e-6
    fd = (shoe.profile(STEP + h) - shoe.profile(STEP - h)) / (2 * h)
    np.testing.assert_allclose(fd, t, atol=1e-8)


def test_curvature_radius_matches_a_numerical_curvature_of_the_profile():
    """R(φ) (eq. 8) against κ = |x′y″ − y′x″| / |r′|³ of the profile, by finite differences of eq. (1) only."""
    phi = np.linspace(-math.pi / 4, math.pi / 4, 101)
    h = 1e-4
    p0, pp, pm = PAPER.profile(phi), PAPER.profile(phi + h), PAPER.profile(phi - h)
    d1 = (pp - pm) / (2 * h)
    d2 = (pp - 2 * p0 + pm) / (h * h)
    kappa = np.abs(d1[:, 0] * d2[:, 1] - d1[:, 1] * d2[:, 0]) / np.linalg.norm(d1, axis=1) ** 3
    np.testing.assert_allclose(1 / kappa, PAPER.curvature_radius(phi), rtol=1e-5)


def test_profile_is_convex_and_polar_angle_monotonic():
    """A3: R > 0 on the step for the printed data; α(φ) monotonic; R ranges from R_min to a + c − b."""
    R = PAPER.curvature_radius(STEP)
    assert R.min() == pytest.approx(PAPER.r_min) and R.min() > 0
    assert R.max() == pytest.approx(PAPER.r_step_end)
    assert PAPER.r_step_end == pytest.approx(PAPER.a + PAPER.c - PAPER.b)
    _, alpha = PAPER.profile_polar(STEP)
    assert np.all(np.diff(alpha) > 0)


@settings(max_examples=50, deadline=None)
@given(shoes)
def test_arc_length_equals_rolling_displacement(shoe):
    """A3: the profile's arc length over a step equals X_II (polyline of eq. (1) vs the closed form)."""
    phi = np.linspace(-math.pi / 4, math.pi / 4, 20001)
    arc = np.linalg.norm(np.diff(shoe.profile(phi), axis=0), axis=1).sum()
    assert arc == pytest.approx(shoe.budget.rolling, rel=1e-7)
    assert shoe.rolling_displacement(math.pi / 4) - shoe.rolling_displacement(-math.pi / 4) == \
        pytest.approx(shoe.budget.rolling, rel=1e-13)


@settings(max_examples=50, deadline=None)
@given(shoes)
def test_displacement_splits_into_rolling_and_crank(shoe):
    """B2: X(φ) = ∫₀^φ R + 3b sin 2φ; X(±π/4) = ±X_01/2; the crank part totals X_I = 6b; dX/dφ = rate."""
    X = shoe.displacement(STEP)
    np.testing.assert_allclose(X, shoe.rolling_displacement(STEP) + shoe.crank_displacement(STEP), atol=1e-14)
    assert shoe.displacement(math.pi / 4) == pytest.approx(shoe.budget.total / 2, rel=1e-14)
    assert shoe.crank_displacement(math.pi / 4) - shoe.crank_displacement(-math.pi / 4) == \
        pytest.approx(shoe.budget.crank, rel=1e-14)
    h = 1e-6
    fd = (shoe.displacement(STEP[1:-1] + h) - shoe.displacement(STEP[1:-1] - h)) / (2 * h)
    np.testing.assert_allclose(fd, shoe.displacement_rate(STEP[1:-1]), rtol=1e-7)
    # within a step the rolling rate is R itself
    h_r = (shoe.rolling_displacement(STEP + h) - shoe.rolling_displacement(STEP - h)) / (2 * h)
    np.testing.assert_allclose(h_r, shoe.curvature_radius(STEP), rtol=1e-7)


def test_displacement_repeats_every_step():
    """X(φ + π/2) = X(φ) + X_01 (periodic), and stays increasing across step boundaries."""
    phi = np.linspace(-2.0, 2.0, 4001)
    X = PAPER.displacement(phi)
    np.testing.assert_allclose(PAPER.displacement(phi + 2 * STEP_HALF_ANGLE), X + PAPER.budget.total, atol=1e-13)
    assert np.all(np.diff(X) > 0)
    # the analytic extension agrees inside the step and differs beyond it
    assert PAPER.displacement(0.5, periodic=False) == pytest.approx(PAPER.displacement(0.5))
    assert PAPER.displacement(1.0, periodic=False) != pytest.approx(PAPER.displacement(1.0))


@pytest.mark.parametrize("a,b,c,field,text", [
    (0.06, 0.1, 0.3, "c", "R_min = a − 4b + c = -0.04 m ≤ 0"),
    (-0.06, 0.1, 0.36, "a", "must be a finite length > 0 m: -0.06"),
    (0.06, float("nan"), 0.36, "b", "must be a finite length > 0 m: nan"),
])
def test_bad_shoes_name_the_quantity(a, b, c, field, text):
    with pytest.raises(SpecError) as exc:
        Shoe(a, b, c)
    assert exc.value.problems[0][0] == field
    assert text in exc.value.problems[0][1]
