"""The co-design law of a geared walking leg (src/assur/codesign/) on examples/walker_fourbar.toml (paper 004's
four-bar leg, docs/papers/004.md).

Every reference is computed independently in the test: the engine's exact derivatives (dpos_dq), scipy's adaptive
quadrature, finite differences, the gear package's own pitch curves (assur.gears.pitch.pitch_pair: radii from the
law's ratio, slopes and curvature by finite differences of the polar curve) and a Cartesian finite-difference
curvature of points on those curves."""
import math
from pathlib import Path

import numpy as np
import pytest

import assur
from assur.analysis.gait import gait_metrics
from assur.errors import SpecError, UnbuildableError
from assur.codesign.checks import gear_checks, pitch_terms
from assur.codesign.law import CodesignLaw, foot_law, foot_law_from_samples, geared_vx_spread, support_window
from assur.codesign.margins import MARGIN_NAMES
from assur.codesign.transfer import CodesignProblem, codesign, optimize_transfer, tradeoff, window_pressure_bound
from assur.gears.pitch import closure_report, pitch_pair

TWO_PI = 2.0 * math.pi
WALKER = Path(__file__).resolve().parents[1] / "examples" / "walker_fourbar.toml"


@pytest.fixture(scope="module")
def plan():
    return assur.compile(assur.load(WALKER))


@pytest.fixture(scope="module")
def foot(plan):
    return foot_law(plan)


@pytest.fixture(scope="module")
def law(foot):
    return CodesignLaw(foot, 0.8)


def _engine_x(plan, q, order=1):
    s = assur.solve(plan, None, np.asarray(q)[:, None], order=2)
    i = plan.point_index("H")
    return (s.pos[:, i, 0], s.dpos_dq[:, i, 0, 0], s.d2pos_dq2[:, i, 0, 0, 0])[order]


# ---------------------------------------------------------------------------------------------------------------
# the foot law


def test_foot_spline_derivative_matches_engine(plan, foot):
    """x′ of the quintic spline against the engine's exact dpos_dq (ground = +x), at the nodes and halfway between
    them, where the spline interpolates; x″ likewise (one order less accurate)."""
    h = TWO_PI / foot.q.size
    for q in (foot.q[::7], foot.q[::7] + 0.5 * h):
        exact = _engine_x(plan, q, 1)
        assert np.max(np.abs(foot.dx(q) - exact)) < 1e-9 * np.max(np.abs(exact))
        assert np.max(np.abs(foot.x_at(q) - _engine_x(plan, q, 0))) < 1e-12
        assert np.max(np.abs(foot.d2x(q) - _engine_x(plan, q, 2))) < 1e-6


def test_foot_contact_arc_and_stride_are_the_gait_metrics(plan, foot):
    """The contact arc is gait_metrics' one; the stride's ends are the engine's x there and span its step length."""
    m = gait_metrics(plan)
    assert (foot.contact_start, foot.contact_end) == (m.contact_start, m.contact_end)
    assert foot.x_max - foot.x_min == pytest.approx(m.step_length, rel=1e-12)
    ends = _engine_x(plan, np.array([m.contact_start, m.contact_end]), 0)
    assert sorted(ends) == pytest.approx([foot.x_min, foot.x_max], abs=1e-15)


def test_support_window_is_the_central_fraction(foot):
    """x(q1), x(q2) are the window's bounds of the stride; q1 < q2 inside the contact arc; x monotone between."""
    for f in (0.5, 0.8, 0.9):
        q1, q2 = support_window(foot, f)
        mid, half = 0.5 * (foot.x_min + foot.x_max), 0.5 * f * (foot.x_max - foot.x_min)
        assert sorted([float(foot.x_at(q1)), float(foot.x_at(q2))]) == pytest.approx([mid - half, mid + half],
                                                                                      abs=1e-13)
        arc = np.mod(np.array([q1, q2]) - foot.contact_start, TWO_PI)
        assert np.all(arc < foot.contact_end - foot.contact_start) and q1 < q2
        assert np.all(foot.dx(np.linspace(q1, q2, 1001)) > 0)   # the paper-004 foot moves +x in support


# ---------------------------------------------------------------------------------------------------------------
# the law


