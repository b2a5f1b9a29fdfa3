"""Instant centres, centrodes, the inflection circle, Euler–Savary and Bobillier.

- Kennedy's theorem: the three centres of every triple of bodies are collinear (|det| of their unit homogeneous
  coordinates ≤ 1e-12), on every planar example at inputs over its run;
- the instant-centre method (from one body's motion and the centres) gives every body's angular velocity and every
  point's velocity as the engine's jets do, to 1e-12 relative;
- the fixed and moving centrodes of a four-bar's coupler roll without slipping: their tangents agree in direction and
  length at every instant (central differences of both curves, each in its own body's frame), and their arc lengths
  between the same inputs are equal;
- a coupler point's centre of curvature found three ways agrees: Bobillier's construction (ruler and compass on the
  four-bar), Euler–Savary on the inflection circle (the exact pole velocity), and v × a from the engine's jets; a
  point on the inflection circle has a straight path at that instant.
"""
from __future__ import annotations

import math
import warnings

import numpy as np
import pytest

import assur
from assur.analysis.centrodes import bobillier, curvature_centre, euler_savary, inflection_circle
from assur.analysis.instant_centres import KINDS, instant_centres, velocities_from_centres
from assur.analysis.study import Study
from conftest import EXAMPLES


def _planar():
    out = []
    for p in sorted(EXAMPLES.glob("*.toml")):
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            try:
                m = assur.load(p)
            except assur.SpecError:
                continue
        if m.dimension == 2:
            out.append(p.name)
    return out


PLANAR = _planar()


def _run(name, steps=48):
    plan = assur.compile(assur.load(EXAMPLES / name))
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        study = Study(plan, steps=steps)
        st = study.state
    return plan, study, st


@pytest.mark.parametrize("name", PLANAR)
def test_kennedy_collinearity_and_the_instant_centre_method(name):
    plan, study, st = _run(name)
    ic = study.instant_centres
    valid = np.asarray(st.valid, bool)
    B = plan.n_bodies
    assert ic.homogeneous.shape[1] == B * (B - 1) // 2
    res = ic.kennedy_residual()[valid]
    assert res.size == 0 or float(np.max(res)) <= 1e-12
    assert not np.any(ic.kind[valid] == KINDS.index("undetermined"))
    # velocities from the centres: the driver's link (or an actuator's cylinder) as the known body
    d = plan.mechanism.drivers[0]
    ref = plan.body_names.index(d.link if d.kind == "rotary" else f"{d.actuator}.cylinder")
    g = plan.structure.graph
    worst = 0.0
    for s in np.flatnonzero(valid)[::6]:
        z = st.pos[s, :, 0] + 1j * st.pos[s, :, 1]
        v = st.vel[s, :, 0] + 1j * st.vel[s, :, 1]
        scale = max(np.max(np.abs(v)), np.max(np.abs(st.body_omega[s])) * plan.length_scale)
        i = plan.point_index(g.bodies[ref].points[0])
        omega, field = velocities_from_centres(ic, s, ref, st.body_omega[s, ref], z[i], v[i])
        worst = max(worst, np.max(np.abs(omega - st.body_omega[s])) * plan.length_scale / scale)
        for b, body in enumerate(g.bodies):
            for p in body.points:
                k = plan.point_index(p)
                worst = max(worst, abs(field(z[k], b) - v[k]) / scale)
    assert worst <= 1e-12


def test_a_rocker_at_rest_gets_its_centres_by_kennedy():
    """In the cam press's dwells the rocker, the rod and the ram stand still: their centres with the frame are
    undetermined by the velocities and come from Kennedy's lines — and still satisfy every triple."""
    plan, study, st = _run("cam_press.toml", 72)
    ic = study.instant_centres
    assert np.any(ic.kind == KINDS.index("kennedy"))
    assert float(np.max(ic.kennedy_residual())) <= 1e-12


