"""Paper 001 revisited (assur issue 15): the wheel-step mover's gear drive redesigned with the co-design law, so
that the pitch curves have no corners: the search for the transfer (:func:`wheelstep_codesign`), the measured mover
speed, the paper's cornered pair measured by the same code (:func:`paper_pair`) and the gear file of a design.

The law, its mapping onto the co-design machinery (one hub step ↔ one crank turn, q = S·θ + π) and the paper's
closed form: :mod:`assur.codesign.wheelstep_law`. The checks are the co-design's own
(:func:`assur.codesign.checks.gear_checks`, over one hub step), the search's margins those of
:class:`assur.codesign.margins.TransferMargins` with G = n·g and hub-angle derivatives.

The mover speed is measured independently of the law's construction (:func:`mover_speed`): from the exact pitch
curves of :func:`~assur.gears.pitch.pitch_pair` (θ̇/ψ̇ = r1/r2 at the pitch point) and the shoe's displacement rate
X′(θ) (:meth:`~assur.gears.wheelstep.Shoe.displacement_rate`), as :meth:`WheelStepLaw.mover_speed_ratio` does.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..analysis.gait import central_vx_spread
from ..errors import SpecError
from ..gears.law import WheelStepLaw
from ..gears.pitch import find_corners, pitch_pair
from ..gears.wheelstep import STEP_HALF_ANGLE, Shoe
from .checks import GearChecks, check_angle, check_bounds, check_bumps, check_length, gear_checks
from .law import CodesignLaw, check_fraction, smooth_coefficients, support_window, transfer_basis
from .margins import TransferMargins, check_spread, search_transfer
from .wheelstep_law import STEPS, WheelStepCodesignLaw, check_turns, driven_perimeter, step_foot

TWO_PI = 2.0 * math.pi
#: the window fractions of the comparison (the mover speed spread is reported over these central fractions)
SPREAD_FRACTIONS = (0.8, 0.9)


def window_pressure_bound(shoe: Shoe, fraction: float, *, driving_turns: int = 2, points: int = 4001) -> float:
    """A lower bound (rad) on the centrode pressure angle inside the window, whatever the transfer: on the window
    tan μ = |X″|/(X′·(1 + K·X′)) (G = K·X′), decreasing in K, and the closure with G > 0 on the transfer caps
    K < n·π/(2·f·X_01) (the window alone takes less than the step's n·π/2 of driving angle)."""
    f = check_fraction(fraction)
    n = check_turns(driving_turns)
    foot = step_foot(shoe)
    q1, q2 = support_window(foot, f)
    theta = (np.linspace(q1, q2, int(points)) - math.pi) / STEPS
    k_max = n * math.pi / (2.0 * f * shoe.budget.total)
    d1 = shoe.displacement_rate(theta, periodic=False)
    d2 = np.abs(6.0 * shoe.b * np.sin(2.0 * theta))
    return float(np.max(np.arctan(d2 / (d1 * (1.0 + k_max * d1)))))



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


def step_margins(foot, fraction, n_bumps, driving_turns, centre_distance, module, pressure_angle, max_pressure_angle,
                 ratio_bounds, points=1024) -> TransferMargins:
    """The closed-form margins (:class:`~assur.codesign.margins.TransferMargins`) of the transfer coefficients c
    (n_bumps,) on fixed samples of one step (``points`` on the window and on the transfer each): the ratio
    G = n·g with hub-angle derivatives (d/dθ = S·d/dq). Its ``basis`` is the transfer basis of the step."""
    basis = transfer_basis(foot, support_window(foot, fraction), n_bumps)
    qw = np.linspace(basis.q1, basis.q2, points)
    s = np.linspace(0.0, 1.0, points)
    scale = np.array([1.0, STEPS, STEPS ** 2])[:, None] * driving_turns
    window = np.stack([basis.direction * foot.derivative(qw, o) for o in (1, 2, 3)]) * scale
    hermite = np.stack([basis.hermite.deriv(o)(s) / basis.span ** o for o in (0, 1, 2)]) * scale
    bumps = np.stack([np.stack([b.deriv(o)(s) / basis.span ** o for b in basis.bumps])
                      if basis.bumps else np.zeros((0, points)) for o in (0, 1, 2)]) * scale[:, None]
    k0 = basis.closure_k(np.zeros(n_bumps))
    dk = np.array([basis.closure_k(np.eye(n_bumps)[j]) - k0 for j in range(n_bumps)])
    margins = TransferMargins(window, hermite, bumps, k0, dk, centre_distance=centre_distance,
                              undercut_limit=module / math.sin(pressure_angle) ** 2,
                              max_pressure_angle=max_pressure_angle, ratio_bounds=check_bounds(ratio_bounds))
    margins.basis = basis
    return margins


# ---------------------------------------------------------------------------------------------------------------
# the redesign


@dataclass(frozen=True)
class PaperPair:
    """The paper's cornered pair (:class:`~assur.gears.law.WheelStepLaw`, rounding 0) measured by the same code:
    law, checks (away from the corners), corner = the largest tangent jump (rad), speed_spread (as
    :func:`mover_speed_spread`)."""
    law: WheelStepLaw
    checks: GearChecks
    corner: float
    speed_spread: dict


@dataclass(frozen=True)
class WheelStepCodesign:
    """Result of :func:`wheelstep_codesign`: the redesigned law (a TransmissionLaw for
    :func:`~assur.gears.pitch.pitch_pair` and the tooth generator), its checks, the transfer coefficients and the
    margins (name → value), the measured mover speed spread ({"0.8", "0.9", f"{fraction:g}", "range"}), the
    corner (largest tangent jump of both pitch curves, rad; 0 = none), and the paper's pair for comparison."""
    law: WheelStepCodesignLaw
    checks: GearChecks
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
    law = WheelStepLaw(shoe, check_turns(driving_turns))
    pair = pitch_pair(law, check_length("centre_distance", centre_distance), samples=4096)
    checks = gear_checks(law, centre_distance, module=module, pressure_angle=pressure_angle,
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
    bridge, minimising the objective of :meth:`~assur.codesign.margins.TransferMargins.objective` (violations and
    concave depth first, then the worst margin); without ``optimize`` the smoothest bridge. ``compare``: also
    measure the paper's pair (:func:`paper_pair`). Raises SpecError for bad arguments."""
    f = check_fraction(fraction)
    n = check_turns(driving_turns)
    L = check_length("centre_distance", centre_distance)
    m = check_length("module", module)
    alpha = check_angle("pressure_angle", pressure_angle)
    mu_max = check_angle("max_pressure_angle", max_pressure_angle)
    n_bumps = check_bumps(n_bumps)
    foot = step_foot(shoe)
    problem = step_margins(foot, f, n_bumps, n, L, m, alpha, mu_max, ratio_bounds)
    if coefficients is not None:
        best = np.asarray(coefficients, dtype=float).reshape(-1)
        if best.size != n_bumps or not np.all(np.isfinite(best)):
            raise SpecError([("coefficients", f"need {n_bumps} finite values (n_bumps): {coefficients!r}")])
    else:
        best = smooth_coefficients(problem.basis)
        if optimize and n_bumps > 0:
            best, _, _ = search_transfer(problem.objective, best, spread=check_spread(spread), seed=seed,
                                         maxiter=maxiter, popsize=popsize)
    law = WheelStepCodesignLaw(CodesignLaw(foot, f, best), shoe, n)
    checks = gear_checks(law, L, module=m, pressure_angle=alpha, max_pressure_angle=mu_max,
                         ratio_bounds=ratio_bounds)
    pair = pitch_pair(law, L, samples=4096)
    spread_measured = mover_speed_spread(pair, shoe, sorted(set(SPREAD_FRACTIONS) | {f}))
    paper = paper_pair(shoe, centre_distance=L, module=m, driving_turns=n, pressure_angle=alpha,
                       max_pressure_angle=mu_max) if compare else None
    return WheelStepCodesign(law, checks, best, dict(zip(problem.names, problem.margins(best).tolist())),
                             spread_measured, max_tangent_jump(pair), paper)


# ---------------------------------------------------------------------------------------------------------------
# a gear file


def gear_file_text(result: WheelStepCodesign, *, module: float, driving_teeth: int,
                   centre_distance: float | None = None, samples: int = 2048, name: str = "", description: str = "",
                   extra_teeth: str = "") -> str:
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
            'kind = "table"             # generated by assur.codesign.wheelstep.gear_file_text',
            f"driving_turns = {n}", f"phi = {column(psi_deg)}", f"theta = {column(np.degrees(theta))}", "",
            "[pair]", f"centre_distance = {centre_distance * 1e3:.9f}", "", "[teeth]", 'method = "envelope"',
            f"module = {module * 1e3:.9g}", f"driving_teeth = {int(driving_teeth)}",
            f"driven_teeth = {n * int(driving_teeth)}"]
    if extra_teeth:
        text.append(extra_teeth.rstrip("\n"))
    return "\n".join(text) + "\n"


__all__ = ["PaperPair", "SPREAD_FRACTIONS", "WheelStepCodesign", "gear_file_text", "max_tangent_jump", "mover_speed",
           "mover_speed_spread", "paper_pair", "polyline_max_turn", "step_margins", "wheelstep_codesign",
           "window_pressure_bound"]
