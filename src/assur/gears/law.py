"""Transmission laws θ(φ) of a non-circular gear pair: driven rotation θ as a function of driving rotation φ.

Conventions (shared with :mod:`assur.gears.pitch`): φ is the driving gear's rotation, θ the driven gear's, both in
radians, θ(0) = 0, and the law is increasing. ``driving_turns = n`` means the driving gear turns n times per turn
of the driven gear, so over one driving turn θ advances 2π/n, and the law continues periodically:
θ(φ + 2π) = θ(φ) + 2π/n. That periodicity is what makes the driving pitch curve close after one of its turns;
the driven curve then closes after n driving turns.

Laws: :class:`WheelStepLaw` (the paper-001 constant-mover-speed law, docs/papers/001.md B2, built in),
:func:`law_from_callable` (θ(φ) vectorised), :func:`law_from_table` (φ_i, θ_i over one driving turn),
:func:`law_from_ratio` (k(φ) = dθ/dφ).
The three generic ones are periodic cubic splines of the excess e(φ) = θ(φ) − φ/n over one driving turn.
"""
from __future__ import annotations

import math
from typing import Callable

import numpy as np

from ..errors import GearError
from .errors import angle_ranges
from ..tolerances import DEFAULT as TOL
from .wheelstep import STEP_HALF_ANGLE, Shoe

TWO_PI = 2.0 * math.pi
#: closure tolerance of a law, rad (θ after the full cycle must be 2π within this)
CLOSURE_TOLERANCE = TOL.law_closure


def _reduce(x, period):
    """(j, u) with x = j·period + u, u ∈ [0, period)."""
    j = np.floor(x / period)
    u = x - j * period
    # floating point can give u == period
    over = u >= period
    return np.where(over, j + 1, j), np.where(over, u - period, u)


def invert_increasing(f: Callable, df: Callable, target, lo: float, hi: float, guess=None, iterations: int = 100):
    """Solve f(x) = target for x ∈ [lo, hi], f increasing with f(lo) ≤ target ≤ f(hi); vectorised over target (...).

    Newton steps kept inside a shrinking bracket (bisection when Newton leaves it); converges to round-off."""
    target = np.asarray(target, dtype=float)
    lo_a = np.full(target.shape, float(lo))
    hi_a = np.full(target.shape, float(hi))
    x = np.clip(np.asarray(guess, dtype=float), lo, hi) if guess is not None else 0.5 * (lo_a + hi_a)
    x = np.broadcast_to(x, target.shape).copy()
    for _ in range(iterations):
        fx = f(x) - target
        below = fx < 0
        lo_a = np.where(below, x, lo_a)
        hi_a = np.where(below, hi_a, x)
        with np.errstate(divide="ignore", invalid="ignore"):
            xn = x - fx / df(x)
        outside = ~((xn > lo_a) & (xn < hi_a))
        xn = np.where(outside, 0.5 * (lo_a + hi_a), xn)
        done = np.all((np.abs(xn - x) <= 4e-16 * np.maximum(1.0, np.abs(x))) | (fx == 0))
        x = np.where(fx == 0, x, xn)
        if done:
            break
    return x


class TransmissionLaw:
    """Base class: θ(φ), its rate k = dθ/dφ and the inverse φ(θ), over the whole cycle.

    Subclasses implement ``_turn_theta(u)`` and ``_turn_ratio(u)`` for u ∈ [0, 2π] (one driving turn, θ(0) = 0,
    θ(2π) = 2π/n); everything else follows."""

    driving_turns: int = 1
    #: short description for reports
    description: str = "law"

    def theta(self, phi) -> np.ndarray:
        """Driven rotation θ(φ), (...) → (...), rad."""
        j, u = _reduce(np.asarray(phi, dtype=float), TWO_PI)
        return j * (TWO_PI / self.driving_turns) + self._turn_theta(u)

    def ratio(self, phi) -> np.ndarray:
        """Speed ratio k(φ) = dθ/dφ = r_driving / r_driven, (...) → (...)."""
        _, u = _reduce(np.asarray(phi, dtype=float), TWO_PI)
        return self._turn_ratio(u)

    def phi_of(self, theta) -> np.ndarray:
        """Inverse law φ(θ), (...) → (...), rad."""
        per = TWO_PI / self.driving_turns
        j, t = _reduce(np.asarray(theta, dtype=float), per)
        u = invert_increasing(self._turn_theta, self._turn_ratio, t, 0.0, TWO_PI, guess=t * self.driving_turns)
        return j * TWO_PI + u

    def ratio_of_theta(self, theta) -> np.ndarray:
        """k at the driving angle where the driven angle is θ, (...) → (...)."""
        return self.ratio(self.phi_of(theta))

    def _turn_theta(self, u):  # pragma: no cover - abstract
        raise NotImplementedError

    def _turn_ratio(self, u):  # pragma: no cover - abstract
        raise NotImplementedError