def test_closure_positive_ratio_and_window_law(foot, law):
    assert law.motor_angle(TWO_PI) - law.motor_angle(0.0) == pytest.approx(TWO_PI, abs=1e-12)
    assert law.motor_angle(0.0) == 0.0
    q = np.linspace(0.0, TWO_PI, 20001)
    assert np.all(law.g(q) > 0)
    # on the window g is k·x′ (x increases there): the foot covers equal x per motor radian
    qw = np.linspace(law.q1, law.q2, 101)
    assert np.allclose(law.g(qw), law.k * foot.dx(qw), rtol=1e-14)


def test_joints_are_c2(law):
    """g, g′, g″ from the two sides of each joint (the window's formula at the joint, the transfer polynomial just
    past it and vice versa) agree; the step of 1e-9 rad moves them by at most |next derivative|·1e-9."""
    eps = 1e-9
    for q_joint, inside, outside in ((law.q2, law.q2, law.q2 + eps), (law.q1, law.q1, law.q1 - eps)):
        for fn in (law.g, law.dg, law.d2g):
            a, b = float(fn(inside)), float(fn(outside))
            assert abs(a - b) < 1e-6 * max(1.0, abs(a)), (fn.__name__, q_joint, a, b)
        assert bool(law.in_window(inside)) and not bool(law.in_window(outside))


def test_motor_angle_is_the_integral_of_g(law):
    """τ(q) against scipy's adaptive quadrature of g (breakpoints at the joints)."""
    from scipy.integrate import quad
    for q in (0.7, law.q1 + 0.3, 4.0, 5.5, TWO_PI, TWO_PI + 1.0):
        joints = [p for p in (law.q1, law.q2, law.q1 + TWO_PI) if 0 < p < q]
        ref, _ = quad(lambda t: float(law.g(t)), 0.0, q, points=joints or None, limit=400, epsabs=1e-13,
                      epsrel=1e-13)
        assert float(law.motor_angle(q)) == pytest.approx(ref, rel=1e-11, abs=1e-12)


def test_crank_angle_inverts_and_its_rates(law):
    tau = np.linspace(-1.0, 2.0 * TWO_PI, 97)
    q = law.crank_angle(tau)
    assert np.allclose(law.motor_angle(q), tau, rtol=0, atol=1e-12)
    h = 1e-5
    fd1 = (law.crank_angle(tau + h) - law.crank_angle(tau - h)) / (2 * h)
    assert np.allclose(law.crank_rate(tau), fd1, rtol=1e-8, atol=1e-9)
    h = 1e-3        # second difference: truncation ~h²·q⁗/12, round-off ~1e-16/h²
    fd2 = (law.crank_angle(tau + h) - 2 * q + law.crank_angle(tau - h)) / h ** 2
    assert np.allclose(law.crank_accel(tau), fd2, rtol=1e-5, atol=1e-5)


def test_window_speed_is_constant_through_the_engine(plan, foot, law):
    """The geared leg in motor time, solved by the engine at q(τ) with dq/dt, d²q/dt²: the spread of |v_x| over the
    central 0.8 of the stride is round-off, against 0.366 for the uniform crank (gait_metrics)."""
    uniform = gait_metrics(plan).vx_spread["0.8"]
    assert uniform > 0.3
    measured = geared_vx_spread(law)
    assert measured["0.8"] <= 1e-6
    assert measured["0.9"] < uniform
    # the window's ends are refined: a coarse motor-time grid gives the fine grid's spread over 0.9
    assert geared_vx_spread(law, samples=512)["0.9"] == pytest.approx(measured["0.9"], rel=1e-4)
    # and the speed is the law's ω/k, checked at the window's middle with the engine's velocity
    omega = foot.omega
    q_mid = 0.5 * (law.q1 + law.q2)
    s = assur.solve(plan, None, np.array([[q_mid]]), speeds=np.array([[omega / float(law.g(q_mid))]]), order=1)
    assert abs(s.vel[0, plan.point_index("H"), 0]) == pytest.approx(law.window_speed(omega), rel=1e-9)


