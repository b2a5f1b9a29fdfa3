"""Paper 001 revisited (src/assur/codesign/wheelstep.py, wheelstep_law.py): the wheel-step drive with the co-design law.

References: the paper's shoe a = 0.06, b = 0.1, c = 0.36 m and X_01 = 0.8027 m (docs/papers/001.md A1, A4, printed);
the displacement law X(θ) = (a − b + c)θ + 1.5b·sin 2θ and the corner of the paper's pitch curves, a tangent turn of
2·atan(|dr/dθ|/r) with the one-sided slope from dk/dφ = ∓6πb/X_01 at the step end (docs/papers/001.md B2, B6.3).
Everything else is computed independently in the tests: the mover's rate from eq. (7)'s radius of curvature plus the
crank part (A3), finite differences, scipy quadrature, the pitch curves' own finite-difference curvature and slope
(assur.gears.pitch.PitchCurve), and the displacement's linearity in the driving angle."""
import json
import math
from pathlib import Path

import numpy as np
import pytest

from assur.errors import SpecError
from assur.gears import WheelStepLaw, closure_report, find_corners, pitch_pair
from assur.codesign.checks import gear_checks
from assur.codesign.wheelstep import (max_tangent_jump, mover_speed_spread, polyline_max_turn, wheelstep_codesign,
                                      window_pressure_bound)
from assur.codesign.wheelstep_law import STEPS, StepDisplacement, WheelStepCodesignLaw
from assur.gears.wheelstep import Shoe
from assur.io.gear_file import load_design

ROOT = Path(__file__).resolve().parents[1]
SMOOTH_FILE = ROOT / "examples" / "gears_001_smooth.toml"
L_P, MODULE = 0.1435, 0.002            # docs/papers/001.md B1: L_p printed, m = 2 mm inferred
X01_PRINTED = 0.8027                   # docs/papers/001.md A4


@pytest.fixture(scope="module")
def shoe():
    return Shoe(0.06, 0.1, 0.36)


@pytest.fixture(scope="module")
def smooth(shoe):
    """f = 0.8 with the smoothest bridge (no optimisation: fast)."""
    return wheelstep_codesign(shoe, 0.8, centre_distance=L_P, module=MODULE, optimize=False, compare=False)


@pytest.fixture(scope="module")
def smooth_pair(smooth):
    return pitch_pair(smooth.law, L_P, samples=4096)


@pytest.fixture(scope="module")
def paper_pair_(shoe):
    return pitch_pair(WheelStepLaw(shoe, driving_turns=2), L_P, samples=4096)


def independent_rate(shoe, theta):
    """X′(θ) = R(θ) by eq. (7) (rolling part) + d/dθ of the crank part 3b·sin 2θ (docs/papers/001.md A3, B2)."""
    return shoe.curvature_radius_eq7(theta) + 6.0 * shoe.b * np.cos(2.0 * theta)


def reduced(theta):
    return theta - np.round(theta / (math.pi / 2)) * (math.pi / 2)


# ---------------------------------------------------------------------------------------------------------------
# the mapping


def test_step_displacement_is_the_mover_displacement(shoe):
    """x(q) = X((q − π)/4): order 0 against the closed form of B2, orders 1–3 against central differences."""
    x = StepDisplacement(shoe)
    q = np.linspace(0.3, 6.0, 23)
    theta = (q - math.pi) / STEPS
    a, b = shoe.a - shoe.b + shoe.c, shoe.b
    assert np.allclose(x(q), a * theta + 1.5 * b * np.sin(2 * theta), atol=1e-15)
    h = 1e-3
    for order in (1, 2, 3):
        fd = (x(q + h, order - 1) - x(q - h, order - 1)) / (2 * h)
        assert np.allclose(x(q, order), fd, rtol=1e-6, atol=1e-9)
    assert x(np.array([2 * math.pi - 1e-12]))[0] == pytest.approx(X01_PRINTED / 2, abs=1e-4)


def test_window_is_the_central_fraction_of_the_step(shoe, smooth):
    t1, t2 = smooth.law.window
    assert t1 == pytest.approx(-t2, abs=1e-12)
    assert abs(shoe.displacement(t2, periodic=False)) == pytest.approx(0.8 * X01_PRINTED / 2, rel=1e-4)


# ---------------------------------------------------------------------------------------------------------------
# closure, continuity, speed, corners


