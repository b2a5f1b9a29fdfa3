"""Pitch curves from a transmission law (assur.gears.pitch / law).

Independent references: the elliptic pair (two equal ellipses about their foci, centre distance 2a,
r(β) = a(1 − e²)/(1 − e cos β), law tan(θ/2) = ((1 + e)/(1 − e))·tan(φ/2), perimeter 4a·E(e²), curvature radius
b²/a at the major vertices) from classical non-circular gear theory (Litvin, "Gear Geometry", elliptical gears);
paper 001's law from docs/papers/001.md B2/B6, the sections cited below (closure, perimeter ratio 2, corners with
jump 2·atan(|dr/dθ|/r)).
"""
import math
import re

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from assur.gears import (GearError, PitchCurve, PitchPair, WheelStepLaw, check_module, closure_report,
                         curvature_report, find_corners, law_from_callable, law_from_ratio, law_from_table,
                         pitch_pair, speed_law)
from assur.gears.wheelstep import Shoe

A, E = 0.05, 0.5
L_P = 0.1435


def ellipse_radius(beta, a=A, e=E):
    return a * (1 - e * e) / (1 - e * np.cos(beta))


def ellipse_law(phi, e=E):
    """θ(φ) for φ ∈ [0, 2π]: 2·atan2(c·sin(φ/2), cos(φ/2)), c = (1 + e)/(1 − e)."""
    c = (1 + e) / (1 - e)
    return 2 * np.arctan2(c * np.sin(phi / 2), np.cos(phi / 2))


def ellipse_ratio(phi, e=E):
    """dθ/dφ of ellipse_law, differentiated by hand: c / (cos²(φ/2) + c² sin²(φ/2))."""
    c = (1 + e) / (1 - e)
    return c / (np.cos(phi / 2) ** 2 + c * c * np.sin(phi / 2) ** 2)


@pytest.fixture(scope="module")
def ellipse_pair():
    return pitch_pair(ellipse_law, 2 * A)


@pytest.fixture(scope="module")
def paper_pair():
    return pitch_pair(WheelStepLaw(Shoe(0.06, 0.1, 0.36)), L_P)


BETA = np.linspace(0, 2 * np.pi, 37)


def test_elliptic_pair_from_callable(ellipse_pair):
    """Both pitch curves are the ellipse about its focus; driving body angle −φ and driven π + θ."""
    np.testing.assert_allclose(ellipse_pair.driving.radius_at(BETA), ellipse_radius(BETA), rtol=1e-9)
    np.testing.assert_allclose(ellipse_pair.driven.radius_at(BETA), ellipse_radius(BETA), rtol=1e-9)
    phi = np.linspace(0, 2 * np.pi, 50, endpoint=False)
    np.testing.assert_allclose(ellipse_pair.law(phi), ellipse_law(phi), atol=1e-10)
    np.testing.assert_allclose(ellipse_pair.ratio(phi), ellipse_ratio(phi), rtol=1e-8)
    r1, r2 = ellipse_pair.contact_radii(phi)
    np.testing.assert_allclose(r1 + r2, 2 * A, rtol=1e-14)
    np.testing.assert_allclose(speed_law(ellipse_pair, phi), r1 / r2, rtol=1e-8)


def test_elliptic_perimeter_and_curvature(ellipse_pair):
    from scipy.special import ellipe
    perimeter = 4 * A * ellipe(E * E)
    assert ellipse_pair.driving.perimeter == pytest.approx(perimeter, rel=1e-7)
    assert ellipse_pair.driven.perimeter == pytest.approx(perimeter, rel=1e-7)
    b = A * math.sqrt(1 - E * E)
    # major vertices (β = 0, π): curvature radius b²/a; minor: a²/b at the ends of the minor axis (not about focus
    # angles, so check the extremes over the curve)
    kappa = ellipse_pair.driving.curvature(np.linspace(0, 2 * np.pi, 4001))
    assert 1 / kappa.max() == pytest.approx(b * b / A, rel=1e-5)
    assert 1 / kappa.min() == pytest.approx(A * A / b, rel=1e-5)
    assert find_corners(ellipse_pair.driving) == []


