"""Closed-form kinetostatics of the slider-crank, derived by hand, against ``assur.forces``.

The references are the classical statics of the slider-crank, derived in each test's docstring and
computed in the test (no number here is copied from the program's output):

* the crank effort of an in-line slider-crank loaded at the piston, T = F·r·sin(θ + β)/cos β with
  sin β = r·sin θ / l (the connecting rod a two-force member; e.g. the "crank effort" of the
  inertia-forces chapter of Khurmi & Gupta's or Rattan's Theory of Machines);
* the same with Coulomb slide friction μ at the piston, at θ = 90°;
* a published example to its printed digits: the horizontal steam engine of Khurmi & Gupta's Theory of
  Machines, Example 15.7 (slide-bar reaction, rod thrust, crank-pin force, turning moment), with its
  reciprocating mass at speed (see the comment above its tests for the source and the book's method).
"""
from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest

import assur
from assur.model.dynamics import Dynamics, Friction, Load, MassProperties


def with_dynamics(m, dyn):
    return dataclasses.replace(m, dynamics=dyn)


def inline_slider_crank(r=0.1, L=0.4):
    """An in-line slider-crank sketched at the crank angle 90°: A = (0, r), B = (√(L² − r²), 0)."""
    return (assur.Builder(units="m", angle="rad").point("O", 0, 0).point("A", 0, r)
            .point("B", math.sqrt(L * L - r * r), 0)
            .frame("O").link("crank", "O", "A").link("rod", "A", "B")
            .slider(name="slot", point="B", guide="frame", through="O", angle=0.0)
            .crank("crank", pivot="O", arm="A", zero=0.0, speed="60 rpm", name="crank").build())


def test_crank_effort_of_a_piston_load():
    """A force F along the line of stroke on the piston B, towards the crank (−x̂): the rod (a two-force
    member at the angle β to the line of stroke, sin β = r·sin θ / l) carries F/cos β, whose moment about O
    is the crank effort F·r·sin(θ + β)/cos β, turning the crank clockwise for 0 < θ < π (the piston pushes
    the crank back), so the motor's counter-clockwise torque is −F·r·sin(θ + β)/cos β."""
    r, L, F = 0.1, 0.4, 1000.0
    plan = assur.compile(inline_slider_crank(r, L))
    theta = np.radians(np.arange(10.0, 360.0, 20.0))
    f = assur.forces(plan, inputs=theta, point_loads=[("B", np.array([-F, 0.0]))])
    beta = np.arcsin(r * np.sin(theta) / L)
    effort = F * r * np.sin(theta + beta) / np.cos(beta)
    np.testing.assert_allclose(f.driver[:, 0], -effort, rtol=1e-12, atol=1e-9 * F * r)
    # the side thrust on the cylinder wall is F·tan β (the normal reaction of the guide on the piston)
    np.testing.assert_allclose(np.abs(f.normal[:, f.pair("slot")]), F * np.abs(np.tan(beta)), rtol=1e-12,
                               atol=1e-9 * F)


def test_slide_friction_matches_a_hand_derivation():
    """Massless in-line slider-crank at φ = 90° (ccw), a resisting force P0 on the slider, slide friction μ.

    At φ = 90° the slider moves in −x at ω·r, so the load is +P0·x̂ and friction +μ|N|·x̂. The rod is a
    two-force member: its force on the block is C·e, e = (c, −s) = unit(B − A), s = r/L, c = √(1 − s²).
    Block: x: C·c + P0 + μ|N| = 0, y: −C·s + N = 0; C < 0, so |N| = −C·s and C = −P0/(c − μ·s).
    Crank about O: T = cross(A, C·e) = −C·r·c = P0·r·c/(c − μ·s) (without friction P0·r, as by virtual
    power).
    """
    r, L, P0, mu = 0.1, 0.4, 500.0, 0.2
    m = inline_slider_crank(r, L)
    load = Load(point="B", link="slot.block", force=(P0, 0.0), opposes="velocity")
    s = r / L
    c = math.sqrt(1 - s * s)
    plan = assur.compile(with_dynamics(m, Dynamics(loads=(load,), friction=Friction(slide=mu))))
    f = assur.forces(plan, inputs=[math.pi / 2], friction=True)
    assert f.converged and f.iterations > 0
    assert f.driver[0, 0] == pytest.approx(P0 * r * c / (c - mu * s), rel=1e-10)
    assert f.normal[0, f.pair("slot")] == pytest.approx(-P0 * s / (c - mu * s), rel=1e-10)      # N = C·s
    plain = assur.forces(plan, inputs=[math.pi / 2], friction=False)
    assert plain.iterations == 0 and plain.driver[0, 0] == pytest.approx(P0 * r, rel=1e-10)


