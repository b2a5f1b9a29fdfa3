"""Teeth cut by a rack along the exact pitch curve (assur.gears.teeth).

Independent references: the involute of the base circle r_b = r·cos α (closed form inv α = tan α − α) for circular
gears; the circular-gear tooth thickness at the pitch circle p/2 − j_n/(2 cos α); the classical undercut limit of a
rack-generated spur gear z_min = 2·h_a*/sin²α (= 17.1 for α = 20°); the elliptic pair about foci, whose law
tan(θ/2) = ((1+e)/(1−e))·tan(φ/2) follows from r1 dφ = r2 dθ with r = p/(1 − e cos) (integrated in the test).
"""
import math
from pathlib import Path

import numpy as np
import pytest
from hypothesis import assume, given, settings, strategies as st

from assur.gears import GearError, pitch_pair
from assur.gears.teeth import ToothParameters, cut_gear, cut_pair, tooth_count

M = 2e-3
ALPHA = math.radians(20.0)


def circular(r):
    return lambda a: np.full(np.shape(a), r)


def inv(x):
    return np.tan(x) - x


def involute_error(outline, r, tooth, z):
    """Largest distance (m) between outline points on the involute band and the exact involute of the base
    circle, for a gear with a tooth centred at ψ = π/z (a space at ψ = 0)."""
    a = tooth.pressure_angle
    rb = r * math.cos(a)
    ha, hf = tooth.addendum_height, tooth.dedendum_height
    # the involute starts where the rack's straight flank ends (its tip line at −h_f): form radius
    form = math.hypot(rb, r * math.sin(a) - hf / math.sin(a))
    psi, rho = outline.angle, outline.radius
    band = (rho > form + 1e-6) & (rho < r + ha - 1e-6)
    pitch_angle = 2 * math.pi / z
    k = np.round((psi - pitch_angle / 2) / pitch_angle)
    rel = np.abs(psi - pitch_angle / 2 - k * pitch_angle)          # angle from the nearest tooth centre
    half_thickness = (0.5 * tooth.pitch - 0.5 * tooth.backlash / math.cos(a)) / (2 * r)
    exact = half_thickness + inv(a) - inv(np.arccos(np.minimum(1.0, rb / rho)))
    return float(np.max(np.abs(rel - exact)[band] * rho[band])), int(band.sum())


def test_circular_flank_is_the_involute_of_the_base_circle():
    z, r = 30, M * 30 / 2
    tooth = ToothParameters(module=M, pressure_angle=ALPHA, backlash=0.1e-3)
    g = cut_gear(circular(r), tooth, z)
    err, n = involute_error(g, r, tooth, z)
    assert n > 50 * z                       # the flanks are densely sampled (160 rays per tooth sector)
    assert err < 1e-8                       # 0.01 µm: exact, not an approximation of the involute
    assert g.root_radius == pytest.approx(r - 1.25 * M, abs=1e-8)     # 10 nm (arcs sampled as polylines)
    assert g.tip_radius == pytest.approx(r + M, abs=1e-8)
    assert not g.undercut and not g.corners


def tooth_thickness_at(g, radius, z):
    """Angular width of the material at ``radius`` around the tooth centred at π/z (rad)."""
    fine = np.linspace(0, 2 * math.pi / z, 4001)
    inside = g.radius_at(fine) >= radius
    return inside.sum() * (fine[1] - fine[0])