class WheelStepLaw(TransmissionLaw):
    """The paper-001 law (docs/papers/001.md B2): the mover runs at constant speed when the driving gear does.

    In the paper's symbols the driving-gear angle is θ and the driven (hub) angle φ; here, following the gear
    package, the driving angle is ``phi`` and the driven angle ``theta``. With X(·) the mover displacement over a
    step of the hub (:meth:`assur.gears.wheelstep.Shoe.displacement`, periodic) and X_01 its value per step:

        driving angle = (n·π/2) · X(hub angle) / X_01,     n = driving_turns

    so one step (hub ±π/4) takes n·π/2 of the driving gear: n = 2 is the paper's drive (driver ±π/2 per step, two
    identical halves; driven four quarters); n = 4 is the variant the paper mentions first (one step per driving
    turn); n = 1 puts 4 steps on one driving turn. The driven angle is the hub angle, θ = 0 at the symmetry axis
    (driver minimum radius, driven maximum radius).

    ``rounding`` = δ (rad of hub angle, default 0 = the paper's law) smooths the law's kink at the step ends
    (docs/papers/001.md B6.3/B7.8), which otherwise gives the pitch curves corners: within δ of a step end the rate
    X′ = A + 3b·sin 2w (A = a − b + c, w = distance of the hub angle from the step end) is replaced by
    A + 3b·sin 2s(w) with s(w) = (w²/δ + δ)/2, which joins |w| with equal value and slope at w = ±δ, so k is C¹ and
    the pitch curves are smooth. The per-step total is renormalised so the curves still close; the mover speed is
    then constant only outside the rounded zones (:meth:`mover_speed_ratio`).
    """

    description = "wheel-step constant-speed law (paper 001, docs/papers/001.md B2)"

    def __init__(self, shoe: Shoe, driving_turns: int = 2, rounding: float = 0.0):
        if driving_turns not in (1, 2, 4):
            raise GearError(f"driving_turns of the wheel-step law must be 1, 2 or 4 (a whole number of hub steps "
                            f"of 90° per driving turn): {driving_turns!r}")
        if not (np.isfinite(rounding) and 0.0 <= rounding <= STEP_HALF_ANGLE / 2):
            raise GearError(f"the corner rounding of the wheel-step law must lie in [0°, 22.5°] of hub angle: "
                            f"{math.degrees(rounding) if np.isfinite(rounding) else rounding}°")
        self.shoe = shoe
        self.driving_turns = int(driving_turns)
        self.rounding = float(rounding)
        self._rate_const = shoe.a - shoe.b + shoe.c
        self._step_total = 2.0 * self._half_step(STEP_HALF_ANGLE) if rounding > 0 else shoe.budget.total
        self._scale = self.driving_turns * math.pi / 2.0 / self._step_total   # driving rad per metre (law)
        if rounding > 0:
            self.description = (f"wheel-step constant-speed law (paper 001, docs/papers/001.md B2), step ends "
                                f"rounded over ±{math.degrees(rounding):.4g}° of hub angle")

    def __repr__(self):
        return (f"WheelStepLaw(a={self.shoe.a!r}, b={self.shoe.b!r}, c={self.shoe.c!r}, "
                f"driving_turns={self.driving_turns}, rounding={self.rounding!r})")

    # ---- the (possibly rounded) displacement used by the law, per step ---------------------------------------
    def _s(self, w):
        d = self.rounding
        return np.where(w < d, 0.5 * (w * w / d + d), w) if d > 0 else w

    def _rate(self, u):
        """Law rate dX/du for u ∈ [−π/4, π/4] (m/rad)."""
        w = STEP_HALF_ANGLE - np.abs(u)
        return self._rate_const + 3.0 * self.shoe.b * np.sin(2.0 * self._s(w))

    def _half_step(self, u):
        """Law displacement X(u) for u ∈ [0, π/4] (odd in u), exact closed form plus a Gauss–Legendre integral of
        the smooth rounded rate over the rounded zone."""
        u = np.asarray(u, dtype=float)
        x = self.shoe.displacement(u, periodic=False)
        d = self.rounding
        if d <= 0:
            return x
        edge = STEP_HALF_ANGLE - d
        in_zone = u > edge
        nodes, weights = np.polynomial.legendre.leggauss(24)
        lo = np.full(u.shape, edge)
        hi = np.where(in_zone, u, edge)
        mid, half = 0.5 * (lo + hi), 0.5 * (hi - lo)
        pts = mid[..., None] + half[..., None] * nodes
        integral = (half[..., None] * weights * self._rate(pts)).sum(axis=-1)
        return np.where(in_zone, self.shoe.displacement(np.minimum(u, edge), periodic=False) + integral, x)

    def _law_x(self, t):
        """Periodic law displacement of hub angles t (...,), m."""
        t = np.asarray(t, dtype=float)
        j = np.round(t / (2.0 * STEP_HALF_ANGLE))
        u = t - j * 2.0 * STEP_HALF_ANGLE
        return j * self._step_total + np.sign(u) * self._half_step(np.abs(u))

    def _law_rate(self, t):
        t = np.asarray(t, dtype=float)
        u = t - np.round(t / (2.0 * STEP_HALF_ANGLE)) * 2.0 * STEP_HALF_ANGLE
        return self._rate(u)

    # explicit direction: driving angle as a function of the hub (driven) angle
    def phi_of(self, theta) -> np.ndarray:
        return self._scale * self._law_x(theta)

    def ratio_of_theta(self, theta) -> np.ndarray:
        return 1.0 / (self._scale * self._law_rate(theta))

    def mover_speed_ratio(self, theta) -> np.ndarray:
        """Mover speed / nominal speed X_01/(n·π/2) per driving radian, at hub angles θ (...,): exactly 1 for the
        paper's law; below/above 1 inside the rounded zones."""
        nominal = self.shoe.budget.total / (self.driving_turns * math.pi / 2.0)
        true_rate = self.shoe.displacement_rate(theta, periodic=True)
        return true_rate * self.ratio_of_theta(theta) / nominal

    def _turn_theta(self, u):
        per = TWO_PI / self.driving_turns
        return invert_increasing(self.phi_of, lambda t: 1.0 / self.ratio_of_theta(t), u, -1e-9, per + 1e-9,
                                 guess=u / self.driving_turns)

    def _turn_ratio(self, u):
        return self.ratio_of_theta(self._turn_theta(u))

    def corner_thetas(self) -> np.ndarray:
        """Driven angles of the law's kinks (step boundaries, hub = ±45°, ±135°): (4,), rad in [0, 2π);
        empty when the law is rounded."""
        if self.rounding > 0:
            return np.empty(0)
        return np.mod(STEP_HALF_ANGLE + np.arange(4) * 2.0 * STEP_HALF_ANGLE, TWO_PI)