# --- A published example: Khurmi & Gupta, "Theory of Machines", the horizontal engine of Example 15.7 ---
#
# Source of the data and of the printed answers: R. S. Khurmi and J. K. Gupta, *Theory of Machines*
# (S. Chand, New Delhi), chapter 15 "Inertia Forces in Reciprocating Parts", solved Example 15.7, as
# transcribed with its printed answers in the course handout "EXAMPLES" (problem [4], answers
# "[68.73 KN, 50.62 KN, 48.28 KN, 14.484 KN-m] [R.S.Khurmi, S-15.7]"),
# https://www.scribd.com/document/468809524/tm-pdf. (No page number is given there.)
#
# "The crank-pin circle radius of a horizontal engine is 300 mm. The mass of the reciprocating parts is
# 250 kg. When the crank has travelled 60° from I.D.C., the difference between the driving and the back
# pressure is 0.35 N/mm². The connecting rod length between centres is 1.2 m and cylinder bore is 0.5 m.
# If the engine runs at 250 rpm and if the effect of piston rod diameter is neglected, find (a) pressure
# on slide bars, (b) thrust in connecting rod, (c) tangential force on the crank pin, (d) turning moment
# on crank shaft."
#
# The book's working: the
# load on the piston F_L = 0.35·π/4·500² = 68 730 N (printed 68.73 kN, the handout's first number),
# ω = 2π·250/60 = 26.2 rad/s (rounded), the inertia force of the reciprocating parts by the two-term
# series F_I = m·ω²·r·(cos θ + cos 2θ/n), n = l/r = 4, the piston effort F_P = F_L − F_I; then with
# sin φ = sin θ / n: slide-bar reaction F_N = F_P·tan φ, rod thrust F_Q = F_P / cos φ, tangential force
# on the crank pin F_T = F_Q·sin(θ + φ) and turning moment T = F_T·r.
#
# The engine uses the exact piston acceleration (the series truncated at cos 2θ/n is an approximation:
# here it differs by 0.03 %), so the printed digits are checked with the book's own rounded ω and F_L,
# and the exact numbers at the stated data against the closed form computed in the test.

R_CRANK, L_ROD, M_RECIP = 0.300, 1.2, 250.0          # m, m, kg
THETA_BOOK = math.radians(60.0)                      # crank angle from the inner dead centre


def horizontal_engine(piston_load):
    """Khurmi's horizontal engine: the crank O at the origin, the line of stroke the x axis, the piston B
    on +x (θ = 0 the inner dead centre: the crank pointing at the piston), sketched at θ = 60°; the
    reciprocating mass on the piston (crank and rod massless, as in the book), the net steam load on the
    piston towards the crank shaft. The book leaves the weight of the reciprocating parts out, so no
    gravity."""
    r, L = R_CRANK, L_ROD
    ax, ay = r * math.cos(THETA_BOOK), r * math.sin(THETA_BOOK)
    m = (assur.Builder(units="m", angle="rad").point("O", 0, 0).point("A", ax, ay)
         .point("B", ax + math.sqrt(L * L - ay * ay), 0)
         .frame("O").link("crank", "O", "A").link("rod", "A", "B")
         .slider(name="slot", point="B", guide="frame", through="O", angle=0.0)
         .crank("crank", pivot="O", arm="A", zero=0.0, speed="250 rpm", name="crank").build())
    dyn = Dynamics(bodies=(("slot.block", MassProperties(mass=M_RECIP)),),
                   loads=(Load(point="B", link="slot.block", force=(-piston_load, 0.0)),))
    return assur.compile(with_dynamics(m, dyn))


def engine_answers(f):
    """(F_N, F_Q, F_T, T) in N and N·m from a Forces of the engine: the guide's normal reaction on the
    piston, the force in the rod (the pin force at B), the crank-pin force across the crank and the
    torque the rod puts on the crank shaft (the motor's torque with the opposite sign)."""
    fn = abs(f.normal[0, f.pair("slot")])
    fq = float(np.hypot(*f.reaction("B")[0]))          # the rod is a massless two-force member
    torque = -f.driver[0, 0]
    return fn, fq, torque / R_CRANK, torque