@pytest.mark.slow
@settings(max_examples=6, deadline=None)
@given(z=st.integers(18, 60), alpha_deg=st.floats(17.0, 25.0), backlash=st.floats(0.0, 0.1))
def test_circular_tooth_thickness_and_symmetry(z, alpha_deg, backlash):
    assume(z > 2 / math.sin(math.radians(alpha_deg)) ** 2)        # no undercut (classical limit)
    r = M * z / 2
    tooth = ToothParameters(module=M, pressure_angle=math.radians(alpha_deg), backlash=backlash * M)
    g = cut_gear(circular(r), tooth, z)
    expected = (0.5 * tooth.pitch - 0.5 * tooth.backlash / math.cos(tooth.pressure_angle)) / r
    assert tooth_thickness_at(g, r, z) == pytest.approx(expected, abs=2 * math.pi / 4000 / z + 1e-4)
    # z-fold symmetry and mirror symmetry about the tooth centre (geometry, not samples: the rack states fall
    # differently on each tooth, so the vertices differ). Radii along rays: within the simplification tolerance on
    # half the rays and 2 µm on all — a ray that grazes a tip corner turns the corner's discretisation (≲ 0.3 µm: the intersection of
    # the last flank line with the blank polyline) into up to 1/sin(20°) times more along the ray
    a = np.linspace(0, 2 * math.pi / z, 101)
    per = g.radius_at(a[None, :] + (2 * math.pi / z) * np.arange(z)[:, None])
    mirrored = g.radius_at(2 * math.pi / z - a)                   # mirror about ψ = π/z
    # each outline is simplified within SIMPLIFY·m (40 nm at 2 mm), so two of its teeth may differ by that on a ray
    from assur.gears.cutting import SIMPLIFY
    for diff in (np.abs(per - per[0]), np.abs(mirrored - per[0])):
        assert np.median(diff) < SIMPLIFY * M and diff.max() < 2e-6


@pytest.mark.slow
@pytest.mark.parametrize("z, undercut", [(14, True), (16, True), (18, False), (24, False)])
def test_undercut_follows_the_classical_limit(z, undercut):
    # z_min = 2/sin²(20°) = 17.10: below it the rack's straight flank passes the interference point
    assert 2 / math.sin(ALPHA) ** 2 == pytest.approx(17.097, abs=1e-3)
    g = cut_gear(circular(M * z / 2), ToothParameters(module=M), z)
    assert bool(g.undercut) is undercut


def test_tooth_count_must_divide_the_perimeter():
    per = math.pi * M * 40 * 1.01                                   # 40.4 pitches
    with pytest.raises(GearError, match=r"tooth count 40 does not divide the driving pitch perimeter .*40\.4000"):
        tooth_count(per, M, 40)
    assert tooth_count(math.pi * M * 40, M, 40) == (M, 40)
    m, z = tooth_count(per, None, 40)
    assert z == 40 and m == pytest.approx(per / (math.pi * 40))
    with pytest.raises(GearError, match=r"not a whole number of circular pitches .*40\.4000 teeth"):
        tooth_count(per, M, None)


def ellipse(a, e):
    return lambda t: a * (1 - e * e) / (1 - e * np.cos(t))


def elliptic_pair(a=0.04, e=0.3):
    K = (1 + e) / (1 - e)

    def law(phi):
        half = np.arctan(K * np.tan(phi / 2))
        return 2 * half + 2 * math.pi * np.round(phi / (2 * math.pi))   # continuous branch

    return pitch_pair(law, 2 * a), K


def test_elliptic_law_and_pitch_curves_are_the_focal_ellipses():
    a, e = 0.04, 0.3
    pair, K = elliptic_pair(a, e)
    # the law integrates dθ/dφ = r1/r2 with both radii from the ellipse about its focus
    from scipy.integrate import solve_ivp
    r = ellipse(a, e)
    sol = solve_ivp(lambda p, th: r(-p) / r(math.pi + th), (0, 2 * math.pi), [0.0], rtol=1e-11, atol=1e-12,
                    dense_output=True)
    phi = np.linspace(0, 2 * math.pi, 37)
    assert np.max(np.abs(sol.sol(phi)[0] - pair.law(phi))) < 1e-6
    ang = np.linspace(0, 2 * math.pi, 50)
    assert np.max(np.abs(pair.driving.radius_at(ang) - r(ang))) < 1e-7
    assert np.max(np.abs(pair.driven.radius_at(ang) - r(ang))) < 1e-7


