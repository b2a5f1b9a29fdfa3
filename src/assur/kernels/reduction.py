"""Every assembly of a group of revolutes by a one-parameter reduction, its roots bracketed on a certified grid (no
plan, no names: points are slots of a program).

A group is reduced to one parameter φ — the angle of one of its bodies about a known pivot — and one condition: a
binary link of the group is cut out, and the rest, given φ, is a chain of dyads solved in closed form, each with
its two branches. For every branch vector s (one sign per dyad) the cut link's condition

    g_s(φ) = |X_s(φ) − Y_s(φ)|² − L²

(X, Y: the points the cut link joined, L: its length) vanishes exactly at the group's assemblies whose dyads are on
the branches s: every assembly is a root of some g_s, and every root of a g_s where its dyads exist is an assembly.

The program (built by :mod:`assur.engine.planar.assemblies` from the group) is a list of operations on complex slots:

- ``("rot", out, pivot, k)``: ``out = pivot + exp(iφ)·k`` (a point of the driven body; k its offset from the
  pivot in the body's frame turned to φ = 0);
- ``("dyad", out, a, r_a, b, r_b, j)``: ``out`` at distance r_a from slot a and r_b from slot b, on the left of
  a → b when s_j = +1 (as :func:`assur.kernels.planar.circle_circle`);
- ``("place", out, p1, p2, k)``: ``out = p1 + (p2 − p1)·k`` (a further point of a body placed by two of its
  points);
- ``("cut", x, y, L)``: the last operation, the condition g.

:func:`bracket` covers [0, 2π) by cells for every sample and branch vector and evaluates the program on each in
interval arithmetic (:mod:`assur.kernels.interval`, rounding covered outward): a cell is dropped where a dyad
cannot close anywhere on it (its radicand's enclosure is negative) or where the enclosure of g excludes 0, and is
halved otherwise, until it is narrower than ``width``. What remains are clusters of adjacent cells, each narrower
than a few ``width`` unless the enclosures stay loose there: every root of every g_s lies in a cluster (the
guarantee), and a cluster whose ends give g opposite signs holds a root. Two roots closer than ``width`` share one
cluster: they are two assemblies closer than that, a group at a singular position.
"""
from __future__ import annotations

import numpy as np

from .interval import Interval, cos_sin


def _sqr(x):
    return x.sqr() if isinstance(x, Interval) else x * x


def _sqrt(x):
    return x.sqrt() if isinstance(x, Interval) else np.sqrt(np.maximum(x, 0.0))


def _cmul(ar, ai, br, bi):
    return ar * br - ai * bi, ar * bi + ai * br


def evaluate(program, known: dict, cos_phi, sin_phi, signs):
    """Run the program on every cell (or point) at once.

    known : {slot: complex (N,)} the known points (per cell);
    cos_phi, sin_phi : (N,) arrays or :class:`Interval`;
    signs : (N, n_dyads) ±1.

    Returns (slots {slot: (re, im)}, radicands [(N,) per dyad: h² of each dyad, the dyad closes where ≥ 0], g)."""
    Z = {s: (np.real(v), np.imag(v)) for s, v in known.items()}
    radicands = []
    g = None
    for op in program:
        kind = op[0]
        if kind == "rot":
            _, out, pivot, k = op
            kr, ki = np.real(k), np.imag(k)
            re, im = _cmul(cos_phi, sin_phi, kr, ki)
            Z[out] = (re + Z[pivot][0], im + Z[pivot][1])
        elif kind == "dyad":
            _, out, a, ra, b, rb, j = op
            (ax, ay), (bx, by) = Z[a], Z[b]
            dx, dy = bx - ax, by - ay
            d2 = _sqr(dx) + _sqr(dy)
            inv = d2.reciprocal() if isinstance(d2, Interval) else 1.0 / d2
            along = 0.5 + (0.5 * (ra * ra - rb * rb)) * inv            # a = (d² + r_a² − r_b²) / (2d²)
            h2 = (ra * ra) * inv - _sqr(along)
            radicands.append(h2)
            h = _sqrt(h2) * signs[:, j]
            Z[out] = (ax + dx * along - dy * h, ay + dy * along + dx * h)
        elif kind == "place":
            _, out, p1, p2, k = op
            (ax, ay), (bx, by) = Z[p1], Z[p2]
            re, im = _cmul(bx - ax, by - ay, np.real(k), np.imag(k))
            Z[out] = (ax + re, ay + im)
        else:   # "cut"
            _, x, y, length = op
            (xr, xi), (yr, yi) = Z[x], Z[y]
            g = _sqr(xr - yr) + _sqr(xi - yi) - length * length
    return Z, radicands, g