def test_ratio_and_table_laws_give_the_same_pair(ellipse_pair):
    from_ratio = pitch_pair(ratio=ellipse_ratio, centre_distance=2 * A)
    phi = np.linspace(0, 2 * np.pi, 721)
    from_table = pitch_pair(np.stack([phi, ellipse_law(phi)]), 2 * A)
    for pair in (from_ratio, from_table):
        np.testing.assert_allclose(pair.driving.radius_at(BETA), ellipse_radius(BETA), rtol=1e-6)
        np.testing.assert_allclose(pair.driven.radius_at(BETA), ellipse_radius(BETA), rtol=1e-6)


def test_interface_objects_built_directly_interpolate():
    """G2's use: PitchCurve/PitchPair built from arrays only (no exact function, no law object)."""
    n = 2048
    phi = np.arange(n) * (2 * np.pi / n)
    theta = ellipse_law(phi)
    a1 = np.mod(-phi, 2 * np.pi)
    o = np.argsort(a1)
    driving = PitchCurve(a1[o], ellipse_radius(a1[o]))
    a2 = np.mod(np.pi + theta, 2 * np.pi)
    o2 = np.argsort(a2)
    driven = PitchCurve(a2[o2], ellipse_radius(a2[o2]))
    pair = PitchPair(2 * A, 1, phi, theta, driving, driven)
    np.testing.assert_allclose(driving.radius_at(BETA), ellipse_radius(BETA), rtol=1e-7)
    q = np.linspace(0.1, 6.0, 40)
    np.testing.assert_allclose(pair.law(q), ellipse_law(q), atol=1e-5)
    np.testing.assert_allclose(pair.ratio(q), ellipse_ratio(q), rtol=1e-4)
    assert driving.xy().shape == (n, 2) and driving.xy(100).shape == (100, 2)
    from scipy.special import ellipe
    assert driving.perimeter == pytest.approx(4 * A * ellipe(E * E), rel=1e-7)


def test_paper_pair_closes(paper_pair):
    """B6.1/B6.2: r + r_H = L; θ(4π) = 2π; driven perimeter exactly twice the driver's; rolling arcs equal."""
    rep = closure_report(paper_pair)
    assert rep.law_end == pytest.approx(2 * np.pi, abs=1e-12)
    assert rep.centre_distance_error < 1e-15
    assert rep.perimeter_ratio == pytest.approx(2.0, rel=1e-7)
    assert rep.rolling_error < 1e-5
    assert paper_pair.driving_turns == 2 and paper_pair.phi.size == 2 * 2048


def test_paper_pair_symmetries(paper_pair):
    """B2: the driver curve has period π (two halves), the driven curve period π/2 (four quarters)."""
    a = np.linspace(0, 2 * np.pi, 97)
    np.testing.assert_allclose(paper_pair.driving.radius_at(a + np.pi), paper_pair.driving.radius_at(a), rtol=1e-12)
    np.testing.assert_allclose(paper_pair.driven.radius_at(a + np.pi / 2), paper_pair.driven.radius_at(a),
                               rtol=1e-12)
    np.testing.assert_allclose(paper_pair.driving.radius_at(-a), paper_pair.driving.radius_at(a), rtol=1e-12)


def test_paper_law_ratio_closed_form(paper_pair):
    """B2: k = dθ_paper/dφ_paper = π(a − b + c + 3b cos 2φ)/X_01 (driver per hub), so this package's
    ratio (hub per driver) is 1/k; r_driving = L/(1 + k) with k the paper's; mean of k over a step = 2."""
    a, b, c = 0.06, 0.1, 0.36
    x01 = (a - b + c) * np.pi / 2 + 3 * b
    hub = np.linspace(-np.pi / 4, np.pi / 4, 91)
    k = np.pi * (a - b + c + 3 * b * np.cos(2 * hub)) / x01
    driver = np.pi * ((a - b + c) * hub + 1.5 * b * np.sin(2 * hub)) / x01
    np.testing.assert_allclose(paper_pair.law(np.mod(driver, 4 * np.pi)), np.mod(hub, 2 * np.pi), atol=1e-12)
    np.testing.assert_allclose(paper_pair.ratio(driver), 1 / k, rtol=1e-12)
    r1, _ = paper_pair.contact_radii(driver)
    np.testing.assert_allclose(r1, L_P / (1 + k), rtol=1e-12)
    assert np.trapezoid(k, hub) / (np.pi / 2) == pytest.approx(2.0, rel=1e-3)


