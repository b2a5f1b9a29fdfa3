"""Interval arithmetic on numpy arrays (no plan, no names): enclosures of a function over whole cells of its
argument, for root exclusion.

An :class:`Interval` holds arrays ``lo ≤ hi`` of one shape. Every operation returns an enclosure of all the values
the operation takes over its operands' intervals; numpy rounds to nearest, so each result is widened outward by a
few units in the last place (:data:`PAD` of its magnitude), which covers the rounding of that operation. An empty
or undefined result (a square root of a negative interval, a division by an interval holding 0) is the whole line
where it matters and is flagged by the caller's tests (``hi < 0`` and friends).
"""
from __future__ import annotations

import numpy as np

#: outward widening of every result, relative to its magnitude (4 units in the last place)
PAD = 4.0 * np.finfo(float).eps
#: and absolute, against underflow
TINY = 1e-300


def _out(lo, hi):
    """The interval [lo, hi] widened outward by PAD of its magnitude and TINY. ``lo`` and ``hi`` are the operation's
    own new arrays, so the widening is written into them (the same numbers as ``lo - w``, ``hi + w``, without the
    temporaries that dominate the cost on large cell arrays)."""
    if (type(lo) is np.ndarray and type(hi) is np.ndarray and lo is not hi and lo.shape == hi.shape
            and lo.dtype == hi.dtype == np.float64 and lo.flags.writeable and hi.flags.writeable):
        w = np.abs(lo)
        np.maximum(w, np.abs(hi), out=w)
        w *= PAD
        w += TINY
        np.subtract(lo, w, out=lo)
        np.add(hi, w, out=hi)
        return Interval(lo, hi)
    m = np.maximum(np.abs(lo), np.abs(hi))
    w = PAD * m + TINY
    return Interval(lo - w, hi + w)


class Interval:
    """An array of intervals [lo, hi]; +, −, ×, / with intervals or plain numbers (module docstring)."""
    __slots__ = ("lo", "hi")
    __array_priority__ = 1000

    def __init__(self, lo, hi=None):
        self.lo = np.asarray(lo, dtype=float)
        self.hi = self.lo if hi is None else np.asarray(hi, dtype=float)

    def __add__(self, o):
        if isinstance(o, Interval):
            return _out(self.lo + o.lo, self.hi + o.hi)
        return _out(self.lo + o, self.hi + o)

    __radd__ = __add__

    def __neg__(self):
        return Interval(-self.hi, -self.lo)

    def __sub__(self, o):
        if isinstance(o, Interval):
            return _out(self.lo - o.hi, self.hi - o.lo)
        return _out(self.lo - o, self.hi - o)

    def __rsub__(self, o):
        return _out(o - self.hi, o - self.lo)

    def __mul__(self, o):
        if isinstance(o, Interval):
            a, b, c, d = self.lo * o.lo, self.lo * o.hi, self.hi * o.lo, self.hi * o.hi
            return _out(np.minimum(np.minimum(a, b), np.minimum(c, d)), np.maximum(np.maximum(a, b), np.maximum(c, d)))
        o = np.asarray(o, dtype=float)
        a, b = self.lo * o, self.hi * o
        return _out(np.minimum(a, b), np.maximum(a, b))

    __rmul__ = __mul__

    def reciprocal(self):
        """1/x; the whole line where the interval holds 0."""
        holds0 = (self.lo <= 0) & (self.hi >= 0)
        with np.errstate(all="ignore"):
            lo, hi = 1.0 / self.hi, 1.0 / self.lo
        return _out(np.where(holds0, -np.inf, lo), np.where(holds0, np.inf, hi))

    def __truediv__(self, o):
        if isinstance(o, Interval):
            return self * o.reciprocal()
        return self * (1.0 / np.asarray(o, dtype=float))

    def sqr(self):
        """x² (tighter than x·x: never negative)."""
        a, b = self.lo * self.lo, self.hi * self.hi
        holds0 = (self.lo <= 0) & (self.hi >= 0)
        return _out(np.where(holds0, 0.0, np.minimum(a, b)), np.maximum(a, b))

    def sqrt(self):
        """√x of the non-negative part (the caller tests ``hi < 0``, where there is none)."""
        return _out(np.sqrt(np.maximum(self.lo, 0.0)), np.sqrt(np.maximum(self.hi, 0.0)))

    def holds_zero(self):
        return (self.lo <= 0) & (self.hi >= 0)


def cos_sin(lo, hi):
    """Enclosures of cos and sin over the angle intervals [lo, hi] (arrays, hi − lo ≤ 2π)."""
    lo, hi = np.asarray(lo, dtype=float), np.asarray(hi, dtype=float)

    def extremes(f, peak):
        """f over [lo, hi] of a function whose maxima are at peak + 2πk and minima at peak + π + 2πk."""
        a, b = f(lo), f(hi)
        lo_v, hi_v = np.minimum(a, b), np.maximum(a, b)
        k_max = np.ceil((lo - peak) / (2 * np.pi))
        has_max = peak + 2 * np.pi * k_max <= hi
        k_min = np.ceil((lo - peak - np.pi) / (2 * np.pi))
        has_min = peak + np.pi + 2 * np.pi * k_min <= hi
        return _out(np.where(has_min, -1.0, lo_v), np.where(has_max, 1.0, hi_v))

    return extremes(np.cos, 0.0), extremes(np.sin, 0.5 * np.pi)
