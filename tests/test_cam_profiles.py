"""Cam profiles by conjugate geometry: pitch curves, profiles, pressure angles and radii of curvature against closed
forms (1e-9) and against an independent envelope of the roller's positions computed here; flat faces, oscillating
followers, undercut and base-circle sizing.

Closed forms (Norton, *Design of Machinery*, 5th ed., §8.7–8.8; *Cam Design and Manufacturing Handbook*, ch. 7):
translating roller follower with offset ε, prime radius R_p, cam turning counter-clockwise under it:
    pressure angle  φ = atan((v − ε) / (s + √(R_p² − ε²)))              (v = ds/dθ)
    in-line pitch-curve radius  ρ = ((R_p + s)² + v²)^{3/2} / ((R_p + s)² + 2v² − a(R_p + s))
and the profile of a roller is the pitch curve offset inward by the roller radius (ρ_profile = ρ − R_f). A flat-faced
translating follower: φ = 0, the contact off the follower's axis by v, ρ = R_b + s + a.
"""
from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.optimize import minimize_scalar

from assur.cams.followers import oscillating, translating
from assur.cams.laws import program
from assur.cams.sizing import base_circle, prime_radius_inline
from assur.errors import SpecError

RISE = 0.02
LAW = program(("cycloidal", 120, RISE), ("dwell", 60), ("cycloidal", 120, -RISE), ("dwell", 60), unit="deg")
RB, RF = 0.04, 0.01


@pytest.mark.parametrize("offset", [0.0, 0.006, -0.008])
def test_translating_roller_against_closed_forms(offset):
    g = translating(LAW, RB, offset=offset, contact="roller", roller_radius=RF)
    c = g.turn_samples(1440)
    s, v, a, _ = LAW.evaluate(c.x)
    Rp = RB + RF
    y = s + math.sqrt(Rp ** 2 - offset ** 2)
    assert np.max(np.abs(c.pressure_angle - np.arctan((v - offset) / y))) <= 1e-9
    # the pitch curve: the roller's centre (ε, y) seen from the cam turned by x
    assert np.max(np.abs(c.pitch - np.exp(-1j * c.x) * (offset + 1j * y))) <= 1e-9 * Rp
    if offset == 0.0:
        rho = ((Rp + s) ** 2 + v ** 2) ** 1.5 / ((Rp + s) ** 2 + 2 * v ** 2 - a * (Rp + s))
        assert np.max(np.abs(c.pitch_radius - rho) / np.abs(rho)) <= 1e-9
        assert np.max(np.abs(c.profile_radius - (rho - RF)) / np.abs(rho)) <= 1e-9
    # the profile is the pitch curve offset inward by the roller radius, along its normal
    tangent = np.gradient(c.pitch, c.x)
    assert np.all(np.abs(np.abs(c.pitch - c.profile) - RF) <= 1e-12)
    cosang = np.real(np.conj(c.pitch - c.profile) * tangent) / (RF * np.abs(tangent))
    assert np.max(np.abs(cosang[1:-1])) <= 1e-4        # ⟂ to the tangent (to the central difference's own error)


def envelope_radius(pitch_fn, gamma, r):
    """The cam's radius along the ray at angle γ (cam frame): the nearest entry of the ray into any roller disc,
    minimised over the cam turn x (a fine grid, then a bounded search). Independent of the profile code: it
    only knows the roller's centre P(x) in the cam frame."""
    xs = np.linspace(0.0, 2 * math.pi, 4097)
    e = np.exp(1j * gamma)

    def entry(x):
        P = pitch_fn(x)
        t = np.real(np.conj(e) * P)
        d = np.imag(np.conj(e) * P)
        entry = t - np.sqrt(np.maximum(r * r - d * d, 0.0))
        return np.where((np.abs(d) < r) & (entry > 0), entry, np.inf)     # discs ahead of the pivot on the ray

    vals = entry(xs)
    i = int(np.argmin(vals))
    h = xs[1] - xs[0]
    best = minimize_scalar(lambda x: float(entry(np.array([x]))[0]), bounds=(xs[i] - h, xs[i] + h), method="bounded",
                           options={"xatol": 1e-13})
    return min(float(vals[i]), float(best.fun))


@pytest.mark.parametrize("offset", [0.0, 0.007])
def test_profile_is_the_envelope_of_the_roller(offset):
    g = translating(LAW, RB, offset=offset, contact="roller", roller_radius=RF)
    c = g.at(np.linspace(0, 2 * math.pi, 37)[:-1])
    Rp = RB + RF

    def pitch(x):
        s = LAW.evaluate(x)[0]
        return np.exp(-1j * x) * (offset + 1j * (s + math.sqrt(Rp ** 2 - offset ** 2)))

    for p in c.profile:
        want = envelope_radius(pitch, np.angle(p), RF)
        assert abs(abs(p) - want) <= 1e-9 * Rp