def test_centrodes_roll_without_slipping(fourbar_plan):
    study = Study(fourbar_plan, steps=4000)
    c = study.centrodes("coupler")
    q = study.q
    h = q[1] - q[0]
    st = study.state
    b = fourbar_plan.body_names.index("coupler")
    dF = np.gradient(c.fixed_curve, h)                               # the frame: its own frame is the world's
    dM = np.exp(1j * st.body_angle[:, b]) * np.gradient(c.moving_curve, h)
    ok = np.isfinite(c.world) & (np.abs(c.world) < 20 * fourbar_plan.length_scale)
    ok[:2] = ok[-2:] = False
    rel = np.abs(dF - dM)[ok] / np.abs(dF)[ok]
    assert np.median(rel) <= 1e-6 and np.percentile(rel, 95) <= 1e-4
    # the exact pole velocity relative to the frame is the rate along both curves
    rate = c.rate / st.qdot[0]
    assert np.median(np.abs(rate - dF)[ok] / np.abs(dF)[ok]) <= 1e-5
    # equal arc lengths over a stretch where the centre stays finite
    runs = np.flatnonzero(np.diff(ok.astype(int)) != 0)
    seg = slice(runs[0] + 2, runs[1] - 1) if len(runs) >= 2 else slice(2, -2)
    lf = np.sum(np.abs(np.diff(c.fixed_curve[seg])))
    lm = np.sum(np.abs(np.diff(c.moving_curve[seg])))
    assert abs(lf - lm) <= 1e-5 * lf


def test_curvature_centre_three_ways(fourbar_plan):
    plan = fourbar_plan
    study = Study(plan, steps=36)
    st = study.state
    z = lambda n: st.pos[:, plan.point_index(n), 0] + 1j * st.pos[:, plan.point_index(n), 1]   # noqa: E731
    A0, A, B, B0, C = z("O2"), z("A"), z("B"), z("O4"), z("P")
    exact = curvature_centre(plan, st, "P")
    infl = inflection_circle(plan, st, "coupler")
    es = euler_savary(infl, C)
    P, tangent, axis, C0 = bobillier(A0, A, B0, B, C)
    r = np.abs(exact - C)
    ok = np.isfinite(r) & (r < 50 * plan.length_scale)
    assert np.max(np.abs(es - exact)[ok] / r[ok]) <= 1e-10
    assert np.max(np.abs(C0 - exact)[ok] / r[ok]) <= 1e-10
    assert np.max(np.abs(P - infl.pole) / np.maximum(np.abs(infl.pole), plan.length_scale)) <= 1e-12
    assert np.max(np.abs(np.imag(np.conj(tangent) * infl.tangent))) <= 1e-10        # Bobillier's pole tangent
    # a coupler point on the inflection circle: zero path curvature (v × a = 0) at that instant
    s = 5
    X = infl.pole[s] + 0.5 * (infl.inflection_pole[s] - infl.pole[s]) * (1 + np.exp(1j * 0.7))
    e = np.exp(1j * st.body_angle[s, plan.body_names.index("coupler")])
    o = A[s]
    om, al = st.body_omega[s, 3], st.body_alpha[s, 3]
    vA = st.vel[s, plan.point_index("A"), 0] + 1j * st.vel[s, plan.point_index("A"), 1]
    aA = st.acc[s, plan.point_index("A"), 0] + 1j * st.acc[s, plan.point_index("A"), 1]
    assert plan.body_names[3] == "coupler"
    v = vA + 1j * om * (X - o)
    a = aA + (1j * al - om * om) * (X - o)
    assert abs(np.imag(np.conj(v) * a)) <= 1e-10 * abs(v) * abs(a)
    assert e != 0


def test_instant_centres_at_inputs_and_as_json(fourbar_plan):
    study = Study(fourbar_plan, steps=24)
    ic = study.centres_at([0.3, 1.2])
    rows = ic.as_dict()
    assert len(rows) == 2 and len(rows[0]) == 6
    assert {r["kind"] for r in rows[0]} <= set(KINDS)
    pin = next(r for r in rows[0] if r["pair"] == ["frame", "crank"])
    o2 = fourbar_plan.mechanism.sketch("O2")
    assert pin["kind"] == "pin" and math.isclose(pin["x"], o2[0], abs_tol=1e-12)
