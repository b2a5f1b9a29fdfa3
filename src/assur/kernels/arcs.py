"""The sampled contact arc of a walking leg's foot path over one input turn: pure array functions shared by the
gait metrics of a population (:func:`assur.analysis.gait.population_gait`) and the foot loads of a walking module
(:mod:`assur.kinetostatics.gait`).

The two samples of smallest and largest stride coordinate x split the turn into two arcs; the contact (support)
arc is the one whose sample-mean height is lower. An arc is (start, width) in sample indices: the samples k with
``(k − start) mod M ≤ width``; :func:`in_arc` is the same test on input angles (an exact gait's contact arc).
"""
from __future__ import annotations

import math

import numpy as np

TWO_PI = 2.0 * math.pi


def in_arc(q, start, width) -> np.ndarray:
    """(...) bool: the input angles ``q`` (..., rad) on the arc that runs ``width`` (rad, 0 … 2π) forward from
    ``start`` (rad), the turn taken mod 2π; an exact gait's contact arc is ``start`` = contact_start, ``width`` =
    contact_end − contact_start."""
    return np.mod(np.asarray(q, dtype=float) - start, TWO_PI) <= width


def population_contact(pos, *, ground, up) -> tuple[np.ndarray, np.ndarray]:
    """The sampled contact arc of n designs, the one :func:`assur.analysis.gait.population_gait` uses: (start (n,), width (n,)) as
    sample indices, the arc being the samples k with ``(k − start) mod M ≤ width`` (:func:`arc_mask`).
    pos: (n, M, 2) foot positions at M uniform inputs over one turn; ground, up: (2,) directions."""
    g, u = np.asarray(ground, dtype=float), np.asarray(up, dtype=float)
    _, _, start, width = sampled_arcs(pos @ g, pos @ u)
    return start, width


def arc_mask(start, width, M: int, shift=0) -> np.ndarray:
    """(n, M) bool: the samples k of the arcs (start (n,), width (n,) sample indices) of
    :func:`population_contact`, read at sample ``k + shift`` (an integer: a leg ``shift`` samples ahead)."""
    k = np.arange(M) + int(shift)
    return np.mod(k[None, :] - np.asarray(start)[:, None], M) <= np.asarray(width)[:, None]


def sampled_arcs(x, v):
    """(ia, ib, start, width) of stride and height samples x, v (n, M): the samples of smallest and largest x,
    and the contact arc between them with the lower sample-mean height."""
    n, M = x.shape
    ia = np.argmin(np.where(np.isfinite(x), x, np.inf), axis=1)
    ib = np.argmax(np.where(np.isfinite(x), x, -np.inf), axis=1)
    w1, w2 = np.mod(ib - ia, M), np.mod(ia - ib, M)
    arc1, arc2 = arc_mask(ia, w1, M), arc_mask(ib, w2, M)
    with np.errstate(all="ignore"):
        m1 = np.where(arc1, v, 0).sum(axis=1) / arc1.sum(axis=1)
        m2 = np.where(arc2, v, 0).sum(axis=1) / arc2.sum(axis=1)
    first = m1 <= m2
    return ia, ib, np.where(first, ia, ib), np.where(first, w1, w2)
