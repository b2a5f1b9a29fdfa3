"""Paper 001 revisited (assur issue 15): the wheel-step mover's gear drive redesigned with the co-design law of
:mod:`assur.gears.codesign_law`, so that the pitch curves have no corners.

The paper (docs/papers/001.md B2) makes the mover's horizontal speed constant over the **whole** step: the driving
angle ψ is proportional to the mover's displacement X(θ) (θ the hub angle, one step θ ∈ [−π/4, π/4]) and the law is
continued step by step, so dψ/dθ = K·X′(θ) has a kink at every step end and the pitch curves have corners there
(79.55° tangent jumps for the printed design, :class:`~assur.gears.law.WheelStepLaw`). Here the speed is exactly
constant over the central fraction f of each step's displacement (the window) and a C² transfer joins the windows
across the step ends (the co-design law's Hermite bridge + bumps): no kink, no corner.

Mapping onto the co-design machinery, whose "crank" q makes one turn per window + transfer and whose "motor" τ
turns ``driving_turns`` = 1 times per crank turn (g(q) = dτ/dq, ∫ g over a crank turn = 2π):

- one hub step ↔ one crank turn: q = S·θ + π (S = 4 steps per hub turn), so q = 0 and 2π are the step ends
  θ = ∓π/4, q = π the step centre θ = 0; the "foot" stride coordinate is the mover's displacement within the step,
  x(q) = X(θ) = (a − b + c)·θ + 1.5·b·sin 2θ ∈ [−X_01/2, X_01/2] (:meth:`assur.gears.wheelstep.Shoe.displacement`),
  evaluated exactly (not a spline: :class:`StepDisplacement`); the whole step is the support (contact arc
  [0, 2π]); the window is the central fraction f of X_01 (:func:`~assur.gears.codesign_law.support_window`), the
  transfer the rest of the step near its two ends, where the paper has its corners;
- the real driving gear turns n = ``driving_turns`` times per hub turn (the paper: n = 2), i.e. n/S turns per
  step: ψ = (n/S)·(τ(q) − τ(π)), so ψ = 0 at the step centre (the paper's zero: the driver's smallest radius) and
  one driving turn is S/n whole steps (n ∈ {1, 2, 4}, as for WheelStepLaw);
- the gear package's law (driving ψ, driven θ) then has k = dθ/dψ = 1/G with G(θ) = dψ/dθ = n·g(q), and
  dG/dθ = n·S·g′(q), d²G/dθ² = n·S²·g″(q). On the window G = (n·k_c/S)·X′(θ) (k_c the co-design constant): the
  mover speed dX/dt = X′·θ̇ = ω_ψ·X′/G = ω_ψ·S/(n·k_c) is exactly constant.

Pitch curves at centre distance L: driving r1 = L/(1 + G), driven r2 = L·G/(1 + G); the closed-form checks of
:func:`assur.gears.codesign_checks.pitch_terms` apply with G and its θ-derivatives in place of g (the hub angle is
the "crank" angle of that module with one crank turn per hub turn). One step covers every distinct stretch of both
curves (the driven curve is S identical quarters, the driving curve S/n identical parts). With u = 1/r the polar
convexity test u″ + u > 0 reads d²k/dθ² + k + 1 > 0 for the driven curve (u2 = (1 + k)/L) and d²G/dψ² + G + 1 > 0
for the driving one: across the transfer dk/dθ must turn from +|X″|/(K·X′²) at one window edge to its negative at
the next, which a narrow transfer (a wide window) cannot do without a concave stretch of the hub gear.

The mover speed is measured independently of the law's construction (:func:`mover_speed`): from the exact pitch
curves of :func:`~assur.gears.pitch.pitch_pair` (θ̇/ψ̇ = r1/r2 at the pitch point) and the shoe's displacement rate
X′(θ) (:meth:`~assur.gears.wheelstep.Shoe.displacement_rate`), as :meth:`WheelStepLaw.mover_speed_ratio` does.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from ..analysis.gait import central_vx_spread
from ..errors import GearError, SpecError
from .codesign_checks import check_angle, check_bounds, curve_findings, pitch_terms
from .codesign_law import CodesignLaw, FootLaw, check_fraction, smooth_coefficients, support_window, transfer_basis
from .law import TransmissionLaw, WheelStepLaw
from .pitch import find_corners, pitch_pair
from .wheelstep import STEP_HALF_ANGLE, Shoe

TWO_PI = 2.0 * math.pi
#: hub steps per hub turn (a step is 2·STEP_HALF_ANGLE = 90° of hub angle)
STEPS = int(round(math.pi / STEP_HALF_ANGLE))
#: the window fractions of the comparison (the mover speed spread is reported over these central fractions)
SPREAD_FRACTIONS = (0.8, 0.9)


def _check_turns(driving_turns) -> int:
    if isinstance(driving_turns, bool) or driving_turns not in (1, 2, 4):
        raise SpecError([("driving_turns", f"must be 1, 2 or 4 (driving-gear turns per hub turn, so that one "
                                           f"driving turn is a whole number of 90° hub steps): {driving_turns!r}")])
    return int(driving_turns)


def _positive(name, value) -> float:
    if isinstance(value, bool) or not isinstance(value, (int, float, np.floating, np.integer)) \
            or not np.isfinite(value) or value <= 0:
        raise SpecError([(name, f"must be a finite length > 0 m: {value!r}")])
    return float(value)


# ---------------------------------------------------------------------------------------------------------------
# the mover's displacement as the co-design "foot"


class StepDisplacement:
    """The mover's displacement within one hub step as an exact function of the co-design crank angle:
    x(q) = X((q − π)/S), q ∈ [0, 2π) (the step θ ∈ [−π/4, π/4)), with X(θ) = A·θ + 1.5·b·sin 2θ, A = a − b + c
    (docs/papers/001.md B2). Called as ``spline(q, order)`` by :class:`~assur.gears.codesign_law.FootLaw`:
    q (...) → d^order x/dq^order (...), m/rad^order, order 0 … 4."""

    def __init__(self, shoe: Shoe):
        self.shoe = shoe

    def __call__(self, q, order: int = 0):
        theta = (np.asarray(q, dtype=float) - math.pi) / STEPS
        if order == 0:
            return self.shoe.displacement(theta, periodic=False)
        if order == 1:
            rate = self.shoe.displacement_rate(theta, periodic=False)
        else:   # d^o/dθ^o of 1.5·b·sin 2θ = 1.5·b·2^o·sin(2θ + o·π/2)
            rate = 1.5 * self.shoe.b * 2.0 ** order * np.sin(2.0 * theta + order * math.pi / 2.0)
        return rate / STEPS ** order


def step_foot(shoe: Shoe, samples: int = 256) -> FootLaw:
    """The co-design :class:`~assur.gears.codesign_law.FootLaw` of the mover over one hub step (module docstring):
    exact x(q) (:class:`StepDisplacement`), contact arc = the whole step [0, 2π], stride ends ∓X_01/2; ``samples``
    (N,) uniform values are stored for reference only."""
    exact = StepDisplacement(shoe)
    q = np.linspace(0.0, TWO_PI, int(samples), endpoint=False)
    half = 0.5 * shoe.budget.total
    return FootLaw(q, exact(q), exact, 0.0, TWO_PI, -half, half)


# ---------------------------------------------------------------------------------------------------------------
# the law of the gear pair


class WheelStepCodesignLaw(TransmissionLaw):
    """The redesigned wheel-step law as a :class:`~assur.gears.law.TransmissionLaw` (driving ψ, driven = hub θ):
    ψ(θ) = (n/S)·(τ(Sθ + π) − τ(π)) from a co-design law τ(q) over one step (module docstring).

    Attributes: ``codesign`` (the :class:`CodesignLaw`), ``shoe``, ``driving_turns`` n, ``fraction`` f,
    ``window`` (θ1, θ2): the hub angles of the window's ends in the step around θ = 0 (rad)."""

    def __init__(self, codesign: CodesignLaw, shoe: Shoe, driving_turns: int = 2):
        if codesign.driving_turns != 1 or codesign.sense != 1:
            raise GearError("the wheel-step co-design law needs one motor turn per step and a forward crank")
        self.codesign = codesign
        self.shoe = shoe
        self.driving_turns = _check_turns(driving_turns)
        self.fraction = codesign.fraction
        self.window = ((codesign.q1 - math.pi) / STEPS, (codesign.q2 - math.pi) / STEPS)
        self._centre = float(codesign.motor_angle(math.pi))
        self.description = (f"wheel-step law (paper 001) redesigned: constant mover speed over the central "
                            f"{self.fraction:g} of each step, C² transfer across the step ends")

    def __repr__(self):
        return f"WheelStepCodesignLaw({self.codesign!r}, driving_turns={self.driving_turns})"

    def _q(self, theta):
        return STEPS * np.asarray(theta, dtype=float) + math.pi

    def ratio_terms(self, theta):
        """(G, dG/dθ, d²G/dθ²) at hub angles θ (...) → three (...) arrays; G = dψ/dθ = 1/k."""
        q, n = self._q(theta), self.driving_turns
        return (n * self.codesign.g(q), n * STEPS * self.codesign.dg(q), n * STEPS ** 2 * self.codesign.d2g(q))

    def in_window(self, theta) -> np.ndarray:
        """(...) bool: the hub angles θ (...) lie in a constant-speed window."""
        return self.codesign.in_window(self._q(theta))

    def phi_of(self, theta) -> np.ndarray:
        return (self.driving_turns / STEPS) * (self.codesign.motor_angle(self._q(theta)) - self._centre)

    def ratio_of_theta(self, theta) -> np.ndarray:
        return 1.0 / (self.driving_turns * self.codesign.g(self._q(theta)))

    def _hub(self, u):
        return (self.codesign.crank_angle(STEPS * np.asarray(u, dtype=float) / self.driving_turns + self._centre)
                - math.pi) / STEPS

    def _turn_theta(self, u):
        return self._hub(u)

    def _turn_ratio(self, u):
        return self.ratio_of_theta(self._hub(u))

    def corner_thetas(self) -> np.ndarray:
        """No kinks: (0,)."""
        return np.empty(0)


