"""The contact events of the mesh check (assur.gears.contact.events), which solve only the (point, segment) pairs that
can meet, against a brute-force solution of every pair written here: a point p turning about the origin by an
angle sign·δ crosses the segment a→b where |a + t(b − a)| = |p| (a quadratic in t, 0 ≤ t < 1); δ is the angle
from p to the crossing, wrapped to (−π, π], kept where |δ| ≤ W; the point enters the polygon (counter-clockwise)
when its motion points to the left of the segment.
"""
import math

import numpy as np
import pytest

from assur.gears.contact import events, passed


def brute_force(p, a, b, sign, W):
    """Per row and point, the sorted list of (δ, enters) over every segment (plain Python)."""
    out = []
    for s in range(p.shape[0]):
        rows = []
        for v in range(p.shape[1]):
            px, py = p[s, v]
            rho2 = px * px + py * py
            found = []
            for e in range(a.shape[1]):
                ax, ay = a[s, e]
                dx, dy = b[s, e] - a[s, e]
                A, B, C = dx * dx + dy * dy, ax * dx + ay * dy, ax * ax + ay * ay - rho2
                disc = B * B - A * C
                if A <= 0 or disc < 0:
                    continue
                for t in ((-B - math.sqrt(disc)) / A, (-B + math.sqrt(disc)) / A):
                    if not 0 <= t < 1:
                        continue
                    x, y = ax + t * dx, ay + t * dy
                    d = sign * ((math.atan2(y, x) - math.atan2(py, px) + math.pi) % (2 * math.pi) - math.pi)
                    if abs(d) <= W[s]:
                        beta = math.atan2(y, x)
                        found.append((d, bool(dx * sign * math.cos(beta) + dy * sign * math.sin(beta) > 0)))
            rows.append(sorted(found))
        out.append(rows)
    return out


def as_lists(ev, en):
    return [[sorted((float(d), bool(n)) for d, n in zip(ev[s, v], en[s, v]) if np.isfinite(d))
             for v in range(ev.shape[1])] for s in range(ev.shape[0])]


@pytest.mark.parametrize("seed, W, spread", [(0, 0.05, 0.3), (1, 0.3, 1.0), (2, 1.2, math.pi), (3, 3.0, math.pi),
                                                 (4, math.pi, math.pi)])
def test_events_equal_the_brute_force_solution(seed, W, spread):
    # a wavy closed polygon about the origin (a gear-like outline) and points near it; spread: the angular range
    # they cover (π: the whole turn, so windows wrap through ±π), W: the half range of offsets searched
    rng = np.random.default_rng(seed)
    S, V, E = 3, 40, 70
    ang = np.sort(rng.uniform(-spread, spread, (S, E + 1)), axis=1)
    rad = 1.0 + 0.1 * np.sin(12 * ang) + 0.02 * rng.standard_normal((S, E + 1))
    ring = np.stack([rad * np.cos(ang), rad * np.sin(ang)], axis=-1)
    a, b = ring[:, :-1], ring[:, 1:]
    pa = rng.uniform(-spread, spread, (S, V))
    pr = rng.uniform(0.85, 1.15, (S, V))
    p = np.stack([pr * np.cos(pa), pr * np.sin(pa)], axis=-1)
    Wrow = np.full(S, W)
    for sign in (1.0, -1.0):
        ev, en = events(p, a, b, sign, Wrow)
        got, want = as_lists(ev, en), brute_force(p, a, b, sign, Wrow)
        assert sum(len(x) for row in want for x in row) > 20          # the case has crossings to find
        for s in range(S):
            for v in range(V):
                assert [n for _, n in got[s][v]] == [n for _, n in want[s][v]]
                np.testing.assert_allclose([d for d, _ in got[s][v]], [d for d, _ in want[s][v]], rtol=0,
                                           atol=1e-12)


def test_an_event_across_half_a_turn_is_found():
    # the point at 3.13 rad, the segment’s crossing of its circle near −0.1 rad: 3.23 rad apart one way, 3.05 the
    # other, so within W = 3.1 only through the wrap at ±π
    p = np.array([[[math.cos(3.13), math.sin(3.13)]]])
    a = np.array([[[0.95, 0.0]]])
    b = np.array([[[1.05 * math.cos(-0.2), 1.05 * math.sin(-0.2)]]])
    for sign in (1.0, -1.0):
        ev, en = events(p, a, b, sign, np.array([3.1]))
        want = brute_force(p, a, b, sign, np.array([3.1]))
        assert len(want[0][0]) == 1
        (got,) = as_lists(ev, en)[0][0]
        assert got[0] == pytest.approx(want[0][0][0][0], abs=1e-12) and got[1] == want[0][0][0][1]


def test_events_passed_are_counted_as_by_comparison():
    # passed counts, per point and offset, the events ≤ the offset by sorting and searching; here the plain
    # comparison of every event with every offset, with ties (offsets equal to events), −0.0, NaN padding of the
    # events and NaN offsets (none passed)
    rng = np.random.default_rng(5)
    S, P, C, G = 4, 30, 6, 50
    e = np.sort(rng.integers(-5, 6, (P, C)).astype(float) / 4, axis=1)
    e[rng.random((P, C)) < 0.3] = np.inf
    e = np.sort(e, axis=1)
    e[np.isinf(e)] = np.nan
    e[0, 0] = -0.0
    si = np.sort(rng.integers(0, S, P))
    delta = rng.integers(-6, 7, (S, G)).astype(float) / 4
    delta[:, 0] = 0.0
    delta[1, 5:9] = np.nan
    want = np.array([[np.sum(e[p][np.isfinite(e[p])] <= delta[si[p], g]) for g in range(G)] for p in range(P)])
    assert np.array_equal(passed(e, si, delta), want)
    assert want.max() > 0 and (want == 0).any()
