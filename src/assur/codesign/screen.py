"""A necessary condition for a walking leg to have a co-designed gear drive at a window fraction f: checked on the
leg alone, before any transfer law is chosen (:func:`window_screen`).

Notation as :mod:`assur.codesign.law`: g(q) = dτ/dq > 0 motor radians per crank radian, the window [q1, q2]
where g = k·x′ (x′ > 0 read along the stride), the transfer [q2, q1 + 2π] of crank span D, the closure
∫ g dq = 2π·n over a crank turn (n motor turns).

Given k, the window's law is fixed by the leg, so on the window (quantities of :func:`pitch_terms` at g = k·x′):

- both pitch curves convex there: min κ·L ≥ 0 (driving and driven);
- the centrode pressure angle there ≤ μ_max;
- the ratio there within [g_lo, g_hi].

And whatever the transfer, it must close the cycle in the motor time the window leaves: k·f·stride + T ≤ 2π·n,
where T = ∫ g dq over the transfer. A transfer with every check met has g ≥ g_lo and pressure angle ≤ μ_max, i.e.
|h′| ≤ t = tan μ_max for h = ln(g/(1 + g)) (tan μ = |g′|/(g(1 + g)) = |h′|), and starts and ends at the window's
joint values h_a = h(k·x′(q2)), h_b = h(k·x′(q1)). So pointwise h(q) ≥ max(h_a − t·(q − q2), h_b − t·(q1 + 2π − q),
h_lo), and since g = e^h/(1 − e^h) grows with h, T ≥ T_min = ∫ g(that bound) dq. In closed form: along a line
h = h0 − t·s, ∫ g ds from h0 down to h1 is ln((1 − e^h1)/(1 − e^h0))/t; the flat part at h_lo adds g_lo times its
length. (Convexity, C² matching and undercut of the transfer only add constraints, so T_min is a lower bound.)

The screen scans k over (0, k_max), k_max = 2π·n/(f·stride), and keeps the k whose worst scaled margin is largest.
A leg whose best is negative has no transfer law passing every check at that window: no optimiser needs to try.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..errors import SpecError
from .checks import check_angle, check_bounds, pitch_terms
from .law import FootLaw, check_fraction, support_window

TWO_PI = 2.0 * math.pi

#: the margins of :class:`WindowScreen`, in order
SCREEN_NAMES = ("pressure_angle", "convex_driving", "convex_driven", "ratio_low", "ratio_high", "time")
#: the scale that makes each margin dimensionless (rad, κ·L, κ·L, ratio, ratio, motor rad)
SCREEN_SCALES = (0.1, 1.0, 1.0, 0.1, 0.1, 1.0)


@dataclass(frozen=True)
class WindowScreen:
    """The best k of a leg at one window fraction and its margins (each ≥ 0 met).

    ``margins``: name → value (:data:`SCREEN_NAMES`): ``pressure_angle`` μ_max − max μ on the window (rad);
    ``convex_driving``/``convex_driven`` min κ·L on the window; ``ratio_low`` g_min − g_lo and ``ratio_high``
    g_hi − g_max on the window; ``time`` 2π·n − k·f·stride − T_min (motor rad). ``slack``: the least margin divided
    by its scale (:data:`SCREEN_SCALES`); ``feasible``: slack ≥ 0. ``transfer_time_min``: T_min (motor rad)."""
    fraction: float
    k: float
    k_max: float
    margins: dict
    slack: float
    transfer_time_min: float

    @property
    def feasible(self) -> bool:
        return self.slack >= 0.0

    @property
    def worst(self) -> str:
        """The name of the margin that sets the slack."""
        return min(self.margins, key=lambda n: self.margins[n] / SCREEN_SCALES[SCREEN_NAMES.index(n)])


def transfer_time_min(g_start: float, g_end: float, span: float, max_pressure_angle: float,
                      ratio_low: float) -> float:
    """T_min (motor rad): the least ∫ g dq over a transfer of crank ``span`` (rad) from g = ``g_start`` to
    ``g_end`` (> 0) with pressure angle ≤ ``max_pressure_angle`` (rad) and g ≥ ``ratio_low`` (see the module doc)."""
    t = math.tan(max_pressure_angle)
    h = lambda g: math.log(g / (1.0 + g))                                       # noqa: E731
    ha, hb = h(g_start), h(g_end)
    h_lo = min(h(ratio_low), ha, hb) if ratio_low > 0 else -math.inf

    def down(h0, h1):                        # ∫ g ds along h = h0 − t·s from h0 to h1 ≤ h0
        return math.log((1.0 - math.exp(h1)) / (1.0 - math.exp(h0))) / t

    sa, sb = (ha - h_lo) / t, (hb - h_lo) / t
    if sa + sb <= span:
        return down(ha, h_lo) + down(hb, h_lo) + ratio_low * (span - sa - sb)
    s = (ha - hb + t * span) / (2.0 * t)     # the two slopes meet inside the transfer
    meet = ha - t * s
    return down(ha, meet) + down(hb, meet)


def window_screen(foot: FootLaw, fraction: float, *, max_pressure_angle: float = math.radians(30.0),
                  ratio_bounds=(1.0 / 3.0, 3.0), driving_turns: int = 1, points: int = 2001,
                  ks: int = 197) -> WindowScreen:
    """The leg's best k at window ``fraction`` and its margins (:class:`WindowScreen`): ``ks`` values of k/k_max in
    [0.01, 0.99], each judged on ``points`` window samples. SpecError for a window that does not exist
    (:func:`~assur.codesign.law.support_window`) or a bad bound."""
    f = check_fraction(fraction)
    mu = check_angle("max_pressure_angle", max_pressure_angle)
    lo, hi = check_bounds(ratio_bounds)
    n = int(driving_turns)
    q1, q2 = support_window(foot, f)
    q = np.linspace(q1, q2, int(points))
    sign = 1.0 if foot.dx(0.5 * (q1 + q2)) > 0 else -1.0
    d1, d2, d3 = (sign * foot.derivative(q, order) for order in (1, 2, 3))
    k_max = TWO_PI * n / (f * foot.stride)
    span = TWO_PI - (q2 - q1)
    scales = np.asarray(SCREEN_SCALES)
    best = None
    for k in np.linspace(0.01, 0.99, int(ks)) * k_max:
        g = k * d1
        terms = pitch_terms(g, k * d2, k * d3, 1.0)
        t_min = transfer_time_min(float(g[-1]), float(g[0]), span, mu, lo)
        m = np.array([mu - float(np.arctan(terms["tan_pressure"]).max()), float(terms["kappa_driving"].min()),
                      float(terms["kappa_driven"].min()), float(g.min()) - lo, hi - float(g.max()),
                      TWO_PI * n - k * f * foot.stride - t_min])
        slack = float(np.min(m / scales))
        if best is None or slack > best.slack:
            best = WindowScreen(f, float(k), k_max, dict(zip(SCREEN_NAMES, m.tolist())), slack, t_min)
    return best


def critical_fraction(foot: FootLaw, *, low: float = 0.5, high: float = 0.99, tol: float = 1e-3,
                      **options) -> float:
    """The widest window fraction in [low, high] that the leg passes :func:`window_screen` at (bisection; the screen
    tightens as the window widens), or ``low`` if it fails there too; ``options`` go to the screen."""
    def ok(f):
        try:
            return window_screen(foot, f, **options).feasible
        except SpecError:            # the window does not exist (x not monotone there): not passable
            return False
    if not ok(low):
        return float(low)
    if ok(high):
        return float(high)
    a, b = low, high
    while b - a > tol:
        c = 0.5 * (a + b)
        a, b = (c, b) if ok(c) else (a, c)
    return float(a)
