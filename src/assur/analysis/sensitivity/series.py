"""Truncated series in one path variable s and two nilpotent directions ε₁, ε₂ (ε₁² = ε₂² = 0), on arrays.

A :class:`Series` is x(s, ε₁, ε₂) = Σ_k s^k·(x⁰_k + ε₁·x¹_k + ε₂·x²_k + ε₁ε₂·x¹²_k) for k < K: Taylor coefficients in
s (a path in time: k = 0, 1, 2 the value, the velocity, half the acceleration) of the value and of its derivatives
along the direction sets ε₁ (the parameters) and ε₂ (virtual displacements). The parts are arrays with two trailing
direction axes: the value (..., 1, 1), the ε₁ part (..., D₁, 1), the ε₂ part (..., 1, D₂), the mixed part
(..., D₁, D₂), so that every product broadcasts into its place; a part that is identically zero is None.

Arithmetic follows the product rule exactly (no step): this is forward-mode differentiation of the closure and the
equilibrium, written once for the sensitivity solver (:mod:`.closure`, :mod:`.implicit`).
"""
from __future__ import annotations

import numpy as np

PARTS = ("v", "e1", "e2", "e12")


def _add(a, b):
    if a is None:
        return b
    if b is None:
        return a
    return [x + y for x, y in zip(a, b)]


def _neg(a):
    return None if a is None else [-x for x in a]


def _conv(a, b):
    """The truncated Cauchy product of two s-series (lists of arrays of the same length)."""
    if a is None or b is None:
        return None
    K = min(len(a), len(b))
    return [sum(a[m] * b[k - m] for m in range(k + 1)) for k in range(K)]


def _scale(a, c):
    return None if a is None else [x * c for x in a]


def _map(f, a):
    return None if a is None else [f(x) for x in a]


class Series:
    """x = v + ε₁·e1 + ε₂·e2 + ε₁ε₂·e12, each part a list of K arrays (the s-series) or None."""
    __slots__ = ("v", "e1", "e2", "e12")
    __array_priority__ = 1000

    def __init__(self, v, e1=None, e2=None, e12=None):
        self.v, self.e1, self.e2, self.e12 = v, e1, e2, e12

    @property
    def K(self) -> int:
        return len(self.v)

    @staticmethod
    def const(x, K: int) -> "Series":
        """A constant (…) array as a series (its value in the shape (..., 1, 1))."""
        x = np.asarray(x)[..., None, None]
        return Series([x] + [np.zeros_like(x) for _ in range(K - 1)])

    # -- arithmetic ---------------------------------------------------------------------------------------
    def __add__(self, o):
        if isinstance(o, Series):
            return Series(_add(self.v, o.v), _add(self.e1, o.e1), _add(self.e2, o.e2), _add(self.e12, o.e12))
        o = _lift(o)
        return Series([self.v[0] + o] + self.v[1:], self.e1, self.e2, self.e12)

    __radd__ = __add__

    def __neg__(self):
        return Series(_neg(self.v), _neg(self.e1), _neg(self.e2), _neg(self.e12))

    def __sub__(self, o):
        return self + (-o)

    def __rsub__(self, o):
        return (-self) + o

    def __mul__(self, o):
        if not isinstance(o, Series):
            o = _lift(o)
            return Series(_scale(self.v, o), _scale(self.e1, o), _scale(self.e2, o), _scale(self.e12, o))
        a, b = self, o
        v = _conv(a.v, b.v)
        e1 = _add(_conv(a.v, b.e1), _conv(a.e1, b.v))
        e2 = _add(_conv(a.v, b.e2), _conv(a.e2, b.v))
        e12 = _add(_add(_conv(a.v, b.e12), _conv(a.e12, b.v)), _add(_conv(a.e1, b.e2), _conv(a.e2, b.e1)))
        return Series(v, e1, e2, e12)

    __rmul__ = __mul__

    def reciprocal(self) -> "Series":
        """1/x: the value's series by the recurrence y_k = −Σ_{m≥1} x_m·y_{k−m}/x_0; g′ = −y², g″ = 2y³."""
        x = self.v
        y = [1.0 / x[0]]
        for k in range(1, len(x)):
            y.append(-sum(x[m] * y[k - m] for m in range(1, k + 1)) * y[0])
        y2 = _conv(y, y)
        return _unary(self, None, _neg(y2), _scale(_conv(y2, y), 2.0), y)

    def __truediv__(self, o):
        if isinstance(o, Series):
            return self * o.reciprocal()
        return self * (1.0 / _lift(o))

    def __rtruediv__(self, o):
        return self.reciprocal() * o

    # -- complex parts ------------------------------------------------------------------------------------
    def conj(self) -> "Series":
        return Series(_map(np.conj, self.v), _map(np.conj, self.e1), _map(np.conj, self.e2), _map(np.conj, self.e12))

    @property
    def real(self) -> "Series":
        return Series(_map(np.real, self.v), _map(np.real, self.e1), _map(np.real, self.e2), _map(np.real, self.e12))

    @property
    def imag(self) -> "Series":
        return Series(_map(np.imag, self.v), _map(np.imag, self.e1), _map(np.imag, self.e2), _map(np.imag, self.e12))

    def truncate(self, K: int) -> "Series":
        """The first K coefficients of each part."""
        f = (lambda a: None if a is None else a[:K])
        return Series(f(self.v), f(self.e1), f(self.e2), f(self.e12))


