"""Closed-form kinetostatics of the slider-crank, derived by hand, against ``assur.forces``.

The references are the classical statics of the slider-crank, derived in each test's docstring and
computed in the test (no number here is copied from the program's output):

* the crank effort of an in-line slider-crank loaded at the piston, T = F·r·sin(θ + β)/cos β with
  sin β = r·sin θ / l (the connecting rod a two-force member; e.g. the "crank effort" of the
  inertia-forces chapter of Khurmi & Gupta's or Rattan's Theory of Machines);
* the same with Coulomb slide friction μ at the piston, at θ = 90°.
"""
from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest

import assur
from assur.model.dynamics import Dynamics, Friction, Load


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