def sign_vectors(n_dyads: int) -> np.ndarray:
    """(2**n, n) every branch vector, +1 first."""
    n = int(n_dyads)
    idx = np.arange(2 ** n)[:, None]
    return np.where((idx >> np.arange(n)[None, :]) & 1, -1.0, 1.0) if n else np.ones((1, 0))


#: live cells one sample may hold (over its branch vectors) before its enclosures count as not tightening
SAMPLE_CELLS = 65_536


def bracket(program, n_dyads: int, known: dict, n_samples: int, *, width: float = 1e-9, start_cells: int = 64,
            max_cells: int = 2_000_000, sample_cells: int = SAMPLE_CELLS):
    """The clusters holding every root of every g_s, for ``n_samples`` samples at once (module docstring).

    known : {slot: complex (n_samples,)} (or scalars).

    Returns ``(sample, sign index, φ_lo, φ_hi, sign_change, untightened)``: the clusters as arrays, one entry per
    cluster, ``sign_change`` where g has opposite signs at the cluster's ends (a root certainly inside); and
    ``untightened (n_samples,)``: the samples given up because their enclosures do not tighten (more than
    ``sample_cells`` live cells: a continuum of assemblies, or a position too singular for the grid), which have
    no cluster. A batch whose cells exceed ``max_cells`` is bracketed in halves."""
    known = {k: np.broadcast_to(np.asarray(v, dtype=complex), (n_samples,)) for k, v in known.items()}
    try:
        return _bracket(program, n_dyads, known, n_samples, width, start_cells, max_cells, sample_cells)
    except _TooMany:
        if n_samples < 2:
            raise RuntimeError("the reduction's enclosures do not tighten") from None
    half = n_samples // 2
    parts = [(first, bracket(program, n_dyads, {k: v[first:last] for k, v in known.items()}, last - first,
                             width=width, start_cells=start_cells, max_cells=max_cells, sample_cells=sample_cells))
             for first, last in ((0, half), (half, n_samples))]
    sample = np.concatenate([first + r[0] for first, r in parts])       # the halves' samples renumbered
    return (sample, *(np.concatenate([r[i] for _, r in parts]) for i in range(1, 6)))


class _TooMany(Exception):
    """More live cells than the batch may hold, none of its samples over its own limit."""