def paper_ratio_terms(law: WheelStepLaw, theta):
    """(G, G′, G″) of the paper's law (unrounded) at hub angles θ (...), each step's closed form (one-sided at the
    step ends): G = dψ/dθ = K·X′(θ), K = n·π/(2·X_01) (docs/papers/001.md B2), X′ = A + 3b·cos 2u, u the angle
    from the step centre."""
    if law.rounding > 0:
        raise GearError("paper_ratio_terms needs the paper's law (rounding = 0)")
    theta = np.asarray(theta, dtype=float)
    u = theta - np.round(theta / (2.0 * STEP_HALF_ANGLE)) * 2.0 * STEP_HALF_ANGLE
    shoe = law.shoe
    K = law.driving_turns * math.pi / (2.0 * shoe.budget.total)
    b = shoe.b
    return (K * shoe.displacement_rate(u, periodic=False), -6.0 * K * b * np.sin(2.0 * u),
            -12.0 * K * b * np.cos(2.0 * u))


def window_pressure_bound(shoe: Shoe, fraction: float, *, driving_turns: int = 2, points: int = 4001) -> float:
    """A lower bound (rad) on the centrode pressure angle inside the window, whatever the transfer: on the window
    tan μ = |X″|/(X′·(1 + K·X′)) (G = K·X′), decreasing in K, and the closure with G > 0 on the transfer caps
    K < n·π/(2·f·X_01) (the window alone takes less than the step's n·π/2 of driving angle)."""
    f = check_fraction(fraction)
    n = _check_turns(driving_turns)
    foot = step_foot(shoe)
    q1, q2 = support_window(foot, f)
    theta = (np.linspace(q1, q2, int(points)) - math.pi) / STEPS
    k_max = n * math.pi / (2.0 * f * shoe.budget.total)
    d1 = shoe.displacement_rate(theta, periodic=False)
    d2 = np.abs(6.0 * shoe.b * np.sin(2.0 * theta))
    return float(np.max(np.arctan(d2 / (d1 * (1.0 + k_max * d1)))))