def test_paper_corners(paper_pair):
    """B6.3: driver convex vertices at ±90°, driven re-entrant corners at ±45°, ±135°, with tangent jump
    2·atan(|dr/dθ|/r), dr/dθ = −L·k′/((1 + k)²·k), k′ = −6πb sin 2φ/X_01 one-sided at φ = π/4."""
    a, b, c = 0.06, 0.1, 0.36
    x01 = (a - b + c) * np.pi / 2 + 3 * b
    k = np.pi * (a - b + c) / x01
    dk = -6 * np.pi * b / x01
    jump = 2 * math.atan(abs(-L_P * dk / ((1 + k) ** 2 * k)) / (L_P / (1 + k)))
    assert 10 < math.degrees(jump) < 90      # "large (tens of degrees)"
    drv = find_corners(paper_pair.driving)
    assert [round(math.degrees(c.angle), 6) for c in drv] == [90.0, 270.0]
    assert all(c.kind == "convex" and c.tangent_jump == pytest.approx(jump, abs=math.radians(0.001)) for c in drv)
    dvn = find_corners(paper_pair.driven)
    assert [round(math.degrees(c.angle), 6) for c in dvn] == [45.0, 135.0, 225.0, 315.0]
    assert all(c.kind == "re-entrant" and -c.tangent_jump == pytest.approx(jump, abs=math.radians(0.001))
               for c in dvn)
    # the driver has its maximum radius at the vertex and is slightly concave just before it
    rep = curvature_report(paper_pair.driving, module=0.002)
    assert rep.concave_ranges and "89" in rep.concave_ranges
    assert paper_pair.driving.radius_at(np.pi / 2) == pytest.approx(L_P / (1 + k), rel=1e-12)


def test_undercut_check():
    """Ellipse: smallest radius of curvature b²/a = 37.5 mm; the limit m/sin²20° exceeds it for m = 5 mm."""
    pair = pitch_pair(ellipse_law, 2 * A)
    check_module(pair, 0.002)                     # 17.1 mm < 37.5 mm: fine
    with pytest.raises(GearError, match=r"module 5 mm is too large for the curvature of the driving pitch curve"):
        check_module(pair, 0.005)
    rep = curvature_report(pair.driving, module=0.005)
    assert rep.min_convex_radius == pytest.approx(A * (1 - E * E), rel=1e-5)
    assert rep.undercut_limit == pytest.approx(0.005 / math.sin(math.radians(20)) ** 2)


def _degrees_in(message):
    return [float(x) for x in re.findall(r"(-?\d+\.\d)°", message)]


def test_negative_radius_names_the_angle_range():
    """k = 1 + 1.5 cos φ ≤ 0 where cos φ ≤ −2/3: φ ∈ [131.8°, 228.2°]."""
    with pytest.raises(GearError) as exc:
        pitch_pair(ratio=lambda p: 1 + 1.5 * np.cos(p), centre_distance=0.1)
    msg = str(exc.value)
    assert "dθ/dφ" in msg and "≤ 0" in msg
    lo, hi = _degrees_in(msg)[:2]
    edge = math.degrees(math.acos(-2 / 3))
    assert lo == pytest.approx(edge, abs=0.2) and hi == pytest.approx(360 - edge, abs=0.2)
    with pytest.raises(GearError, match=r"not increasing .* for φ ∈ \["):
        law_from_callable(lambda p: p + 1.5 * np.sin(p))


def test_law_that_does_not_close():
    with pytest.raises(GearError, match=r"the law does not close: θ\(2π·1\) = 351.0000°, must be 360°"):
        pitch_pair(lambda p: 0.975 * p, 0.1)
    with pytest.raises(GearError, match=r"∫k dφ over one driving turn = 378.0000°, must be 360°/1"):
        law_from_ratio(lambda p: 1.05 + 0.2 * np.cos(p))
    with pytest.raises(GearError, match=r"θ after one driving turn = 170.0000°, must be 360°/2 = 180.0000°"):
        law_from_table(np.radians([0, 90, 180, 270, 360]), np.radians([0, 40, 90, 130, 170]), driving_turns=2)


