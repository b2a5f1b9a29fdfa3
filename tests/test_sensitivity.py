"""Exact sensitivities against complex-step derivatives of an independent solver (tests/complex_step.py), on every
planar example and every output kind: positions, velocities and accelerations of every point, link angles and
angular velocities, transmission angles, driving efforts, reactions (gear and cam pairs realised), and the gait
metrics of the walking legs; to 1e-10 of each output's scale."""
from __future__ import annotations

import math
import warnings

import numpy as np
import pytest
import sympy as sp
from scipy.optimize import brentq

import assur
from assur.analysis.sensitivity.implicit import body_coordinates
from assur.analysis.sensitivity.outputs import Outputs
from assur.analysis.study import Study
from complex_step import H, Numeric, Oracle
from conftest import EXAMPLES
from test_cam_pairs import LIFTER

PLANAR = sorted(p.name for p in EXAMPLES.glob("*.toml")
                if p.read_text().startswith("format = \"assur/1\"") or "assur/1" in p.read_text()[:200])


def _plans():
    out = {}
    for name in PLANAR:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            try:
                m = assur.load(EXAMPLES / name)
            except assur.SpecError:
                continue
        if m.dimension == 2:
            out[name] = m
    return out


MECHANISMS = _plans()
MECHANISMS["lifter (flat-faced cam)"] = assur.loads(LIFTER)
RTOL = 1e-10


def _samples(plan):
    if plan.input_kinds[0] == "linear":
        r = plan.mechanism.drivers[0].range
        q = np.linspace(r[0], r[1], 6)[1:-1]
    else:
        q = np.linspace(0.37, 2 * math.pi - 0.2, 5)
    inputs = np.repeat(q[:, None], plan.n_inputs, axis=1) if plan.n_inputs > 1 else q[:, None]
    if plan.n_inputs > 1:
        inputs[:, 1:] = plan.sketch_inputs[1:]
    return inputs


def _close(name, mine, want):
    scale = max(1.0, float(np.max(np.abs(want))))
    err = float(np.max(np.abs(mine - want)))
    assert err <= RTOL * scale, f"{name}: |exact − complex step| = {err:.3g} (scale {scale:.3g})"


#: the quick loop keeps one example of each kind of element (dyads, slides, actuators, gears, cams); the six-bars and
#: the legs of seven or eight bodies run with the slow tests
QUICK = {"crank_rocker.toml", "cam_press.toml", "lifter (flat-faced cam)", "walker_fourbar.toml",
         "walker_fourbar_geared.toml", "lever_manipulator.toml", "walker_crank_slider.toml", "slider_crank.toml"}


@pytest.mark.parametrize("name", [n if n in QUICK else pytest.param(n, marks=pytest.mark.slow)
                                  for n in sorted(MECHANISMS)])
def test_every_output_against_complex_step(name):
    m = MECHANISMS[name]
    plan = assur.compile(m)
    inputs = _samples(plan)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        st = assur.solve(plan, inputs=inputs, order=2)
    assert np.all(st.valid)
    n = len(inputs)
    forces = plan.n_inputs == 1 and m.dynamics is not None
    out = Outputs(plan, st, forces=forces)
    names = out.names()
    oracle = Numeric(Oracle(plan))
    X0 = body_coordinates(plan, st, n)
    idx = {b: i for i, b in enumerate(plan.body_names[1:])}
    got = {}
    for k in range(plan.n_params):
        p = plan.defaults.astype(complex)
        p[k] += 1j * H
        s = oracle.solve(X0, inputs, p, plan.speeds)
        assert np.max(np.abs(s["X"].real - X0)) <= 1e-12 * plan.length_scale
        for pt in plan.point_names:
            z, v, a = oracle.point(pt)
            for c, axis in enumerate("xy"):
                for prefix, arr in (("", z), ("v", v), ("a", a)):
                    got.setdefault(f"{pt}.{prefix}{axis}", []).append(arr[:, c].imag / H)
        for b, j in idx.items():
            got.setdefault(f"{b}.angle", []).append(s["X"][:, 3 * j + 2].imag / H)
            got.setdefault(f"{b}.omega", []).append(s["Xd"][:, 3 * j + 2].imag / H)
        for key, mu in _transmission(plan, oracle).items():
            got.setdefault(f"mu.{key}", []).append(mu.imag / H)
        if forces:
            lam, effort = oracle.multipliers()
            for i, d in enumerate(plan.input_names):
                got.setdefault(f"{d}.effort", []).append(effort[:, i].imag / H)
            R = oracle.reactions(lam)
            for kk, nm in _reaction_names(out, plan):
                got.setdefault(f"{nm}.x", []).append(R[:, kk, 0].imag / H)
                got.setdefault(f"{nm}.y", []).append(R[:, kk, 1].imag / H)
    kinds = set()
    for key, cols in got.items():
        want = np.stack(cols, axis=-1)
        _close(f"{name} {key}", out[key].derivative, want)
        kinds.add(out[key].kind)
    expected = {"position", "velocity", "acceleration", "angle", "rate"}
    expected |= {"transmission"} if any(nm.startswith("mu.") for nm in names) else set()
    expected |= {"effort", "reaction"} if forces else set()
    assert expected <= kinds


