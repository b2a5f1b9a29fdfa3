"""Second-order forward-mode jets: a value with its first and second derivative along one path.

A :class:`Jet` carries ``v``, ``d = dv/ds`` and ``dd = d²v/ds²`` for one scalar path parameter s
(a crank angle for the papers' *analogues*, or time). Arithmetic propagates the derivatives
exactly (chain and product rules), so closed-form kernels written with jets give exact
velocities and accelerations, never finite differences.

``order`` is 0, 1 or 2: with order 0 only values are carried (``d`` and ``dd`` are ``None``),
which is what a position-only synthesis objective uses. Operands that are plain arrays or
numbers are constants (zero derivatives). Values may be real or complex arrays of any shape;
shapes broadcast as in numpy.
"""
from __future__ import annotations

import numpy as np


class Jet:
    __slots__ = ("v", "d", "dd")
    __array_priority__ = 1000  # make ndarray <op> Jet defer to Jet

    def __init__(self, v, d=None, dd=None):
        self.v = v
        self.d = d
        self.dd = dd

    # -- construction -------------------------------------------------------------------------
    @staticmethod
    def const(v, order: int) -> "Jet":
        v = np.asarray(v)
        z = np.zeros_like(v)
        return Jet(v, z if order >= 1 else None, z if order >= 2 else None)

    @staticmethod
    def variable(v, d, dd, order: int) -> "Jet":
        return Jet(np.asarray(v), d if order >= 1 else None, dd if order >= 2 else None)

    @property
    def order(self) -> int:
        return 0 if self.d is None else (1 if self.dd is None else 2)

    # -- arithmetic -----------------------------------------------------------------------------
    def __add__(self, o):
        if isinstance(o, Jet):
            return Jet(self.v + o.v, _add(self.d, o.d), _add(self.dd, o.dd))
        return Jet(self.v + o, self.d, self.dd)

    __radd__ = __add__

    def __sub__(self, o):
        if isinstance(o, Jet):
            return Jet(self.v - o.v, _sub(self.d, o.d), _sub(self.dd, o.dd))
        return Jet(self.v - o, self.d, self.dd)

    def __rsub__(self, o):
        return Jet(o - self.v, _neg(self.d), _neg(self.dd))

    def __neg__(self):
        return Jet(-self.v, _neg(self.d), _neg(self.dd))

    def __mul__(self, o):
        if isinstance(o, Jet):
            v = self.v * o.v
            d = dd = None
            if self.d is not None:
                d = self.d * o.v + self.v * o.d
                if self.dd is not None:
                    dd = self.dd * o.v + 2.0 * (self.d * o.d) + self.v * o.dd
            return Jet(v, d, dd)
        return Jet(self.v * o, _mul(self.d, o), _mul(self.dd, o))

    __rmul__ = __mul__

    def reciprocal(self) -> "Jet":
        r = 1.0 / self.v
        d = dd = None
        if self.d is not None:
            r2 = r * r
            d = -self.d * r2
            if self.dd is not None:
                dd = -self.dd * r2 + 2.0 * (self.d * self.d) * (r2 * r)
        return Jet(r, d, dd)

    def __truediv__(self, o):
        if isinstance(o, Jet):
            return self * o.reciprocal()
        return Jet(self.v / o, _div(self.d, o), _div(self.dd, o))

    def __rtruediv__(self, o):
        return self.reciprocal() * o

    # -- complex helpers ------------------------------------------------------------------------
    def conj(self) -> "Jet":
        return Jet(np.conj(self.v), _map(np.conj, self.d), _map(np.conj, self.dd))

    @property
    def real(self) -> "Jet":
        return Jet(np.real(self.v), _map(np.real, self.d), _map(np.real, self.dd))

    @property
    def imag(self) -> "Jet":
        return Jet(np.imag(self.v), _map(np.imag, self.d), _map(np.imag, self.dd))

    def __repr__(self) -> str:  # pragma: no cover - debugging aid
        return f"Jet(v={self.v!r}, d={self.d!r}, dd={self.dd!r})"


def _add(a, b):
    return None if a is None else a + b


def _sub(a, b):
    return None if a is None else a - b


def _neg(a):
    return None if a is None else -a


def _mul(a, c):
    return None if a is None else a * c


def _div(a, c):
    return None if a is None else a / c


def _map(f, a):
    return None if a is None else f(a)


def value(x):
    """The value of a jet or a constant."""
    return x.v if isinstance(x, Jet) else x


def as_jet(x, order: int) -> Jet:
    return x if isinstance(x, Jet) else Jet.const(x, order)


def sqrt(x):
    """Square root of a real, non-negative jet (derivatives are infinite at 0: a toggle), or of an array."""
    if not isinstance(x, Jet):
        return np.sqrt(x)
    s = np.sqrt(x.v)
    d = dd = None
    if x.d is not None:
        inv = 0.5 / s
        d = x.d * inv
        if x.dd is not None:
            dd = x.dd * inv - (x.d * x.d) * (inv * inv * inv) * 2.0
    return Jet(s, d, dd)


