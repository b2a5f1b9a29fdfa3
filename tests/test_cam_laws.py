"""Cam motion laws: SVAJ against closed forms (1e-12), continuity (the fundamental law of cam design), and Norton's
double-dwell cam (Design of Machinery, Examples 8-1 and 8-2) reproduced.

References:
- R. L. Norton, *Cam Design and Manufacturing Handbook*, 2nd ed. (Industrial Press, 2009), ch. 3: the closed forms
  of the simple harmonic, cycloidal, 3-4-5 and 4-5-6-7 polynomial rises, and the definitions of the modified
  trapezoid and modified sine accelerations (sinusoid and constant pieces at 1/8, 3/8, 5/8, 7/8 of the rise and
  at 1/8, 7/8). Their peak factors C_v, C_a, C_j (Norton, Table 3-2 of the handbook; Table 8-3 of *Design of
  Machinery*): modified trapezoid 2.000, 4.888, 61.43; modified sine 1.760, 5.528, 69.47; cycloidal 2.000, 6.283,
  39.48; 3-4-5 1.875, 5.777, 60.00.
- Norton, *Design of Machinery*, 5th ed., Example 8-1 (dwell 90°, rise 1 in in 90°, dwell 90°, fall 1 in in 90°,
  ω = 2π rad/s, simple harmonic: peak velocity 6.28 in/s, acceleration 79 in/s², infinite jerk at the dwells)
  and Example 8-2 (the same with cycloidal rise and fall: 8.00 in/s, 100.5 in/s², 2 527 in/s³, no discontinuity).
"""
from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.integrate import quad

from assur.cams.laws import continuity, peaks, program, spline, svaj
from assur.errors import SpecError
from assur.kernels.cam_motion import LAWS, normalised, segment

PI = math.pi
U = np.linspace(0.0, 1.0, 1001)


def closed_form(law, u):
    """Norton's closed forms of the normalised rise (written here, independently of the kernel)."""
    if law == "harmonic":
        return (1 - np.cos(PI * u)) / 2, PI / 2 * np.sin(PI * u), PI ** 2 / 2 * np.cos(PI * u), -PI ** 3 / 2 * np.sin(PI * u)
    if law == "cycloidal":
        return (u - np.sin(2 * PI * u) / (2 * PI), 1 - np.cos(2 * PI * u), 2 * PI * np.sin(2 * PI * u),
                4 * PI ** 2 * np.cos(2 * PI * u))
    if law == "polynomial_345":
        return (10 * u ** 3 - 15 * u ** 4 + 6 * u ** 5, 30 * u ** 2 - 60 * u ** 3 + 30 * u ** 4,
                60 * u - 180 * u ** 2 + 120 * u ** 3, 60 - 360 * u + 360 * u ** 2)
    if law == "polynomial_4567":
        return (35 * u ** 4 - 84 * u ** 5 + 70 * u ** 6 - 20 * u ** 7,
                140 * u ** 3 - 420 * u ** 4 + 420 * u ** 5 - 140 * u ** 6,
                420 * u ** 2 - 1680 * u ** 3 + 2100 * u ** 4 - 840 * u ** 5,
                840 * u - 5040 * u ** 2 + 8400 * u ** 3 - 4200 * u ** 4)
    raise KeyError(law)


@pytest.mark.parametrize("law", ["harmonic", "cycloidal", "polynomial_345", "polynomial_4567"])
def test_closed_form_laws_equal_their_textbook_forms(law):
    got = normalised(law, U)
    for g, want in zip(got, closed_form(law, U)):
        assert np.max(np.abs(g - want)) <= 1e-12 * max(1.0, np.max(np.abs(want)))


def _piecewise_acceleration(law):
    """Norton's definition of the acceleration of the modified laws, with its peak A from y(1) = 1 (found here by
    quadrature, not from the kernel's closed form)."""
    if law == "modified_trapezoid":
        def shape(u):
            if u <= 1 / 8:
                return math.sin(4 * PI * u)
            if u <= 3 / 8:
                return 1.0
            if u <= 5 / 8:
                return math.cos(4 * PI * (u - 3 / 8))
            if u <= 7 / 8:
                return -1.0
            return -math.cos(4 * PI * (u - 7 / 8))
        breaks = [1 / 8, 3 / 8, 5 / 8, 7 / 8]
    else:
        def shape(u):
            if u <= 1 / 8:
                return math.sin(4 * PI * u)
            if u <= 7 / 8:
                return math.cos(4 * PI / 3 * (u - 1 / 8))
            return -math.cos(4 * PI * (u - 7 / 8))
        breaks = [1 / 8, 7 / 8]

    def integral(f, b):
        pts = [x for x in breaks if x < b]
        return quad(f, 0.0, b, points=pts or None, epsabs=1e-14, epsrel=1e-13, limit=200)[0]

    def vel(u, A=1.0):
        return A * integral(shape, u)

    y1 = quad(lambda t: vel(t), 0.0, 1.0, points=breaks, epsabs=1e-14, epsrel=1e-13, limit=200)[0]
    A = 1.0 / y1
    return shape, vel, A, integral


@pytest.mark.parametrize("law", ["modified_trapezoid", "modified_sine"])
def test_modified_laws_integrate_their_defining_acceleration(law):
    shape, vel, A, integral = _piecewise_acceleration(law)
    y, y1, y2, _ = normalised(law, U)
    want_a = A * np.array([shape(u) for u in U])
    want_v = np.array([vel(u, A) for u in U])
    want_s = np.array([quad(lambda t: vel(t, A), 0.0, u, epsabs=1e-14, epsrel=1e-13, limit=200)[0] for u in U[::50]])
    assert np.max(np.abs(y2 - want_a)) <= 1e-12 * A
    assert np.max(np.abs(y1 - want_v)) <= 1e-12 * A
    assert np.max(np.abs(y[::50] - want_s)) <= 1e-12