def test_flat_faced_translating_follower():
    g = translating(LAW, RB, contact="flat")
    c = g.turn_samples(720)
    s, v, a, _ = LAW.evaluate(c.x)
    assert np.max(np.abs(c.pressure_angle)) <= 1e-15
    assert np.max(np.abs(c.profile_radius - (RB + s + a))) <= 1e-12
    # the contact is v off the follower's axis, on the face at height R_b + s
    assert np.max(np.abs(np.abs(c.contact.real) - np.abs(v))) <= 1e-12
    assert np.max(np.abs(c.contact.imag - (RB + s))) <= 1e-12
    assert g.summary()["base_radius"] == pytest.approx(RB, rel=1e-12)


def test_oscillating_roller_pressure_angle_from_the_pitch_curve_normal():
    """The pressure angle of an oscillating roller follower is the angle between the pitch curve's normal (here from
    the pitch curve's tangent by Richardson-extrapolated central differences of its own formula) and the roller
    centre's direction of motion (⟂ the arm)."""
    law = program(("cycloidal", 120, math.radians(20)), ("dwell", 60), ("modified_sine", 120, -math.radians(20)),
                  ("dwell", 60), unit="deg")
    g = oscillating(law, RB, pivot_distance=0.1, arm_length=0.08, contact="roller", roller_radius=RF)
    x = np.linspace(0.05, 2 * math.pi - 0.05, 41)
    c = g.at(x)
    Of, R0, t = g.follower_pivot, g.trace, g.turn

    def world(x):
        d = law.evaluate(x)[0] - law.evaluate(np.asarray(0.0))[0]
        return Of + (R0 - Of) * np.exp(1j * t * d)

    def pitch(x):
        return np.exp(-1j * x) * world(x)

    h = 1e-3
    d1 = (pitch(x + h) - pitch(x - h)) / (2 * h)
    d2 = (pitch(x + h / 2) - pitch(x - h / 2)) / h
    tangent = (4 * d2 - d1) / 3
    n = 1j * tangent                        # outward for a clockwise traversal (i·tangent)
    n_world = np.exp(1j * x) * n / np.abs(n)
    R = world(x)
    motion = 1j * t * (R - Of) / np.abs(R - Of)
    want = np.arctan2(np.imag(np.conj(motion) * n_world), np.real(np.conj(motion) * n_world))
    assert np.max(np.abs(c.pressure_angle - want)) <= 1e-8


def test_undercut_and_roller_radius_limit():
    """A roller larger than the pitch curve's smallest convex radius undercuts the profile; the limit is that radius
    (from the in-line closed form, minimised here over a fine grid and a bounded search)."""
    steep = program(("cycloidal", 60, 0.03), ("cycloidal", 60, -0.03), ("dwell", 240), unit="deg")
    rp = 0.035

    def rho(x):
        s, v, a, _ = steep.evaluate(np.atleast_1d(x))
        r = ((rp + s) ** 2 + v ** 2) ** 1.5 / ((rp + s) ** 2 + 2 * v ** 2 - a * (rp + s))
        return np.where(r > 0, r, np.inf)

    xs = np.linspace(0, 2 * math.pi, 20001)
    i = int(np.argmin(rho(xs)))
    best = minimize_scalar(lambda x: float(rho(x)[0]), bounds=(xs[i - 1], xs[i + 1]), method="bounded",
                           options={"xatol": 1e-13})
    limit = best.fun
    small = translating(steep, rp - 0.5 * limit, roller_radius=0.5 * limit).summary(20000)
    big = translating(steep, rp - 1.2 * limit, roller_radius=1.2 * limit).summary(20000)
    assert not small["undercut"] and big["undercut"]
    assert small["roller_radius_limit"] == pytest.approx(limit, rel=1e-6)


def test_base_circle_for_a_largest_pressure_angle():
    """In-line roller: the smallest prime radius for |φ| ≤ 30° is max (v/tan 30° − s) (closed form); the search finds
    the same base radius, and a cam of that size reaches 30° but not more."""
    alpha = math.radians(30)
    rp = prime_radius_inline(LAW, alpha)
    s, v, _, _ = LAW.evaluate(np.linspace(0, 2 * math.pi, 200001))
    assert rp == pytest.approx(np.max(np.abs(v) / math.tan(alpha) - s), rel=1e-9)
    rb = base_circle(LAW, contact="roller", roller_radius=RF, max_pressure_angle=alpha, samples=20000)
    assert rb + RF == pytest.approx(rp, rel=1e-6)
    peak = translating(LAW, rb, roller_radius=RF).summary(20000)["pressure_angle_max"]
    assert peak <= alpha and peak == pytest.approx(alpha, rel=1e-5)


def test_flat_face_base_circle_from_curvature():
    """Flat-faced translating follower: the profile is convex iff R_b + s + a > 0 everywhere, so the smallest base
    radius is −min(s + a) (Norton, Design of Machinery §8.8)."""
    s, _, a, _ = LAW.evaluate(np.linspace(0, 2 * math.pi, 200001))
    rb = base_circle(LAW, contact="flat", max_pressure_angle=None, min_curvature=1e-9, samples=20000)
    assert rb == pytest.approx(-np.min(s + a), rel=1e-4)


def test_offset_beyond_the_prime_circle_is_refused():
    with pytest.raises(SpecError, match="offset"):
        translating(LAW, RB, offset=0.06, roller_radius=RF)