class SplineLaw(TransmissionLaw):
    """A law given by the periodic excess e(u) = θ(u) − u/n over one driving turn (a scipy PPoly and its rate)."""

    def __init__(self, excess, excess_rate, driving_turns: int, description: str):
        self._excess = excess
        self._excess_rate = excess_rate
        self.driving_turns = int(driving_turns)
        self.description = description

    def __repr__(self):
        return f"SplineLaw({self.description!r}, driving_turns={self.driving_turns})"

    def _turn_theta(self, u):
        return u / self.driving_turns + self._excess(u)

    def _turn_ratio(self, u):
        return 1.0 / self.driving_turns + self._excess_rate(u)


def _check_turns(driving_turns) -> int:
    if isinstance(driving_turns, bool) or not isinstance(driving_turns, (int, np.integer)) or driving_turns < 1:
        raise GearError(f"driving_turns must be a whole number ≥ 1 (driving-gear turns per driven-gear turn): "
                        f"{driving_turns!r}")
    return int(driving_turns)


def _check_increasing(phi, theta, what):
    dtheta = np.diff(theta)
    bad = ~(dtheta > 0)
    if bad.any():
        mark = np.zeros(phi.size, dtype=bool)
        mark[:-1] |= bad
        mark[1:] |= bad
        raise GearError(f"{what} is not increasing (speed ratio dθ/dφ ≤ 0, so a pitch radius would be ≤ 0) "
                        f"for φ ∈ {angle_ranges(phi, mark)}")