def _terms(law, theta):
    if isinstance(law, WheelStepCodesignLaw):
        return law.ratio_terms(theta)
    if isinstance(law, WheelStepLaw):
        return paper_ratio_terms(law, theta)
    raise GearError(f"a wheel-step law is needed (WheelStepCodesignLaw or WheelStepLaw): {law!r}")


# ---------------------------------------------------------------------------------------------------------------
# gear checks


@dataclass(frozen=True)
class WheelStepGearChecks:
    """Checks of the driving/driven pitch curves of a wheel-step law over one step (hub angles θ, rad; radii m).

    convexity: {"driving", "driven"}: min κ·L (≥ 0 convex; at the paper's step ends the one-sided value, its corners
    themselves are reported by :func:`max_tangent_jump`); concave: {"driving", "driven"}: [(θ_from, θ_to)];
    ratio_min/max: of G = dψ/dθ; teeth (driving, driven): the nearest counts with n·z1 = z2 and z2 a multiple of S
    (every step carries the same whole number of teeth), module = driving perimeter/(π·z1)."""
    centre_distance: float
    module_requested: float
    pressure_angle: float
    driving_turns: int
    driving_teeth: int
    driven_teeth: int
    module: float
    driving_perimeter: float
    driven_perimeter: float
    ratio_min: float
    ratio_max: float
    radius_driving: tuple
    radius_driven: tuple
    max_pressure_angle: float
    max_pressure_angle_at: float
    convexity: dict
    concave: dict
    min_curvature_radius: dict
    undercut_limit: float
    violations: list = field(default_factory=list)

    @property
    def ok(self) -> bool:
        return not self.violations


