"""The co-design law of a geared walking leg: a non-circular gear pair between a uniform motor and the leg's crank
that makes the foot's horizontal speed exactly constant over the central part of the stride.

Notation. q is the crank's signed input of the plan (``plan.sketch_inputs``' coordinate; the crank turns by
``sense·q`` in the file's sense, see the driver's ``sense``), τ the motor angle (uniform in time), g(q) = dτ/dq > 0
the motor radians per crank radian. The foot's stride coordinate is x(q) = P(q)·ground (:mod:`assur.analysis.gait`).

Direction of time. The crank advances in the direction σ = sign(driver speed) of q (σ = +1 for a speed ≥ 0). The
motor angle is τ(q) = σ·∫₀^q g, so τ increases while the crank advances in its own sense, τ(0) = 0 at q = 0, and
dq/dτ = σ/g, d²q/dτ² = −g′/g³ (g′ = dg/dq). The gear package's law θ(φ) (driving = motor φ = τ, driven = crank
θ = σ·q, the crank's |advance| from q = 0) then has ratio k = dθ/dφ = 1/g (:meth:`CodesignLaw.transmission_law`).
Physically the pair is external: if the crank turns counter-clockwise the motor turns clockwise.

The law (one crank turn, cut at the window start q1):

- window [q1, q2] (:func:`support_window`: the part of the contact arc where x lies in the central fraction f of the
  stride, x strictly monotone there): g = k·s·x′(q), s = sign x′ on the window, so the foot's horizontal speed
  |v_x| = |x′|·ω_motor/g = ω_motor/k is exactly constant;
- transfer [q2, q1 + 2π], s = (q − q2)/Δ ∈ [0, 1], Δ = q1 + 2π − q2: g = k·H(s) + Σ_j c_j·B_j(s), H the quintic
  Hermite interpolant of the window's (w, dw/ds, d²w/ds²), w = s·x′, at both ends (so g, g′, g″ are continuous
  across both joints: pitch radius, tangent and curvature of both pitch curves), B_j(s) = 64·s³(1−s)³·P_j(2s − 1)
  (P_j Legendre; B_j and its first two derivatives vanish at both ends; |B_0| ≤ 1);
- closure ∫₀^{2π} g dq = 2π·n (n = ``driving_turns`` motor turns per crank turn) is linear in (k, c): k is solved for
  the given c.

The foot's x(q) is a periodic quintic spline through ``samples`` exact positions (:func:`foot_law`), so x′, x″, x‴
are continuous and the window law is exact to the spline's interpolation error (~1e-13 relative at 4096 samples).
"""
from __future__ import annotations

import math
import threading
import weakref
from dataclasses import dataclass, replace

import numpy as np

from ..analysis.gait import VX_FRACTIONS, critical_points, gait_metrics, resolve_gait, window_vx_spread
from ..engine import solve
from ..errors import GearError, SpecError, UnbuildableError
from ..kernels.runs import runs
from ..gears.law import TransmissionLaw, invert_increasing

TWO_PI = 2.0 * math.pi


def _deg(a) -> str:
    return f"{math.degrees(float(a)):.2f}°"


def check_fraction(fraction) -> float:
    """The window fraction as a float in (0, 1), else SpecError naming ``fraction``."""
    try:
        f = float(fraction)
    except (TypeError, ValueError):
        raise SpecError([("fraction", f"must be a number in (0, 1): {fraction!r}")]) from None
    if not (0.0 < f < 1.0):
        raise SpecError([("fraction", f"the window's share of the stride must lie strictly between 0 and 1: "
                                      f"{fraction!r}")])
    return f


# ---------------------------------------------------------------------------------------------------------------
# the foot's stride coordinate over one crank turn