def _excess_spline(u, theta, n, description):
    from scipy.interpolate import CubicSpline
    excess = theta - u / n
    spline = CubicSpline(u, excess, bc_type="periodic")
    return SplineLaw(spline, spline.derivative(), n, description)


def law_from_callable(func: Callable, *, driving_turns: int = 1, samples: int = 16384) -> SplineLaw:
    """A law from a vectorised callable θ(φ), sampled over the full cycle φ ∈ [0, 2π·n].

    θ is taken relative to θ(0). Errors: non-finite values; not increasing (names the φ range); the law does not
    close (θ(2π·n) − θ(0) ≠ 2π); the driving pitch curve does not close (θ(φ + 2π) − θ(φ) ≠ 2π/n somewhere)."""
    n = _check_turns(driving_turns)
    phi = np.linspace(0.0, TWO_PI * n, samples * n + 1)
    try:
        theta = np.asarray(func(phi), dtype=float)
    except Exception as exc:  # a user function: report what failed
        raise GearError(f"the transmission law θ(φ) could not be evaluated: {exc}") from None
    if theta.shape != phi.shape:
        raise GearError(f"the transmission law θ(φ) must return one value per φ (shape {phi.shape}): got {theta.shape}")
    if not np.all(np.isfinite(theta)):
        raise GearError(f"the transmission law θ(φ) is not finite for φ ∈ {angle_ranges(phi, ~np.isfinite(theta))}")
    theta = theta - theta[0]
    if abs(theta[-1] - TWO_PI) > CLOSURE_TOLERANCE:
        raise GearError(f"the law does not close: θ(2π·{n}) = {math.degrees(theta[-1]):.4f}°, must be 360°"
                        + (f" (driving_turns = {n})" if n > 1 else ""))
    _check_increasing(phi, theta, "the transmission law θ(φ)")
    if n > 1:
        per_turn = theta[samples:] - theta[:-samples]
        bad = np.abs(per_turn - TWO_PI / n) > CLOSURE_TOLERANCE
        if bad.any():
            worst = np.max(np.abs(per_turn - TWO_PI / n))
            raise GearError(f"the driving pitch curve does not close: θ(φ + 360°) − θ(φ) differs from 360°/{n} by "
                            f"up to {math.degrees(worst):.4f}° for φ ∈ {angle_ranges(phi[:-samples], bad)}")
    return _excess_spline(phi[:samples + 1], theta[:samples + 1], n, "θ(φ) callable")


def law_from_table(phi, theta, *, driving_turns: int = 1) -> SplineLaw:
    """A law from a table (φ_i, θ_i), (M,) each, spanning exactly one driving turn (φ_M − φ_1 = 2π, θ_M − θ_1 = 2π/n).

    Angles are taken relative to the first row; interpolation is a periodic cubic spline of θ − φ/n."""
    n = _check_turns(driving_turns)
    phi = np.asarray(phi, dtype=float)
    theta = np.asarray(theta, dtype=float)
    if phi.ndim != 1 or phi.shape != theta.shape or phi.size < 4:
        raise GearError(f"the law table needs two columns φ, θ of equal length ≥ 4: got {phi.shape}, {theta.shape}")
    if not (np.all(np.isfinite(phi)) and np.all(np.isfinite(theta))):
        raise GearError("the law table has non-finite entries")
    phi = phi - phi[0]
    theta = theta - theta[0]
    if not np.all(np.diff(phi) > 0):
        raise GearError(f"the law table's φ column must be strictly increasing: it is not for φ ∈ "
                        f"{angle_ranges(phi[1:], ~(np.diff(phi) > 0))}")
    if abs(phi[-1] - TWO_PI) > CLOSURE_TOLERANCE:
        raise GearError(f"the law table must span one driving turn: φ spans {math.degrees(phi[-1]):.4f}°, "
                        f"must be 360°")
    if abs(theta[-1] - TWO_PI / n) > CLOSURE_TOLERANCE:
        raise GearError(f"the law does not close: θ after one driving turn = {math.degrees(theta[-1]):.4f}°, must "
                        f"be 360°/{n} = {360.0 / n:.4f}°")
    _check_increasing(phi, theta, "the law table's θ(φ)")
    phi[-1], theta[-1] = TWO_PI, TWO_PI / n
    return _excess_spline(phi, theta, n, "θ(φ) table")