def wheelstep_gear_checks(law, centre_distance: float, *, module: float, pressure_angle: float = math.radians(20.0),
                          max_pressure_angle: float = math.radians(30.0), ratio_bounds=None,
                          points: int = 8192) -> WheelStepGearChecks:
    """Convexity of both pitch curves, centrode pressure angle ≤ ``max_pressure_angle``, G = dψ/dθ within
    ``ratio_bounds`` (optional), no undercut (|ρ| ≥ m/sin²α on both curves, concave stretches included, as
    :func:`~assur.gears.pitch.curvature_report`) with the module adjusted to the tooth counts, for a
    :class:`WheelStepCodesignLaw` or the paper's :class:`~assur.gears.law.WheelStepLaw` at ``centre_distance`` (m).
    Sampled at ``points`` hub angles over one step (plus the window's joints); perimeters by
    :func:`driven_perimeter`."""
    L = _positive("centre_distance", centre_distance)
    m = _positive("module", module)
    alpha = check_angle("pressure_angle", pressure_angle)
    mu_max = check_angle("max_pressure_angle", max_pressure_angle)
    lo, hi = check_bounds(ratio_bounds)
    n = law.driving_turns
    theta = np.linspace(-STEP_HALF_ANGLE, STEP_HALF_ANGLE, int(points) + 1)
    if isinstance(law, WheelStepCodesignLaw):
        theta = np.sort(np.append(theta, law.window))
    G, dG, d2G = _terms(law, theta)
    t = pitch_terms(G, dG, d2G, L)
    p2 = driven_perimeter(law, L)
    p1 = p2 / n
    per_step = STEPS // n                       # z1 must be a multiple of S/n for z2 = n·z1 to be one of S
    z1 = max(per_step, per_step * int(round(p1 / (math.pi * m) / per_step)))
    module_adjusted = p1 / (math.pi * z1)
    limit = module_adjusted / math.sin(alpha) ** 2
    mu = np.arctan(t["tan_pressure"])
    i_mu = int(np.argmax(mu))
    convexity, concave, rho_min, violations = curve_findings(
        t, L, limit, mu, mu_max, lambda mask: _runs(theta, mask), float(theta[i_mu]),
        {"driving": "driving", "driven": "driven (hub)"}, "hub angle θ", " of each step")
    if G.min() < lo or G.max() > hi:
        violations.append(f"the ratio G = dψ/dθ spans [{G.min():.4g}, {G.max():.4g}], outside [{lo:.4g}, {hi:.4g}]")
    return WheelStepGearChecks(L, m, alpha, n, z1, n * z1, module_adjusted, p1, p2, float(G.min()), float(G.max()),
                               (float(t["r_driving"].min()), float(t["r_driving"].max())),
                               (float(t["r_driven"].min()), float(t["r_driven"].max())),
                               float(mu[i_mu]), float(theta[i_mu]), convexity, concave, rho_min, limit, violations)


