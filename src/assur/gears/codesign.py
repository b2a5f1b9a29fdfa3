"""Co-design of a walking leg and the non-circular gear pair that drives its crank from a uniform motor
(assur issue 15, part 3): the foot's horizontal speed is exactly constant over the central fraction f of the stride.

The law and its notation: :mod:`assur.gears.codesign_law` (g(q) = dτ/dq, the window [q1, q2], the transfer bridge
g = k·H + Σ c_j·B_j, the closure, the crank's sense σ). The gear checks: :mod:`assur.gears.codesign_checks`. This
module adds the convenience :func:`codesign` (law + checks + the vx spread measured through the engine), the
constraint margins of the transfer coefficients (:class:`CodesignProblem`, reusable by a joint optimisation of the
linkage's dimensions), :func:`optimize_transfer` and :func:`tradeoff` (one row per window fraction, for a figure).

Margins (:data:`MARGIN_NAMES`, each ≥ 0 when met, dimensionless unless named): ``convex_driving`` and
``convex_driven`` min κ·L over each pitch curve; ``pressure_angle`` μ_max − max μ (rad); ``ratio_low`` g_min − lo,
``ratio_high`` hi − g_max; ``undercut_driving``/``undercut_driven`` 1 − (m/sin²α)·max|κ| (the module as given, not
yet adjusted to a whole tooth count). Convexity and pressure angle do not depend on L (r ∝ L, κ ∝ 1/L).

A bound no transfer can beat (:func:`window_pressure_bound`): on the window tan μ = |x″|/(x′·(1 + k·x′)) (x′ > 0
read along the stride), decreasing in k, and the closure with g > 0 on the transfer caps k < 2π·n/(f·stride).
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from ..errors import SpecError
from .codesign_checks import (GearChecks, check_angle, check_bounds, gear_checks, perimeter, pitch_terms,
                              ranges_text)
from .codesign_law import (CodesignLaw, CodesignTransmission, FootLaw, TransferBasis, check_fraction, foot_law,
                           foot_law_from_samples, geared_vx_spread, smooth_coefficients, support_window,
                           transfer_basis)

TWO_PI = 2.0 * math.pi

#: the entries of :meth:`CodesignProblem.margins`, in order
MARGIN_NAMES = ("convex_driving", "convex_driven", "pressure_angle", "ratio_low", "ratio_high", "undercut_driving",
                "undercut_driven")
#: default bounds of g = dτ/dq for the optimiser (motor rad per crank rad)
DEFAULT_RATIO_BOUNDS = (1.0 / 3.0, 3.0)
#: the margin vector of a coefficient set for which the law does not exist (k ≤ 0 or g ≤ 0 somewhere), offset by
#: how far it is from existing
_INVALID = -100.0


@dataclass(frozen=True)
class CodesignResult:
    """law: the :class:`CodesignLaw`; checks: its :class:`GearChecks`; vx_spread: the geared leg's horizontal-speed
    spread measured through the engine in motor time, {"0.8", "0.9", f"{fraction:g}"}."""
    law: CodesignLaw
    checks: GearChecks
    vx_spread: dict


def _positive_length(name, value):
    if isinstance(value, bool) or not isinstance(value, (int, float, np.floating, np.integer)) \
            or not np.isfinite(value) or value <= 0:
        raise SpecError([(name, f"must be a finite length > 0 m: {value!r}")])
    return float(value)


def codesign(plan, fraction: float = 0.8, *, centre_distance: float, module: float, coefficients=None,
             n_bumps: int = 4, params=None, pressure_angle: float = math.radians(20.0),
             max_pressure_angle: float = math.radians(30.0), ratio_bounds=None, samples: int = 4096,
             driving_turns: int = 1) -> CodesignResult:
    """The co-designed law of a walking leg (``plan`` with a ``[gait]`` foot, one crank) for the window ``fraction``
    of the stride, its gear checks at ``centre_distance`` (m) for a rack of ``module`` (m), and the vx spread of the
    geared leg measured through the engine (:func:`~assur.gears.codesign_law.geared_vx_spread`).

    coefficients: the transfer bumps' c (default: the smoothest bridge with ``n_bumps`` bumps)."""
    check_fraction(fraction)
    foot = foot_law(plan, params, samples=samples)
    law = CodesignLaw(foot, fraction, coefficients, n_bumps=n_bumps, driving_turns=driving_turns)
    checks = gear_checks(law, centre_distance, module=module, pressure_angle=pressure_angle,
                         max_pressure_angle=max_pressure_angle, ratio_bounds=ratio_bounds)
    return CodesignResult(law, checks, geared_vx_spread(law))