def abs2(z) -> Jet:
    """|z|² of a complex jet, as a real jet."""
    if not isinstance(z, Jet):
        return np.real(z * np.conj(z))
    v = np.real(z.v * np.conj(z.v))
    d = dd = None
    if z.d is not None:
        zc = np.conj(z.v)
        d = 2.0 * np.real(zc * z.d)
        if z.dd is not None:
            dd = 2.0 * np.real(zc * z.dd) + 2.0 * np.real(z.d * np.conj(z.d))
    return Jet(v, d, dd)


def expi(theta) -> Jet:
    """exp(i·theta) of a real jet: the unit complex number of an angle (of an array, a number or a traced symbol,
    :mod:`.trace`, without derivatives)."""
    if not isinstance(theta, Jet):
        return np.exp(1j * (theta if hasattr(theta, "__array_ufunc__") else np.asarray(theta)))
    e = np.exp(1j * theta.v)
    d = dd = None
    if theta.d is not None:
        d = 1j * theta.d * e
        if theta.dd is not None:
            dd = (1j * theta.dd - theta.d * theta.d) * e
    return Jet(e, d, dd)


def angle(z: Jet) -> Jet:
    """arg(z) of a complex jet, as a real jet: θ' = Im(z'/z), θ'' = Im(z''/z − (z'/z)²)."""
    v = np.angle(z.v)
    d = dd = None
    if z.d is not None:
        q = z.d / z.v
        d = np.imag(q)
        if z.dd is not None:
            dd = np.imag(z.dd / z.v - q * q)
    return Jet(v, d, dd)


def cross(a, b) -> Jet:
    """Planar cross product Im(conj(a)·b) of complex jets (or constants)."""
    if isinstance(a, Jet):
        return (a.conj() * b).imag
    if isinstance(b, Jet):
        return (b * np.conj(a)).imag
    return np.imag(np.conj(a) * b)


def dot(a, b) -> Jet:
    """Planar dot product Re(conj(a)·b) of complex jets (or constants)."""
    if isinstance(a, Jet):
        return (a.conj() * b).real
    if isinstance(b, Jet):
        return (b * np.conj(a)).real
    return np.real(np.conj(a) * b)


def where_valid(x: Jet, valid) -> Jet:
    """NaN out the samples where ``valid`` is False (values and derivatives)."""
    nan = np.nan if not np.iscomplexobj(x.v) else complex(np.nan, np.nan)
    return Jet(np.where(valid, x.v, nan), None if x.d is None else np.where(valid, x.d, nan),
               None if x.dd is None else np.where(valid, x.dd, nan))


# -- generic rules, for values of any shape (complex planar, (..., 3) spatial vectors) -----------------------------------------------------------------------------------
def parts(x):
    """(value, first, second derivative) of a jet; (array, None, None) of a constant."""
    if isinstance(x, Jet):
        return x.v, x.d, x.dd
    return np.asarray(x, dtype=float), None, None


def bilinear(f, a, b):
    """f(a, b) for a function f linear in each argument, on arrays or jets (product rule)."""
    if not isinstance(a, Jet) and not isinstance(b, Jet):
        return f(np.asarray(a, dtype=float), np.asarray(b, dtype=float))
    av, ad, add = parts(a)
    bv, bd, bdd = parts(b)
    v = f(av, bv)
    has_d = ad is not None or bd is not None
    has_dd = add is not None or bdd is not None
    d = dd = None
    if has_d:
        d = 0.0
        if ad is not None:
            d = d + f(ad, bv)
        if bd is not None:
            d = d + f(av, bd)
    if has_dd:
        dd = 0.0
        if add is not None:
            dd = dd + f(add, bv)
        if bdd is not None:
            dd = dd + f(av, bdd)
        if ad is not None and bd is not None:
            dd = dd + 2.0 * f(ad, bd)
    return Jet(v, d, dd)


def unary(x, f, f1, f2):
    """g(x) with g' = f1(x), g'' = f2(x), on arrays or jets (chain rule)."""
    if not isinstance(x, Jet):
        return f(np.asarray(x, dtype=float))
    v = f(x.v)
    d = dd = None
    if x.d is not None:
        g1 = f1(x.v)
        d = g1 * x.d
        if x.dd is not None:
            dd = g1 * x.dd + f2(x.v) * (x.d * x.d)
    return Jet(v, d, dd)


def linear(f, x):
    """f(x) for a linear f, on arrays or jets."""
    if not isinstance(x, Jet):
        return f(np.asarray(x, dtype=float))
    return Jet(f(x.v), None if x.d is None else f(x.d), None if x.dd is None else f(x.dd))
