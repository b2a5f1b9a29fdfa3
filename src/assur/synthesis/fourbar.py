"""Four-bar constraint measures of the path-synthesis literature (docs/papers/synthesis_benchmarks.md §1.3–1.4).

Lengths are ``(n, 4)`` arrays ``[r1 ground, r2 crank, r3 coupler, r4 rocker]``; every measure is a
violation ``V ≥ 0`` (n,) with ``V = 0`` exactly when the constraint holds.

The assembly discriminant of the crank angle θ (measured from the ground line O2 → O4),
``Δ = A² + B² − C²`` with ``A = 2 r3 (r2 cos θ − r1)``, ``B = 2 r3 r2 sin θ``,
``C = r1² + r2² + r3² − r4² − 2 r1 r2 cos θ``, is a concave quadratic in ``c = cos θ``:
``Δ = −4 r1² r2² c² + 4 r1 r2 (K − 2 r3²) c + 4 r3² (r1² + r2²) − K²`` with ``K = r1² + r2² + r3² − r4²``.
Its minimum over any crank interval therefore lies at an end of the interval's cosine range, which
gives ``continuous_motion`` exactly, without sampling or root finding.
"""
from __future__ import annotations

import numpy as np

from ..tolerances import DEFAULT

TWO_PI = 2.0 * np.pi


def discriminant(lengths: np.ndarray, theta: np.ndarray) -> np.ndarray:
    """Δ at crank angles theta. lengths (n, 4), theta (n, N) or (N,) → (n, N)."""
    r1, r2, r3, r4 = (lengths[:, i, None] for i in range(4))
    c = np.cos(theta)
    K = r1 * r1 + r2 * r2 + r3 * r3 - r4 * r4
    return (-4.0 * r1 * r1 * r2 * r2 * c * c + 4.0 * r1 * r2 * (K - 2.0 * r3 * r3) * c
            + 4.0 * r3 * r3 * (r1 * r1 + r2 * r2) - K * K)


def mean_length(lengths):
    return lengths.mean(axis=1)


def cosine_range(start: np.ndarray, width: np.ndarray):
    """(cmin, cmax) of cos θ over θ ∈ [start, start + width] (width ≥ 0; ≥ 2π is the full turn)."""
    a = np.mod(start, TWO_PI)
    b = a + np.minimum(width, TWO_PI)
    ca, cb = np.cos(a), np.cos(b)
    has_pi = (a <= np.pi) & (b >= np.pi) | (b >= 3 * np.pi)
    has_zero = b >= TWO_PI
    cmin = np.where(has_pi, -1.0, np.minimum(ca, cb))
    cmax = np.where(has_zero, 1.0, np.maximum(ca, cb))
    return cmin, cmax


def min_discriminant(lengths, start, width):
    """Exact minimum of Δ over the crank interval [start, start + width] (n,)."""
    cmin, cmax = cosine_range(start, width)
    ends = np.stack([np.arccos(np.clip(cmin, -1, 1)), np.arccos(np.clip(cmax, -1, 1))], axis=1)
    return discriminant(lengths, ends).min(axis=1)


def grashof(lengths):
    s = np.sort(lengths, axis=1)
    return np.maximum(0.0, s[:, 0] + s[:, 3] - s[:, 1] - s[:, 2] - DEFAULT.fourbar_slack * s[:, 3])


def nondegenerate(lengths):
    lbar = mean_length(lengths)[:, None]
    return np.maximum(0.0, DEFAULT.fourbar_slack * lbar - lengths).sum(axis=1)


def crank_shortest(lengths):
    """``r2_shortest``: max(0, r2 − min(r1, r3, r4))."""
    return np.maximum(0.0, lengths[:, 1] - np.minimum.reduce([lengths[:, 0], lengths[:, 2], lengths[:, 3]]))


def cidetec_order(lengths):
    r1, r2, r3, r4 = lengths.T
    parts = [r1 + r2 - r3 - r4, r2 - r3, r3 - r4, r4 - r1]
    return sum(np.maximum(0.0, p) for p in parts)


def continuous_motion(lengths, start, width):
    """max(0, −min Δ over the interval) / L̄⁴ (the C2 measure of docs/papers/synthesis_benchmarks.md §1.4, exact
    here for any interval)."""
    lbar = mean_length(lengths)
    return np.maximum(0.0, -min_discriminant(lengths, start, width)) / lbar ** 4


def assembly(lengths, theta):
    """Σ max(0, −Δ_i) / L̄⁴ over the required crank angles theta (n, N)."""
    lbar = mean_length(lengths)
    return np.maximum(0.0, -discriminant(lengths, theta)).sum(axis=1) / lbar ** 4


def gaps(theta):
    """Counter-clockwise gaps (θ_{i+1} − θ_i) mod 2π, (n, N−1)."""
    return np.mod(np.diff(theta, axis=1), TWO_PI)


def cyclic_order(theta):
    return np.maximum(0.0, gaps(theta).sum(axis=1) - TWO_PI)


def cyclic_order_any(theta):
    cw = np.maximum(0.0, np.mod(-np.diff(theta, axis=1), TWO_PI).sum(axis=1) - TWO_PI)
    return np.minimum(cyclic_order(theta), cw)


def ascending(theta):
    return np.maximum(0.0, -np.diff(np.mod(theta, TWO_PI), axis=1)).sum(axis=1)


__all__ = ["ascending", "assembly", "cidetec_order", "continuous_motion", "crank_shortest", "cyclic_order",
           "from_cidetec_order",
           "cyclic_order_any", "discriminant", "grashof", "min_discriminant", "nondegenerate"]


def from_cidetec_order(x) -> np.ndarray:
    """A design vector in the CIDETEC order ``[r1, r2, r3, r4, rcx, rcy, θ0, x0, y0, θ2…]`` (ECA,
    HNMED) → the canonical order ``[r1, r2, r3, r4, rcx, rcy, x0, y0, θ0, θ2…]``
    (docs/papers/synthesis_benchmarks.md §1.1)."""
    x = np.array(x, dtype=float, copy=True)
    x[..., [6, 7, 8]] = x[..., [7, 8, 6]]
    return x