@pytest.mark.slow
def test_elliptic_pair_teeth():
    pair, _ = elliptic_pair()
    z = 30
    gt = cut_pair(pair, teeth=z, backlash=0.05 * pair.driving.perimeter / (math.pi * z))
    m = gt.tooth.module
    assert m == pytest.approx(pair.driving.perimeter / (math.pi * z))
    assert gt.driving.teeth == gt.driven.teeth == z
    from scipy.spatial import cKDTree
    for g, curve in ((gt.driving, pair.driving), (gt.driven, pair.driven)):
        dense = curve.xy(200_000)
        dist, _ = cKDTree(dense).query(g.xy)
        outside = g.radius > curve.radius_at(g.angle)
        # tip: the pitch curve offset by h_a = m along its normal; root: offset by h_f = 1.25 m
        assert dist[outside].max() == pytest.approx(m, abs=1e-6)
        assert dist[~outside].max() == pytest.approx(1.25 * m, abs=1e-6)
        assert np.all(np.isfinite(g.radius))
        dr = g.radius - curve.radius_at(g.angle)
        above = dr > 0
        assert int(np.sum(above & ~np.roll(above, 1))) == z    # z teeth: z upward crossings of the pitch curve
    # each outline is symmetric about the major axis (the x axis): the mirrored polygon lies on the polygon, up to
    # the scallop a sharp cutter corner leaves between two of its positions where the root meets the fillet
    # (≈ 0.4 × the corner's step; the step is ≲ 10 µm at 128 cutter positions per pitch: below 5 µm)
    for g in (gt.driving, gt.driven):
        dense = densify(g.xy, 20)
        dist, _ = cKDTree(dense).query(g.xy * np.array([1.0, -1.0]))
        assert np.median(dist) < 1e-9 and dist.max() < 5e-6


def densify(xy, n):
    """Closed polygon (M, 2) with n points per edge."""
    nxt = np.roll(xy, -1, axis=0)
    f = np.arange(n)[None, :, None] / n
    return (xy[:, None, :] + f * (nxt - xy)[:, None, :]).reshape(-1, 2)


@pytest.mark.slow
def test_module_too_large_for_the_curvature():
    # ellipse a = 20 mm, e = 0.6: smallest radius of curvature b²/a = a(1−e²) = 12.8 mm at the major-axis ends;
    # 5 teeth on its ≈ 113 mm perimeter need m ≈ 7.2 mm, tooth depth 2.25·m ≈ 16 mm > 12.8 mm
    pair, _ = elliptic_pair(a=0.02, e=0.6)
    with pytest.raises(GearError, match=r"driving gear: the module 7\.\d+ mm is too large for the curvature .* "
                                        r"radius of curvature 12\.8\d+ mm < tooth depth .* body angle ∈ \["):
        cut_pair(pair, teeth=5)
    cut_pair(pair, teeth=24)     # m ≈ 1.5 mm, depth ≈ 3.4 mm < 12.8 mm: cut


def test_bad_tooth_parameters():
    with pytest.raises(GearError, match="module must be > 0"):
        ToothParameters(module=-1.0).check()
    with pytest.raises(GearError, match="rack cutter comes to a point"):
        ToothParameters(module=M, pressure_angle=math.radians(40), clearance=1.0).check()


@pytest.mark.slow
def test_paper_pair_envelope_outlines_are_simple_and_located():
    # paper 001's pair (docs/papers/001.md), corners rounded: both outlines are simple polygons (GEOS validity,
    # computed by shapely independently of the cut), no two consecutive points farther apart than m/8; where the
    # straight rack cannot follow the driven gear's concave stretches (around its four re-entrant corners at body
    # angles 45°, 135°, 225°, 315°) the thinned teeth are reported with their body angles
    shapely = pytest.importorskip("shapely")
    from assur.io.gear_file import load_design
    from assur.gears.teeth import rounded_pair
    d = load_design(Path(__file__).resolve().parents[1] / "examples" / "gears_001.toml")
    pair = d.pair()
    cut_on, _ = rounded_pair(pair, pair.driving.perimeter / (math.pi * 48), d.pressure_angle)
    gt = cut_pair(cut_on, teeth=48, backlash=d.backlash)
    m = gt.tooth.module
    for g in (gt.driving, gt.driven):
        assert shapely.Polygon(g.xy).is_valid
        assert np.max(np.hypot(*(np.roll(g.xy, -1, axis=0) - g.xy).T)) <= m / 8 * (1 + 1e-9)
    assert not gt.driving.defects
    (found,) = gt.driven.defects
    angles = [float(a) for a in __import__("re").findall(r"(\d+\.\d+)° \(", found)]
    assert angles and all(min(abs((a - c + 180) % 360 - 180) for c in (45, 135, 225, 315)) < 15 for a in angles)
    assert any("thinner" in n for n in gt.notes)