def _lift(c):
    """A constant operand (a number, or an array (...) of the batch) in the value's (..., 1, 1) layout."""
    c = np.asarray(c)
    return c if c.ndim == 0 else c[..., None, None]


def _unary(x: Series, f0, f1, f2, series) -> Series:
    """g(x) for a function with derivatives f1 = g′(x₀(s)) and f2 = g″(x₀(s)) given as s-series, and the value's
    s-series ``series`` (g of the value's series)."""
    g1, g2 = f1, f2
    e1 = _conv(x.e1, g1) if x.e1 is not None else None
    e2 = _conv(x.e2, g1) if x.e2 is not None else None
    e12 = None
    if x.e12 is not None:
        e12 = _conv(x.e12, g1)
    if x.e1 is not None and x.e2 is not None:
        e12 = _add(e12, _conv(_conv(x.e1, x.e2), g2))
    return Series(series, e1, e2, e12)


def expi(theta: Series) -> Series:
    """exp(i·θ) of a real series."""
    t = theta.v
    e = [np.exp(1j * t[0])]
    for k in range(1, len(t)):                      # y′ = i·θ′·y: k·y_k = Σ m·i·θ_m·y_{k−m}
        e.append(sum(m * 1j * t[m] * e[k - m] for m in range(1, k + 1)) / k)
    ie = [1j * x for x in e]
    me = [-x for x in e]
    return _unary(theta, None, ie, me, e)


def sqrt(x: Series) -> Series:
    """√x of a real, positive series."""
    a = x.v
    y = [np.sqrt(a[0])]
    for k in range(1, len(a)):
        y.append((a[k] - sum(y[m] * y[k - m] for m in range(1, k))) / (2.0 * y[0]))
    inv = Series(y).reciprocal().v                                  # 1/√x
    g1 = [0.5 * c for c in inv]
    g2 = _scale(_conv(_conv(inv, inv), inv), -0.25)                   # −x^{−3/2}/4
    return _unary(x, None, g1, g2, y)


def abs_complex(z: Series) -> Series:
    """|z| of a complex series."""
    return sqrt((z * z.conj()).real)


def arg(z: Series) -> Series:
    """arg z of a complex series (the value in (−π, π]; the rest exact): Im log z."""
    u = z / Series.const(z.v[0][..., 0, 0], z.K)                      # u₀ = 1
    a = u.v
    L = [np.zeros_like(np.real(a[0]))]                                # log u: k·l_k = k·u_k − Σ m·l_m·u_{k−m}
    for k in range(1, len(a)):
        L.append(a[k] - sum(m * L[m] * a[k - m] for m in range(1, k)) / k)
    inv = u.reciprocal().v
    g1 = inv
    g2 = _neg(_conv(inv, inv))
    out = _unary(u, None, g1, g2, L)
    out.v = [out.v[0] + 1j * np.angle(z.v[0])] + out.v[1:]
    return out.imag


def variable(value, directions: np.ndarray | None, part: str, K: int, series=None) -> Series:
    """A series whose value is ``value`` (...) (or the s-series ``series``) and whose derivative along ``part``
    ('e1' or 'e2') is ``directions`` (..., D): the unit seeds of a direction set."""
    v = series if series is not None else [np.asarray(value)[..., None, None]] + \
        [np.zeros(np.shape(value) + (1, 1)) for _ in range(K - 1)]
    out = Series(v)
    if directions is not None:
        d = directions[..., :, None] if part == "e1" else directions[..., None, :]
        setattr(out, part, [d] + [np.zeros_like(d) for _ in range(K - 1)])
    return out