def test_khurmi_horizontal_engine_to_the_printed_digits():
    """Khurmi & Gupta, Theory of Machines, Example 15.7 (see the block comment above): printed F_Q =
    50.62 kN, F_T = 48.28 kN, T = 14.484 kN·m. The book works with rounded intermediates: F_L = 68.73 kN
    (printed) and ω = 2π·250/60 taken as 26.2 rad/s (not printed in the source read; it is the rounding
    the printed answers carry). At the unrounded data the exact answers are F_Q = 50.641 kN, F_T =
    48.298 kN, T = 14.490 kN·m (next test), which differ from the printed ones in the fourth figure. With
    the book's F_L and ω the engine (exact piston acceleration) gives F_Q = 50.619 kN, F_T = 48.277 kN:
    equal to the printed two decimals. The printed T = 14.484 kN·m is the book's F_T rounded to 48.28 kN times
    r = 0.3 m; the engine's T = 14.483 kN·m agrees within that rounding (|ΔT| ≤ 0.005 kN × 0.3 m).
    The handout's first number 68.73 kN is the piston load F_L (the book's slide-bar reaction is
    F_P·tan φ ≈ 10.96 kN; checked here against the closed form, not a printed value)."""
    f_load = 68.73e3                                   # N, the book's printed load on the piston
    omega = 26.2                                       # rad/s, the book's printed 2π·250/60
    plan = horizontal_engine(f_load)
    f = assur.forces(plan, inputs=[THETA_BOOK], speeds=[omega], accels=[0.0])
    assert f.valid.all()
    fn, fq, ft, torque = engine_answers(f)
    assert round(fq / 1e3, 2) == 50.62                 # kN, printed to 2 decimals
    assert round(ft / 1e3, 2) == 48.28                 # kN, printed to 2 decimals
    assert abs(torque / 1e3 - 14.484) <= 0.005 * R_CRANK   # kN·m: printed as 48.28 kN × 0.3 m
    # the book's F_N = F_P·tan φ by its own series (an independent evaluation of its formula)
    n = L_ROD / R_CRANK
    phi = math.asin(math.sin(THETA_BOOK) / n)
    f_p = f_load - M_RECIP * omega ** 2 * R_CRANK * (math.cos(THETA_BOOK) + math.cos(2 * THETA_BOOK) / n)
    assert round(fn / 1e3, 2) == round(f_p * math.tan(phi) / 1e3, 2)


def test_khurmi_horizontal_engine_exact_at_the_stated_data():
    """The same engine at the stated data (ω = 2π·250/60 rad/s, F_L = 0.35 N/mm² × π/4 × (500 mm)²)
    against the exact closed form computed here: piston x = r cos θ + √(l² − r² sin² θ), its exact
    acceleration ẍ = ω²·d²x/dθ² (constant ω), the piston effort F_P = F_L + m·ẍ (ẍ < 0: towards the crank),
    F_N = F_P tan φ, F_Q = F_P / cos φ, T = F_Q·r·sin(θ + φ); and the book's two-term series, which this
    exact acceleration must match to O((r/l)³)."""
    r, L, m, th = R_CRANK, L_ROD, M_RECIP, THETA_BOOK
    omega = 2 * math.pi * 250 / 60
    f_load = 0.35e6 * math.pi / 4 * 0.5 ** 2
    plan = horizontal_engine(f_load)
    f = assur.forces(plan, inputs=[th])               # the file's speed: 250 rpm
    assert f.qdot[0] == pytest.approx(omega, rel=1e-12)
    fn, fq, ft, torque = engine_answers(f)
    s, c = math.sin(th), math.cos(th)
    q = math.sqrt(L * L - r * r * s * s)
    xdd = omega ** 2 * (-r * c - r * r * (c * c - s * s) / q - r ** 4 * s * s * c * c / q ** 3)
    series = -omega ** 2 * r * (c + math.cos(2 * th) / (L / r))
    assert xdd == pytest.approx(series, rel=3 * (r / L) ** 3)
    f_p = f_load + m * xdd
    phi = math.asin(r * s / L)
    assert fn == pytest.approx(f_p * math.tan(phi), rel=1e-9)
    assert fq == pytest.approx(f_p / math.cos(phi), rel=1e-9)
    assert torque == pytest.approx(f_p / math.cos(phi) * r * math.sin(th + phi), rel=1e-9)
    assert ft == pytest.approx(f_p / math.cos(phi) * math.sin(th + phi), rel=1e-9)
