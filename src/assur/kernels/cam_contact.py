"""The lift a given cam profile imposes on its follower: the inverse of conjugate profile generation.

Pure functions on arrays (no plan, no names). The profile is a closed curve ``P (M,)`` (complex, the cam's frame, the
cam's pivot at the origin, densely sampled from a smooth curve). When the cam has turned by x (counter-clockwise),
the follower, seen from the cam, has turned by −x about the pivot; its lift is where it first touches the profile
moving away from the cam:

- translating (the trace point R₀ + t·u, u the direction of lift): a knife touches where its line crosses the profile
  (farthest crossing), a roller of radius r at t = max over the profile of ((P − R₀)·u + √(r² − d²)) with d the
  point's distance from the line, a flat face of normal n at t = max (P − R₀)·n / (u·n);
- oscillating (the trace point turning about O_f by ψ in the sense of lift): a roller or knife at the largest ψ that
  brings the circle of radius r round R(ψ) onto a profile point.

Each maximum over the samples is refined by the parabola through the best sample and its two neighbours (the
samples lie on a smooth curve), so the error falls as the fourth power of the spacing.
"""
from __future__ import annotations

import numpy as np


def _refine(values: np.ndarray, i: np.ndarray) -> np.ndarray:
    """The parabola's peak through values[..., i − 1], [i], [i + 1] (cyclic), per row."""
    M = values.shape[-1]
    rows = np.arange(values.shape[0])
    a, b, c = values[rows, (i - 1) % M], values[rows, i], values[rows, (i + 1) % M]
    den = a - 2 * b + c
    with np.errstate(invalid="ignore", divide="ignore"):
        peak = b - 0.125 * (c - a) ** 2 / den
    return np.where(np.isfinite(peak) & (den < 0), peak, b)


#: cam turns solved at once (bounds the (turns, profile samples) arrays)
BLOCK = 64


def _blocked(fn):
    """Run ``fn(profile, xs, …)`` on blocks of :data:`BLOCK` cam turns and join the results."""
    def run(profile, xs, *args, **kwargs):
        xs = np.atleast_1d(np.asarray(xs, float))
        return np.concatenate([fn(profile, xs[i:i + BLOCK], *args, **kwargs) for i in range(0, len(xs), BLOCK)])
    run.__doc__, run.__name__ = fn.__doc__, fn.__name__
    return run


@_blocked
def translating_lift(profile, xs, R0: complex, u: complex, contact: str, r: float = 0.0,
                     normal: complex | None = None) -> np.ndarray:
    """t (N,) along ``u`` of a translating follower's trace point (R₀ at t = 0) for cam turns ``xs (N,)``."""
    P = np.asarray(profile)[None, :]
    turn = np.exp(1j * np.asarray(xs, float))[:, None]
    Q = P * turn                                             # the profile turned by x: the same as the follower by −x
    w = Q - R0
    along = np.real(np.conj(u) * w)
    if contact == "flat":
        n = normal if normal is not None else u
        vals = np.real(np.conj(n) * w) / np.real(np.conj(n) * u)
        return _refine(vals, np.argmax(vals, axis=-1))
    d = np.imag(np.conj(u) * w)
    if contact == "roller":
        vals = np.where(np.abs(d) <= r, along + np.sqrt(np.maximum(r * r - d * d, 0.0)), -np.inf)
        i = np.argmax(vals, axis=-1)
        # the roller's touching function is smooth across the strip; off the strip use the tangent parabola
        full = along + np.sqrt(np.maximum(r * r - d * d, 0.0))
        return _refine(full, i)
    # a knife edge: the farthest crossing of its line with the profile's polygon (linear between samples)
    d2 = np.roll(d, -1, axis=-1)
    a2 = np.roll(along, -1, axis=-1)
    cross = (d <= 0) & (d2 > 0) | (d >= 0) & (d2 < 0)
    with np.errstate(invalid="ignore", divide="ignore"):
        t = along + (a2 - along) * d / (d - d2)
    t = np.where(cross, t, -np.inf)
    return np.max(t, axis=-1)


@_blocked
def oscillating_lift(profile, xs, Of: complex, R0: complex, turn: float, contact: str, r: float = 0.0) -> np.ndarray:
    """ψ (N,) of an oscillating follower's turn about ``Of`` in the sense ``turn`` (R₀ at ψ = 0) for cam turns ``xs``:
    the largest turn that keeps the roller (or knife) clear of the profile, refined on the samples."""
    P = np.asarray(profile)[None, :]
    Q = P * np.exp(1j * np.asarray(xs, float))[:, None]
    rho = abs(R0 - Of)
    w = Q - Of
    dist = np.abs(w)
    phi0 = np.angle(R0 - Of)
    # R(ψ) = O_f + ρ·e^{i(φ0 + turn·ψ)} meets the circle of radius r about Q where the angle between (Q − O_f) and
    # (R − O_f) is ±acos((ρ² + |w|² − r²)/(2ρ|w|)); the follower lifts until the first of them
    with np.errstate(invalid="ignore"):
        c = (rho * rho + dist * dist - r * r) / (2 * rho * dist)
        half = np.arccos(np.clip(c, -1.0, 1.0))
        base = turn * (np.angle(w) - phi0)
        base = (base + np.pi) % (2 * np.pi) - np.pi
        reach = np.where(np.abs(c) <= 1.0, base + half, -np.inf)
        full = base + half
    i = np.argmax(reach, axis=-1)
    return _refine(np.where(np.isfinite(full), full, -np.inf), i)
