"""Tolerances, their envelopes and Monte Carlo, and joint clearance.

- ISO 286-1:2010 Table 1 as held, against the formula it rounds (i = 0.45·∛D + 0.001·D µm, D the geometric mean of
  the size range; IT5 … IT18 = 7i … 2500i: ISO 286-1, Annex A) and against a few of its printed values;
- the worst-case envelope is the sum of the contributions |∂y/∂p|·t, the RSS their root sum square (≤ the worst
  case), the band round a path the same along its normal;
- a Monte Carlo of a four-bar's tolerances on the batched engine stays inside the first-order worst-case band where
  the mechanism is far from a toggle, and leaves it (and loses buildable samples) near one;
- joint clearance: the worst case over every orientation bounds the exact Monte Carlo of random orientations on a
  four-bar and a slider-crank, and bounds the effective links' error.
"""
from __future__ import annotations

import math
import warnings

import numpy as np
import pytest

import assur
from assur.analysis.sensitivity.clearance import clearance
from assur.analysis.sensitivity.iso286 import LIMITS, TABLE, parse_grade, tolerance
from assur.analysis.sensitivity.montecarlo import monte_carlo
from assur.analysis.sensitivity.tolerance import envelope, parse_tolerances, path_band
from assur.analysis.study import Study
from assur.errors import SpecError

MULTIPLIER = {5: 7, 6: 10, 7: 16, 8: 25, 9: 40, 10: 64, 11: 100, 12: 160, 13: 250, 14: 400, 15: 640, 16: 1000,
              17: 1600, 18: 2500}


def test_iso286_table_against_its_formula_and_printed_values():
    lo = 1.0
    for L in LIMITS:
        D = math.sqrt(lo * L)
        i = 0.45 * D ** (1 / 3) + 0.001 * D
        for grade, k in MULTIPLIER.items():
            rel = TABLE[L][grade - 1] / (k * i) - 1
            assert abs(rel) <= (0.16 if L == 3 else 0.10), (L, grade, rel)
        lo = L
    # printed values (µm): 18–30 mm IT8 33, 30–50 mm IT7 25, 50–80 mm IT9 74, 120–180 mm IT11 250
    assert tolerance(8, 25) == 33 and tolerance(7, 40) == 25 and tolerance(9, 60) == 74 and tolerance(11, 150) == 250
    assert tolerance(7, 30) == 21 and tolerance(7, 30.001) == 25            # a size on a range's limit
    assert tolerance(9, 700) == pytest.approx(40 * (0.004 * math.sqrt(630 * 800) + 2.1))
    assert parse_grade("it7") == 7 and parse_grade(12) == 12
    for bad in ("IT0", "IT19", "seven"):
        with pytest.raises(SpecError):
            parse_grade(bad)


def test_default_and_given_tolerances(walking_fourbar_plan):
    p = walking_fourbar_plan
    tol = parse_tolerances(p, ["crank.length=0.001", "O1.x=IT6", "coupler.H.angle=0.5"], grade="IT8")
    k = p.param_index
    assert tol.half[k("crank.length")] == pytest.approx(0.001)                 # a file in m
    assert tol.half[k("O1.x")] == pytest.approx(0.5 * tolerance(6, 567) * 1e-6)
    assert tol.half[k("coupler.H.angle")] == pytest.approx(math.radians(0.5))
    assert tol.half[k("rocker.length")] == pytest.approx(0.5 * tolerance(8, 638) * 1e-6)
    assert tol.half[k("crank.zero")] == 0.0                                     # a phase is held
    with pytest.raises(SpecError, match="--tolerance"):
        parse_tolerances(p, ["nothing=1"])
    with pytest.raises(SpecError, match="--tolerance"):
        parse_tolerances(p, ["crank.length=-1"])


def test_envelopes_are_sums_of_contributions(walking_fourbar_plan):
    study = Study(walking_fourbar_plan, steps=90)
    sens = study.sensitivity
    tol = parse_tolerances(walking_fourbar_plan)
    for name in ("H.y", "coupler.angle", "mu.L", "crank.effort", "gait.step"):
        env = envelope(sens[name], tol)
        c = np.abs(np.asarray(sens[name].derivative)) * tol.half
        assert np.allclose(env.worst, c.sum(axis=-1)) and np.allclose(env.rss, np.sqrt(np.sum(c * c, axis=-1)))
        assert np.all(env.rss <= env.worst + 1e-18)
    band = path_band(sens, "H", tol)
    D = sens["H.x"].derivative + 1j * sens["H.y"].derivative
    n = band.normal[:, None]
    assert np.allclose(band.worst, np.sum(np.abs(np.real(np.conj(n) * D)) * tol.half, axis=-1))