@dataclass(frozen=True, eq=False)
class FootLaw:
    """The foot's stride coordinate x(q) over one crank turn as a periodic quintic spline, with its contact arc.

    q: (N,) uniform crank inputs linspace(0, 2π, N, endpoint=False), rad; x: (N,) exact x at q, m;
    spline: the periodic quintic BSpline of x over [0, 2π]; contact_start < contact_end (≤ contact_start + 2π): the
    contact arc in increasing q (:func:`assur.analysis.gait.gait_metrics`); x_min, x_max: the stride's ends, m;
    sense: σ = +1 when q increases in time (driver speed ≥ 0), −1 otherwise; omega: |crank speed| of the plan
    (rad/s); plan, params, foot, ground: the leg (None for a law built from samples)."""
    q: np.ndarray
    x: np.ndarray
    spline: object
    contact_start: float
    contact_end: float
    x_min: float
    x_max: float
    sense: int = 1
    omega: float = 1.0
    plan: object = None
    params: np.ndarray | None = None
    foot: str | None = None
    ground: tuple = (1.0, 0.0)
    #: the leg's gait metrics (:class:`~assur.analysis.gait.GaitMetrics`), None for a law built from samples
    metrics: object = None

    @property
    def stride(self) -> float:
        """x_max − x_min, m."""
        return self.x_max - self.x_min

    def derivative(self, q, order: int = 0) -> np.ndarray:
        """d^order x / dq^order at crank inputs q (...) → (...) (periodic), m/rad^order; order 0 … 4."""
        q = np.asarray(q, dtype=float)
        return self.spline(np.mod(q, TWO_PI), order)

    def x_at(self, q):
        """x(q), (...) → (...), m."""
        return self.derivative(q, 0)

    def dx(self, q):
        """x′(q), (...) → (...), m/rad."""
        return self.derivative(q, 1)

    def d2x(self, q):
        """x″(q), (...) → (...), m/rad²."""
        return self.derivative(q, 2)

    def d3x(self, q):
        """x‴(q), (...) → (...), m/rad³."""
        return self.derivative(q, 3)


def _periodic_quintic(x):
    from scipy.interpolate import make_interp_spline
    n = len(x)
    q = np.linspace(0.0, TWO_PI, n + 1)
    return make_interp_spline(q, np.append(x, x[0]), k=5, bc_type="periodic")


def foot_law_from_samples(x, contact_start: float, contact_end: float, *, x_min: float | None = None,
                          x_max: float | None = None, sense: int = 1, omega: float = 1.0) -> FootLaw:
    """A :class:`FootLaw` from N uniform samples x (N,) of a periodic stride coordinate over one turn (q =
    linspace(0, 2π, N, endpoint=False)) and a given contact arc (rad, contact_start < contact_end); the stride's
    ends default to the spline's x at the arc's two ends. For synthetic legs and tests; no plan attached."""
    x = np.asarray(x, dtype=float)
    if x.ndim != 1 or x.size < 16 or not np.all(np.isfinite(x)):
        raise SpecError([("x", f"needs at least 16 finite samples over one turn: shape {x.shape}")])
    cs, ce = float(contact_start), float(contact_end)
    if not (np.isfinite(cs) and np.isfinite(ce) and cs < ce <= cs + TWO_PI):
        raise SpecError([("contact", f"the contact arc must satisfy start < end ≤ start + 360°: "
                                     f"[{cs!r}, {ce!r}] rad")])
    spline = _periodic_quintic(x)
    ends = spline(np.mod([cs, ce], TWO_PI))
    lo = float(np.min(ends)) if x_min is None else float(x_min)
    hi = float(np.max(ends)) if x_max is None else float(x_max)
    q = np.linspace(0.0, TWO_PI, x.size, endpoint=False)
    return FootLaw(q, x, spline, cs, ce, lo, hi, -1 if sense < 0 else 1, float(omega))


#: the foot laws made in this process, per plan (weakly: they go with it) and (params, samples), each kept without
#: its plan: a co-design's searches and trade-off rows, the window screen and the leg ranking ask for the same leg's
#: law again
_FOOT_LAWS = weakref.WeakKeyDictionary()
_FOOT_LAWS_LOCK = threading.Lock()
#: laws kept per plan (the latest)
_FOOT_LAWS_PER_PLAN = 8