def window_pressure_bound(foot: FootLaw, fraction: float, *, driving_turns: int = 1, points: int = 4001) -> float:
    """A lower bound (rad) on the centrode pressure angle inside the window, whatever the transfer: max over the
    window of atan(|x″|/(x′·(1 + k_max·x′))) with k_max = 2π·n/(f·stride) (x′ taken positive along the stride)."""
    f = check_fraction(fraction)
    q1, q2 = support_window(foot, f)
    q = np.linspace(q1, q2, int(points))
    d1, d2 = np.abs(foot.dx(q)), np.abs(foot.d2x(q))
    k_max = TWO_PI * int(driving_turns) / (f * foot.stride)
    return float(np.max(np.arctan(d2 / (d1 * (1.0 + k_max * d1)))))


class CodesignProblem:
    """The constraint margins of the transfer coefficients c (n_bumps,) of a leg's co-designed law, fast (closed
    forms on fixed samples), for optimisers: :meth:`margins` (plan params, c) → (len(MARGIN_NAMES),), and the scalar
    :meth:`objective` of :func:`optimize_transfer`.

    The foot law is recomputed when ``params`` change (the last one is kept). Arguments as :func:`codesign`;
    ``points``: samples on the window and on the transfer each."""

    def __init__(self, plan, fraction: float, *, centre_distance: float, module: float, n_bumps: int = 4,
                 pressure_angle: float = math.radians(20.0), max_pressure_angle: float = math.radians(30.0),
                 ratio_bounds=DEFAULT_RATIO_BOUNDS, samples: int = 4096, points: int = 1024, driving_turns: int = 1):
        self.plan = plan
        self.fraction = check_fraction(fraction)
        self.centre_distance = _positive_length("centre_distance", centre_distance)
        self.module = _positive_length("module", module)
        self.pressure_angle = check_angle("pressure_angle", pressure_angle)
        self.max_pressure_angle = check_angle("max_pressure_angle", max_pressure_angle)
        self.ratio_bounds = check_bounds(ratio_bounds)
        if isinstance(n_bumps, bool) or not isinstance(n_bumps, (int, np.integer)) or n_bumps < 0:
            raise SpecError([("n_bumps", f"must be a whole number ≥ 0: {n_bumps!r}")])
        self.n_bumps = int(n_bumps)
        self.samples, self.points, self.driving_turns = int(samples), int(points), int(driving_turns)
        self.undercut_limit = self.module / math.sin(self.pressure_angle) ** 2
        self._key = None
        self._cache = None

    # -- per-leg precomputation ------------------------------------------------------------------------------
    def prepared(self, params=None) -> dict:
        """The foot law, window, basis and sampled basis values of the leg at ``params`` (kept for the last one)."""
        params = self.plan.defaults if params is None else np.asarray(params, dtype=float)
        key = params.tobytes()
        if key != self._key:
            foot = foot_law(self.plan, params, samples=self.samples)
            basis = transfer_basis(foot, support_window(foot, self.fraction), self.n_bumps)
            qw = np.linspace(basis.q1, basis.q2, self.points)
            s = np.linspace(0.0, 1.0, self.points)
            window = np.stack([basis.direction * foot.derivative(qw, order) for order in (1, 2, 3)])  # (3, P)
            hermite = np.stack([basis.hermite.deriv(order)(s) for order in (0, 1, 2)])               # (3, P)
            bumps = np.stack([np.stack([b.deriv(order)(s) for b in basis.bumps]) if basis.bumps
                              else np.zeros((0, s.size)) for order in (0, 1, 2)])                     # (3, nb, P)
            k0 = basis.closure_k(np.zeros(self.n_bumps), self.driving_turns)
            dk = np.array([basis.closure_k(np.eye(self.n_bumps)[j], self.driving_turns) - k0
                           for j in range(self.n_bumps)])
            scale = np.array([1.0, 1.0 / basis.span, 1.0 / basis.span ** 2])[:, None]
            self._cache = {"foot": foot, "basis": basis, "q": np.concatenate([qw, basis.q2 + s * basis.span]),
                           "window": window, "hermite": hermite * scale, "bumps": bumps * scale[:, None],
                           "k0": k0, "dk": dk}
            self._key = key
        return self._cache

    def default_coefficients(self, params=None) -> np.ndarray:
        """The smoothest bridge's coefficients (:func:`~assur.gears.codesign_law.smooth_coefficients`)."""
        return smooth_coefficients(self.prepared(params)["basis"], self.driving_turns)

    def ratio_samples(self, coefficients, params=None):
        """(k, g (3, 2P)): g, g′, g″ on the window samples then the transfer samples."""
        p = self.prepared(params)
        c = np.asarray(coefficients, dtype=float).reshape(-1)
        if c.size != self.n_bumps:
            raise SpecError([("coefficients", f"need {self.n_bumps} values (n_bumps): {c.size} given")])
        k = p["k0"] + float(p["dk"] @ c)
        transfer = k * p["hermite"] + np.einsum("j,ojp->op", c, p["bumps"])
        return k, np.concatenate([k * p["window"], transfer], axis=1)

    def margins(self, coefficients, params=None) -> np.ndarray:
        """(7,) the margins of :data:`MARGIN_NAMES` (≥ 0 met) for the coefficients c (n_bumps,) and the leg's
        ``params`` (default the plan's). A law that does not exist (k ≤ 0 or g ≤ 0) gives every margin
        −100 + min(k, min g) (≤ −100)."""
        k, (g, dg, d2g) = self.ratio_samples(coefficients, params)
        g_min = float(g.min())
        if not (k > 0 and g_min > 0):
            return np.full(len(MARGIN_NAMES), _INVALID + min(k, g_min))
        t = pitch_terms(g, dg, d2g, self.centre_distance)
        L = self.centre_distance
        lo, hi = self.ratio_bounds
        return np.array([float(t["kappa_driving"].min() * L), float(t["kappa_driven"].min() * L),
                         self.max_pressure_angle - float(np.arctan(t["tan_pressure"]).max()),
                         g_min - lo, hi - float(g.max()),
                         1.0 - self.undercut_limit * float(np.abs(t["kappa_driving"]).max()),
                         1.0 - self.undercut_limit * float(np.abs(t["kappa_driven"]).max())])

    def objective(self, coefficients, params=None) -> float:
        """Scalar to minimise: the total violation V = Σ max(0, −margin) + the mean concave depth of both curves
        (mean of max(0, −κ·L)) when V > 0, else −min(margins) (the worst margin, maximised)."""
        m = self.margins(coefficients, params)
        if m[0] <= _INVALID + 1.0 and np.all(m == m[0]):
            return float(1e3 - m[0])
        k, (g, dg, d2g) = self.ratio_samples(coefficients, params)
        t = pitch_terms(g, dg, d2g, self.centre_distance)
        depth = sum(float(np.mean(np.maximum(0.0, -t[f"kappa_{n}"] * self.centre_distance)))
                    for n in ("driving", "driven"))
        violation = float(np.sum(np.maximum(0.0, -m))) + depth
        return violation if violation > 0 else -float(np.min(m))


