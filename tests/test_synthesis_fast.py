"""The compiled whole-cycle reduction of synthesis: gait terms, path distances without timing, the worst
transmission angle and the smooth buildability penalty, each equal to the general (numpy-array) route's
sampled values to round-off, and the sampled gait terms within a stated sampling error of analysis.gait's
exact (refined) values."""
import math
import tomllib
from pathlib import Path

import numpy as np
import pytest

import assur
from assur.engine.planar.numba_backend import available
from assur.synthesis import Evaluator, load_problem, problem_from_dict

SYN = Path(__file__).resolve().parent.parent / "examples" / "synthesis"
WALKER = SYN / "walker_fourbar_gait.toml"
GAIT = ("gait.step", "gait.lift", "gait.sag", "gait.duty", "gait.speed_mean", "gait.speed_spread", "gait.vx_spread",
        "gait.vx_spread_90", "gait.top")
needs_numba = pytest.mark.skipif(not available(), reason="numba not installed: no compiled route")


def _population(problem, n, seed=3):
    lo, hi = problem.bounds.T
    return lo + (hi - lo) * np.random.default_rng(seed).random((n, problem.n_vars))


def _gait_problem():
    """The walking-leg example with every gait term named (as limits with no effect on feasibility)."""
    data = tomllib.loads(WALKER.read_text(encoding="utf-8"))
    data["constraints"]["limits"] += [{"quantity": "gait.duty", "min": 0.0},
                                      {"quantity": "gait.speed_mean", "min": 0.0},
                                      {"quantity": "gait.vx_spread", "min": 0.0},
                                      {"quantity": "gait.vx_spread_90", "min": 0.0},
                                      {"quantity": "gait.top", "max": 1e9}]
    return problem_from_dict(data, base_dir=SYN)


def _path_problem():
    """Benchmark C3's points as a path without timing, with a transmission-angle limit."""
    data = tomllib.loads((SYN / "c3_eighteen_points_closed.toml").read_text(encoding="utf-8"))
    del data["variables"]["theta2_1"]
    data["targets"] = {k: v for k, v in data["targets"].items() if k in ("point", "xy")}
    data["targets"]["timing"] = "path"
    data["constraints"]["use"] = ["grashof", "nondegenerate"]
    data["constraints"]["limits"] = [{"quantity": "transmission.min", "min": 20}]
    data.setdefault("options", {})["cycle_samples"] = 120
    return problem_from_dict(data, base_dir=SYN)


def _assert_same(a, b, keys, smooth=True):
    """The same feasibility, the same NaN pattern and the same numbers to round-off. ``smooth`` False: b has
    no smooth buildability penalty (the numpy backend measures the unbuildable share), so only where the
    buildable constraint holds is compared there."""
    assert np.array_equal(a.feasible, b.feasible)
    for k in keys:
        x, y = a.quantities[k], b.quantities[k]
        assert np.array_equal(np.isnan(x), np.isnan(y)), k
        np.testing.assert_allclose(x, y, rtol=1e-9, atol=1e-12, equal_nan=True, err_msg=k)
    for k in b.violations:
        if k == "buildable" and not smooth:
            assert np.array_equal(a.violations[k] == 0, b.violations[k] == 0)
            continue
        np.testing.assert_allclose(a.violations[k], b.violations[k], rtol=1e-9, atol=1e-12, err_msg=k)
    if smooth:
        np.testing.assert_allclose(a.penalised, b.penalised, rtol=1e-9, atol=1e-12)


@needs_numba
def test_gait_terms_take_the_compiled_route_and_equal_the_general_route():
    p = _gait_problem()
    ev = Evaluator(p)
    assert ev._cycle_fast and ev.chunk == Evaluator.FUSED_CHUNK
    X = _population(p, 1500)
    fast, general = ev(X), ev(X, detail=True)            # detail: the general route, numpy arrays per sample
    assert 0 < fast.feasible.sum() < len(X)               # both feasible and infeasible designs are compared
    assert set(fast.quantities) == set(general.quantities)
    _assert_same(fast, general, GAIT + ("transmission.min", "unbuildable"))
    assert np.any(general.violations["buildable"] > 0)   # the smooth penalty of unbuildable designs is compared


