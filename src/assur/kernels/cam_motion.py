"""Normalised cam motion laws: y(u) and its first three derivatives on u ∈ [0, 1], y(0) = 0, y(1) = 1.

A rise of height h over a cam angle β is s(θ) = h·y(u) with u = (θ − θ_0)/β, so ds/dθ = h·y′/β,
d²s/dθ² = h·y″/β² and d³s/dθ³ = h·y‴/β³ (the SVAJ of the segment per unit of cam angle). A fall is the same
with h < 0. Pure functions on arrays: the engine evaluates a cam pair's law through them (exact jets), and
:mod:`assur.cams.laws` builds whole laws (dwell–rise–dwell–return programs) on top of them.

Closed forms (Norton, *Cam Design and Manufacturing Handbook*, 2nd ed., ch. 3; the modified trapezoid and the
modified sine as Norton's piecewise sinusoid–constant accelerations, pieces at u = 1/8, 3/8, 5/8, 7/8 and at
u = 1/8, 7/8 respectively):

==================== ===================================================== ==========================
law                  y(u)                                                  peak |y″| (Norton's C_a)
==================== ===================================================== ==========================
``harmonic``         (1 − cos πu)/2                                        π²/2
``cycloidal``        u − sin(2πu)/(2π)                                     2π
``polynomial_345``   10u³ − 15u⁴ + 6u⁵                                     5.7735
``polynomial_4567``  35u⁴ − 84u⁵ + 70u⁶ − 20u⁷                             7.5132
``modified_trapezoid`` piecewise: y″ = A·sin 4πu, A, A·cos 4π(u − 3/8), …   A = 8π/(2 + π) ≈ 4.888
``modified_sine``    piecewise: y″ = A·sin 4πu, A·cos (4π/3)(u − 1/8), …   A = π²/(π + 4)·4/π … ≈ 5.528
==================== ===================================================== ==========================
"""
from __future__ import annotations

import math

import numpy as np

PI = math.pi
#: the laws this module evaluates (a dwell is a segment of zero lift and needs none)
LAWS = ("harmonic", "cycloidal", "polynomial_345", "polynomial_4567", "modified_trapezoid", "modified_sine")

#: peak acceleration factor of the modified trapezoid: y(1) = A·(1/(4π) + 1/8) = 1
_MT_A = 1.0 / (1.0 / (4.0 * PI) + 1.0 / 8.0)
#: peak acceleration factor of the modified sine: y(1) = A·(1/(4π) + 1/π²) = 1
_MS_A = 1.0 / (1.0 / (4.0 * PI) + 1.0 / (PI * PI))


def _polynomial(coefficients, u):
    """y, y′, y″, y‴ of Σ c_k·u^k (``coefficients`` {power: c})."""
    out = [np.zeros_like(u) for _ in range(4)]
    for k, c in coefficients.items():
        for d in range(4):
            if k - d < 0:
                break
            f = c * math.prod(range(k - d + 1, k + 1))
            out[d] = out[d] + f * u ** (k - d)
    return out


def _harmonic(u):
    a = PI * u
    return 0.5 * (1.0 - np.cos(a)), 0.5 * PI * np.sin(a), 0.5 * PI ** 2 * np.cos(a), -0.5 * PI ** 3 * np.sin(a)


def _cycloidal(u):
    a = 2.0 * PI * u
    return (u - np.sin(a) / (2.0 * PI), 1.0 - np.cos(a), 2.0 * PI * np.sin(a), 4.0 * PI ** 2 * np.cos(a))