@dataclass(frozen=True)
class TransferDesign:
    """Result of :func:`optimize_transfer`: the law with the chosen coefficients, its checks (``checks.ok`` is the
    success), the margins (name → value), the objective, the optimiser's message and evaluation count."""
    law: CodesignLaw
    checks: GearChecks
    coefficients: np.ndarray
    margins: dict
    objective: float
    success: bool
    message: str
    evaluations: int
    vx_spread: dict = field(default_factory=dict)


def optimize_transfer(plan, fraction: float = 0.8, *, centre_distance: float, module: float,
                      pressure_angle: float = math.radians(20.0), max_pressure_angle: float = math.radians(30.0),
                      ratio_bounds=DEFAULT_RATIO_BOUNDS, n_bumps: int = 6, seed: int | None = 0, params=None,
                      spread: float = 6.0, maxiter: int = 300, popsize: int = 20, samples: int = 4096,
                      measure: bool = True) -> TransferDesign:
    """Choose the transfer coefficients c (n_bumps,) so that both pitch curves are convex (or least concave), the
    centrode pressure angle ≤ ``max_pressure_angle``, g within ``ratio_bounds`` and no undercut for ``module``
    (:meth:`CodesignProblem.objective`, by scipy's differential evolution over c ∈ c_smooth ± ``spread``, seeded,
    starting from the smoothest bridge, then polished). ``success`` = the final :func:`gear_checks` pass (with the
    module adjusted to a whole tooth count). ``measure``: also measure the geared leg's vx spread (engine)."""
    from scipy.optimize import differential_evolution
    problem = CodesignProblem(plan, fraction, centre_distance=centre_distance, module=module, n_bumps=n_bumps,
                              pressure_angle=pressure_angle, max_pressure_angle=max_pressure_angle,
                              ratio_bounds=ratio_bounds, samples=samples)
    if not (np.isfinite(spread) and spread > 0):
        raise SpecError([("spread", f"must be a positive number: {spread!r}")])
    prep = problem.prepared(params)
    c0 = problem.default_coefficients(params)
    if problem.n_bumps == 0:
        best, message, evaluations = c0, "no bumps: the Hermite bridge alone", 1
    else:
        bounds = [(c - spread, c + spread) for c in c0]
        res = differential_evolution(lambda c: problem.objective(c, params), bounds, x0=c0, seed=seed,
                                     maxiter=int(maxiter), popsize=int(popsize), tol=1e-10, polish=True)
        best = res.x if res.fun <= problem.objective(c0, params) else c0
        message, evaluations = str(res.message), int(res.nfev)
    law = CodesignLaw(prep["foot"], problem.fraction, best, driving_turns=problem.driving_turns)
    checks = gear_checks(law, problem.centre_distance, module=problem.module, pressure_angle=problem.pressure_angle,
                         max_pressure_angle=problem.max_pressure_angle, ratio_bounds=ratio_bounds)
    margins = dict(zip(MARGIN_NAMES, problem.margins(best, params).tolist()))
    return TransferDesign(law, checks, np.asarray(best, dtype=float), margins, problem.objective(best, params),
                          checks.ok, message, evaluations, geared_vx_spread(law) if measure else {})


