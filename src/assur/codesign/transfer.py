"""Co-design of a walking leg and the non-circular gear pair that drives its crank from a uniform motor
(assur issue 15, part 3): the foot's horizontal speed is exactly constant over the central fraction f of the stride.

The law and its notation: :mod:`assur.codesign.law` (g(q) = dτ/dq, the window [q1, q2], the transfer bridge
g = k·H + Σ c_j·B_j, the closure, the crank's sense σ). The gear checks: :mod:`assur.codesign.checks`; their fast
margins on fixed samples: :mod:`assur.codesign.margins`. This module adds the convenience :func:`codesign` (law +
checks + the vx spread measured through the engine), the constraint margins of the transfer coefficients
(:class:`CodesignProblem`, reusable by the joint optimisation of the linkage's dimensions,
:mod:`assur.codesign.joint`), :func:`optimize_transfer` and :func:`tradeoff` (one row per window fraction, for a
figure). A torque limit (``max_torque``, N·m) adds the margin ``torque`` (:mod:`assur.codesign.torque`) and the
check that the finished design's peak motor torque stays below it.

A bound no transfer can beat (:func:`window_pressure_bound`): on the window tan μ = |x″|/(x′·(1 + k·x′)) (x′ > 0
read along the stride), decreasing in k, and the closure with g > 0 on the transfer caps k < 2π·n/(f·stride).
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from ..errors import SpecError
from .checks import GearChecks, check_angle, check_bounds, check_bumps, check_length, gear_checks
from .law import CodesignLaw, FootLaw, check_fraction, foot_law, geared_vx_spread, motor_speed, \
    smooth_coefficients, support_window, transfer_basis
from .margins import MARGIN_NAMES, TransferMargins, check_spread, search_transfer

TWO_PI = 2.0 * math.pi

#: default bounds of g = dτ/dq for the optimiser (motor rad per crank rad)
DEFAULT_RATIO_BOUNDS = (1.0 / 3.0, 3.0)


@dataclass(frozen=True)
class CodesignResult:
    """law: the :class:`CodesignLaw`; checks: its :class:`GearChecks`; vx_spread: the geared leg's horizontal-speed
    spread measured through the engine in motor time, {"0.8", "0.9", f"{fraction:g}"}."""
    law: CodesignLaw
    checks: GearChecks
    vx_spread: dict


def codesign(plan, fraction: float = 0.8, *, centre_distance: float, module: float, coefficients=None,
             n_bumps: int = 4, params=None, pressure_angle: float = math.radians(20.0),
             max_pressure_angle: float = math.radians(30.0), ratio_bounds=None, samples: int = 4096,
             driving_turns: int = 1, max_torque: float | None = None) -> CodesignResult:
    """The co-designed law of a walking leg (``plan`` with a ``[gait]`` foot, one crank) for the window ``fraction``
    of the stride, its gear checks at ``centre_distance`` (m) for a rack of ``module`` (m) (and the motor torque
    against ``max_torque``, N·m, when given), and the vx spread of the geared leg measured through the engine
    (:func:`~assur.codesign.law.geared_vx_spread`).

    coefficients: the transfer bumps' c (default: the smoothest bridge with ``n_bumps`` bumps)."""
    check_fraction(fraction)
    foot = foot_law(plan, params, samples=samples)
    law = CodesignLaw(foot, fraction, coefficients, n_bumps=n_bumps, driving_turns=driving_turns)
    checks = gear_checks(law, centre_distance, module=module, pressure_angle=pressure_angle,
                         max_pressure_angle=max_pressure_angle, ratio_bounds=ratio_bounds, max_torque=max_torque)
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
    forms on fixed samples, :class:`~assur.codesign.margins.TransferMargins`), for optimisers: :meth:`margins`
    (plan params, c) → (len(:attr:`margin_names`),), and the scalar :meth:`objective` of :func:`optimize_transfer`.

    The foot law is recomputed when ``params`` change (the last one is kept). Arguments as :func:`codesign`;
    ``points``: samples on the window and on the transfer each; ``max_torque`` (N·m): the margin ``torque``,
    1 − peak/limit, of the peak motor torque over those samples against the limit less
    :data:`~assur.codesign.torque.SEARCH_SAFETY` (:mod:`assur.codesign.torque`; the leg solved for its crank torque
    once per ``params``)."""

    def __init__(self, plan, fraction: float, *, centre_distance: float, module: float, n_bumps: int = 4,
                 pressure_angle: float = math.radians(20.0), max_pressure_angle: float = math.radians(30.0),
                 ratio_bounds=DEFAULT_RATIO_BOUNDS, samples: int = 4096, points: int = 1024, driving_turns: int = 1,
                 max_torque: float | None = None):
        self.plan = plan
        self.fraction = check_fraction(fraction)
        self.centre_distance = check_length("centre_distance", centre_distance)
        self.module = check_length("module", module)
        self.pressure_angle = check_angle("pressure_angle", pressure_angle)
        self.max_pressure_angle = check_angle("max_pressure_angle", max_pressure_angle)
        self.ratio_bounds = check_bounds(ratio_bounds)
        self.n_bumps = check_bumps(n_bumps)
        self.samples, self.points, self.driving_turns = int(samples), int(points), int(driving_turns)
        self.undercut_limit = self.module / math.sin(self.pressure_angle) ** 2
        self.max_torque = None
        if max_torque is not None:
            from .torque import check_max_torque
            self.max_torque = check_max_torque(max_torque, plan)
        self._key = None
        self._cache = None

    @property
    def margin_names(self) -> tuple:
        """The names of :meth:`margins`' entries: :data:`~assur.codesign.margins.MARGIN_NAMES` (+ ``"torque"``)."""
        return MARGIN_NAMES + (("torque",) if self.max_torque is not None else ())

    # -- per-leg precomputation ------------------------------------------------------------------------------
    def prepared(self, params=None) -> dict:
        """The foot law, window, basis and the :class:`~assur.codesign.margins.TransferMargins` of the leg at
        ``params`` (kept for the last one): {"foot", "basis", "q" (2P,) the sample crank angles, "margins"}."""
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
            q = np.concatenate([qw, basis.q2 + s * basis.span])
            margins = TransferMargins(window, hermite * scale, bumps * scale[:, None], k0, dk,
                                      centre_distance=self.centre_distance, undercut_limit=self.undercut_limit,
                                      max_pressure_angle=self.max_pressure_angle, ratio_bounds=self.ratio_bounds,
                                      torque=self._torque(foot, params, q), torque_limit=self._search_limit())
            self._cache = {"foot": foot, "basis": basis, "q": q, "margins": margins}
            self._key = key
        return self._cache

    def _search_limit(self):
        """The limit the margin ``torque`` holds the sampled peak to: a hair inside ``max_torque``
        (:data:`~assur.codesign.torque.SEARCH_SAFETY`), so the refined peak of the design stays within it."""
        if self.max_torque is None:
            return None
        from .torque import SEARCH_SAFETY
        return self.max_torque * (1.0 - SEARCH_SAFETY)

    def _torque(self, foot, params, q):
        """(g, g′, g″) on the samples q → peak motor torque (N·m), or None without a limit."""
        if self.max_torque is None:
            return None
        from .torque import crank_torque_terms, motor_torque
        terms = crank_torque_terms(self.plan, params, q)
        omega = motor_speed(foot, self.driving_turns)
        return lambda g, dg, d2g: float(np.max(np.abs(motor_torque(terms, g, dg, omega, foot.sense))))

    def default_coefficients(self, params=None) -> np.ndarray:
        """The smoothest bridge's coefficients (:func:`~assur.codesign.law.smooth_coefficients`)."""
        return smooth_coefficients(self.prepared(params)["basis"], self.driving_turns)

    def _coefficients(self, coefficients) -> np.ndarray:
        c = np.asarray(coefficients, dtype=float).reshape(-1)
        if c.size != self.n_bumps:
            raise SpecError([("coefficients", f"need {self.n_bumps} values (n_bumps): {c.size} given")])
        return c

    def ratio_samples(self, coefficients, params=None):
        """(k, g (3, 2P)): g, g′, g″ on the window samples then the transfer samples."""
        return self.prepared(params)["margins"].ratio_samples(self._coefficients(coefficients))

    def margins(self, coefficients, params=None) -> np.ndarray:
        """The margins of :attr:`margin_names` (≥ 0 met) for the coefficients c (n_bumps,) and the leg's ``params``
        (default the plan's). A law that does not exist (k ≤ 0 or g ≤ 0) gives every margin −100 + min(k, min g)
        (≤ −100)."""
        return self.prepared(params)["margins"].margins(self._coefficients(coefficients))

    def objective(self, coefficients, params=None) -> float:
        """Scalar to minimise (:meth:`~assur.codesign.margins.TransferMargins.objective`): the total violation and
        the mean concave depth of both curves while something fails, else −(the worst margin)."""
        return self.prepared(params)["margins"].objective(self._coefficients(coefficients))


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
                      measure: bool = True, max_torque: float | None = None) -> TransferDesign:
    """Choose the transfer coefficients c (n_bumps,) so that both pitch curves are convex (or least concave), the
    centrode pressure angle ≤ ``max_pressure_angle``, g within ``ratio_bounds``, no undercut for ``module`` and,
    with ``max_torque`` (N·m), the peak motor torque within it (:meth:`CodesignProblem.objective`, by scipy's
    differential evolution over c ∈ c_smooth ± ``spread``, seeded, starting from the smoothest bridge, then
    polished). ``success`` = the final :func:`~assur.codesign.checks.gear_checks` pass (with the module adjusted to
    a whole tooth count, and the torque's peak refined between samples): a design that breaks the torque limit is
    not a success, its violation names the peak and where. ``measure``: also measure the geared leg's vx spread
    (engine)."""
    problem = CodesignProblem(plan, fraction, centre_distance=centre_distance, module=module, n_bumps=n_bumps,
                              pressure_angle=pressure_angle, max_pressure_angle=max_pressure_angle,
                              ratio_bounds=ratio_bounds, samples=samples, max_torque=max_torque)
    spread = check_spread(spread)
    prep = problem.prepared(params)
    c0 = problem.default_coefficients(params)
    if problem.n_bumps == 0:
        best, message, evaluations = c0, "no bumps: the Hermite bridge alone", 1
    else:
        best, message, evaluations = search_transfer(lambda c: problem.objective(c, params), c0, spread=spread,
                                                     seed=seed, maxiter=maxiter, popsize=popsize)
    law = CodesignLaw(prep["foot"], problem.fraction, best, driving_turns=problem.driving_turns)
    checks = gear_checks(law, problem.centre_distance, module=problem.module, pressure_angle=problem.pressure_angle,
                         max_pressure_angle=problem.max_pressure_angle, ratio_bounds=ratio_bounds,
                         max_torque=problem.max_torque)
    margins = dict(zip(problem.margin_names, problem.margins(best, params).tolist()))
    return TransferDesign(law, checks, np.asarray(best, dtype=float), margins, problem.objective(best, params),
                          checks.ok, message, evaluations, geared_vx_spread(law) if measure else {})