@pytest.mark.parametrize("law,cv,ca,cj", [("modified_trapezoid", 2.000, 4.888, 61.43), ("modified_sine", 1.760, 5.528,
                                           69.47), ("cycloidal", 2.000, 6.283, 39.48)])
def test_peak_factors_match_nortons_table(law, cv, ca, cj):
    y, y1, y2, y3 = normalised(law, np.linspace(0, 1, 200001))
    assert round(np.max(np.abs(y1)), 3) == cv
    assert round(np.max(np.abs(y2)), 3) == ca
    assert round(np.max(np.abs(y3)), 2) == pytest.approx(cj, abs=0.011)


def test_polynomial_345_peaks_are_exact():
    """y′ peaks at u = 1/2 (15/8), y″ where y‴ = 0, u = (3 − √3)/6 (10/√3), y‴ at u = 0 (60)."""
    y, y1, y2, y3 = normalised("polynomial_345", np.array([0.5, (3 - math.sqrt(3)) / 6, 0.0]))
    assert abs(y1[0] - 15 / 8) <= 1e-14 and abs(y2[1] - 10 / math.sqrt(3)) <= 1e-13 and abs(y3[2] - 60) <= 1e-13


@pytest.mark.parametrize("law", LAWS)
def test_derivatives_are_derivatives(law):
    """Each of v, a, j is the derivative of the one before (central differences, Richardson-extrapolated)."""
    u = np.linspace(0.02, 0.98, 49) + 1e-3          # off the pieces' boundaries
    h = 1e-3

    def d(f, k):
        a = (f(u + h)[k] - f(u - h)[k]) / (2 * h)
        b = (f(u + h / 2)[k] - f(u - h / 2)[k]) / h
        return (4 * b - a) / 3

    f = lambda x: normalised(law, x)   # noqa: E731
    for k in range(3):
        assert np.max(np.abs(d(f, k) - f(u)[k + 1])) <= 1e-7 * max(1.0, np.max(np.abs(f(u)[k + 1])))


def test_segment_scales_rise_and_return():
    th = np.linspace(1.0, 2.0, 11)
    s, v, a, j = segment("cycloidal", th, 1.0, 1.0, -0.02, 0.05)
    y = closed_form("cycloidal", th - 1.0)
    assert np.allclose(s, 0.05 - 0.02 * y[0], atol=1e-15) and np.allclose(v, -0.02 * y[1], atol=1e-15)
    assert np.allclose(a, -0.02 * y[2], atol=1e-15) and np.allclose(j, -0.02 * y[3], atol=1e-15)


IN = 0.0254


def test_nortons_double_dwell_cam_examples_8_1_and_8_2():
    """Design of Machinery, Examples 8-1 (simple harmonic: 6.28 in/s, 79 in/s², infinite jerk) and 8-2 (cycloidal:
    8.00 in/s, 100.5 in/s², 2527 in/s³, continuous acceleration) at ω = 2π rad/s."""
    shm = program(("dwell", 90), ("harmonic", 90, IN), ("dwell", 90), ("harmonic", 90, -IN), unit="deg")
    cyc = program(("dwell", 90), ("cycloidal", 90, IN), ("dwell", 90), ("cycloidal", 90, -IN), unit="deg")
    p = peaks(shm, speed=2 * PI)
    assert round(p["v"] / IN, 2) == 6.28 and round(p["a"] / IN) == 79
    c = continuity(shm)
    assert not c.ok and c.smooth == 1 and [b.order for b in c.boundaries] == [2, 2, 2, 2]
    assert "infinite jerk" in c.findings()[0]
    p = peaks(cyc, speed=2 * PI)
    assert round(p["v"] / IN, 2) == 8.00 and round(p["a"] / IN, 1) == 100.5 and round(p["j"] / IN) == 2527
    c = continuity(cyc)
    assert c.ok and c.smooth == 2 and not c.findings()


def test_spline_law_is_c2_and_passes_through_its_points():
    angles = [0, 60, 120, 200, 280]
    lifts = [0.0, 0.004, 0.012, 0.009, 0.002]
    law = spline(angles, lifts, unit="deg")
    s = svaj(law, np.radians(angles)).s
    assert np.max(np.abs(s - lifts)) <= 1e-15
    c = continuity(law)
    assert c.smooth == 2 and c.ok                    # s, v, a continuous at every knot (the jerk jumps)
    assert all(b.order == 3 for b in c.boundaries)
    # periodic: the value and the first two derivatives agree across the turn's end
    a0 = svaj(law, [0.0]), svaj(law, [2 * PI - 1e-9])
    for q in ("s", "v", "a"):
        assert abs(getattr(a0[0], q)[0] - getattr(a0[1], q)[0]) <= 1e-7


def test_program_errors_are_located():
    with pytest.raises(SpecError, match=r"segments\[1\]"):
        program(("dwell", 180), ("wiggle", 180, 1.0), unit="deg")
    with pytest.raises(SpecError, match="not 360"):
        program(("dwell", 180), ("cycloidal", 90, 0.01), unit="deg")
    with pytest.raises(SpecError, match="does not close"):
        program(("dwell", 180), ("cycloidal", 180, 0.01), unit="deg")


def test_svaj_in_time_scales_by_the_speed():
    law = program(("cycloidal", 180, 0.01), ("cycloidal", 180, -0.01), unit="deg")
    a, b = svaj(law, samples=64), svaj(law, samples=64, speed=3.0)
    assert np.allclose(b.v, 3 * a.v) and np.allclose(b.a, 9 * a.a) and np.allclose(b.j, 27 * a.j)
