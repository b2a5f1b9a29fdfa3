"""The uniqueness ball that proves a Newton-solved group's sample far from its other assemblies
(newton_group.alone_within, docs/assemblies.md), checked on the class-IV six-bar against what it rests on:

- the Lipschitz bound of the scaled Jacobian, against the Jacobians at random pairs of poses;
- the reach bound (points within d put the poses within reach·d), against random displacements;
- the conclusion, against the group's own assemblies enumerated by the certified reduction: no assembly is ever
  proven alone within the distance at which another assembly actually is, down to two assemblies about to merge at
  the end of a locked range, while the ordinary separation (1e-6 of the length scale) is proven almost everywhere.
"""
from __future__ import annotations

import numpy as np
import pytest

import assur
from assur.engine.planar.continuation import execute
from assur.engine.planar.group_assemblies import before_group, group_assemblies, group_points, take_rows
from assur.engine.planar.newton_group import _residual_and_jacobian, alone_within, ball_constants
from assur.kernels.jet import Jet
from assur.tolerances import DEFAULT


def _assemblies(plan, params, q):
    """Every assembly of the class-IV group at the inputs q: (context rows, poses X (M, 3k), the group step, the
    distance (m) from each to the nearest other assembly at its input)."""
    st = [s for s in plan.steps if s.kind == "newton"][0]
    n = len(q)
    flat = before_group(execute(plan, plan.steps, params, [Jet.const(q, 0)], 0, DEFAULT), st)
    poses, found, _, _, _ = group_assemblies(flat, st, n, DEFAULT)
    rows, ks = np.nonzero(found)
    X = poses[rows, ks]
    sub = take_rows(flat, rows, n)
    z = group_points(sub, st, X, np.arange(len(X)), len(X))
    nearest = np.full(len(X), np.inf)
    for i in range(len(X)):
        same = np.flatnonzero((rows == rows[i]) & (np.arange(len(X)) != i))
        if len(same):
            nearest[i] = np.min(np.max(np.abs(z[same] - z[i]), axis=-1))
    return sub, X, st, nearest


def _counts(plan, params, q):
    st = [s for s in plan.steps if s.kind == "newton"][0]
    flat = before_group(execute(plan, plan.steps, params, [Jet.const(q, 0)], 0, DEFAULT), st)
    return group_assemblies(flat, st, len(q), DEFAULT)[1].sum(axis=1)


@pytest.fixture(scope="module")
def classiv():
    from conftest import EXAMPLES
    return assur.compile(assur.load(EXAMPLES / "classiv_sixbar.toml"))


def test_the_scaled_jacobian_turns_no_faster_than_gamma(classiv):
    sub, X, st, _ = _assemblies(classiv, classiv.defaults, np.linspace(0, 2 * np.pi, 37))
    gamma, cols, _, _ = ball_constants(sub, st, len(X))
    rng = np.random.default_rng(1)
    ratios = []
    for size in (1e-4, 1e-2, 1.0):
        V = X + rng.normal(size=X.shape) * size * np.tile([classiv.length_scale] * 2 + [1.0], len(st.bodies))
        J = _residual_and_jacobian(sub, st, X, (len(X),))[1] / cols[:, None, :]
        JV = _residual_and_jacobian(sub, st, V, (len(X),))[1] / cols[:, None, :]
        lhs = np.linalg.norm(J - JV, ord=2, axis=(1, 2))
        ratios.append(lhs / (gamma * np.linalg.norm((X - V) * cols, axis=-1)))
    ratios = np.concatenate(ratios)
    assert np.all(ratios <= 1 + 1e-9)
    assert ratios.max() > 0.3          # and the bound is not loose by orders of magnitude


def test_points_within_d_put_the_poses_within_reach_times_d(classiv):
    sub, X, st, _ = _assemblies(classiv, classiv.defaults, np.linspace(0, 2 * np.pi, 37))
    _, cols, reach, smallest = ball_constants(sub, st, len(X))
    rng = np.random.default_rng(2)
    checked = 0
    for size in (1e-6, 1e-3, 3e-2, 0.3):
        V = X + rng.normal(size=X.shape) * size * np.tile([classiv.length_scale] * 2 + [1.0], len(st.bodies))
        m = len(X)
        d = np.max(np.abs(group_points(sub, st, V, np.arange(m), m) - group_points(sub, st, X, np.arange(m), m)),
                   axis=-1)
        diff = X - V
        diff[:, 2::3] = (diff[:, 2::3] + np.pi) % (2 * np.pi) - np.pi       # the short way round
        ok = d <= smallest
        assert np.all(np.linalg.norm(diff * cols, axis=-1)[ok] <= (reach * d)[ok] * (1 + 1e-12))
        checked += ok.sum()
    assert checked > 2 * len(X)


@pytest.mark.slow            # about 9 s
def test_no_assembly_is_proven_alone_where_another_is(classiv):
    """A design whose group locks over part of the turn (the binary b2 at 0.8 of its length): at the ends of the
    locked range two assemblies meet, so the nearest other one comes arbitrarily close."""
    params = classiv.defaults.copy()
    params[classiv.param_names.index("b2.length")] *= 0.8
    q = np.linspace(0, 2 * np.pi, 361)
    counts = _counts(classiv, params, q)
    assert set(counts) == {0, 2}
    built = assur.solve(classiv, params, q).valid
    assert np.array_equal(built, counts > 0)
    edges = np.flatnonzero(built[:-1] != built[1:])
    assert len(edges) >= 2
    near_edges = []
    for i in edges:                     # bisect towards each end of the locked range, keeping the assembled side
        inside, outside = (q[i], q[i + 1]) if built[i] else (q[i + 1], q[i])
        for _ in range(18):
            mid = 0.5 * (inside + outside)
            if assur.solve(classiv, params, mid).valid:
                inside = mid
            else:
                outside = mid
        near_edges += [inside, 0.5 * (inside + q[i if built[i] else i + 1])]
    sub, X, st, nearest = _assemblies(classiv, params, np.concatenate([q[counts > 0], near_edges]))
    assert np.isfinite(nearest).all() and nearest.min() < 2e-4 * classiv.length_scale
    F, J = _residual_and_jacobian(sub, st, X, (len(X),))
    assert not alone_within(sub, st, X, F, J, nearest).any()
    assert not alone_within(sub, st, X, F, J, 1.0001 * nearest).any()
    sep = DEFAULT.assembly_separation * classiv.length_scale
    proven = alone_within(sub, st, X, F, J, np.full(len(X), sep))
    assert proven[:int(counts.sum())].mean() > 0.95 and proven[nearest > 1e-2 * classiv.length_scale].all()