def _bracket(program, n_dyads, known, n_samples, width, start_cells, max_cells, sample_cells):
    signs = sign_vectors(n_dyads)
    n_s = len(signs)
    untightened = np.zeros(n_samples, dtype=bool)
    h = 2 * np.pi / start_cells
    sample = np.repeat(np.arange(n_samples), n_s * start_cells)
    sgn = np.tile(np.repeat(np.arange(n_s), start_cells), n_samples)
    lo = np.tile(np.arange(start_cells) * h, n_samples * n_s)
    hi = lo + h
    done_s, done_g, done_lo, done_hi = [], [], [], []
    while len(lo):
        if len(lo) > min(sample_cells, max_cells):
            over = np.bincount(sample, minlength=n_samples) > sample_cells
            if over.any():                       # give those samples up, keep on with the others
                untightened |= over
                keep = ~over[sample]
                sample, sgn, lo, hi = sample[keep], sgn[keep], lo[keep], hi[keep]
            if len(lo) > max_cells:
                raise _TooMany
        c, s = cos_sin(lo, hi)
        cells_known = {k: v[sample] for k, v in known.items()}
        _, rads, g = evaluate(program, cells_known, c, s, signs[sgn])
        keep = g.holds_zero()
        for r in rads:
            keep &= r.hi >= 0
        sample, sgn, lo, hi = sample[keep], sgn[keep], lo[keep], hi[keep]
        small = (hi - lo) <= width
        done_s.append(sample[small])
        done_g.append(sgn[small])
        done_lo.append(lo[small])
        done_hi.append(hi[small])
        sample, sgn, lo, hi = sample[~small], sgn[~small], lo[~small], hi[~small]
        mid = 0.5 * (lo + hi)
        sample, sgn = np.repeat(sample, 2), np.repeat(sgn, 2)
        lo, hi = np.stack([lo, mid], -1).ravel(), np.stack([mid, hi], -1).ravel()
    sample, sgn, lo, hi = (np.concatenate(x) if x else np.zeros(0) for x in (done_s, done_g, done_lo, done_hi))
    sample, sgn = sample.astype(int), sgn.astype(int)
    keep = ~untightened[sample]                  # a sample given up has no cluster, not some of them
    sample, sgn, lo, hi = sample[keep], sgn[keep], lo[keep], hi[keep]
    if len(lo) == 0:
        return sample, sgn, lo, hi, np.zeros(0, dtype=bool), untightened
    order = np.lexsort((lo, sgn, sample))
    sample, sgn, lo, hi = sample[order], sgn[order], lo[order], hi[order]
    # adjacent cells of one sample and branch vector make one cluster (the turn is closed: 2π touches 0)
    new = np.ones(len(lo), dtype=bool)
    new[1:] = (sample[1:] != sample[:-1]) | (sgn[1:] != sgn[:-1]) | (lo[1:] > hi[:-1])
    starts = np.flatnonzero(new)
    ends = np.append(starts[1:], len(lo)) - 1
    c_sample, c_sgn, c_lo, c_hi = sample[starts], sgn[starts], lo[starts], hi[ends]
    wrap = _wraps(c_sample, c_sgn, c_lo, c_hi)
    keep = np.ones(len(c_lo), dtype=bool)
    for first, last in wrap:   # a cluster ending at 2π continues the one starting at 0
        c_lo[first] = c_lo[last] - 2 * np.pi
        keep[last] = False
    c_sample, c_sgn, c_lo, c_hi = c_sample[keep], c_sgn[keep], c_lo[keep], c_hi[keep]
    change = _sign_change(program, known, signs, c_sample, c_sgn, c_lo, c_hi)
    return c_sample, c_sgn, c_lo, c_hi, change, untightened


def _wraps(sample, sgn, lo, hi):
    """Pairs (first, last) of clusters of one sample and branch vector where the last ends at 2π and the first
    starts at 0."""
    out = []
    for i in np.flatnonzero(lo <= 0.0):
        j = np.flatnonzero((sample == sample[i]) & (sgn == sgn[i]) & (hi >= 2 * np.pi))
        if len(j) and j[-1] != i:
            out.append((i, j[-1]))
    return out


def _sign_change(program, known, signs, sample, sgn, lo, hi):
    """(clusters,) bool: g has opposite signs at the two ends of the cluster, both on closing dyads."""
    if len(lo) == 0:
        return np.zeros(0, dtype=bool)
    ends = []
    for phi in (lo, hi):
        cells_known = {k: v[sample] for k, v in known.items()}
        _, rads, g = evaluate(program, cells_known, np.cos(phi), np.sin(phi), signs[sgn])
        ok = np.ones(len(phi), dtype=bool)
        for r in rads:
            ok &= r >= 0
        ends.append(np.where(ok, g, np.nan))
    return np.sign(ends[0]) * np.sign(ends[1]) < 0