def law_from_ratio(ratio: Callable, *, driving_turns: int = 1, samples: int = 16384) -> SplineLaw:
    """A law from a vectorised speed-ratio function k(φ) = dθ/dφ, 2π-periodic; θ = ∫₀^φ k.

    Errors: k ≤ 0 (names the φ range); ∫ k over one driving turn ≠ 2π/n (the law does not close)."""
    from scipy.interpolate import CubicSpline
    n = _check_turns(driving_turns)
    u = np.linspace(0.0, TWO_PI, samples + 1)
    try:
        k = np.asarray(ratio(u), dtype=float)
    except Exception as exc:
        raise GearError(f"the speed ratio k(φ) could not be evaluated: {exc}") from None
    if k.shape != u.shape:
        raise GearError(f"the speed ratio k(φ) must return one value per φ (shape {u.shape}): got {k.shape}")
    bad = ~(np.isfinite(k) & (k > 0))
    if bad.any():
        raise GearError(f"the speed ratio k(φ) = dθ/dφ must be finite and > 0 (else a pitch radius is ≤ 0): it is "
                        f"not for φ ∈ {angle_ranges(u, bad)}")
    if abs(k[-1] - k[0]) > TOL.ratio_periodic * max(1.0, abs(k[0])):
        raise GearError(f"the speed ratio must be 360°-periodic (the driving pitch curve must close): "
                        f"k(0) = {k[0]:.6g}, k(360°) = {k[-1]:.6g}")
    k[-1] = k[0]
    rate = CubicSpline(u, k - 1.0 / n, bc_type="periodic")
    total = float(rate.integrate(0.0, TWO_PI)) + TWO_PI / n
    if abs(total - TWO_PI / n) > CLOSURE_TOLERANCE:
        raise GearError(f"the law does not close: ∫k dφ over one driving turn = {math.degrees(total):.4f}°, must be "
                        f"360°/{n} = {360.0 / n:.4f}°")
    return SplineLaw(rate.antiderivative(), rate, n, "k(φ) ratio")


def as_law(law=None, *, ratio=None, driving_turns=None, samples: int = 16384) -> TransmissionLaw:
    """Normalise the accepted law forms to a :class:`TransmissionLaw`.

    ``law`` is a TransmissionLaw, a callable θ(φ), or a table ``(phi, theta)`` ((2, M) or (M, 2)); or give
    ``ratio=`` a callable k(φ). ``driving_turns`` defaults to the law's own (or 1)."""
    if (law is None) == (ratio is None):
        raise GearError("give exactly one of a law θ(φ) (callable or table) or ratio= k(φ)")
    if isinstance(law, TransmissionLaw):
        if driving_turns is not None and int(driving_turns) != law.driving_turns:
            raise GearError(f"driving_turns = {driving_turns} contradicts the law's own {law.driving_turns}")
        return law
    n = 1 if driving_turns is None else driving_turns
    if ratio is not None:
        return law_from_ratio(ratio, driving_turns=n, samples=samples)
    if callable(law):
        return law_from_callable(law, driving_turns=n, samples=samples)
    table = np.asarray(law, dtype=float)
    if table.ndim == 2 and table.shape[0] == 2:
        return law_from_table(table[0], table[1], driving_turns=n)
    if table.ndim == 2 and table.shape[1] == 2:
        return law_from_table(table[:, 0], table[:, 1], driving_turns=n)
    raise GearError(f"a law table must have shape (2, M) or (M, 2): got {table.shape}")