TOGGLE = """
format = "assur/1"
name = "four-bar near its change point"
[units]
length = "mm"
angle = "deg"
[points]
O = [0, 0]
Q = [100, 0]
A = [49, 0]
B = [147.0392, 19.7030]
[links]
frame = ["O", "Q"]
crank = ["O", "A"]
coupler = ["A", "B"]
rocker = ["Q", "B"]
[[drivers]]
name = "crank"
kind = "rotary"
link = "crank"
pivot = "O"
arm = "A"
"""


def test_monte_carlo_holds_far_from_a_toggle_and_fails_near_one(walking_fourbar_plan):
    study = Study(walking_fourbar_plan, steps=90)
    tol = parse_tolerances(walking_fourbar_plan, grade="IT9")
    band = path_band(study.sensitivity, "H", tol)
    mc = monte_carlo(study, band, tol, 3000)
    assert mc.buildable == mc.samples and not mc.failures(study.q)
    assert float(np.nanmax(mc.ratio)) <= 1.0
    # the four-bar 2 mm from its change point (s + l = 149 ≤ p + q = 151): second-order effects leave the band
    plan = assur.compile(assur.loads(TOGGLE))
    near = Study(plan, steps=120)
    assert near.buildable.full_rotation
    tol = parse_tolerances(plan, grade="IT15")
    band = path_band(near.sensitivity, "B", tol)
    mc = monte_carlo(near, band, tol, 3000)
    assert mc.buildable_fraction < 1.0
    assert float(np.nanmax(mc.ratio)) > 1.5 and mc.failures(near.q)


SLIDER = """
format = "assur/1"
name = "slider-crank with masses"
[units]
length = "mm"
angle = "deg"
[points]
O = [0, 0]
A = [40, 0]
B = [160, 10]
G = [0, 10]
[links]
frame = ["O", "G"]
[links.crank]
points = ["O", "A"]
mass = "0.5 kg"
[links.rod]
points = ["A", "B"]
mass = "0.8 kg"
[[prismatic]]
name = "slide"
point = "B"
guide = "frame"
through = "G"
angle = 0
mass = "1.5 kg"
[[drivers]]
name = "crank"
kind = "rotary"
link = "crank"
pivot = "O"
arm = "A"
speed = "600 rpm"
[dynamics]
gravity = [0, -9.81]
[[loads]]
point = "B"
link = "rod"
force = [-200, 0]
"""


@pytest.mark.parametrize("which", ["four-bar", "slider-crank"])
def test_clearance_worst_case_bounds_the_monte_carlo(which, walking_fourbar_plan):
    if which == "four-bar":
        plan, point, c = walking_fourbar_plan, "H", 2e-4
    else:
        plan, point, c = assur.compile(assur.loads(SLIDER)), "B", 5e-5
    study = Study(plan, steps=60)
    r = clearance(study, point, c, samples=150)
    assert len(r.joints) >= 3 and np.all(r.radius == c / 2)
    err = np.linalg.norm(r.effective, axis=-1)
    assert np.all(err <= r.worst * (1 + 1e-9))
    assert np.all(r.monte_carlo <= r.worst * (1 + 1e-6))
    assert float(np.max(r.monte_carlo / r.worst)) > 0.5         # the random orientations come near the bound
    # the effective-link error is the exact offset solve's to first order: a tenfold smaller clearance, a tenfold
    # smaller error
    small = clearance(study, point, c / 10, samples=0)
    assert np.allclose(np.linalg.norm(small.effective, axis=-1) * 10, err, rtol=1e-9)


def test_clearance_flags_contact_loss():
    """The slider-crank's load reverses with the rod's inertia at 1500 rpm: its pins' reactions pass near zero (the
    200 N load on the rod's end, so the wrist pin carries the ram's inertia against it)."""
    plan = assur.compile(assur.loads(SLIDER.replace("600 rpm", "1500 rpm")))
    r = clearance(Study(plan, steps=360), "B", 1e-4, samples=0, loss=0.05)
    assert r.contact_loss
    with pytest.raises(SpecError, match="unknown joint"):
        clearance(Study(plan, steps=36), "B", {"Z": 1e-4}, samples=0)