def tradeoff(plan, fractions=(0.6, 0.7, 0.8, 0.85, 0.9, 0.95), *, centre_distance: float, module: float,
             **options) -> list[dict]:
    """For each window fraction: the best transfer (:func:`optimize_transfer`, ``options`` passed on) and what it
    reaches — rows {"fraction", "success", "convexity" (min κ·L over both curves), "max_pressure_angle" (deg),
    "pressure_bound" (deg, :func:`window_pressure_bound`: no transfer gets below it), "ratio_min", "ratio_max",
    "teeth", "k", "vx_spread_0.8", "vx_spread_0.9", "violations"}, or {"fraction", "error"} where the window itself
    does not exist (x not monotone there)."""
    rows = []
    for f in fractions:
        try:
            d = optimize_transfer(plan, f, centre_distance=centre_distance, module=module, **options)
        except SpecError as exc:
            rows.append({"fraction": float(f), "error": str(exc)})
            continue
        c = d.checks
        bound = window_pressure_bound(d.law.foot, f, driving_turns=d.law.driving_turns)
        rows.append({"fraction": float(f), "success": d.success, "convexity": min(c.convexity.values()),
                     "max_pressure_angle": math.degrees(c.max_pressure_angle), "pressure_bound": math.degrees(bound),
                     "ratio_min": c.ratio_min,
                     "ratio_max": c.ratio_max, "teeth": c.teeth, "k": d.law.k,
                     "vx_spread_0.8": d.vx_spread.get("0.8", math.nan),
                     "vx_spread_0.9": d.vx_spread.get("0.9", math.nan), "violations": list(c.violations)})
    return rows


__all__ = ["MARGIN_NAMES", "CodesignLaw", "CodesignProblem", "CodesignResult", "CodesignTransmission", "FootLaw",
           "GearChecks", "TransferBasis", "TransferDesign", "codesign", "foot_law", "foot_law_from_samples",
           "gear_checks", "geared_vx_spread", "optimize_transfer", "perimeter", "pitch_terms", "ranges_text",
           "smooth_coefficients", "support_window", "tradeoff", "transfer_basis", "window_pressure_bound"]