def test_law_closes_and_repeats_every_step(smooth, smooth_pair):
    law = smooth.law
    rep = closure_report(smooth_pair)
    assert rep.law_end == pytest.approx(2 * math.pi, abs=1e-9)
    assert rep.perimeter_ratio == pytest.approx(2.0, rel=1e-6)            # two driving turns per hub turn
    assert rep.centre_distance_error < 1e-12
    assert rep.rolling_error < 1e-6
    theta = np.linspace(-1.0, 1.0, 17)
    assert np.allclose(law.phi_of(theta + math.pi / 2) - law.phi_of(theta), math.pi, atol=1e-12)   # ½ turn/step
    assert np.allclose(law.phi_of(-theta), -law.phi_of(theta), atol=1e-12)                       # symmetric step
    psi = np.linspace(0.0, 4 * math.pi, 29)
    assert np.allclose(law.phi_of(law.theta(psi)), psi, atol=1e-12)


def one_sided(f, x0, side, h=5e-4, points=9, degree=6):
    """(f, f′, f″) at x0 from a polynomial fit to f on one side only (x0 + side·h·i, i = 0 … points − 1)."""
    t = side * h * np.arange(points)
    c = np.polynomial.polynomial.polyfit(t, f(x0 + t), degree)
    return np.array([c[0], c[1], 2 * c[2]])


def test_law_is_c2_at_the_joints_while_the_papers_kinks(shoe, smooth):
    """G = dψ/dθ = 1/k from the gear package's ratio: equal one-sided value, slope and curvature at each joint of
    window and transfer; the same estimator at the paper's step end finds its kink, dG/dθ jumping by 12πb/X_01
    (docs/papers/001.md B6.3: from −6πb/X_01 to +6πb/X_01)."""
    law = smooth.law
    G = lambda t: 1.0 / law.ratio_of_theta(t)   # noqa: E731
    for joint in (*law.window, law.window[0] + math.pi / 2, law.window[1] - math.pi):
        left, right = one_sided(G, joint, -1.0), one_sided(G, joint, +1.0)
        assert abs(left[0] - right[0]) < 1e-12 * left[0]
        assert abs(left[1] - right[1]) < 1e-8 * abs(left[1])           # the fits' own error: ~1e-11, ~1e-7
        assert abs(left[2] - right[2]) < 1e-5 * max(1.0, abs(left[2]))
    paper = WheelStepLaw(shoe, driving_turns=2)
    Gp = lambda t: 1.0 / paper.ratio_of_theta(t)   # noqa: E731
    left, right = one_sided(Gp, math.pi / 4, -1.0), one_sided(Gp, math.pi / 4, +1.0)
    assert abs(left[0] - right[0]) < 1e-12 * left[0]
    assert right[1] - left[1] == pytest.approx(12 * math.pi * shoe.b / shoe.budget.total, rel=1e-6)


def test_mover_speed_is_constant_on_the_window(shoe, smooth, smooth_pair):
    """Speed = X′(θ)·r1/r2 with X′ from eq. (7) + the crank part and r1, r2 the pitch radii at the pitch point;
    and, without derivatives, the displacement is linear in the driving angle on the window."""
    psi = np.arange(40000) * (2 * math.pi / 20000)          # two driving turns, as mover_speed_spread samples
    theta = reduced(smooth_pair.law(psi))
    r1, r2 = smooth_pair.contact_radii(psi)
    speed = independent_rate(shoe, theta) * r1 / r2
    x = shoe.displacement(theta, periodic=False)
    inside = np.abs(x) <= 0.8 * shoe.budget.total / 2
    window = speed[inside]
    assert (window.max() - window.min()) / window.mean() <= 1e-6
    # linearity: one window (the step around θ = 0, ψ ∈ (−π/2, π/2))
    sel = inside & (np.abs(psi - 2 * math.pi) < math.pi / 2)
    p, xs = psi[sel], x[sel]
    fit = np.polynomial.polynomial.polyfit(p, xs, 1)
    assert np.max(np.abs(np.polynomial.polynomial.polyval(p, fit) - xs)) < 1e-9 * shoe.budget.total
    assert fit[1] == pytest.approx(window.mean(), rel=1e-9)
    # outside the window it is not constant: the spread over the central 90 % is that of the samples
    outer = speed[np.abs(x) <= 0.9 * shoe.budget.total / 2]
    measured = mover_speed_spread(smooth_pair, shoe, (0.8, 0.9), samples=20000)
    assert measured["0.8"] <= 1e-6
    assert measured["0.9"] == pytest.approx((outer.max() - outer.min()) / outer.mean(), rel=1e-9)
    assert measured["0.9"] > 1e-3