def foot_law(plan, params=None, *, samples: int = 4096) -> FootLaw:
    """The foot's stride coordinate of a walking leg over one crank turn (see :class:`FootLaw`).

    The leg is solved (order 2) at ``samples`` uniform crank inputs; x = foot·ground (the plan's ``[gait]``); the
    contact arc and the stride's ends are those of :func:`~assur.analysis.gait.gait_metrics` (exact extremes).
    Raises SpecError (no ``[gait]`` foot, not one rotary input, too few samples), UnbuildableError (the crank
    cannot turn fully). The law of a plan, parameters and sample count made before in this process is returned again
    (a FootLaw is frozen)."""
    if isinstance(samples, bool) or not isinstance(samples, (int, np.integer)) or samples < 64:
        raise SpecError([("samples", f"must be a whole number ≥ 64: {samples!r}")])
    try:
        key = (np.asarray(plan.defaults if params is None else params, dtype=float).tobytes(), int(samples))
        with _FOOT_LAWS_LOCK:
            law = _FOOT_LAWS.setdefault(plan, {}).get(key)
    except (TypeError, ValueError):     # parameters that are not numbers (refused below), a plan not kept weakly
        return _foot_law(plan, params, samples)
    if law is not None:
        return replace(law, plan=plan)
    law = _foot_law(plan, params, samples)
    with _FOOT_LAWS_LOCK:
        kept = _FOOT_LAWS.setdefault(plan, {})
        kept[key] = replace(law, plan=None)          # kept without the plan, so that the entry goes with it
        while len(kept) > _FOOT_LAWS_PER_PLAN:
            kept.pop(next(iter(kept)))
    return law


def _foot_law(plan, params, samples) -> FootLaw:
    """:func:`foot_law`, made."""
    foot, ground, _ = resolve_gait(plan)
    if plan.n_inputs != 1 or plan.input_kinds[0] != "rotary":
        raise SpecError([("drivers", f"a geared leg needs exactly one rotary input (the crank): the mechanism has "
                                     f"{plan.n_inputs} ({', '.join(plan.input_kinds)})")])
    params = plan.defaults if params is None else np.asarray(params, dtype=float)
    metrics = gait_metrics(plan, params, support="arc")       # raises UnbuildableError if the crank stops
    q = np.linspace(0.0, TWO_PI, int(samples), endpoint=False)
    state = solve(plan, params, q[:, None], order=2)
    if not np.all(state.valid):
        bad = q[~state.valid]
        raise UnbuildableError(f"the crank cannot turn fully: {np.count_nonzero(~state.valid)} of {samples} "
                               f"positions cannot be assembled (from {_deg(bad.min())} to {_deg(bad.max())})",
                               int(np.count_nonzero(~state.valid)), int(samples))
    i = plan.point_index(foot)
    g = np.asarray(ground, dtype=float)
    x = state.pos[:, i, :] @ g
    ends = solve(plan, params, np.array([[metrics.contact_start], [metrics.contact_end]]), order=0).pos[:, i, :] @ g
    speed = float(plan.speeds[0])
    return FootLaw(q, x, _periodic_quintic(x), float(metrics.contact_start), float(metrics.contact_end),
                   float(np.min(ends)), float(np.max(ends)), -1 if speed < 0 else 1, abs(speed), plan, params,
                   foot, tuple(float(v) for v in g), metrics)