def test_driving_curve_that_does_not_close():
    """n = 2: θ(4π) = 2π, but θ(φ + 2π) − θ(φ) ≠ π, so the driving curve differs on its two turns."""
    with pytest.raises(GearError, match=r"the driving pitch curve does not close"):
        pitch_pair(lambda p: p / 2 + 0.1 * np.sin(p / 2), 0.1, driving_turns=2)


@pytest.mark.parametrize("L", [0.0, -0.1, float("nan"), float("inf"), None])
def test_bad_centre_distance(L):
    with pytest.raises(GearError, match="centre distance must be a finite length > 0 m"):
        pitch_pair(ellipse_law, L)


@settings(max_examples=10, deadline=None)
@given(st.floats(0.0, 0.6), st.integers(1, 3), st.floats(0.01, 1.0))
def test_fourier_ratio_laws_roll_and_close(amp, n, L):
    """Any positive 2π-periodic k with mean 1/n: r1 + r2 = L, driven/driving perimeter = n, equal rolling arcs."""
    ratio = lambda p: (1 + amp * np.cos(p) + 0.1 * amp * np.sin(2 * p)) / n   # noqa: E731
    pair = pitch_pair(ratio=ratio, centre_distance=L, driving_turns=n, samples=512)
    rep = closure_report(pair, steps=16)
    assert rep.perimeter_ratio == pytest.approx(n, rel=1e-6)
    assert rep.centre_distance_error < 1e-12 * L
    assert rep.rolling_error < 1e-6
    assert rep.law_end == pytest.approx(2 * np.pi, abs=1e-9)


def test_rounded_wheelstep_law_has_smooth_closed_pitch_curves():
    """B7.8 (round off the corner): with rounding δ the law stays closed and increasing, its rate is the
    derivative of its angle (central differences), the pitch curves have no corners, and the mover speed is exactly
    nominal outside the rounded zones and lower inside them (the cost of smoothing)."""
    shoe = Shoe(0.06, 0.1, 0.36)
    delta = math.radians(10)
    law = WheelStepLaw(shoe, rounding=delta)
    t = np.linspace(-3, 3, 1201)
    h = 1e-6
    fd = (law.phi_of(t + h) - law.phi_of(t - h)) / (2 * h)
    np.testing.assert_allclose(fd, 1 / law.ratio_of_theta(t), rtol=1e-8)
    assert law.phi_of(np.pi / 4) == pytest.approx(np.pi / 2, rel=1e-14)
    pair = pitch_pair(law, L_P)
    assert find_corners(pair.driving) == [] and find_corners(pair.driven) == []
    assert closure_report(pair).perimeter_ratio == pytest.approx(2.0, rel=1e-7)
    hub = np.linspace(-np.pi / 4, np.pi / 4, 2001)
    speed = law.mover_speed_ratio(hub)
    outside = np.abs(hub) < np.pi / 4 - delta
    np.testing.assert_allclose(speed[outside], speed[outside][0], rtol=1e-12)
    assert speed[outside][0] > 1 and speed.min() < 0.9
    assert np.all(WheelStepLaw(shoe).mover_speed_ratio(hub) == pytest.approx(1.0, rel=1e-14))
    with pytest.raises(GearError, match="corner rounding"):
        WheelStepLaw(shoe, rounding=math.radians(30))


def _rotate(xy, angle):
    c, s = np.cos(angle), np.sin(angle)
    return np.stack([c * xy[..., 0] - s * xy[..., 1], s * xy[..., 0] + c * xy[..., 1]], axis=-1)