def driven_perimeter(law, centre_distance: float, *, panels: int = 128, nodes: int = 8) -> float:
    """Perimeter (m) of the driven (hub) pitch curve, S·∫ √(r2² + (dr2/dθ)²) dθ over one step (r2 = L·G/(1 + G)),
    by Gauss–Legendre quadrature on ``panels`` panels of each smooth piece (window and the transfer's two halves;
    the paper's step is one piece). The driving curve is 1/n of it (both roll the same arc)."""
    x, w = np.polynomial.legendre.leggauss(nodes)
    ends = [-STEP_HALF_ANGLE, STEP_HALF_ANGLE]
    if isinstance(law, WheelStepCodesignLaw):
        ends = [-STEP_HALF_ANGLE, *law.window, STEP_HALF_ANGLE]
    total = 0.0
    for lo, hi in zip(ends[:-1], ends[1:]):
        edges = np.linspace(lo, hi, panels + 1)
        mid, half = 0.5 * (edges[1:] + edges[:-1]), 0.5 * (edges[1:] - edges[:-1])
        G, dG, _ = _terms(law, (mid[:, None] + half[:, None] * x).ravel())
        ds = np.hypot(G / (1.0 + G), dG / (1.0 + G) ** 2)
        total += float(np.sum((half[:, None] * w).ravel() * ds))
    return STEPS * total * float(centre_distance)


def _runs(theta, mask):
    from ..kernels.runs import runs
    return [(float(theta[a]), float(theta[b])) for a, b in runs(mask)]


# ---------------------------------------------------------------------------------------------------------------
# measurements on the pitch curves


def mover_speed(pair, shoe: Shoe, psi) -> tuple[np.ndarray, np.ndarray]:
    """(x, v) at driving angles ψ (...): x the mover's displacement from the centre of the current step (m) and v
    its speed per driving radian (m/rad), v = X′(θ)·r1/r2 with θ = θ(ψ) and the pitch radii r1, r2 at the pitch
    point of the pair's exact pitch curves (θ̇/ψ̇ = r1/r2, rolling without slip)."""
    psi = np.asarray(psi, dtype=float)
    theta = pair.law(psi)
    r1, r2 = pair.contact_radii(psi)
    u = theta - np.round(theta / (2.0 * STEP_HALF_ANGLE)) * 2.0 * STEP_HALF_ANGLE
    return shoe.displacement(u, periodic=False), shoe.displacement_rate(u, periodic=False) * r1 / r2


def mover_speed_spread(pair, shoe: Shoe, fractions=SPREAD_FRACTIONS, *, samples: int = 4096) -> dict:
    """{f"{f:g}": (max − min)/mean of the mover speed over the samples whose displacement lies in the central
    fraction f of their step} (:func:`~assur.analysis.gait.central_vx_spread`), the mover speed measured by
    :func:`mover_speed` at ``samples`` uniform driving angles per driving turn over the whole cycle; plus
    "range": (min, max) of the speed over whole steps relative to the nominal X_01/(n·π/2) per driving radian."""
    psi = np.arange(int(samples) * pair.driving_turns) * (TWO_PI / int(samples))
    x, v = mover_speed(pair, shoe, psi)
    half = 0.5 * shoe.budget.total
    contact = np.ones(psi.shape, dtype=bool)
    out = {f"{f:g}": float(central_vx_spread(x, v, contact, f, -half, half)) for f in fractions}
    nominal = shoe.budget.total / (pair.driving_turns * math.pi / 2.0)
    out["range"] = (float(v.min() / nominal), float(v.max() / nominal))
    return out


def max_tangent_jump(pair) -> float:
    """The largest |tangent jump| (rad) of the corners of both pitch curves (:func:`~assur.gears.pitch.find_corners`),
    0 when neither has a corner."""
    jumps = [abs(c.tangent_jump) for curve in (pair.driving, pair.driven) for c in find_corners(curve)]
    return max(jumps, default=0.0)


def polyline_max_turn(curve, points: int) -> float:
    """The largest turning angle (rad) between consecutive chords of the closed polyline through ``points``
    uniform body angles of a pitch curve: ~κ·ds (→ 0 as points grow) on a smooth curve, the tangent jump at a
    corner whatever the sampling."""
    pts = curve.xy(int(points))
    seg = np.roll(pts, -1, axis=0) - pts
    heading = np.arctan2(seg[:, 1], seg[:, 0])
    return float(np.max(np.abs(np.angle(np.exp(1j * (heading - np.roll(heading, 1)))))))


