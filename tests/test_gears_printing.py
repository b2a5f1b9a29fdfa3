"""What a printer needs from the envelope teeth (assur.gears.teeth, assur.io.cad): rack tip radius, profile shift,
print clearance, bore and face width in the exports.

Independent references: the fillet cut by a rack corner of radius ρ is the offset by ρ of the path of the corner
arc's centre, so its radius of curvature is at least ρ (a sharp corner, ρ = 0, leaves a fillet of radius
≈ h_f²/(r + h_f), 0.19 mm for the gear below: the ridge); the circular-gear tooth thickness on the pitch circle
s = p/2 + 2·x·m·tan α − j_n/(2 cos α) (profile shift x, e.g. Niemann/Winter, Maschinenelemente II, §21.2);
the print clearance c moves each flank into the tooth by c along the pitch curve (its definition), so s − 2c.
"""
import math

import numpy as np
import pytest
import shapely

from assur.gears import GearError
from assur.gears.teeth import ToothParameters, cut_gear

M = 2e-3
Z = 30
R = M * Z / 2
ALPHA = math.radians(20.0)


def circular(a):
    return np.full(np.shape(a), R)


def smallest_concave_radius(xy, ds=2e-5, span=1e-4):
    """Smallest circumradius of point triples ``span`` apart along the outline (resampled every ``ds``) where the
    outline turns clockwise (concave: the fillets and the root of a counter-clockwise gear outline)."""
    closed = np.vstack([xy, xy[:1]])
    seg = np.hypot(*np.diff(closed, axis=0).T)
    s = np.concatenate([[0], np.cumsum(seg)])
    t = np.arange(0, s[-1], ds)
    p = np.column_stack([np.interp(t, s, closed[:, 0]), np.interp(t, s, closed[:, 1])])
    k = int(round(span / ds))
    a, b, c = np.roll(p, k, axis=0), p, np.roll(p, -k, axis=0)
    cross = (b[:, 0] - a[:, 0]) * (c[:, 1] - a[:, 1]) - (b[:, 1] - a[:, 1]) * (c[:, 0] - a[:, 0])
    la, lb, lc = (np.hypot(*(b - c).T), np.hypot(*(a - c).T), np.hypot(*(a - b).T))
    with np.errstate(divide="ignore"):
        radius = la * lb * lc / np.abs(2 * cross)
    concave = cross < 0
    return float(radius[concave].min())


def thickness_on_pitch_circle(xy):
    """Mean length of the outline's pieces on the pitch circle (the teeth there), m, and their number."""
    a = np.linspace(0, 2 * math.pi, 16384, endpoint=False)
    ring = shapely.LinearRing(np.column_stack([R * np.cos(a), R * np.sin(a)]))
    on = shapely.line_merge(shapely.Polygon(xy).intersection(ring))
    pieces = [g.length for g in getattr(on, "geoms", [on])]
    return float(np.mean(pieces)), len(pieces)


def test_tip_radius_removes_the_ridge_at_the_root_fillet():
    rho = 0.38                                   # ISO 53 profile A, in modules
    sharp = cut_gear(circular, ToothParameters(module=M, backlash=0.1e-3), Z)
    round_ = cut_gear(circular, ToothParameters(module=M, backlash=0.1e-3, tip_radius=rho), Z)
    assert smallest_concave_radius(sharp.xy) < 0.3e-3               # the sharp corner's fillet: ≈ 0.19 mm
    assert smallest_concave_radius(round_.xy) >= rho * M * (1 - 0.03)   # ≥ ρ = 0.76 mm within 3 %
    # the root stays where it was (the rounded corner is tangent to the tip line) and the working flanks too
    assert round_.root_radius == pytest.approx(R - 1.25 * M, abs=1e-6)
    # (both within 0.5 µm: the rack states, 256 a pitch, and the outline simplification)
    assert thickness_on_pitch_circle(round_.xy)[0] == pytest.approx(thickness_on_pitch_circle(sharp.xy)[0], abs=0.5e-6)
    assert not round_.defects


@pytest.mark.parametrize("clearance, shift", [(0.1e-3, 0.0), (0.05e-3, 0.3), (0.0, -0.2)])
def test_print_clearance_and_profile_shift_set_the_tooth_thickness(clearance, shift):
    jn = 0.1e-3
    tooth = ToothParameters(module=M, backlash=jn, print_clearance=clearance, profile_shift=shift)
    g = cut_gear(circular, tooth, Z, shift=shift)
    s, count = thickness_on_pitch_circle(g.xy)
    assert count == Z
    expected = math.pi * M / 2 + 2 * shift * M * math.tan(ALPHA) - jn / (2 * math.cos(ALPHA)) - 2 * clearance
    assert s == pytest.approx(expected, abs=0.5e-6)                     # 0.5 µm on the pitch circle
    assert g.tip_radius == pytest.approx(R + (1 + shift) * M, abs=1e-6)
    assert g.root_radius == pytest.approx(R - (1.25 - shift) * M, abs=1e-6)


def test_tip_radius_limits():
    with pytest.raises(GearError, match="tip radius 0.5·m too large"):
        ToothParameters(module=M, tip_radius=0.5).check()               # > c*/(1 − sin α) = 0.38
    with pytest.raises(GearError, match="print clearance must be ≥ 0"):
        ToothParameters(module=M, print_clearance=-1e-4).check()