def support_window(foot: FootLaw, fraction: float, *, points: int = 8192) -> tuple[float, float]:
    """(q1, q2), rad, q1 ∈ [0, 2π), q1 < q2 < q1 + 2π: the crank interval of the contact arc on which the foot's x
    lies in the central ``fraction`` f of the stride, |x − (x_min + x_max)/2| ≤ f·(x_max − x_min)/2, ends refined by
    Brent's method on the spline.

    SpecError (field ``fraction``) when f ∉ (0, 1), or when x is not strictly monotone there (it reverses inside
    the window, or the window is cut in pieces): the message gives the crank angles."""
    f = check_fraction(fraction)
    from scipy.optimize import brentq
    cs, ce = foot.contact_start, foot.contact_end
    mid, half = 0.5 * (foot.x_min + foot.x_max), 0.5 * f * (foot.x_max - foot.x_min)
    qq = np.linspace(cs, ce, int(points) + 1)
    xx, dx = foot.x_at(qq), foot.dx(qq)
    inside = np.abs(xx - mid) <= half
    found = runs(inside)
    if len(found) == 0:
        raise SpecError([("fraction", f"no point of the contact arc [{_deg(cs)}, {_deg(ce)}] lies in the central "
                                      f"{f:g} of the stride")])
    reversals = qq[:-1][np.sign(dx[:-1]) * np.sign(dx[1:]) <= 0]
    if len(found) > 1:
        raise SpecError([("fraction", f"the foot's x is not monotone on the contact arc: it leaves and re-enters "
                                      f"the central {f:g} of the stride ({len(found)} pieces, reversing near q = "
                                      f"{', '.join(_deg(r) for r in reversals[:4])}); choose a smaller fraction")])
    a, b = (int(v) for v in found[0])
    if a == 0 or b == len(qq) - 1:
        raise SpecError([("fraction", f"the central {f:g} of the stride reaches an end of the contact arc "
                                      f"[{_deg(cs)}, {_deg(ce)}]: the stride's ends are not the arc's extremes")])
    window_dx = dx[a:b + 1]
    direction = 1.0 if window_dx[len(window_dx) // 2] > 0 else -1.0
    if not np.all(direction * window_dx > 0):
        where = qq[a:b + 1][~(direction * window_dx > 0)]
        raise SpecError([("fraction", f"the foot's x is not strictly monotone over the central {f:g} of the stride: "
                                      f"x′ = 0 or reverses for q ∈ [{_deg(where.min())}, {_deg(where.max())}] "
                                      f"(window {_deg(qq[a])} … {_deg(qq[b])}); choose a smaller fraction")])
    lo_end, hi_end = mid - direction * half, mid + direction * half
    q1 = brentq(lambda t: float(foot.x_at(t)) - lo_end, qq[a - 1], qq[a], xtol=1e-15, rtol=1e-15)
    q2 = brentq(lambda t: float(foot.x_at(t)) - hi_end, qq[b], qq[b + 1], xtol=1e-15, rtol=1e-15)
    if not (direction * foot.dx(q1) > 0 and direction * foot.dx(q2) > 0):
        raise SpecError([("fraction", f"x′ vanishes at an end of the window [{_deg(q1)}, {_deg(q2)}]")])
    shift = math.floor(q1 / TWO_PI) * TWO_PI
    return float(q1 - shift), float(q2 - shift)


# ---------------------------------------------------------------------------------------------------------------
# the transfer basis and the law


@dataclass(frozen=True, eq=False)
class TransferBasis:
    """The polynomials (in s ∈ [0, 1]) of the transfer law for k = 1 and unit coefficients.

    hermite: numpy Polynomial H(s); bumps: list of Polynomial B_j(s); window_integral: s·(x(q2) − x(q1)) (m), the
    window's ∫ w dq; span Δ (rad); direction s = sign x′ on the window; q1, q2 (rad)."""
    q1: float
    q2: float
    span: float
    direction: float
    hermite: object
    bumps: tuple
    window_integral: float

    def closure_k(self, coefficients, turns: int = 1) -> float:
        """k solving ∫ g = 2π·turns for coefficients c (n_bumps,)."""
        c = np.asarray(coefficients, dtype=float).reshape(-1)
        bump = sum(float(cj) * _integral01(b) for cj, b in zip(c, self.bumps))
        return (TWO_PI * turns - self.span * bump) / (self.window_integral + self.span * _integral01(self.hermite))


def smooth_coefficients(basis: TransferBasis, turns: int = 1, points: int = 2001) -> np.ndarray:
    """The coefficients c (n_bumps,) of least ∫₀¹ (dg/ds)² ds on the transfer, k following from the closure (k is
    affine in c, so this is a linear least-squares problem on ``points`` samples of s)."""
    n = len(basis.bumps)
    if n == 0:
        return np.zeros(0)
    k0 = basis.closure_k(np.zeros(n), turns)
    dk = np.array([basis.closure_k(np.eye(n)[j], turns) - k0 for j in range(n)])
    s = np.linspace(0.0, 1.0, int(points))
    dh = basis.hermite.deriv(1)(s)
    columns = np.stack([dk[j] * dh + basis.bumps[j].deriv(1)(s) for j in range(n)], axis=1)
    c, *_ = np.linalg.lstsq(columns, -k0 * dh, rcond=None)
    return c


def _integral01(p) -> float:
    return float(p.integ()(1.0) - p.integ()(0.0))


def _hermite_quintic(v0, d0, a0, v1, d1, a1):
    """The quintic polynomial p(s) with p, p′, p″ = (v0, d0, a0) at s = 0 and (v1, d1, a1) at s = 1."""
    from numpy.polynomial import Polynomial
    rows = []
    for s in (0.0, 1.0):
        rows.append([s ** j for j in range(6)])
        rows.append([j * s ** (j - 1) if j >= 1 else 0.0 for j in range(6)])
        rows.append([j * (j - 1) * s ** (j - 2) if j >= 2 else 0.0 for j in range(6)])
    m = np.array([rows[0], rows[1], rows[2], rows[3], rows[4], rows[5]])
    return Polynomial(np.linalg.solve(m, np.array([v0, d0, a0, v1, d1, a1], dtype=float)))


def bump_polynomials(n_bumps: int) -> tuple:
    """B_j(s) = 64·s³(1−s)³·P_j(2s − 1), j = 0 … n_bumps − 1, as numpy Polynomials in s."""
    from numpy.polynomial import Legendre, Polynomial
    cube = Polynomial([0.0, 0.0, 0.0, 64.0]) * Polynomial([1.0, -1.0]) ** 3
    return tuple(cube * Legendre.basis(j, domain=[0.0, 1.0]).convert(kind=Polynomial) for j in range(int(n_bumps)))


def transfer_basis(foot: FootLaw, window: tuple[float, float], n_bumps: int) -> TransferBasis:
    """The :class:`TransferBasis` of a window (q1, q2) of ``foot`` (see the module docstring)."""
    q1, q2 = window
    span = q1 + TWO_PI - q2
    direction = 1.0 if foot.dx(0.5 * (q1 + q2)) > 0 else -1.0
    w = [direction * foot.derivative(q, order) for q in (q2, q1) for order in (1, 2, 3)]
    hermite = _hermite_quintic(w[0], span * w[1], span * span * w[2], w[3], span * w[4], span * span * w[5])
    window_integral = direction * float(foot.x_at(q2) - foot.x_at(q1))
    return TransferBasis(float(q1), float(q2), float(span), direction, hermite, bump_polynomials(n_bumps),
                         window_integral)


class CodesignLaw:
    """g(q) = dτ/dq of the geared leg over one crank turn (the module docstring), from a :class:`FootLaw`, the
    window fraction f ∈ (0, 1) and the transfer coefficients c (n_bumps,) (default None: :func:`smooth_coefficients`
    with ``n_bumps`` bumps, the bridge of least ∫(dg/ds)² ds).

    Attributes: foot, fraction, q1, q2, span (rad), direction (sign x′ on the window), k (rad of motor per m of
    foot travel), coefficients (n_bumps,), driving_turns, sense (σ). Raises SpecError (``coefficients``) when the
    closure gives k ≤ 0 or g ≤ 0 somewhere on the transfer (naming the crank-angle range)."""

    def __init__(self, foot: FootLaw, fraction: float, coefficients=None, *, n_bumps: int = 4,
                 driving_turns: int = 1):
        self.foot = foot
        self.fraction = check_fraction(fraction)
        if isinstance(driving_turns, bool) or not isinstance(driving_turns, (int, np.integer)) or driving_turns < 1:
            raise SpecError([("driving_turns", f"must be a whole number ≥ 1 (motor turns per crank turn): "
                                               f"{driving_turns!r}")])
        self.driving_turns = int(driving_turns)
        window = support_window(foot, self.fraction)
        if coefficients is None:
            if isinstance(n_bumps, bool) or not isinstance(n_bumps, (int, np.integer)) or n_bumps < 0:
                raise SpecError([("n_bumps", f"must be a whole number ≥ 0: {n_bumps!r}")])
            basis = transfer_basis(foot, window, int(n_bumps))
            c = smooth_coefficients(basis, self.driving_turns)
        else:
            c = np.asarray(coefficients, dtype=float).reshape(-1)
            if not np.all(np.isfinite(c)):
                raise SpecError([("coefficients", f"must be finite numbers: {coefficients!r}")])
            basis = transfer_basis(foot, window, len(c))
        self.coefficients = c
        self.basis = basis
        self.q1, self.q2, self.span, self.direction = basis.q1, basis.q2, basis.span, basis.direction
        self.sense = foot.sense
        self.k = k = basis.closure_k(c, self.driving_turns)
        if not (np.isfinite(k) and k > 0):
            raise SpecError([("coefficients", f"the closure ∫g dq = 2π·{self.driving_turns} gives k = {k:.6g} ≤ 0 "
                                              f"(the transfer takes more than the whole motor turn): reduce them")])
        poly = k * basis.hermite
        for cj, b in zip(c, basis.bumps):
            poly = poly + float(cj) * b
        self._poly, self._dpoly, self._d2poly = poly, poly.deriv(1), poly.deriv(2)
        self._ipoly = poly.integ(lbnd=0.0)
        self._window_total = k * basis.window_integral
        self.total = self._window_total + self.span * float(self._ipoly(1.0))
        self._check_positive()
        self._offset = 0.0
        self._offset = float(self._raw_integral(np.array(0.0)))
        grid = self.q1 + np.linspace(0.0, TWO_PI, 2049)
        self._table = (self._turn_integral(grid), grid)

    def __repr__(self):
        return (f"CodesignLaw(fraction={self.fraction:g}, window=[{_deg(self.q1)}, {_deg(self.q2)}], k={self.k:.6g}, "
                f"coefficients={self.coefficients.tolist()}, driving_turns={self.driving_turns})")

    def _check_positive(self):
        extremes = [0.0, 1.0] + [float(r.real) for r in self._dpoly.roots() if abs(r.imag) < 1e-12 and 0 < r.real < 1]
        if min(float(self._poly(s)) for s in extremes) > 0:
            return
        s = np.linspace(0.0, 1.0, 4001)
        bad = self._poly(s) <= 0
        where = self.q2 + s * self.span
        pieces = runs(bad)
        text = ", ".join(f"[{_deg(np.mod(where[a], TWO_PI))}, {_deg(np.mod(where[b], TWO_PI))}]" for a, b in pieces)
        raise SpecError([("coefficients", f"g = dτ/dq ≤ 0 on the transfer for crank angle q ∈ {text or 'a point'} "
                                          f"(a pitch radius would vanish): change the transfer coefficients")])

    # -- pieces -----------------------------------------------------------------------------------------------
    def _split(self, q):
        u = self.q1 + np.mod(np.asarray(q, dtype=float) - self.q1, TWO_PI)
        return u, u <= self.q2, (u - self.q2) / self.span

    def in_window(self, q) -> np.ndarray:
        """(...) bool: the crank inputs q (...) lie in the constant-speed window [q1, q2] (mod 2π)."""
        return self._split(q)[1]

    def g(self, q) -> np.ndarray:
        """g(q) = dτ/dq (motor rad per crank rad), (...) → (...)."""
        u, win, s = self._split(q)
        return np.where(win, self.k * self.direction * self.foot.dx(u), self._poly(s))

    def dg(self, q) -> np.ndarray:
        """dg/dq, (...) → (...), 1/rad."""
        u, win, s = self._split(q)
        return np.where(win, self.k * self.direction * self.foot.d2x(u), self._dpoly(s) / self.span)

    def d2g(self, q) -> np.ndarray:
        """d²g/dq², (...) → (...), 1/rad²."""
        u, win, s = self._split(q)
        return np.where(win, self.k * self.direction * self.foot.d3x(u), self._d2poly(s) / self.span ** 2)

    def _turn_integral(self, u):
        """∫_{q1}^{u} g for u ∈ [q1, q1 + 2π] (...): exact on both pieces."""
        u = np.asarray(u, dtype=float)
        win = u <= self.q2
        window = self.k * self.direction * (self.foot.x_at(np.minimum(u, self.q2)) - self.foot.x_at(self.q1))
        s = np.clip((u - self.q2) / self.span, 0.0, 1.0)
        return np.where(win, window, self._window_total + self.span * self._ipoly(s))

    def _raw_integral(self, q):
        q = np.asarray(q, dtype=float)
        j = np.floor((q - self.q1) / TWO_PI)
        return j * self.total + self._turn_integral(q - j * TWO_PI) - self._offset

    # -- motor and crank --------------------------------------------------------------------------------------
    def motor_angle(self, q) -> np.ndarray:
        """τ(q) = σ·∫₀^q g (rad), (...) → (...): τ(0) = 0 and τ grows by 2π·driving_turns per crank turn."""
        return self.sense * self._raw_integral(q)

    def crank_angle(self, tau) -> np.ndarray:
        """The inverse q(τ) (rad), (...) → (...), to round-off (Newton in a bracket on the exact τ(q))."""
        y = self.sense * np.asarray(tau, dtype=float) + self._offset
        j = np.floor(y / self.total)
        r = np.clip(y - j * self.total, 0.0, self.total)
        values, grid = self._table
        guess = np.interp(r, values, grid)
        u = invert_increasing(self._turn_integral, self.g, r, self.q1, self.q1 + TWO_PI, guess=guess)
        return u + j * TWO_PI

    def crank_rate(self, tau) -> np.ndarray:
        """dq/dτ = σ/g at motor angles τ (...) → (...)."""
        return self.sense / self.g(self.crank_angle(tau))

    def crank_accel(self, tau) -> np.ndarray:
        """d²q/dτ² = −g′/g³ at motor angles τ (...) → (...)."""
        q = self.crank_angle(tau)
        return -self.dg(q) / self.g(q) ** 3

    def window_speed(self, motor_speed: float = 1.0) -> float:
        """The foot's constant |v_x| on the window for a motor speed ω (rad/s): ω/k, m/s."""
        return abs(float(motor_speed)) / self.k

    def transmission_law(self) -> "CodesignTransmission":
        """The gear package's law (driving = motor φ = τ, driven = crank θ = σ·q), usable by
        :func:`~assur.gears.pitch.pitch_pair`. GearError unless driving_turns = 1 (a law that is not periodic in
        2π/n of crank angle cannot close the motor's pitch curve)."""
        return CodesignTransmission(self)


class CodesignTransmission(TransmissionLaw):
    """A :class:`CodesignLaw` as a :class:`~assur.gears.law.TransmissionLaw`: θ(φ) = σ·q(φ), k = dθ/dφ = 1/g.

    The explicit direction is exact (φ(θ) = τ(σθ), k(θ) = 1/g(σθ)); θ(φ) inverts it to round-off."""

    def __init__(self, law: CodesignLaw):
        if law.driving_turns != 1:
            raise GearError(f"a co-designed law with {law.driving_turns} motor turns per crank turn is not periodic "
                            f"over one motor turn, so the motor's pitch curve would not close: use driving_turns = 1")
        self.law = law
        self.driving_turns = 1
        self.description = (f"co-designed walking-leg law: constant foot speed over the central "
                            f"{law.fraction:g} of the stride")

    def __repr__(self):
        return f"CodesignTransmission({self.law!r})"

    def phi_of(self, theta) -> np.ndarray:
        return self.law.motor_angle(self.law.sense * np.asarray(theta, dtype=float))

    def ratio_of_theta(self, theta) -> np.ndarray:
        return 1.0 / self.law.g(self.law.sense * np.asarray(theta, dtype=float))

    def _turn_theta(self, u):
        return self.law.sense * self.law.crank_angle(u)

    def _turn_ratio(self, u):
        return 1.0 / self.law.g(self.law.crank_angle(u))


def motor_speed(foot: FootLaw, driving_turns: int = 1) -> float:
    """ω_m (rad/s) of a uniform motor driving the leg of ``foot`` through a pair of ``driving_turns`` motor turns per
    crank turn: the plan's crank speed (1 rad/s when it has none) times the turns, so the crank's mean speed is the
    plan's."""
    return driving_turns * (foot.omega if foot.omega > 0 else 1.0)


class _GearedFoot:
    """The geared leg's foot by the motor angle τ: its stride coordinate x and the derivatives dx/dτ and d|x|'/dτ,
    solved through the engine (the evaluator :func:`~assur.analysis.gait.window_vx_spread` refines with)."""

    def __init__(self, law: CodesignLaw, omega: float):
        self.law, self.omega = law, omega
        self.i = law.foot.plan.point_index(law.foot.foot)
        self.ground = np.asarray(law.foot.ground, dtype=float)

    def eval(self, tau) -> dict:
        """tau (n,) motor angles → {"x", "dx", "absdx", "dabsdx"} (n,) each: m, m/rad, m/rad, m/rad²."""
        law, omega = self.law, self.omega
        q = law.crank_angle(np.atleast_1d(np.asarray(tau, dtype=float)))
        g, dg = law.g(q), law.dg(q)
        state = solve(law.foot.plan, law.foot.params, q[:, None], speeds=(law.sense * omega / g)[:, None],
                      accels=(-(omega ** 2) * dg / g ** 3)[:, None], order=2)
        dx = state.vel[:, self.i, :] @ self.ground / omega
        d2x = state.acc[:, self.i, :] @ self.ground / omega ** 2
        return {"x": state.pos[:, self.i, :] @ self.ground, "dx": dx, "absdx": np.abs(dx),
                "dabsdx": np.sign(dx) * d2x}


def geared_vx_spread(law: CodesignLaw, *, samples: int = 4096, fractions=None) -> dict:
    """The foot's horizontal-speed spread of the geared leg in motor time, measured through the engine.

    The motor turns uniformly (ω = driving_turns·|crank speed| of the plan, so the crank's mean speed is the plan's):
    the leg is solved at q(τ) for ``samples`` uniform motor angles τ over its contact arc with speeds dq/dt = σω/g
    and accelerations d²q/dt² = −ω²g′/g³, and the spread is :func:`~assur.analysis.gait.window_vx_spread` of those
    samples (the window's ends and the extremes of |v_x| refined to round-off, the mean over motor time). Returns
    {"0.8": …, "0.9": …} and the law's own fraction (keys ``f"{f:g}"``)."""
    foot = law.foot
    if foot.plan is None:
        raise SpecError([("foot", "the foot law has no plan to solve (built from samples)")])
    evaluator = _GearedFoot(law, motor_speed(foot, law.driving_turns))
    ends = sorted(float(t) for t in law.motor_angle(np.array([foot.contact_start, foot.contact_end])))
    tau = np.linspace(ends[0], ends[1], int(samples))
    values = evaluator.eval(tau)
    critical = critical_points(evaluator, ("dabsdx", "dx"), tau, values)     # |v_x|'s extremes, once for every window
    critical = (critical, evaluator.eval(critical)["absdx"] if critical.size else np.empty(0))
    keys = sorted(set(VX_FRACTIONS if fractions is None else fractions) | {law.fraction})
    return {f"{f:g}": float(window_vx_spread(evaluator, tau, values, foot.x_min, foot.x_max, f, critical))
            for f in keys}


__all__ = ["CodesignLaw", "CodesignTransmission", "FootLaw", "TransferBasis", "bump_polynomials", "check_fraction",
           "foot_law", "foot_law_from_samples", "geared_vx_spread", "smooth_coefficients", "support_window",
           "transfer_basis"]