# ---------------------------------------------------------------------------------------------------------------
# the transfer's coefficients


#: the entries of the margin vector of :class:`_TransferMargins`, in order
MARGIN_NAMES = ("convex_driving", "convex_driven", "pressure_angle", "ratio_low", "ratio_high", "undercut_driving",
                "undercut_driven")


class _TransferMargins:
    """Closed-form margins (≥ 0 met, :data:`MARGIN_NAMES`) of the transfer coefficients c (n_bumps,) on fixed
    samples of one step (``points`` on the window and on the transfer each), the objective of
    :meth:`~assur.gears.codesign.CodesignProblem.objective` transposed to G = n·g and hub-angle derivatives."""

    def __init__(self, foot, fraction, n_bumps, driving_turns, centre_distance, module, pressure_angle,
                 max_pressure_angle, ratio_bounds, points=1024):
        self.basis = basis = transfer_basis(foot, support_window(foot, fraction), n_bumps)
        self.n, self.L, self.mu_max = driving_turns, centre_distance, max_pressure_angle
        self.bounds = check_bounds(ratio_bounds)
        self.limit = module / math.sin(pressure_angle) ** 2
        qw = np.linspace(basis.q1, basis.q2, points)
        s = np.linspace(0.0, 1.0, points)
        scale = np.array([1.0, STEPS, STEPS ** 2])[:, None] * driving_turns
        self.window = np.stack([basis.direction * foot.derivative(qw, o) for o in (1, 2, 3)]) * scale
        self.hermite = np.stack([basis.hermite.deriv(o)(s) / basis.span ** o for o in (0, 1, 2)]) * scale
        self.bumps = np.stack([np.stack([b.deriv(o)(s) / basis.span ** o for b in basis.bumps])
                               if basis.bumps else np.zeros((0, points)) for o in (0, 1, 2)]) * scale[:, None]
        self.k0 = basis.closure_k(np.zeros(n_bumps))
        self.dk = np.array([basis.closure_k(np.eye(n_bumps)[j]) - self.k0 for j in range(n_bumps)])

    def terms(self, c):
        k = self.k0 + float(self.dk @ c) if len(c) else self.k0
        return k, np.concatenate([k * self.window, k * self.hermite + np.einsum("j,ojp->op", c, self.bumps)], axis=1)

    def margins(self, c) -> np.ndarray:
        c = np.asarray(c, dtype=float).reshape(-1)
        k, (G, dG, d2G) = self.terms(c)
        if not (k > 0 and G.min() > 0):
            return np.full(len(MARGIN_NAMES), -100.0 + min(k, float(G.min())))
        t = pitch_terms(G, dG, d2G, self.L)
        lo, hi = self.bounds
        return np.array([t["kappa_driving"].min() * self.L, t["kappa_driven"].min() * self.L,
                         self.mu_max - float(np.arctan(t["tan_pressure"]).max()), G.min() - lo, hi - G.max(),
                         1.0 - self.limit * np.abs(t["kappa_driving"]).max(),
                         1.0 - self.limit * np.abs(t["kappa_driven"]).max()])

    def objective(self, c) -> float:
        """Total violation + mean concave depth of both curves when something fails, else −(worst margin)."""
        m = self.margins(c)
        if m[0] <= -99.0 and np.all(m == m[0]):
            return float(1e3 - m[0])
        _, (G, dG, d2G) = self.terms(np.asarray(c, dtype=float).reshape(-1))
        t = pitch_terms(G, dG, d2G, self.L)
        depth = sum(float(np.mean(np.maximum(0.0, -t[f"kappa_{k}"] * self.L))) for k in ("driving", "driven"))
        violation = float(np.sum(np.maximum(0.0, -m))) + depth
        return violation if violation > 0 else -float(np.min(m))


# ---------------------------------------------------------------------------------------------------------------
# the redesign


@dataclass(frozen=True)
class PaperPair:
    """The paper's cornered pair (:class:`~assur.gears.law.WheelStepLaw`, rounding 0) measured by the same code:
    law, checks (away from the corners), corner = the largest tangent jump (rad), speed_spread (as
    :func:`mover_speed_spread`)."""
    law: WheelStepLaw
    checks: WheelStepGearChecks
    corner: float
    speed_spread: dict


