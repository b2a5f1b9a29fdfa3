"""Contact events of two polygons turning against each other, for the mesh check (:mod:`assur.gears.mesh`).

A point p turning about the origin by sign·δ crosses a segment a→b where its circle |x| = |p| meets the segment;
:func:`events` lists those offsets δ within ±W for every point (entering or leaving the polygon's material),
solving only the (point, segment) pairs that can meet (:func:`near_pairs`). :func:`status`, :func:`inside_any` and
:func:`depth_of` read, at any offsets, which points are inside the other polygon and how deep.
"""
from __future__ import annotations

import math

import numpy as np

from .raster import TWO_PI, wrap_angle


#: angular margin (rad) of the candidate (point, segment) pairs of :func:`near_pairs`, far above round-off
_ANGLE_MARGIN = 1e-9


def _complex_pairs(first, second):
    """(first, second) as complex numbers (broadcast), which numpy sorts and searches lexicographically: the
    real part exactly ``first``, the imaginary part exactly ``second`` (even ±inf)."""
    first, second = np.broadcast_arrays(np.asarray(first, dtype=float), np.asarray(second, dtype=float))
    out = np.empty(first.shape, dtype=complex)
    out.real, out.imag = first, second
    return out


def near_pairs(p, rho, a, b, rmin, rmax, W):
    """The (point, segment) pairs that can meet: the circle of point p[s, v] (radius rho[s, v]) crosses the radial
    range [rmin, rmax][s, e] of segment a[s, e]→b[s, e], and the arc of angles ±W[s] it sweeps about the origin
    can reach the segment's angular span. Returns (si, vi, ei) index arrays ordered by (s, v, e), a subset of
    ``np.nonzero`` of the full (S, V, E) radial mask holding every pair of it that can give a crossing within ±W.
    The points of each row are sorted by radius, so each segment's radial range is one slice of them."""
    S, V = rho.shape
    E = rmin.shape[1]
    # (row, radius) as complex numbers, which numpy orders lexicographically: one exact sorted search for all rows
    row = np.arange(S)[:, None]
    key = _complex_pairs(row, rho).ravel()                                            # (S·V,)
    order = np.argsort(key, kind="stable")
    key = key[order]
    first = np.searchsorted(key, _complex_pairs(row, rmin).ravel(), side="left")     # rho ≥ rmin
    last = np.searchsorted(key, _complex_pairs(row, rmax).ravel(), side="right")     # rho ≤ rmax
    count = np.maximum(last - first, 0)                                               # (S·E,)
    owner = np.repeat(np.arange(S * E), count)
    j = np.arange(owner.size) - np.repeat(np.cumsum(count) - count, count) + np.repeat(first, count)
    si, ei = np.divmod(owner, E)
    vi = order[j] - si * V
    # angles relative to the segment's start: the segment spans [min(0, t), max(0, t)], the point sweeps
    # [g − W, g + W]; pairs near half a turn apart (angles that could wrap) are kept
    beta_a = np.arctan2(a[..., 1], a[..., 0])                                        # (S, E)
    t = wrap_angle(np.arctan2(b[..., 1], b[..., 0]) - beta_a)[si, ei]
    g = wrap_angle(np.arctan2(p[..., 1], p[..., 0])[si, vi] - beta_a[si, ei])
    reach = np.asarray(W, dtype=float)[si] + _ANGLE_MARGIN
    near = (g + reach >= np.minimum(t, 0.0)) & (g - reach <= np.maximum(t, 0.0))
    keep = near | (np.abs(g) + reach + np.abs(t) >= 0.9 * math.pi)
    si, vi, ei = si[keep], vi[keep], ei[keep]
    o = np.argsort((si * V + vi) * E + ei, kind="stable")
    return si[o], vi[o], ei[o]


def events(p, a, b, sign, W):
    """Driven offsets δ at which points p (S, V, 2), moving on circles about the origin by the angle sign·δ, cross
    the segments a→b (S, E, 2) of a counter-clockwise polygon within ±W (S,): δ (S, V, C) sorted per point (NaN
    padded) and whether the point enters the polygon's material there (S, V, C). Only the (point, segment) pairs
    that can meet within ±W are solved (:func:`near_pairs`)."""
    S, V = p.shape[:2]
    rho = np.hypot(p[..., 0], p[..., 1])                                    # (S, V)
    d = b - a                                                               # (S, E, 2)
    dd = np.einsum("sei,sei->se", d, d)
    ad = np.einsum("sei,sei->se", a, d)
    with np.errstate(divide="ignore", invalid="ignore"):
        foot = np.clip(-ad / dd, 0.0, 1.0)
    foot = np.where(dd > 0, foot, 0.0)
    rmin = np.hypot(a[..., 0] + foot * d[..., 0], a[..., 1] + foot * d[..., 1])
    rmax = np.maximum(np.hypot(a[..., 0], a[..., 1]), np.hypot(b[..., 0], b[..., 1]))
    si, vi, ei = near_pairs(p, rho, a, b, rmin, rmax, W)
    A, B = dd[si, ei], ad[si, ei]
    aa = a[si, ei]
    dv = d[si, ei]
    C = aa[:, 0] ** 2 + aa[:, 1] ** 2 - rho[si, vi] ** 2
    disc = B * B - A * C
    ok = (disc >= 0) & (A > 0)
    sq = np.sqrt(np.where(ok, disc, 0.0))
    beta0 = np.arctan2(p[si, vi, 1], p[si, vi, 0])
    ds, en, key = [], [], []
    for root in (-sq, sq):
        with np.errstate(divide="ignore", invalid="ignore"):
            tt = (-B + root) / A
        hit = ok & (tt >= 0) & (tt < 1)
        x = aa[:, 0] + tt * dv[:, 0]
        y = aa[:, 1] + tt * dv[:, 1]
        beta = np.arctan2(y, x)
        delta = sign * (np.mod(beta - beta0 + math.pi, TWO_PI) - math.pi)
        hit &= np.abs(delta) <= W[si]
        # the point's motion as δ grows: ccw (sign +1) or cw (sign −1) about the origin
        tx, ty = -sign * np.sin(beta), sign * np.cos(beta)
        ds.append(delta[hit])
        en.append(((dv[:, 0] * ty - dv[:, 1] * tx) > 0)[hit])
        key.append((si * V + vi)[hit])
    ds, en, key = np.concatenate(ds), np.concatenate(en), np.concatenate(key)
    order = np.lexsort((ds, key))
    ds, en, key = ds[order], en[order], key[order]
    start = np.searchsorted(key, key, side="left")
    rank = np.arange(key.size) - start
    Cn = int(rank.max()) + 1 if rank.size else 1
    ev = np.full((S * V, Cn), np.nan)
    ent = np.zeros((S * V, Cn), dtype=bool)
    ev[key, rank] = ds
    ent[key, rank] = en
    return ev.reshape(S, V, Cn), ent.reshape(S, V, Cn)