def test_no_corners_while_the_paper_has_79_55_degree_jumps(shoe, smooth_pair, paper_pair_):
    """The same code on both pairs: find_corners and the largest turn between neighbouring chords of a polyline,
    which halves with the spacing on a smooth curve and stays at the jump at a corner. The paper's jump from B6.3:
    2·atan(|dr/dθ|/r) = 2·atan(|G′|/(G·(1 + G))) at the step end, G = πA/X_01, |G′| = 6πb/X_01."""
    X01, A, b = shoe.budget.total, shoe.a - shoe.b + shoe.c, shoe.b
    G, dG = math.pi * A / X01, 6 * math.pi * b / X01
    expected = 2 * math.atan(dG / (G * (1 + G)))
    assert math.degrees(expected) == pytest.approx(79.55, abs=0.005)
    paper_corners = find_corners(paper_pair_.driving) + find_corners(paper_pair_.driven)
    assert len(find_corners(paper_pair_.driving)) == 2 and len(find_corners(paper_pair_.driven)) == 4
    for c in paper_corners:
        assert abs(c.tangent_jump) == pytest.approx(expected, abs=1e-4)
    assert max_tangent_jump(paper_pair_) == pytest.approx(expected, abs=1e-4)
    assert find_corners(smooth_pair.driving) == [] and find_corners(smooth_pair.driven) == []
    assert max_tangent_jump(smooth_pair) == 0.0
    for curve in (smooth_pair.driving, smooth_pair.driven):
        coarse, fine = polyline_max_turn(curve, 4096), polyline_max_turn(curve, 8192)
        assert fine < math.radians(0.5) and 0.4 < fine / coarse < 0.6
    for curve in (paper_pair_.driving, paper_pair_.driven):
        for n in (4096, 8192):
            assert polyline_max_turn(curve, n) > expected - math.radians(0.5)


# ---------------------------------------------------------------------------------------------------------------
# gear checks


def test_checks_agree_with_the_pitch_curves(smooth, smooth_pair):
    """Closed-form κ, μ, perimeters against the pitch curves' finite-difference curvature and slope and scipy
    quadrature of the arc length."""
    from scipy.integrate import quad
    law, c = smooth.law, smooth.checks
    theta = np.linspace(-math.pi / 4, math.pi / 4, 4001)
    driven_k = smooth_pair.driven.curvature(math.pi + theta) * L_P
    driving_k = smooth_pair.driving.curvature(-law.phi_of(theta)) * L_P
    assert c.convexity["driven"] == pytest.approx(driven_k.min(), rel=1e-3)
    assert c.convexity["driving"] == pytest.approx(driving_k.min(), rel=1e-3)
    r = smooth_pair.driven.radius_at(math.pi + theta)
    mu = np.arctan(np.abs(smooth_pair.driven.slope(math.pi + theta)) / r)
    assert c.max_pressure_angle == pytest.approx(mu.max(), abs=1e-5)

    def ds(t):
        G, dG, _ = law.ratio_terms(np.array([t]))
        return float(np.hypot(L_P * G / (1 + G), L_P * dG / (1 + G) ** 2)[0])
    quarter = sum(quad(ds, a, b, epsabs=1e-13, limit=200)[0] for a, b in
                  ((-math.pi / 4, law.window[0]), (law.window[0], law.window[1]), (law.window[1], math.pi / 4)))
    assert c.driven_perimeter == pytest.approx(4 * quarter, rel=1e-10)
    assert c.driven_perimeter == pytest.approx(smooth_pair.driven.perimeter, rel=1e-7)   # polyline, 2¹⁵ points
    assert c.driving_perimeter == pytest.approx(2 * quarter, rel=1e-10)
    assert c.driven_teeth == 2 * c.driving_teeth and c.driven_teeth % 4 == 0
    assert c.module * math.pi * c.driving_teeth == pytest.approx(c.driving_perimeter, rel=1e-12)
    assert abs(c.module - MODULE) < MODULE * 4 / c.driving_teeth