@dataclass(frozen=True)
class WheelStepCodesign:
    """Result of :func:`wheelstep_codesign`: the redesigned law (a TransmissionLaw for
    :func:`~assur.gears.pitch.pitch_pair` and the tooth generator), its checks, the transfer coefficients and the
    margins (name → value), the measured mover speed spread ({"0.8", "0.9", f"{fraction:g}", "range"}), the
    corner (largest tangent jump of both pitch curves, rad; 0 = none), and the paper's pair for comparison."""
    law: WheelStepCodesignLaw
    checks: WheelStepGearChecks
    coefficients: np.ndarray
    margins: dict
    speed_spread: dict
    corner: float
    paper: PaperPair | None

    @property
    def success(self) -> bool:
        """No corner and every check met."""
        return self.corner == 0.0 and self.checks.ok


def paper_pair(shoe: Shoe, *, centre_distance: float, module: float, driving_turns: int = 2,
               pressure_angle: float = math.radians(20.0), max_pressure_angle: float = math.radians(30.0),
               fractions=SPREAD_FRACTIONS) -> PaperPair:
    """The paper's cornered pair measured as the redesign is (:class:`PaperPair`)."""
    law = WheelStepLaw(shoe, _check_turns(driving_turns))
    pair = pitch_pair(law, _positive("centre_distance", centre_distance), samples=4096)
    checks = wheelstep_gear_checks(law, centre_distance, module=module, pressure_angle=pressure_angle,
                                   max_pressure_angle=max_pressure_angle)
    return PaperPair(law, checks, max_tangent_jump(pair), mover_speed_spread(pair, shoe, fractions))


def wheelstep_codesign(shoe: Shoe, fraction: float, *, centre_distance: float, module: float, driving_turns: int = 2,
                       n_bumps: int = 4, seed: int | None = 0, coefficients=None, optimize: bool = True,
                       pressure_angle: float = math.radians(20.0), max_pressure_angle: float = math.radians(30.0),
                       ratio_bounds=None, spread: float = 6.0, maxiter: int = 300, popsize: int = 20,
                       compare: bool = True) -> WheelStepCodesign:
    """Redesign the wheel-step drive of ``shoe``: constant mover speed over the central ``fraction`` of each step,
    a C² transfer across the step ends (module docstring), checked at ``centre_distance`` (m) for a rack of
    ``module`` (m) and ``pressure_angle``.

    The transfer's ``n_bumps`` coefficients: ``coefficients`` if given; else, with ``optimize``, scipy's
    differential evolution (``seed``, ``maxiter``, ``popsize``) over c_smooth ± ``spread`` from the smoothest
    bridge, minimising the objective of :meth:`~assur.gears.codesign.CodesignProblem.objective` (violations and
    concave depth first, then the worst margin); without ``optimize`` the smoothest bridge. ``compare``: also
    measure the paper's pair (:func:`paper_pair`). Raises SpecError for bad arguments."""
    f = check_fraction(fraction)
    n = _check_turns(driving_turns)
    L = _positive("centre_distance", centre_distance)
    m = _positive("module", module)
    alpha = check_angle("pressure_angle", pressure_angle)
    mu_max = check_angle("max_pressure_angle", max_pressure_angle)
    if isinstance(n_bumps, bool) or not isinstance(n_bumps, (int, np.integer)) or n_bumps < 0:
        raise SpecError([("n_bumps", f"must be a whole number ≥ 0: {n_bumps!r}")])
    foot = step_foot(shoe)
    problem = _TransferMargins(foot, f, int(n_bumps), n, L, m, alpha, mu_max, ratio_bounds)
    if coefficients is not None:
        best = np.asarray(coefficients, dtype=float).reshape(-1)
        if best.size != n_bumps or not np.all(np.isfinite(best)):
            raise SpecError([("coefficients", f"need {n_bumps} finite values (n_bumps): {coefficients!r}")])
    else:
        best = smooth_coefficients(problem.basis)
        if optimize and n_bumps > 0:
            from scipy.optimize import differential_evolution
            if not (np.isfinite(spread) and spread > 0):
                raise SpecError([("spread", f"must be a positive number: {spread!r}")])
            res = differential_evolution(problem.objective, [(c - spread, c + spread) for c in best], x0=best,
                                         seed=seed, maxiter=int(maxiter), popsize=int(popsize), tol=1e-10,
                                         polish=True)
            if res.fun <= problem.objective(best):
                best = np.asarray(res.x, dtype=float)
    law = WheelStepCodesignLaw(CodesignLaw(foot, f, best), shoe, n)
    checks = wheelstep_gear_checks(law, L, module=m, pressure_angle=alpha, max_pressure_angle=mu_max,
                                   ratio_bounds=ratio_bounds)
    pair = pitch_pair(law, L, samples=4096)
    spread_measured = mover_speed_spread(pair, shoe, sorted(set(SPREAD_FRACTIONS) | {f}))
    paper = paper_pair(shoe, centre_distance=L, module=m, driving_turns=n, pressure_angle=alpha,
                       max_pressure_angle=mu_max) if compare else None
    return WheelStepCodesign(law, checks, best, dict(zip(MARGIN_NAMES, problem.margins(best).tolist())),
                             spread_measured, max_tangent_jump(pair), paper)