@needs_numba
def test_the_compiled_route_is_chunk_independent():
    p = load_problem(WALKER)
    X = _population(p, 300)
    assert np.array_equal(Evaluator(p, chunk=7)(X).penalised, Evaluator(p, chunk=1000)(X).penalised)


def test_the_numpy_route_gives_the_same_numbers():
    """Without numba the general numpy route runs: the same sampled definitions (the smooth buildability
    penalty, past the groups' toggles, is the compiled backend's; numpy penalises the unbuildable share)."""
    p = _gait_problem()
    X = _population(p, 400)
    a, b = Evaluator(p)(X), Evaluator(p, backend="numpy")(X)
    _assert_same(a, b, GAIT + ("transmission.min", "unbuildable"), smooth=not available())


def _polyline_distance(path, targets):
    """Independent: distance of each target to the closed polyline, point by point and segment by segment."""
    out = []
    for p in targets:
        best = math.inf
        for k in range(len(path)):
            a, b = path[k], path[(k + 1) % len(path)]
            ab = b - a
            t = min(max(float(np.dot(p - a, ab) / np.dot(ab, ab)), 0.0), 1.0)
            best = min(best, float(np.linalg.norm(a + t * ab - p)))
        out.append(best)
    return np.array(out)


@needs_numba
def test_path_distance_without_timing_and_transmission_take_the_compiled_route():
    p = _path_problem()
    ev = Evaluator(p)
    assert ev._cycle_fast
    X = _population(p, 600)
    fast, general = ev(X), ev(X, detail=True)
    _assert_same(fast, general, ("deviation", "transmission.min", "unbuildable"))
    # independent: the sampled coupler path and its polyline distances, for three buildable designs
    ok = np.flatnonzero(fast.quantities["unbuildable"] == 0)[:3]
    assert len(ok) == 3
    plan = p.plan
    q = np.linspace(0.0, 2 * math.pi, p.cycle_samples, endpoint=False)
    for i in ok:
        st = assur.solve(plan, ev.params(X[i:i + 1])[0], q[:, None], backend="numpy")
        path = st.pos[:, plan.point_index("P"), :]
        d = _polyline_distance(path, p.targets.xy) * p.length_scale
        assert fast.quantities["deviation"][i] == pytest.approx(np.sum(d * d), rel=1e-9)


def _fourbar_lengths(p, x):
    """(crank a, coupler b, rocker c, ground d, ground angle) of a walker design (SI)."""
    v = dict(zip(p.names, x))
    d = math.hypot(v["O1.x"], v["O1.y"])
    return v["crank.length"], v["coupler.length"], v["rocker.length"], d, math.atan2(v["O1.y"], v["O1.x"])


def _feasible_designs(p, n=4):
    ev = Evaluator(p)
    X = _population(p, 3000, seed=11)
    e = ev(X)
    good = X[e.feasible][:n]
    assert len(good) == n
    plan = p.plan
    template = np.array([plan.defaults[plan.param_index(name)] for name in p.names])
    return ev, np.vstack([template, good])


