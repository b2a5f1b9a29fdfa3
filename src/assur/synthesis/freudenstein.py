"""Function generation in closed form: Freudenstein's equation for the four-bar and its analogue for the
slider-crank, exact for three precision points and least squares for more, and Chebyshev spacing.

Four-bar (Freudenstein 1955; in the form of Norton, *Design of Machinery*, §5.12): ground pivots A0 = (0, 0)
and B0 = (d, 0), crank A0A = a at the input angle φ, coupler AB = b, rocker B0B = c at the output angle ψ,
both angles measured counter-clockwise from the ground line A0 → B0. Loop closure |B − A| = b gives

    K1·cos ψ − K2·cos φ + K3 = cos(φ − ψ),   K1 = d/a,  K2 = d/c,  K3 = (a² − b² + c² + d²) / (2ac),

linear in (K1, K2, K3). Negative a or c are allowed: the crank or the rocker then points along φ + π or
ψ + π (the link lengths are their magnitudes).

Slider-crank: crank pivot at the origin, crank a at φ, connecting rod b to a pin at (s, e) on the slide line
y = e along x. Loop closure (s − a cos φ)² + (e − a sin φ)² = b² gives

    2a·s·cos φ + 2ae·sin φ − (a² + e² − b²) = s²,

linear in (2a, 2ae, a² + e² − b²).
"""
from __future__ import annotations

import numpy as np

from ..errors import SpecError


def chebyshev_points(n: int, lo: float, hi: float) -> np.ndarray:
    """The n Chebyshev spacing points of [lo, hi]: (lo + hi)/2 − (hi − lo)/2·cos((2j − 1)π / 2n), j = 1…n
    (Norton, *Design of Machinery*, §5.12; Freudenstein & Sandor), ascending from lo to hi."""
    if not isinstance(n, (int, np.integer)) or isinstance(n, bool) or n < 1:
        raise SpecError([("n", f"must be a positive whole number of points: {n!r}")])
    lo, hi = float(lo), float(hi)
    if not (np.isfinite(lo) and np.isfinite(hi)) or hi <= lo:
        raise SpecError([("interval", f"must be finite with lo < hi: [{lo}, {hi}]")])
    j = np.arange(1, n + 1)
    return (lo + hi) / 2 - (hi - lo) / 2 * np.cos((2 * j - 1) * np.pi / (2 * n))


def precision_pairs(inputs, outputs, where=("inputs", "outputs")) -> tuple[np.ndarray, np.ndarray]:
    """Two equal-length finite 1-D arrays of at least 3 values, inputs strictly monotone."""
    try:
        x = np.asarray(inputs, dtype=float)
        y = np.asarray(outputs, dtype=float)
    except (TypeError, ValueError):
        raise SpecError([(where[0], "must be arrays of numbers")]) from None
    problems = []
    if x.ndim != 1 or len(x) < 3:
        problems.append((where[0], f"must be a 1-D array of at least 3 precision points: shape {x.shape}"))
    if y.shape != x.shape:
        problems.append((where[1], f"must have the shape of {where[0]} {x.shape}: {y.shape}"))
    if not problems and not (np.all(np.isfinite(x)) and np.all(np.isfinite(y))):
        problems.append((where[0], "must be finite numbers"))
    if not problems:
        dx = np.diff(x)
        if not (np.all(dx > 0) or np.all(dx < 0)):
            problems.append((where[0], "must be strictly increasing or strictly decreasing (the order the input "
                                       "passes them)"))
        elif abs(x[-1] - x[0]) >= 2 * np.pi:
            problems.append((where[0], "must span less than one turn (2π rad)"))
    if problems:
        raise SpecError(problems)
    return x, y


def freudenstein(phi, psi, ground: float = 1.0):
    """Least-squares (exact for 3 points) Freudenstein coefficients and the signed link lengths.

    phi, psi (n,) rad → dict(K=(K1, K2, K3), a, b, c, d, rank) with a, c signed; None when the fit has no
    four-bar (a coefficient zero: an infinite link, or b² ≤ 0)."""
    phi, psi = np.asarray(phi, float), np.asarray(psi, float)
    M = np.stack([np.cos(psi), -np.cos(phi), np.ones_like(phi)], axis=1)
    rhs = np.cos(phi - psi)
    K, _, rank, _ = np.linalg.lstsq(M, rhs, rcond=None)
    if rank < 3 or abs(K[0]) < 1e-12 or abs(K[1]) < 1e-12:
        return None
    d = float(ground)
    a, c = d / K[0], d / K[1]
    b2 = a * a + c * c + d * d - 2 * a * c * K[2]
    if not b2 > 0:
        return None
    return {"K": tuple(float(k) for k in K), "a": float(a), "b": float(np.sqrt(b2)), "c": float(c), "d": d}


def slider_freudenstein(phi, s):
    """Slider-crank function generation: phi (n,) rad, slider positions s (n,) along the slide line →
    dict(a, b, e) with a > 0 or None (no real rod)."""
    phi, s = np.asarray(phi, float), np.asarray(s, float)
    M = np.stack([s * np.cos(phi), np.sin(phi), -np.ones_like(phi)], axis=1)
    X, _, rank, _ = np.linalg.lstsq(M, s * s, rcond=None)
    if rank < 3 or abs(X[0]) < 1e-12:
        return None
    a = X[0] / 2.0
    e = X[1] / X[0]
    b2 = a * a + e * e - X[2]
    if not b2 > 0:
        return None
    if a < 0:           # a negative crank is the same crank turned by π: keep a > 0 and report it
        return {"a": float(-a), "b": float(np.sqrt(b2)), "e": float(e), "flip": True}
    return {"a": float(a), "b": float(np.sqrt(b2)), "e": float(e), "flip": False}


__all__ = ["chebyshev_points", "freudenstein", "precision_pairs", "slider_freudenstein"]