def test_window_pressure_bound_is_below_every_design(shoe, smooth):
    bound = window_pressure_bound(shoe, 0.8)
    t1, t2 = smooth.law.window
    theta = np.linspace(t1, t2, 2001)
    X1 = independent_rate(shoe, theta)
    X2 = np.gradient(X1, theta)
    K = 1.0 / (smooth.law.ratio_of_theta(0.0) * X1[1000])       # G = K·X′ on the window
    mu = np.arctan(np.abs(X2) / (X1 * (1 + K * X1)))
    assert bound <= mu.max() + 1e-6
    assert K < 2 * math.pi / (2 * 0.8 * shoe.budget.total)


@pytest.mark.slow
def test_optimised_window_of_0_6_passes_every_check_and_0_8_leaves_the_hub_gear_concave(shoe):
    d6 = wheelstep_codesign(shoe, 0.6, centre_distance=L_P, module=MODULE, seed=0, compare=False)
    assert d6.checks.ok and d6.corner == 0.0 and d6.success
    assert d6.speed_spread["0.6"] <= 1e-6
    d8 = wheelstep_codesign(shoe, 0.8, centre_distance=L_P, module=MODULE, seed=0, compare=False)
    pair = pitch_pair(d8.law, L_P)
    assert pair.driven.curvature(math.pi + math.pi / 4) < 0                    # concave at the step end
    assert not d8.checks.ok and d8.checks.concave["driven"] and not d8.checks.concave["driving"]
    assert d8.corner == 0.0


def test_paper_checks_report_its_corner_pressure_angle(shoe):
    """At the step end the paper's pair has the one-sided pressure angle of half its corner (B6.3)."""
    c = gear_checks(WheelStepLaw(shoe, 2), L_P, module=MODULE)
    X01, A, b = shoe.budget.total, shoe.a - shoe.b + shoe.c, shoe.b
    G, dG = math.pi * A / X01, 6 * math.pi * b / X01
    assert c.max_pressure_angle == pytest.approx(math.atan(dG / (G * (1 + G))), abs=1e-9)
    assert not c.ok


# ---------------------------------------------------------------------------------------------------------------
# the shipped gear file


@pytest.mark.slow
def test_shipped_file_is_the_f_0_6_design(shoe):
    design = load_design(SMOOTH_FILE)
    assert design.method == "envelope" and design.driving_teeth == 48 and design.driven_teeth == 96
    pair = design.pair(samples=4096)
    assert pair.driving.perimeter == pytest.approx(48 * math.pi * design.module, rel=1e-6)
    assert max_tangent_jump(pair) == 0.0
    d6 = wheelstep_codesign(shoe, 0.6, centre_distance=L_P, module=MODULE, seed=0, compare=False)
    assert isinstance(d6.law, WheelStepCodesignLaw)
    psi = np.linspace(0.0, 4 * math.pi, 1001)
    assert np.max(np.abs(design.law.theta(psi) - d6.law.theta(psi))) < 1e-8
    spread = mover_speed_spread(pair, shoe, (0.6,))
    assert spread["0.6"] <= 1e-6


@pytest.mark.slow
def test_shipped_file_envelope_teeth_pass_the_outline_and_mesh_checks(tmp_path, capsys):
    from assur.cli.main import main
    out = tmp_path / "g"
    assert main(["gears", str(SMOOTH_FILE), "-o", str(out), "--frames", "0"]) == 0
    capsys.readouterr()
    mesh = json.loads((out / "summary.json").read_text(encoding="utf-8"))["envelope"]["mesh"]
    assert mesh["outline_valid"] and mesh["outline_defects"] == []
    assert not mesh["interference"] and mesh["interfering_positions"] == 0


# ---------------------------------------------------------------------------------------------------------------
# bad input


@pytest.mark.parametrize("kwargs, field", [
    ({"fraction": 1.2}, "fraction"),
    ({"fraction": 0.8, "driving_turns": 3}, "driving_turns"),
    ({"fraction": 0.8, "coefficients": [0.1, 0.2]}, "coefficients"),
    ({"fraction": 0.8, "centre_distance": -1.0}, "centre_distance"),
    ({"fraction": 0.8, "n_bumps": -1}, "n_bumps"),
])
def test_bad_arguments_name_the_field(shoe, kwargs, field):
    args = {"centre_distance": L_P, "module": MODULE, "compare": False, "optimize": False, **kwargs}
    fraction = args.pop("fraction")
    with pytest.raises(SpecError) as err:
        wheelstep_codesign(shoe, fraction, **args)
    assert err.value.problems[0][0] == field