def _reaction_names(out, plan):
    t = out.motion.closure.tables
    names = [fp.name for fp in t.pairs]
    for k, fp in enumerate(t.pairs):
        if fp.kind == "T":
            continue
        yield k, (f"R.{fp.name}" if names.count(fp.name) == 1 else f"R.{fp.name}@{plan.body_names[fp.later]}")


def _transmission(plan, oracle):
    """μ of each dyad from the oracle's points (arccos of the normalised dot product: analytic for the complex step)."""
    o = oracle.o

    def P(name):
        return oracle.point(name)[0]

    def unit_normal(line):
        rec = plan.lines[line]
        if rec[0] == "actuator":                   # an actuator's slide runs along its cylinder
            U = oracle._value(("Ucyl", rec[1]), [sp.cos(o.angle(f"{rec[1]}.cylinder")),
                                                sp.sin(o.angle(f"{rec[1]}.cylinder"))])
        else:
            pr = next(p for p in plan.mechanism.prismatic if p.name == rec[1])
            U = oracle._value(("U", pr.name), list(o._line(pr)[0]))
        return np.stack([-U[:, 1], U[:, 0]], -1)

    def ang(a, b, acute):
        c = np.sum(a * b, -1) / np.sqrt(np.sum(a * a, -1) * np.sum(b * b, -1))
        mu = np.arccos(c)
        return np.where(acute & (mu.real > math.pi / 2), math.pi - mu, mu)

    out = {}
    for st in plan.steps:
        if st.kind == "RRR":
            out[st.joint] = ang(P(st.point_a) - P(st.joint), P(st.point_b) - P(st.joint), False)
        elif st.kind == "RRP":
            out[st.joint] = ang(P(st.joint) - P(st.point_a), unit_normal(st.line), True)
        elif st.kind == "RPR":
            out[st.key_point] = ang(P(st.slider_point) - P(st.guide_point), unit_normal(st.line), True)
    return out


WALKERS = [n for n, m in MECHANISMS.items() if m.gait is not None and m.dimension == 2
           and len(m.drivers) == 1]