@pytest.mark.slow
def test_crank_turning_clockwise_in_time(plan):
    """A leg whose driver speed is negative (q decreases in time): τ grows as q decreases, one motor turn per
    crank turn, and the window speed is still exact through the engine."""
    text = WALKER.read_text(encoding="utf-8").replace('speed = "27 rpm"', 'speed = "-27 rpm"')
    cw = assur.compile(assur.loads(text))
    law = CodesignLaw(foot_law(cw), 0.8)
    assert law.sense == -1
    assert law.motor_angle(-TWO_PI) == pytest.approx(TWO_PI, abs=1e-12)
    assert law.motor_angle(-0.5) > 0
    assert geared_vx_spread(law)["0.8"] <= 1e-6
    pair = pitch_pair(law.transmission_law(), 0.1, samples=512)
    assert closure_report(pair).centre_distance_error < 1e-12


# ---------------------------------------------------------------------------------------------------------------
# gears


@pytest.mark.slow
def test_transmission_law_and_pitch_radii(law):
    tl = law.transmission_law()
    phi = np.linspace(0.0, TWO_PI, 61)
    theta = tl.theta(phi)
    assert np.allclose(tl.phi_of(theta), phi, atol=1e-12)
    assert np.allclose(tl.ratio(phi), 1.0 / law.g(theta), rtol=1e-12)
    L = 0.12
    pair = pitch_pair(tl, L, samples=1024)
    rep = closure_report(pair)
    assert rep.law_end == pytest.approx(TWO_PI, abs=1e-12)
    assert rep.rolling_error < 1e-6
    r1, r2 = pair.contact_radii(phi)
    assert np.allclose(r1, L / (1 + law.g(theta)), rtol=1e-12)


def _numerical_curvature(curve, a, h=1e-4):
    """Signed curvature of a pitch curve from Cartesian central differences of its points (x(a), y(a))."""
    p0, pp, pm = curve.xy_at(a), curve.xy_at(a + h), curve.xy_at(a - h)
    d1 = (pp - pm) / (2 * h)
    d2 = (pp - 2 * p0 + pm) / h ** 2
    return (d1[..., 0] * d2[..., 1] - d1[..., 1] * d2[..., 0]) / np.hypot(d1[..., 0], d1[..., 1]) ** 3


def test_pressure_angle_and_curvature_formulas_against_pitch_pair(law):
    """tan μ = |g′|/(g(1+g)) and the closed-form curvatures against pitch_pair's curves: tan μ = |dr/dα|/r (its
    finite-difference slope), κ from Cartesian finite differences of points on its curves."""
    L = 0.12
    pair = pitch_pair(law.transmission_law(), L, samples=1024)
    q = np.linspace(0.05, TWO_PI - 0.05, 73)
    t = pitch_terms(law.g(q), law.dg(q), law.d2g(q), L)
    a1 = -law.motor_angle(q)                   # the motor's pitch point: body angle −φ
    a2 = math.pi + law.sense * q               # the crank's: body angle π + θ
    for curve, a, name in ((pair.driving, a1, "driving"), (pair.driven, a2, "driven")):
        assert np.allclose(curve.radius_at(a), t[f"r_{name}"], rtol=1e-11)
        tan_mu = np.abs(curve.slope(a)) / curve.radius_at(a)
        assert np.allclose(tan_mu, t["tan_pressure"], rtol=1e-6, atol=1e-8)
        kappa = _numerical_curvature(curve, a)
        assert np.allclose(kappa * L, t[f"kappa_{name}"] * L, rtol=1e-4, atol=1e-4)


def test_gear_checks_against_pitch_pair(law):
    """Perimeter (both curves, pitch_pair's 2¹⁵-point polylines), the tooth count, the concave stretches (sign of
    pitch_pair's curvature) and the maximum pressure angle (its slopes)."""
    L, m = 0.12, 0.002
    c = gear_checks(law, L, module=m)
    pair = pitch_pair(law.transmission_law(), L, samples=2048)
    assert c.perimeter == pytest.approx(pair.driving.perimeter, rel=1e-8)
    assert c.perimeter == pytest.approx(pair.driven.perimeter, rel=1e-8)
    assert c.teeth == round(pair.driven.perimeter / (math.pi * m))
    assert c.module * math.pi * c.teeth == pytest.approx(c.perimeter, rel=1e-14)
    q = np.linspace(0.0, TWO_PI, 4096, endpoint=False)
    kappa = pair.driven.curvature(math.pi + q)
    concave_q = q[kappa < 0]
    assert concave_q.size > 0 and not c.convex["driven"]     # the smoothest bridge leaves the crank gear concave
    for qc in concave_q:
        assert any(lo - 0.01 <= qc <= hi + 0.01 if lo <= hi else (qc >= lo - 0.01 or qc <= hi + 0.01)
                   for lo, hi in c.concave["driven"])
    a = -law.motor_angle(q)
    mu = np.arctan(np.abs(pair.driving.slope(a)) / pair.driving.radius_at(a))
    assert c.max_pressure_angle == pytest.approx(mu.max(), abs=2e-3)
    assert c.ratio_min == pytest.approx(float(np.min(law.g(q))), abs=1e-3)
    assert not c.ok and any("concave" in v for v in c.violations)


