"""Interpolants of the reduced equation's terms that are cheap to evaluate inside an integrator.

* :class:`PeriodicSeries`: a trigonometric (Fourier) interpolant of samples on a uniform grid of one input turn,
  truncated where its coefficients fall below rounding. For the smooth periodic terms of a mechanism that turns
  fully it converges geometrically with the number of samples; its derivative and antiderivative are exact for
  the interpolant, so J*′ is the derivative of the interpolated J* (the equation of the interpolated model then
  conserves its own energy exactly).
* :class:`TableSeries`: the terms on a fine uniform grid (a turn, or the interval of a stroke or of the part of a
  turn where the mechanism assembles): J* by cubic Hermite interpolation on its exact values and slopes, the
  forces linearly (the terms of a load against velocity, or of a load law, have kinks where a spectral series
  converges slowly). :class:`PeriodicTable` is the same for a batch of Fourier series (the population's).

:func:`fit_periodic` samples an exact function on a grid, measures the interpolant's error at the grid's
midpoints and doubles the grid until that error is below the tolerance; :func:`fit_table` measures a table's.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

TWO_PI = 2.0 * math.pi


@dataclass(frozen=True)
class PeriodicSeries:
    """f(q) = Re Σ_k c_k·e^{ik(q − start)}, k = 0 … K. ``coefficients`` (..., K + 1, n_terms) complex: the
    batch, the harmonics, then several functions sharing the grid (J*, Q, …)."""
    start: float
    coefficients: np.ndarray

    @classmethod
    def from_samples(cls, values, start: float = 0.0, keep: float = 1e-15, scale=None) -> "PeriodicSeries":
        """Samples ``values (..., n, n_terms)`` at start + 2πj/n, j = 0 … n − 1. Harmonics whose coefficients are
        below ``keep`` times ``scale (n_terms,)`` (default: each term's largest coefficient) over the whole batch
        are dropped from the top; the Nyquist harmonic is always dropped (it has no unique derivative)."""
        values = np.asarray(values, dtype=float)
        n = values.shape[-2]
        F = np.fft.rfft(values, axis=-2) / n
        F[..., 1:, :] *= 2.0
        F = F[..., : (n + 1) // 2, :]            # no Nyquist harmonic
        mag = np.abs(F).reshape(-1, F.shape[-2], F.shape[-1]).max(axis=0)     # (K + 1, n_terms)
        scale = np.maximum(mag.max(axis=0) if scale is None else np.asarray(scale, dtype=float), 1e-300)
        big = np.nonzero(np.any(mag > keep * scale, axis=1))[0]
        K = int(big[-1]) + 1 if big.size else 1
        return cls(float(start), np.ascontiguousarray(F[..., :K, :]))

    @property
    def harmonics(self) -> int:
        return self.coefficients.shape[-2] - 1

    def _phase(self, q):
        k = np.arange(self.coefficients.shape[-2])
        return np.exp(1j * (np.asarray(q, dtype=float)[..., None] - self.start) * k), k

    def __call__(self, q, derivative: bool = False):
        """Values (..., n_terms) at q (...); with ``derivative`` also d/dq (..., n_terms)."""
        c = self.coefficients
        if c.ndim == 2 and np.ndim(q) == 0:           # one design at one input: a plain dot product
            k = np.arange(c.shape[0])
            E = np.exp(1j * (float(q) - self.start) * k)
            value = (E @ c).real
            return (value, ((E * (1j * k)) @ c).real) if derivative else value
        E, k = self._phase(q)
        value = np.einsum("...k,...kt->...t", E, c).real
        if not derivative:
            return value
        return value, np.einsum("...k,...kt->...t", E * (1j * k), c).real

    def mean(self):
        """(..., n_terms) the mean over a turn."""
        return self.coefficients[..., 0, :].real

    def antiderivative(self, q):
        """(..., n_terms) ∫ from start to q of (f − mean): periodic; add mean·(q − start) for the whole integral."""
        E, k = self._phase(q)
        c = self.coefficients[..., 1:, :]
        kk = k[1:]
        return (np.einsum("...k,...kt->...t", (E[..., 1:] - 1.0) / (1j * kk), c)).real


@dataclass(frozen=True)
class PeriodicTable:
    """A batch's :class:`PeriodicSeries` tabulated on a fine uniform grid of ``n`` inputs per turn, values and
    first derivatives (``table`` (D, n, n_terms, 2)), evaluated by cubic Hermite interpolation: a handful of
    operations per design whatever the number of harmonics (what a population's integrator evaluates at every
    stage). Its error is the Hermite remainder, h⁴·max|f⁗|/384 with h = 2π/n."""
    start: float
    table: np.ndarray

    @classmethod
    def from_series(cls, series: PeriodicSeries, n: int = 512) -> "PeriodicTable":
        c = series.coefficients                          # (..., K + 1, n_terms)
        K1 = c.shape[-2]
        if K1 > n // 2:
            raise ValueError(f"a table of {n} inputs holds at most {n // 2 - 1} harmonics, not {K1 - 1}")
        spectrum = np.zeros(c.shape[:-2] + (n // 2 + 1, c.shape[-1]), complex)
        spectrum[..., :K1, :] = c
        spectrum[..., 1:, :] *= 0.5
        k = np.arange(n // 2 + 1)[:, None]
        value = np.fft.irfft(spectrum, n, axis=-2) * n
        slope = np.fft.irfft(spectrum * (1j * k), n, axis=-2) * n
        return cls(series.start, np.ascontiguousarray(np.stack([value, slope], axis=-1)))

    def flat(self) -> np.ndarray:
        """(D·n, 2·n_terms): one row per design and node, its values then its slopes (built on first use)."""
        flat = self.__dict__.get("_flat")
        if flat is None:
            D, n, n_terms, _ = self.table.shape
            flat = np.ascontiguousarray(np.concatenate([self.table[..., 0], self.table[..., 1]], axis=-1)
                                        .reshape(D * n, 2 * n_terms))
            object.__setattr__(self, "_flat", flat)
        return flat

    def __call__(self, q, rows):
        """(values (m, n_terms), derivatives (m, n_terms)) of the designs ``rows`` (m,) at q (m,)."""
        D, n, n_terms, _ = self.table.shape
        flat = self.flat()
        h = TWO_PI / n
        x = (np.asarray(q, dtype=float) - self.start) / h
        i = np.floor(x)
        s = (x - i)[:, None]
        i = i.astype(np.int64) % n
        base = np.asarray(rows, dtype=np.int64) * n
        a, b = flat[base + i], flat[base + (i + 1) % n]             # (m, 2·n_terms)
        a0, a1, b0, b1 = a[:, :n_terms], a[:, n_terms:], b[:, :n_terms], b[:, n_terms:]
        # the cubic Hermite polynomial in Horner form: a0 + s·(h·a1 + s·(c2 + s·c3))
        d, ha1, hb1 = b0 - a0, h * a1, h * b1
        c2 = 3.0 * d - 2.0 * ha1 - hb1
        c3 = ha1 + hb1 - 2.0 * d
        value = a0 + s * (ha1 + s * (c2 + s * c3))
        slope = (ha1 + s * (2.0 * c2 + 3.0 * s * c3)) / h
        return value, slope


@dataclass(frozen=True)
class TableSeries:
    """The terms at ``nodes (n,)`` (increasing; one turn [lo, lo + 2π) when ``periodic``, else a closed interval):
    J* (column 0) by cubic Hermite interpolation on its exact samples and slopes (column 1; the equation's J*′ is
    that interpolant's derivative), the forces (columns 2, 3) by a cubic spline through their samples (periodic, or
    not-a-knot): C², so a high-order integrator keeps its order between the nodes, and local at the kinks of a load
    against velocity, where a Fourier series converges slowly. ``values (n, n_terms)``."""
    nodes: np.ndarray
    periodic: bool
    values: np.ndarray

    @property
    def forces(self):
        """The cubic spline of the columns 2 and 3, built on first use."""
        spline = self.__dict__.get("_forces")
        if spline is None:
            from scipy.interpolate import CubicSpline
            x, y = self.nodes, self.values[:, 2:]
            if self.periodic:
                x, y = np.append(x, x[0] + TWO_PI), np.vstack([y, y[:1]])
            spline = CubicSpline(x, y, axis=0, bc_type="periodic" if self.periodic else "not-a-knot")
            object.__setattr__(self, "_forces", spline)
        return spline

    def _wrap(self, q):
        q = np.asarray(q, dtype=float)
        return self.nodes[0] + np.mod(q - self.nodes[0], TWO_PI) if self.periodic else q

    def _locate(self, q):
        """(i, j, s, h): the nodes around q (...), the fraction s of the interval and its length h."""
        x = self._wrap(q)
        nodes, n = self.nodes, self.nodes.size
        if self.periodic:
            i = np.clip(np.searchsorted(nodes, x, side="right") - 1, 0, n - 1)
            j = (i + 1) % n
            right = np.where(j == 0, nodes[0] + TWO_PI, nodes[j])
        else:
            i = np.clip(np.searchsorted(nodes, x, side="right") - 1, 0, n - 2)
            j = i + 1
            right = nodes[j]
        h = right - nodes[i]
        return i, j, (x - nodes[i]) / h, h

    def __call__(self, q, derivative: bool = False):
        i, j, s, h = self._locate(q)
        a, b = self.values[i], self.values[j]
        x = self._wrap(q)
        value = np.empty(np.shape(x) + (self.values.shape[1],))
        slope = np.empty_like(value)
        value[..., 2:] = self.forces(x)
        slope[..., 2:] = self.forces(x, 1)
        s2, s3 = s * s, s * s * s
        value[..., 0] = (2 * s3 - 3 * s2 + 1) * a[..., 0] + (s3 - 2 * s2 + s) * h * a[..., 1] \
            + (3 * s2 - 2 * s3) * b[..., 0] + (s3 - s2) * h * b[..., 1]
        slope[..., 0] = (6 * s2 - 6 * s) / h * a[..., 0] + (3 * s2 - 4 * s + 1) * a[..., 1] \
            + (6 * s - 6 * s2) / h * b[..., 0] + (3 * s2 - 2 * s) * b[..., 1]
        value[..., 1] = slope[..., 0]
        slope[..., 1] = np.nan
        return (value, slope) if derivative else value

    def mean(self):
        """(n_terms,) the mean over a turn (J* of its Hermite interpolant by trapezoids, the forces of their
        spline; periodic tables)."""
        h = np.diff(np.append(self.nodes, self.nodes[0] + TWO_PI))
        nxt = np.roll(self.values, -1, axis=0)
        out = np.sum(0.5 * (self.values + nxt) * h[:, None], axis=0) / TWO_PI
        f = self.forces
        out[2:] = (f.integrate(self.nodes[0], self.nodes[0] + TWO_PI)) / TWO_PI
        return out

    def integral(self, q, column: int = 2):
        """∫ from the first node to q of the spline of force ``column`` (…); for a periodic table of the column less
        its mean (periodic)."""
        f = self.forces.antiderivative()
        q = np.asarray(q, dtype=float)
        x0 = self.nodes[0]
        k = column - 2
        if not self.periodic:
            return f(q)[..., k] - f(x0)[k]
        mean = self.mean()[column]
        turns = np.floor((q - x0) / TWO_PI)
        x = self._wrap(q)
        return f(x)[..., k] - f(x0)[k] + turns * (f(x0 + TWO_PI)[k] - f(x0)[k]) - mean * (q - x0)


@dataclass(frozen=True)
class Fit:
    """An interpolant and how well it reproduces the exact function: ``error (n_terms,)`` the largest difference
    at the midpoints of the grid (between the samples, where it is largest) relative to ``scale (n_terms,)``, the
    largest magnitude of each term; ``samples`` the grid size used."""
    series: object
    error: np.ndarray
    scale: np.ndarray
    samples: int


def _relative(err, scale):
    return np.where(scale > 0, err / np.where(scale > 0, scale, 1.0), 0.0)


def _scale(values, scales):
    mag = np.max(np.abs(values), axis=0)
    return mag if scales is None else scales(mag)


def fit_table(exact, lo: float, span: float, n: int, *, periodic: bool, scales=None) -> Fit:
    """A :class:`TableSeries` of ``exact`` on n inputs: uniform over the turn from ``lo`` when ``periodic``, else
    Chebyshev–Lobatto points of [lo, lo + span] (dense towards the ends, where a dead centre makes J* grow fast);
    its error measured at the midpoints of the nodes."""
    if periodic:
        q = lo + span * np.arange(n) / n
        mid = q + 0.5 * span / n
    else:
        q = lo + 0.5 * span * (1.0 - np.cos(np.pi * np.arange(n) / (n - 1)))
        q[0], q[-1] = lo, lo + span
        mid = 0.5 * (q[1:] + q[:-1])
    values = exact(q)
    series = TableSeries(q, bool(periodic), np.ascontiguousarray(values, dtype=float))
    exact_mid = exact(mid)
    scale = _scale(np.concatenate([values, exact_mid]), scales)
    err = _relative(np.max(np.abs(series(mid) - exact_mid), axis=0), scale)
    return Fit(series, err, scale, n)


def fit_periodic(exact, start: float, n: int, *, tol: float, n_max: int, first=None, scales=None) -> Fit:
    """A :class:`PeriodicSeries` of ``exact(q (m,)) → (m, n_terms)`` from n, 2n, … samples of the turn from
    ``start`` until the relative error at the midpoints is ≤ ``tol`` (or n reaches ``n_max``). ``first``: the
    values at the first grid, when already known. ``scales(max |value| (n_terms,)) → (n_terms,)``: what each
    term's error is relative to (default: its own largest magnitude)."""
    values = first
    while True:
        q = start + TWO_PI * np.arange(n) / n
        if values is None:
            values = exact(q)
        series = PeriodicSeries.from_samples(values, start, scale=_scale(values, scales))
        mid = q + math.pi / n
        exact_mid = exact(mid)
        scale = _scale(np.concatenate([values, exact_mid]), scales)
        err = _relative(np.max(np.abs(series(mid) - exact_mid), axis=0), scale)
        if np.all(err <= tol) or 2 * n > n_max:
            return Fit(series, err, scale, n)
        merged = np.empty((2 * n,) + values.shape[1:])
        merged[0::2], merged[1::2] = values, exact_mid
        values, n = merged, 2 * n


__all__ = ["Fit", "PeriodicSeries", "PeriodicTable", "TableSeries", "fit_periodic", "fit_table"]