@pytest.mark.parametrize("which", ["ellipse", "paper"])
def test_pitch_points_meet_on_the_line_of_centres(which, ellipse_pair, paper_pair):
    """Module convention: driver turned ccw by φ, driven (centre (L, 0)) cw by θ(φ); both pitch points land on
    (r1, 0), and the curves are tangent there (equal tangent directions after placement)."""
    pair = ellipse_pair if which == "ellipse" else paper_pair
    L = pair.centre_distance
    phi = np.linspace(0.05, 2 * np.pi * pair.driving_turns - 0.05, 31)
    theta = pair.law(phi)
    p1 = _rotate(pair.driving.xy_at(-phi), phi)
    p2 = _rotate(pair.driven.xy_at(np.pi + theta), -theta) + [L, 0]
    r1, _ = pair.contact_radii(phi)
    np.testing.assert_allclose(p1, np.stack([r1, 0 * r1], -1), atol=1e-12)
    np.testing.assert_allclose(p2, p1, atol=1e-12)
    h = 1e-6
    t1 = _rotate(pair.driving.xy_at(-phi + h) - pair.driving.xy_at(-phi - h), phi)
    t2 = _rotate(pair.driven.xy_at(np.pi + theta + h) - pair.driven.xy_at(np.pi + theta - h), -theta)
    cross = t1[:, 0] * t2[:, 1] - t1[:, 1] * t2[:, 0]
    np.testing.assert_allclose(cross / (np.linalg.norm(t1, axis=1) * np.linalg.norm(t2, axis=1)), 0, atol=1e-6)


@settings(max_examples=20, deadline=None)
@given(st.sampled_from([1, 2, 4]), st.floats(-20, 20))
def test_wheelstep_law_inverse_and_periodicity(n, phi):
    """θ(φ(θ)) = θ; θ(φ + 2π) = θ(φ) + 2π/n; one hub step (π/2) takes n·π/2 of the driver."""
    law = WheelStepLaw(Shoe(0.06, 0.1, 0.36), driving_turns=n)
    assert law.phi_of(law.theta(phi)) == pytest.approx(phi, abs=1e-12)
    assert law.theta(phi + 2 * np.pi) == pytest.approx(law.theta(phi) + 2 * np.pi / n, abs=1e-12)
    assert law.phi_of(np.pi / 4) - law.phi_of(-np.pi / 4) == pytest.approx(n * np.pi / 2, rel=1e-14)


def test_corner_between_grid_points_of_a_ratio_law():
    """k = 1 + 0.3(|sin(φ − 0.7)| − 2/π) (mean 1) has kinks at φ = 0.7 and 0.7 + π, off every sample grid. On the
    driving curve (body angle −φ) they are re-entrant corners with jump 2·atan(|r′|/r), r = Lk/(1 + k),
    |r′| = 0.3·L/(1 + k)² (one-sided dr/dφ = L·k′/(1 + k)², k′ = ±0.3), i.e. |r′|/r = 0.3/(k(1 + k))."""
    L = 0.1
    pair = pitch_pair(ratio=lambda p: 1 + 0.3 * (np.abs(np.sin(p - 0.7)) - 2 / np.pi), centre_distance=L)
    k = 1 - 0.6 / np.pi
    jump = 2 * math.atan(0.3 / (k * (1 + k)))
    corners = find_corners(pair.driving)
    assert [c.kind for c in corners] == ["re-entrant", "re-entrant"]
    np.testing.assert_allclose([c.angle for c in corners], np.sort(np.mod([-0.7, -0.7 - np.pi], 2 * np.pi)),
                               atol=1e-3)
    for c in corners:
        assert -c.tangent_jump == pytest.approx(jump, abs=math.radians(0.1))


def test_the_old_name_of_a_pitch_pair_warns_and_is_the_same_class():
    """A pair of pitch curves is a PitchPair; its old name GearPair (also the name of a mechanism's gear pair,
    assur.model.gearing.GearPair) stays importable for one release, with a DeprecationWarning naming PitchPair."""
    import assur.gears
    import assur.gears.pitch
    from assur.model.gearing import GearPair as MechanismGearPair
    for module in (assur.gears.pitch, assur.gears):
        with pytest.warns(DeprecationWarning, match=r"GearPair is deprecated: use PitchPair"):
            old = module.GearPair
        assert old is PitchPair and old is not MechanismGearPair
    with pytest.warns(DeprecationWarning, match="use PitchPair"):
        from assur.gears.pitch import GearPair  # noqa: F401
    assert "GearPair" not in assur.gears.__all__ and "PitchPair" in assur.gears.__all__
    with pytest.raises(AttributeError):
        assur.gears.pitch.NoSuchPair