def _modified_trapezoid(u):
    """Norton's modified trapezoid: y″ = A·sin 4πu (u ≤ 1/8), A (≤ 3/8), A·cos 4π(u − 3/8) (≤ 5/8), −A (≤ 7/8),
    −A·cos 4π(u − 7/8) (≤ 1); y′ and y by exact integration piece by piece."""
    A, w = _MT_A, 4.0 * PI
    y1_18, y_18 = A / w, A / w * (1 / 8 - 1 / w)                 # at u = 1/8
    y1_38 = y1_18 + A / 4                                         # at u = 3/8
    y_38 = y_18 + y1_18 / 4 + A / 32
    y_58 = y_38 + y1_38 / 4 + 2 * A / w ** 2                      # at u = 5/8 (y′ back to y1_38)
    y_78 = y_58 + y1_38 / 4 - A / 32                              # at u = 7/8 (y′ = y1_18)
    p1, p2, p3, p4 = u <= 1 / 8, u <= 3 / 8, u <= 5 / 8, u <= 7 / 8
    t2, t3, t4, t5 = u - 1 / 8, u - 3 / 8, u - 5 / 8, u - 7 / 8
    y = np.select([p1, p2, p3, p4],
                  [A / w * (u - np.sin(w * u) / w),
                   y_18 + y1_18 * t2 + 0.5 * A * t2 ** 2,
                   y_38 + y1_38 * t3 + A / w ** 2 * (1 - np.cos(w * t3)),
                   y_58 + y1_38 * t4 - 0.5 * A * t4 ** 2],
                  y_78 + y1_18 * t5 - A / w * (-np.cos(w * t5) / w + 1 / w))
    y1 = np.select([p1, p2, p3, p4],
                   [A / w * (1 - np.cos(w * u)), y1_18 + A * t2, y1_38 + A / w * np.sin(w * t3), y1_38 - A * t4],
                   y1_18 - A / w * np.sin(w * t5))
    y2 = np.select([p1, p2, p3, p4], [A * np.sin(w * u), A + 0 * u, A * np.cos(w * t3), -A + 0 * u],
                   -A * np.cos(w * t5))
    y3 = np.select([p1, p2, p3, p4], [A * w * np.cos(w * u), 0 * u, -A * w * np.sin(w * t3), 0 * u],
                   A * w * np.sin(w * t5))
    return y, y1, y2, y3


def _modified_sine(u):
    """Norton's modified sine: y″ = A·sin 4πu (u ≤ 1/8), A·cos (4π/3)(u − 1/8) (≤ 7/8), −A·cos 4π(u − 7/8) (≤ 1)."""
    A, w, v = _MS_A, 4.0 * PI, 4.0 * PI / 3.0
    y1_18, y_18 = A / w, A / w * (1 / 8 - 1 / w)
    y_78 = y_18 + y1_18 * 0.75 + A / v ** 2 * 2.0                 # ∫ over the middle piece
    p1, p2 = u <= 1 / 8, u <= 7 / 8
    t2, t3 = u - 1 / 8, u - 7 / 8
    y = np.select([p1, p2], [A / w * (u - np.sin(w * u) / w), y_18 + y1_18 * t2 + A / v ** 2 * (1 - np.cos(v * t2))],
                  y_78 + y1_18 * t3 + A / w ** 2 * (np.cos(w * t3) - 1))
    y1 = np.select([p1, p2], [A / w * (1 - np.cos(w * u)), y1_18 + A / v * np.sin(v * t2)],
                   y1_18 - A / w * np.sin(w * t3))
    y2 = np.select([p1, p2], [A * np.sin(w * u), A * np.cos(v * t2)], -A * np.cos(w * t3))
    y3 = np.select([p1, p2], [A * w * np.cos(w * u), -A * v * np.sin(v * t2)], A * w * np.sin(w * t3))
    return y, y1, y2, y3


_EVALUATORS = {
    "harmonic": _harmonic,
    "cycloidal": _cycloidal,
    "polynomial_345": lambda u: _polynomial({3: 10.0, 4: -15.0, 5: 6.0}, u),
    "polynomial_4567": lambda u: _polynomial({4: 35.0, 5: -84.0, 6: 70.0, 7: -20.0}, u),
    "modified_trapezoid": _modified_trapezoid,
    "modified_sine": _modified_sine,
}


def normalised(law: str, u) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """(y, y′, y″, y‴) of a normalised law at ``u (...)`` in [0, 1] (clipped there), each (...).

    KeyError for a name not in :data:`LAWS`."""
    u = np.clip(np.asarray(u, dtype=float), 0.0, 1.0)
    y = _EVALUATORS[law](u)
    return tuple(np.broadcast_to(np.asarray(c, dtype=float), u.shape).copy() for c in y)


def segment(law: str, theta, start: float, span: float, lift: float, base: float = 0.0):
    """(s, s′, s″, s‴) of one segment s = base + lift·y((θ − start)/span) per unit of cam angle θ (rad), each
    shaped like ``theta``; ``law`` None (or a zero lift) is a dwell at ``base``."""
    theta = np.asarray(theta, dtype=float)
    if law is None or lift == 0.0:
        z = np.zeros(theta.shape)
        return base + z, z.copy(), z.copy(), z.copy()
    y, y1, y2, y3 = normalised(law, (theta - start) / span)
    return base + lift * y, lift / span * y1, lift / span ** 2 * y2, lift / span ** 3 * y3