def test_worst_transmission_angle_within_the_sampling_error_of_the_closed_form():
    """Independent closed form (four-bar, e.g. Norton, Design of Machinery, §4.10): the coupler–rocker angle μ
    has cos μ = (b² + c² − s²)/(2bc), s = |K O1| ranging over [d − a, d + a], so the worst folded angle is at
    one of the two extremes of s (μ is monotone in s). The samples are exact values of the same function, so
    the sampled worst angle lies above the exact one by at most ½·max|μ''|·h² (a smooth interior extreme within
    h of a sample, h = 2π/M)."""
    p = load_problem(WALKER)
    ev, X = _feasible_designs(p)
    got = np.radians(ev(X).quantities["transmission.min"])
    h = 2 * math.pi / p.cycle_samples
    for x, mu_s in zip(X, got):
        a, b, c, d, phi = _fourbar_lengths(p, x)
        mu = lambda s: math.acos((b * b + c * c - s * s) / (2 * b * c))  # noqa: E731
        exact = min(min(m, math.pi - m) for m in (mu(d - a), mu(d + a)))
        th = np.linspace(0, 2 * math.pi, 20001)
        folded = np.array([min(m, math.pi - m) for m in map(mu, np.sqrt(a * a + d * d - 2 * a * d * np.cos(th)))])
        curv = np.max(np.abs(np.gradient(np.gradient(folded, th), th)))
        assert exact - 1e-12 <= mu_s <= exact + 0.5 * curv * h * h + 1e-12


def test_sampled_gait_terms_within_the_stated_sampling_error_of_the_exact_metrics():
    """analysis.gait refines the extremes and the arc ends (root solves of the exact derivatives); the sampled
    terms take them at samples h = 2π/M apart. Bounds, from the design's own derivatives by q (dense grid):
    - step, lift: extremes of x, v at smooth interior optima, a sample within h of each: ½·max|f''|·h²;
    - the arc ends are samples within h of the exact ends: duty within 3/M (each end within h, and the
      sampled arc counts both end samples); sag within h·max|v'| + ½·max|v''|·h² (an extreme may sit at an end);
    - support speed: its max and min within h·max|s'| (same reason); its mean is a sample mean over the arc,
      within 3h/W·(max s − min s) + h·max|s'| of the time mean over the exact arc of width W; the spread's
      bound follows from those by the quotient rule."""
    p = _gait_problem()
    ev, X = _feasible_designs(p)
    e = ev(X)
    plan, M = p.plan, p.cycle_samples
    h = 2 * math.pi / M
    w = abs(float(plan.speeds[0]))
    foot = plan.point_index("H")
    for i, x in enumerate(X):
        params = ev.params(x[None, :])[0]
        g = assur.gait_metrics(plan, params)
        qd = np.linspace(0, 2 * math.pi, 40 * M, endpoint=False)
        st = assur.solve(plan, params, qd[:, None], order=2, backend="numpy")
        dP, d2P = st.dpos_dq[:, foot, :, 0], st.d2pos_dq2[:, foot, :, 0, 0]
        x1, v1, x2, v2 = np.abs(dP[:, 0]), np.abs(dP[:, 1]), np.abs(d2P[:, 0]), np.abs(d2P[:, 1])
        speed = w * np.hypot(dP[:, 0], dP[:, 1])
        s1 = w * np.abs(np.sum(dP * d2P, axis=1)) / np.hypot(dP[:, 0], dP[:, 1])
        q = {k: e.quantities[k][i] for k in GAIT}
        assert abs(q["gait.step"] - g.step_length) <= 0.5 * x2.max() * h * h + 1e-12
        assert abs(q["gait.lift"] - g.lift) <= 0.5 * v2.max() * h * h + 1e-12
        assert abs(q["gait.duty"] - g.duty_factor) <= 3 / M
        assert abs(q["gait.sag"] - g.sag) <= h * v1.max() + 0.5 * v2.max() * h * h
        W = g.contact_end - g.contact_start
        srange, ds = g.support_speed.max - g.support_speed.min, h * s1.max()
        dmean = 3 * h / W * srange + ds
        assert abs(q["gait.speed_mean"] - g.support_speed.mean) <= dmean
        spread = srange / g.support_speed.mean
        dspread = 2 * ds / g.support_speed.mean + spread * dmean / g.support_speed.mean
        assert abs(q["gait.speed_spread"] - spread) <= dspread + 1e-12
        assert speed.max() >= g.support_speed.max - 1e-9      # the dense grid's speed bounds the arc's