@pytest.mark.slow
@pytest.mark.parametrize("name", WALKERS)
def test_gait_metrics_against_complex_step(name):
    """Step length and lift: extremes refined here by Brent's method on the oracle's own ∂x/∂q, then complex-stepped
    (the envelope theorem); the duty factor from the contact arc's ends moving as −(∂²x/∂q∂p)/(∂²x/∂q²) with the
    mixed derivative complex-stepped."""
    m = MECHANISMS[name]
    plan = assur.compile(m)
    study = Study(plan, steps=360)
    gm = study.gait
    if gm is None:
        pytest.skip("the crank does not turn fully")
    sens = study.sensitivity
    oracle = Numeric(Oracle(plan))
    g, u = np.array(m.gait.ground), np.array(m.gait.up_vector)
    w = float(plan.speeds[0])

    def at(q, p=None):
        st = study.state_at(np.array([q]))
        s = oracle.solve(body_coordinates(plan, st, 1), np.array([[q]]),
                         plan.defaults.astype(complex) if p is None else p, plan.speeds)
        z, v, a = oracle.point(m.gait.foot)
        return z[0], v[0] / w, a[0] / (w * w)

    q = study.q
    P = study.state.pos[:, plan.point_index(m.gait.foot)]

    def extreme(axis, pick):
        vals = P @ axis
        i = int(pick(vals))
        h = q[1] - q[0]
        f = lambda t: float(np.real(at(t)[1] @ axis))   # noqa: E731
        return brentq(f, q[i] - h, q[i] + h, xtol=1e-14, rtol=1e-15)

    qa, qb = extreme(g, np.argmin), extreme(g, np.argmax)
    qv0, qv1 = extreme(u, np.argmin), extreme(u, np.argmax)
    step, lift, duty_ends = [], [], []
    for k in range(plan.n_params):
        p = plan.defaults.astype(complex)
        p[k] += 1j * H
        step.append(((at(qb, p)[0] - at(qa, p)[0]) @ g).imag / H)
        lift.append(((at(qv1, p)[0] - at(qv0, p)[0]) @ u).imag / H)
        moves = []
        for qe in (qa, qb):
            mixed = (at(qe, p)[1] @ g).imag / H
            moves.append(-mixed / float(np.real(at(qe)[2] @ g)))
        duty_ends.append(moves)
    _close(f"{name} gait.step", sens["gait.step"].derivative, np.array(step))
    _close(f"{name} gait.lift", sens["gait.lift"].derivative, np.array(lift))
    start_is_a = abs(((qa - gm.contact_start + math.pi) % (2 * math.pi)) - math.pi) < 1e-6
    duty = np.array([(mb - ma) if start_is_a else (ma - mb) for ma, mb in duty_ends]) / (2 * math.pi)
    _close(f"{name} gait.duty", sens["gait.duty"].derivative, duty)
    # the sag: the height's range over the contact arc; an extreme inside the arc moves by ∂v/∂p (the envelope
    # theorem, complex-stepped at the root of ∂v/∂q found here by Brent's method), one at an end of the arc by
    # ∂v/∂p + ∂v/∂q·dq_e/dp
    start, end = (qa, qb) if start_is_a else (qb, qa)
    moves = dict(zip((qa, qb), np.array(duty_ends).T))
    width = (end - start) % (2 * math.pi)
    grid = start + np.linspace(0.0, width, 721)
    hv = np.array([float(np.real(at(t)[0] @ u)) for t in grid[::8]])
    extremes = []
    for i in (int(np.argmin(hv)), int(np.argmax(hv))):
        t = grid[::8][i]
        end_of = next((e for e in (start, end) if abs(((t - e + math.pi) % (2 * math.pi)) - math.pi) < 1e-9), None)
        if end_of is None:
            h = 8 * (grid[1] - grid[0])
            f = lambda x: float(np.real(at(x)[1] @ u))       # noqa: E731
            if f(t - h) * f(t + h) < 0:
                t = brentq(f, t - h, t + h, xtol=1e-14, rtol=1e-15)
            else:                                            # the extreme sits at an end after all
                end_of = min((start, end), key=lambda e: abs(((t - e + math.pi) % (2 * math.pi)) - math.pi))
                t = end_of
        slope = 0.0 if end_of is None else float(np.real(at(t)[1] @ u))
        d = []
        for k in range(plan.n_params):
            p = plan.defaults.astype(complex)
            p[k] += 1j * H
            d.append((at(t, p)[0] @ u).imag / H + (0.0 if end_of is None else slope * moves[end_of][k]))
        extremes.append(np.array(d))
    got = sens["gait.sag"].derivative
    if np.all(np.isnan(got)):       # a kink (an extreme shared by both ends of a symmetric arc): the heights tie
        heights = [float(np.real(at(e)[0] @ u)) for e in (start, end)]
        assert abs(heights[0] - heights[1]) <= 1e-9 * gm.lift
    else:
        _close(f"{name} gait.sag", got, extremes[1] - extremes[0])