def status(ev, en, delta, far):
    """The points that have events (index arrays si, vi (P,)), and at offsets delta (S, G) whether each of them
    is inside the other polygon (P, G) and its circumferential depth factor (P, G), rad: the distance to the
    nearer of its next and previous events, ``far`` (S,) on a side without one. A point without events is inside
    or not at every offset (its ``base``)."""
    C = ev.shape[-1]
    nvalid = np.sum(np.isfinite(ev), axis=-1)                                     # (S, V)
    si, vi = np.nonzero(nvalid)
    e, n_e = ev[si, vi], en[si, vi]                                               # (P, C)
    dg = delta[si]                                                                # (P, G)
    k = passed(e, si, delta)                                                     # (P, G) events passed
    nxt_i = np.minimum(k, C - 1)
    prv_i = np.maximum(k - 1, 0)
    has_n = k < nvalid[si, vi][:, None]
    has_p = k > 0
    en_n = np.take_along_axis(n_e, nxt_i, axis=-1)
    en_p = np.take_along_axis(n_e, prv_i, axis=-1)
    inside = np.where(has_n, ~en_n, en_p)           # a point with events has a next or a previous one
    f = far[si][:, None]
    nxt = np.where(has_n, np.take_along_axis(e, nxt_i, axis=-1) - dg, f)
    prv = np.where(has_p, dg - np.take_along_axis(e, prv_i, axis=-1), f)
    return si, vi, inside, np.minimum(nxt, prv)


def passed(e, si, delta):
    """(P, G) how many of the events e[p] (P, C; sorted, NaN padded) are ≤ each offset of row si[p] of delta (S, G)
    (none for a NaN offset). Many offsets: each event is placed among the row's sorted offsets (one search for all
    rows: (row, value) as complex numbers, ordered lexicographically) and the placements are summed up."""
    P, C = e.shape
    S, G = delta.shape
    if G * C <= 64:
        return np.sum(e[:, None, :] <= delta[si][:, :, None], axis=-1)
    d = np.where(np.isnan(delta), np.inf, delta)
    order = np.argsort(d, axis=1, kind="stable")
    keys = _complex_pairs(np.arange(S)[:, None], np.take_along_axis(d, order, axis=1)).ravel()
    pp, cc = np.nonzero(np.isfinite(e))
    at = np.searchsorted(keys, _complex_pairs(si[pp], e[pp, cc]), side="left") - si[pp] * G   # first offset ≥ the event
    below = np.cumsum(np.bincount(pp * (G + 1) + at, minlength=P * (G + 1)).reshape(P, G + 1)[:, :G], axis=1)
    rank = np.empty_like(order)
    np.put_along_axis(rank, order, np.arange(G)[None, :], axis=1)                # rank[s, g]: place of offset g
    k = np.take_along_axis(below, rank[si], axis=1)
    k[np.isnan(delta)[si]] = 0
    return k


def inside_any(ev, en, base):
    """(S,) whether any point is inside the other polygon at offset 0."""
    si, vi, inside, _ = status(ev, en, np.zeros((ev.shape[0], 1)), np.ones(ev.shape[0]))
    out = np.any(base & ~np.isfinite(ev).any(axis=-1), axis=1)                 # points without events
    np.logical_or.at(out, si, inside[:, 0])
    return out


def depth_of(ev, en, base, rho, delta, far):
    """(S, G) the largest penetration (m) of any point at offsets delta (S, G): per point inside, its
    circumferential depth factor (the nearer exit, or ``far`` (S,) when none) times its radius rho (S, V)."""
    si, vi, inside, d = status(ev, en, delta, far)
    S, G = delta.shape
    fixed = np.where(base & ~np.isfinite(ev).any(axis=-1), far[:, None] * rho, 0.0).max(axis=1)   # (S,)
    out = np.repeat(fixed[:, None], G, axis=1)
    if si.size:
        val = np.where(inside, d * rho[si, vi][:, None], 0.0)                                         # (P, G)
        rows, start = np.unique(si, return_index=True)
        out[rows] = np.maximum(out[rows], np.maximum.reduceat(val, start, axis=0))
    return out


__all__ = ["depth_of", "events", "inside_any", "near_pairs", "passed", "status"]