def test_margins_agree_with_gear_checks(plan, law):
    """The optimiser's fast margins (its own samples) against gear_checks for the same coefficients."""
    problem = CodesignProblem(plan, 0.8, centre_distance=0.12, module=0.002, n_bumps=len(law.coefficients),
                              ratio_bounds=None)
    m = dict(zip(MARGIN_NAMES, problem.margins(law.coefficients)))
    c = gear_checks(law, 0.12, module=0.002)
    assert m["convex_driven"] == pytest.approx(c.convexity["driven"], abs=2e-2)
    assert m["convex_driving"] == pytest.approx(c.convexity["driving"], abs=2e-2)
    assert math.radians(30) - m["pressure_angle"] == pytest.approx(c.max_pressure_angle, abs=2e-3)
    assert m["ratio_low"] == pytest.approx(c.ratio_min, abs=1e-3)


@pytest.mark.slow
def test_optimized_transfer_makes_a_working_pair(plan):
    """Window 0.8 of the paper-004 leg: six bumps make both pitch curves convex, μ ≤ 30°, 1/3 ≤ g ≤ 3 and no
    undercut (checked by gear_checks, independent of the optimiser's samples), and the window stays exact."""
    d = optimize_transfer(plan, 0.8, centre_distance=0.12, module=0.002, n_bumps=6, seed=1)
    assert d.success and d.checks.ok, d.checks.violations
    assert all(v >= 0 for v in d.margins.values())
    assert d.vx_spread["0.8"] <= 1e-6
    assert d.vx_spread["0.9"] < gait_metrics(plan).vx_spread["0.9"] / 4
    pair = pitch_pair(d.law.transmission_law(), 0.12, samples=2048)
    from assur.gears.pitch import curvature_report
    for curve in (pair.driving, pair.driven):
        assert curvature_report(curve, module=d.checks.module).concave_ranges == ""
    # the tooth generator cuts both gears with the adjusted module, without undercut or outline defects
    from assur.gears.teeth import cut_pair
    teeth = cut_pair(pair, module=d.checks.module)
    assert teeth.notes == () and teeth.driving.teeth == d.checks.teeth


def test_window_pressure_bound(foot, law):
    """No transfer beats the bound: the law's own maximum pressure angle on its window (sampled, from its g) is at
    least the bound, which uses the largest k the closure allows (g > 0 on the transfer)."""
    bound = window_pressure_bound(foot, 0.8)
    q = np.linspace(law.q1, law.q2, 2001)
    mu = np.arctan(pitch_terms(law.g(q), law.dg(q), law.d2g(q), 1.0)["tan_pressure"])
    assert bound <= mu.max()
    assert law.k < 2 * math.pi / (0.8 * foot.stride)


@pytest.mark.slow
def test_tradeoff_rows(plan):
    """Window 0.9 of the paper-004 leg cannot meet μ ≤ 30° (its window bound exceeds it) but is exact at 0.9; window
    0.7 can."""
    rows = tradeoff(plan, (0.7, 0.9), centre_distance=0.12, module=0.002, seed=1, measure=True)
    wide = rows[1]
    assert rows[0]["success"] and not wide["success"]
    assert wide["pressure_bound"] > 30.0 and wide["max_pressure_angle"] >= wide["pressure_bound"] - 1e-6
    assert wide["vx_spread_0.9"] <= 1e-6 and rows[0]["vx_spread_0.9"] > 1e-3


def test_codesign_convenience(plan):
    r = codesign(plan, 0.8, centre_distance=0.12, module=0.002)
    assert r.vx_spread["0.8"] <= 1e-6
    assert r.checks.teeth > 0 and r.law.fraction == 0.8


# ---------------------------------------------------------------------------------------------------------------
# bad input