# ---------------------------------------------------------------------------------------------------------------
# a gear file


def gear_file_text(result: WheelStepCodesign, *, module: float, driving_teeth: int,
                   centre_distance: float | None = None, samples: int = 2048, name: str = "", description: str = "", extra_teeth: str = "") -> str:
    """An ``assur-gears/1`` file (mm, deg) of the redesigned pair: law kind "table" with ``samples`` + 1 rows of
    (ψ, θ(ψ)) over one driving turn (ψ uniform, θ from the exact law, 17 significant digits), envelope teeth of
    ``module`` (m), ``driving_teeth`` and n·driving_teeth driven teeth; ``centre_distance`` (m) defaults to the one
    that makes the driving perimeter z1·π·m exactly. ``extra_teeth``: further ``[teeth]`` lines, verbatim."""
    law = result.law
    n = law.driving_turns
    if centre_distance is None:
        unit = driven_perimeter(law, 1.0) / n
        centre_distance = math.pi * module * driving_teeth / unit
    psi_deg = np.arange(int(samples) + 1) * (360.0 / int(samples))
    theta = law.theta(np.radians(psi_deg))
    theta[0], theta[-1] = 0.0, TWO_PI / n

    def column(values):
        body = ",\n".join("    " + ", ".join(repr(float(v)) for v in values[i:i + 6]) for i in range(0, len(values), 6))
        return f"[\n{body},\n]"

    import json
    quote = "'''"     # a TOML multi-line literal string keeps the description readable
    about = (f"{quote}\n{description.strip()}\n{quote}" if quote not in description
             else json.dumps(description, ensure_ascii=False))
    text = ['format = "assur-gears/1"', f"name = {json.dumps(name, ensure_ascii=False)}", f"description = {about}",
            "", "[units]", 'length = "mm"', 'angle = "deg"', "", "[law]",
            'kind = "table"             # generated by assur.gears.codesign_wheelstep.gear_file_text',
            f"driving_turns = {n}", f"phi = {column(psi_deg)}", f"theta = {column(np.degrees(theta))}", "",
            "[pair]", f"centre_distance = {centre_distance * 1e3:.9f}", "", "[teeth]", 'method = "envelope"',
            f"module = {module * 1e3:.9g}", f"driving_teeth = {int(driving_teeth)}",
            f"driven_teeth = {n * int(driving_teeth)}"]
    if extra_teeth:
        text.append(extra_teeth.rstrip("\n"))
    return "\n".join(text) + "\n"


__all__ = ["MARGIN_NAMES", "PaperPair", "SPREAD_FRACTIONS", "STEPS", "StepDisplacement", "WheelStepCodesign",
           "WheelStepCodesignLaw", "WheelStepGearChecks", "driven_perimeter", "gear_file_text", "max_tangent_jump",
           "mover_speed", "mover_speed_spread", "paper_pair", "paper_ratio_terms", "polyline_max_turn", "step_foot",
           "wheelstep_codesign", "wheelstep_gear_checks", "window_pressure_bound"]