def tradeoff(plan, fractions=(0.6, 0.7, 0.8, 0.85, 0.9, 0.95), *, centre_distance: float, module: float,
             **options) -> list[dict]:
    """For each window fraction: the best transfer (:func:`optimize_transfer`, ``options`` passed on) and what it
    reaches — rows {"fraction", "success", "convexity" (min κ·L over both curves), "max_pressure_angle" (deg),
    "pressure_bound" (deg, :func:`window_pressure_bound`: no transfer gets below it), "ratio_min", "ratio_max",
    "teeth", "k", "vx_spread_0.8", "vx_spread_0.9", "violations"} (and "torque_peak", N·m, with a torque limit),
    or {"fraction", "error"} where the window itself does not exist (x not monotone there)."""
    rows = []
    for f in fractions:
        try:
            d = optimize_transfer(plan, f, centre_distance=centre_distance, module=module, **options)
        except SpecError as exc:
            if any(path == "max_torque" for path, _ in exc.problems):
                raise
            rows.append({"fraction": float(f), "error": str(exc)})
            continue
        c = d.checks
        bound = window_pressure_bound(d.law.foot, f, driving_turns=d.law.driving_turns)
        row = {"fraction": float(f), "success": d.success, "convexity": min(c.convexity.values()),
               "max_pressure_angle": math.degrees(c.max_pressure_angle), "pressure_bound": math.degrees(bound),
               "ratio_min": c.ratio_min,
               "ratio_max": c.ratio_max, "teeth": c.teeth, "k": d.law.k,
               "vx_spread_0.8": d.vx_spread.get("0.8", math.nan),
               "vx_spread_0.9": d.vx_spread.get("0.9", math.nan), "violations": list(c.violations)}
        if c.torque_peak is not None:
            row["torque_peak"] = c.torque_peak
        rows.append(row)
    return rows


__all__ = ["DEFAULT_RATIO_BOUNDS", "MARGIN_NAMES", "CodesignProblem", "CodesignResult", "TransferDesign",
           "codesign", "optimize_transfer", "tradeoff", "window_pressure_bound"]