def _fields(exc):
    return [p for p, _ in exc.value.problems]


@pytest.mark.parametrize("fraction", [0.0, 1.0, 1.5, -0.2, "wide", float("nan")])
def test_bad_fraction(foot, fraction):
    with pytest.raises(SpecError) as exc:
        support_window(foot, fraction)
    assert _fields(exc) == ["fraction"]


def test_leg_without_gait():
    text = WALKER.read_text(encoding="utf-8")
    start, end = text.index("[gait]"), text.index("# -- forces")
    plan = assur.compile(assur.loads(text[:start] + text[end:]))
    with pytest.raises(SpecError) as exc:
        foot_law(plan)
    assert _fields(exc) == ["gait.foot"]


def test_unassemblable_leg(plan):
    params = plan.defaults.copy()
    params[plan.param_index("crank.length")] = 0.6      # longer than the rocker's reach: the crank cannot turn
    with pytest.raises(UnbuildableError, match="cannot turn fully"):
        foot_law(plan, params)


def test_non_monotone_window():
    """A synthetic foot x = −cos q + 0.3 sin 4q on the contact arc [0, π]: x′ = sin q + 1.2 cos 4q < 0 near 45°."""
    q = np.linspace(0.0, TWO_PI, 1024, endpoint=False)
    foot = foot_law_from_samples(-np.cos(q) + 0.3 * np.sin(4 * q), 0.0, math.pi)
    with pytest.raises(SpecError, match="not .*monotone") as exc:
        support_window(foot, 0.9)
    assert _fields(exc) == ["fraction"]
    smooth = foot_law_from_samples(-np.cos(q), 0.0, math.pi)
    q1, q2 = support_window(smooth, 0.9)
    assert -math.cos(q1) == pytest.approx(-0.9, abs=1e-12) and -math.cos(q2) == pytest.approx(0.9, abs=1e-12)


def test_coefficients_that_break_the_law(foot):
    with pytest.raises(SpecError, match="≤ 0") as exc:
        CodesignLaw(foot, 0.8, [-3.0, 0.0, 0.0, 0.0])
    assert _fields(exc) == ["coefficients"]
    with pytest.raises(SpecError) as exc:
        CodesignLaw(foot, 0.8, [float("inf")])
    assert _fields(exc) == ["coefficients"]


@pytest.mark.parametrize("kwargs, field", [({"centre_distance": -1.0}, "centre_distance"),
                                           ({"module": 0.0}, "module"),
                                           ({"module": 1e-320}, "module"),    # infinite teeth: was a traceback
                                           ({"module": 1e-6}, "module"),      # some 10⁵ teeth (at most 10 000)
                                           ({"pressure_angle": 2.0}, "pressure_angle"),
                                           ({"ratio_bounds": (2.0, 1.0)}, "ratio_bounds")])
def test_bad_gear_check_input(law, kwargs, field):
    args = {"centre_distance": 0.12, "module": 0.002} | kwargs
    L = args.pop("centre_distance")
    with pytest.raises(SpecError) as exc:
        gear_checks(law, L, **args)
    assert _fields(exc) == [field]


def test_a_foot_law_asked_for_again_is_the_one_made_and_goes_with_its_plan(monkeypatch):
    """foot_law keeps the laws it made per plan: asked again (same parameters and samples) it gives the same law on the
    plan it was asked for without making it again; other parameters give another law, equal to one made afresh on a
    new compile of the file; and nothing keeps the plan alive."""
    import gc
    import weakref
    from assur.codesign import law as law_module
    plan = assur.compile(assur.load(WALKER))
    first = foot_law(plan, samples=256)
    made = []
    real = law_module._foot_law
    monkeypatch.setattr(law_module, "_foot_law", lambda *a: made.append(len(a)) or real(*a))
    again = foot_law(plan, samples=256)
    assert again.plan is plan and not made
    assert np.array_equal(again.x, first.x) and again.contact_start == first.contact_start
    other = plan.defaults * 1.01
    moved = foot_law(plan, other, samples=256)
    assert len(made) == 1
    fresh = foot_law(assur.compile(assur.load(WALKER)), other, samples=256)
    assert not np.array_equal(moved.x, first.x) and np.array_equal(moved.x, fresh.x)
    gone = weakref.ref(plan)
    del plan, first, again, moved
    gc.collect()
    assert gone() is None
