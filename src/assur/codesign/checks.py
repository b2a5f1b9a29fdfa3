"""The gear checks of a co-designed law, one type (:class:`GearChecks`) and one function (:func:`gear_checks`) for
both co-designs: the walking leg's motor/crank pair (:class:`~assur.codesign.law.CodesignLaw`, one crank turn) and
paper 001's wheel-step drive (:class:`~assur.codesign.wheelstep_law.WheelStepCodesignLaw` or the paper's
:class:`~assur.gears.law.WheelStepLaw`, one hub step). Convexity, centrode pressure angle, ratio range, undercut and
tooth counts, all in closed form from the ratio G = d(driving)/d(driven) and its derivatives along the driven angle.

Pitch radii at centre distance L (k = dθ/dφ = 1/G, :mod:`assur.gears.pitch`): driving r1 = L/(1 + G), driven
r2 = L·G/(1 + G); primes are derivatives along the driven angle (the leg's crank angle q, the mover's hub angle θ).

- driven curve: dr2/dα = ±r2′, d²r2/dα² = r2″ (α its body angle);
- driving curve, dα/d(driven) = −G (up to the sense): dr1/dα = ∓r1′/G, d²r1/dα² = (r1″·G − r1′·G′)/G³;
- polar curvature κ = (r² + 2r_α² − r·r_αα)/(r² + r_α²)^{3/2} (> 0 convex);
- centrode pressure angle μ: the angle between the common tangent of the pitch curves and the normal to the line of
  centres, tan μ = |r_α|/r; for both curves tan μ = |G′|/(G·(1 + G)) (r2′/r2 = G′/(G(1+G)), |r1′|/(G·r1) the same);
- both curves roll the same arc: the driven perimeter ∫ √(r2² + r2′²) over the driven turn is n times the driving
  one (n driving turns per driven turn), so with z1 driving teeth and z2 = n·z1 driven teeth one module
  perimeter/(π·z) serves both (the module is adjusted to it);
- undercut: a rack of module m and pressure angle α cuts a stretch of pitch curve of radius of curvature ρ without
  undercut if |ρ| ≥ m/sin²α (the rule of :func:`assur.gears.pitch.curvature_report`).

What differs between the two co-designs is only where the samples lie and how the teeth are counted
(:class:`PitchSamples`): the leg over a whole crank turn from its window start (ranges wrap around), the wheel-step
drive over one hub step (every step is the same), with a driving tooth count that gives each step whole teeth.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from ..errors import SpecError
from ..kernels.runs import cyclic_runs, runs
from .law import CodesignLaw
from .wheelstep_law import STEP_HALF_ANGLE, STEPS, WheelStepCodesignLaw, driven_perimeter, step_terms

TWO_PI = 2.0 * math.pi


def pitch_terms(g, dg, d2g, centre_distance: float) -> dict:
    """Closed-form pitch-curve quantities from G, G′, G″ (...) at centre distance L (m).

    Returns arrays (...): ``r_driving``, ``r_driven`` (m); ``kappa_driving``, ``kappa_driven`` (1/m, > 0 convex);
    ``numerator_driving``, ``numerator_driven`` (r² + 2r_α² − r·r_αα, m²); ``tan_pressure`` (tan μ)."""
    g, dg, d2g = (np.asarray(v, dtype=float) for v in (g, dg, d2g))
    L = float(centre_distance)
    a = 1.0 + g
    a2 = a ** 2
    r1 = L / a
    r1p = -L * dg / a2
    r1pp = -L * d2g / a2 + 2.0 * L * dg ** 2 / a ** 3
    r2, r2p, r2pp = L - r1, -r1p, -r1pp
    d1 = r1p / g
    dd1 = (r1pp * g - r1p * dg) / g ** 3
    n1 = r1 * r1 + 2.0 * d1 * d1 - r1 * dd1
    n2 = r2 * r2 + 2.0 * r2p * r2p - r2 * r2pp
    return {"r_driving": r1, "r_driven": r2, "numerator_driving": n1, "numerator_driven": n2,
            "kappa_driving": n1 / (r1 * r1 + d1 * d1) ** 1.5, "kappa_driven": n2 / (r2 * r2 + r2p * r2p) ** 1.5,
            "tan_pressure": np.abs(dg) / (g * a)}


def ranges_text(ranges) -> str:
    """``"[a°, b°], …"`` of (from, to) pairs in rad."""
    return ", ".join(f"[{math.degrees(a):.1f}°, {math.degrees(b):.1f}°]" for a, b in ranges)


def perimeter(law, *, panels: int = 256, nodes: int = 8) -> float:
    """Arc length of either pitch curve of a leg's :class:`~assur.codesign.law.CodesignLaw` per unit centre distance
    (multiply by L), by Gauss–Legendre quadrature over ``panels`` panels on the window and on the transfer
    separately (g is C² across their joints)."""
    x, w = np.polynomial.legendre.leggauss(nodes)
    total = 0.0
    for lo, hi in ((law.q1, law.q2), (law.q2, law.q1 + TWO_PI)):
        edges = np.linspace(lo, hi, panels + 1)
        mid, half = 0.5 * (edges[1:] + edges[:-1]), 0.5 * (edges[1:] - edges[:-1])
        q = (mid[:, None] + half[:, None] * x).ravel()
        g = law.g(q)
        ds = np.hypot(g / (1.0 + g), law.dg(q) / (1.0 + g) ** 2)      # √(r2² + r2′²) for L = 1
        total += float(np.sum((half[:, None] * w).ravel() * ds))
    return total


# ---------------------------------------------------------------------------------------------------------------
# arguments


#: the most teeth a gear of a checked pair may have (a module far too small for its pitch curve is refused)
MAX_TEETH = 10_000


def check_length(name, value) -> float:
    """A finite length > 0 (m) as a float, else SpecError naming ``name``."""
    if isinstance(value, bool) or not isinstance(value, (int, float, np.floating, np.integer)) \
            or not np.isfinite(value) or value <= 0:
        raise SpecError([(name, f"must be a finite length > 0 m: {value!r}")])
    return float(value)


def check_angle(name, value, upper=math.pi / 2):
    """A finite angle in (0, upper) rad, else SpecError naming ``name``."""
    if isinstance(value, bool) or not isinstance(value, (int, float, np.floating, np.integer)) \
            or not np.isfinite(value) or not (0 < value < upper):
        raise SpecError([(name, f"must be an angle in (0°, {math.degrees(upper):g}°), in rad: {value!r}")])
    return float(value)


def check_bounds(ratio_bounds):
    """(lo, hi) with 0 ≤ lo < hi (hi may be inf), else SpecError naming ``ratio_bounds``."""
    if ratio_bounds is None:
        return 0.0, math.inf
    try:
        lo, hi = (float(v) for v in ratio_bounds)
    except (TypeError, ValueError):
        raise SpecError([("ratio_bounds", f"must be a pair (min, max) of dτ/dq: {ratio_bounds!r}")]) from None
    if not (0.0 <= lo < hi):
        raise SpecError([("ratio_bounds", f"must satisfy 0 ≤ min < max: {ratio_bounds!r}")])
    return lo, hi


def check_bumps(n_bumps) -> int:
    """A whole number of transfer bumps ≥ 0, else SpecError naming ``n_bumps``."""
    if isinstance(n_bumps, bool) or not isinstance(n_bumps, (int, np.integer)) or n_bumps < 0:
        raise SpecError([("n_bumps", f"must be a whole number ≥ 0: {n_bumps!r}")])
    return int(n_bumps)


# ---------------------------------------------------------------------------------------------------------------
# where a law is checked


@dataclass(frozen=True)
class PitchSamples:
    """What :func:`gear_checks` reads of a law: the driven angles it is sampled at and the ratio there.

    angles: (n,) sorted driven angles (rad); ratio: (G, G′, G″) at them, three (n,) arrays; cyclic: the angles span
    a whole turn (ranges wrap, reported in [0, 2π)) rather than one step; unit_perimeter: the driven pitch curve's
    perimeter per unit centre distance; driving_turns n; teeth_multiple: the driving tooth count is a multiple of it;
    angle (``"crank angle q"``), ratio_name, curve names and the ranges' suffix, for the messages."""
    angles: np.ndarray
    ratio: tuple
    cyclic: bool
    unit_perimeter: float
    driving_turns: int
    teeth_multiple: int
    angle: str
    ratio_name: str
    names: dict
    suffix: str

    def ranges(self, mask) -> list[tuple[float, float]]:
        """[(from, to)] (rad) of the runs of ``mask`` (n,) over the samples."""
        if self.cyclic:
            return [(float(np.mod(self.angles[a], TWO_PI)), float(np.mod(self.angles[b], TWO_PI)))
                    for a, b in cyclic_runs(mask)]
        return [(float(self.angles[a]), float(self.angles[b])) for a, b in runs(mask)]

    def at(self, i: int) -> float:
        """The angle of sample ``i`` as reported (rad)."""
        return float(np.mod(self.angles[i], TWO_PI)) if self.cyclic else float(self.angles[i])


def pitch_samples(law, points: int = 8192) -> PitchSamples:
    """The :class:`PitchSamples` of a co-designed law: a leg's :class:`~assur.codesign.law.CodesignLaw` at
    ``points`` crank angles over a turn from the window start (plus the window's end), or a wheel-step law
    (:func:`~assur.codesign.wheelstep_law.step_terms`) at ``points`` + 1 hub angles over one step (plus the window's
    ends). GearError for any other law."""
    if isinstance(law, CodesignLaw):
        q = law.q1 + np.linspace(0.0, TWO_PI, int(points), endpoint=False)
        q = np.sort(np.append(q, law.q2))
        return PitchSamples(q, (law.g(q), law.dg(q), law.d2g(q)), True, perimeter(law), 1, 1, "crank angle q",
                            "g = dτ/dq", {"driving": "motor (driving)", "driven": "crank (driven)"}, "")
    theta = np.linspace(-STEP_HALF_ANGLE, STEP_HALF_ANGLE, int(points) + 1)
    if isinstance(law, WheelStepCodesignLaw):
        theta = np.sort(np.append(theta, law.window))
    terms = step_terms(law, theta)
    n = law.driving_turns
    return PitchSamples(theta, terms, False, driven_perimeter(law, 1.0), n, STEPS // n, "hub angle θ",
                        "G = dψ/dθ", {"driving": "driving", "driven": "driven (hub)"}, " of each step")


# ---------------------------------------------------------------------------------------------------------------
# the checks


@dataclass(frozen=True)
class GearChecks:
    """Checks of the driving/driven pitch curves of a co-designed law at one centre distance.

    Angles are the driven angles of :attr:`angle` (the leg's crank angle q over a turn; the wheel-step drive's hub
    angle θ over one step, every step alike); radii and lengths in m. ``convexity``: {"driving", "driven"}: min κ·L
    over the curve (≥ 0 convex; at the paper's wheel-step corners the one-sided value); ``concave``: their concave
    ranges; teeth: z1 driving and z2 = n·z1 driven, the nearest counts that fit (the wheel-step drive: whole teeth
    on every step), ``module`` = driving perimeter/(π·z1). ``torque_peak``, ``torque_limit``,
    ``torque_peak_at``: the geared leg's peak motor torque (N·m) against the limit asked for, and where
    (:mod:`assur.codesign.torque`); None without a limit."""
    centre_distance: float
    module_requested: float
    pressure_angle: float                 #: the rack's pressure angle α, rad
    driving_turns: int                    #: n, driving turns per driven turn
    driving_teeth: int                    #: z1
    driven_teeth: int                     #: z2 = n·z1
    module: float                         #: driving perimeter/(π·z1), m
    driving_perimeter: float              #: m
    driven_perimeter: float               #: m (n times the driving one)
    ratio_min: float                      #: min G (the leg's g = dτ/dq, the wheel-step drive's dψ/dθ)
    ratio_max: float                      #: max G
    radius_driving: tuple                 #: (min, max) pitch radius of the driving gear
    radius_driven: tuple                  #: (min, max) pitch radius of the driven gear
    max_pressure_angle: float             #: max centrode pressure angle μ, rad
    max_pressure_angle_at: float          #: the driven angle of it, rad
    convexity: dict
    concave: dict
    min_curvature_radius: dict            #: {"driving", "driven"}: min |ρ| over the curve, m
    undercut_limit: float                 #: m/sin²α with the adjusted module, m
    violations: list = field(default_factory=list)
    angle: str = "crank angle q"          #: the driven angle the ranges are given in
    torque_peak: float | None = None
    torque_limit: float | None = None
    torque_peak_at: float | None = None

    @property
    def ok(self) -> bool:
        """No violation."""
        return not self.violations

    @property
    def convex(self) -> dict:
        """{"driving", "driven"}: the curve is convex everywhere."""
        return {name: not ranges for name, ranges in self.concave.items()}

    @property
    def teeth(self) -> int:
        """z1, the driving gear's teeth (both gears' when the pair turns 1:1 on average, as a leg's)."""
        return self.driving_teeth

    @property
    def perimeter(self) -> float:
        """The driving pitch curve's perimeter, m (either curve's when the pair turns 1:1 on average)."""
        return self.driving_perimeter


def gear_checks(law, centre_distance: float, *, module: float, pressure_angle: float = math.radians(20.0),
                max_pressure_angle: float = math.radians(30.0), ratio_bounds=None, points: int = 8192,
                max_torque: float | None = None) -> GearChecks:
    """Check the gear pair of a co-designed law at ``centre_distance`` (m) for a rack of ``module`` (m) and
    ``pressure_angle`` (rad): convexity of both pitch curves, centrode pressure angle ≤ ``max_pressure_angle``,
    the ratio within ``ratio_bounds`` (optional (min, max)), no undercut (|ρ| ≥ m/sin²α on both curves, concave
    stretches included) with the module adjusted to whole tooth counts. ``law``: a leg's
    :class:`~assur.codesign.law.CodesignLaw`, sampled at ``points`` crank angles from the window start (plus the
    joints), or a wheel-step law sampled at ``points`` + 1 hub angles over one step (:func:`pitch_samples`).

    ``max_torque`` (N·m, a leg with masses or loads only): the geared leg's peak motor torque must not exceed it
    (:func:`~assur.codesign.torque.torque_check`)."""
    L = check_length("centre_distance", centre_distance)
    m = check_length("module", module)
    alpha = check_angle("pressure_angle", pressure_angle)
    mu_max = check_angle("max_pressure_angle", max_pressure_angle)
    lo, hi = check_bounds(ratio_bounds)
    s = pitch_samples(law, points)
    G, dG, d2G = s.ratio
    t = pitch_terms(G, dG, d2G, L)
    p2 = s.unit_perimeter * L
    n = s.driving_turns
    p1 = p2 / n
    step = s.teeth_multiple                     # z1 a multiple of S/n for z2 = n·z1 to be one of S (wheel-step)
    if not p1 / (math.pi * m) <= MAX_TEETH:
        raise SpecError([("module", f"{m * 1000:.3g} mm gives the driving gear {p1 / (math.pi * m):.3g} teeth on "
                                    f"its {p1 * 1000:.4g} mm pitch curve (at most {MAX_TEETH}): use a larger module")])
    z1 = max(step, step * int(round(p1 / (math.pi * m) / step)))
    module_adjusted = p1 / (math.pi * z1)
    limit = module_adjusted / math.sin(alpha) ** 2
    mu = np.arctan(t["tan_pressure"])
    i_mu = int(np.argmax(mu))
    convexity, concave, rho_min, violations = curve_findings(t, L, limit, mu, mu_max, s.ranges, s.at(i_mu),
                                                             s.names, s.angle, s.suffix)
    if G.min() < lo or G.max() > hi:
        violations.append(f"the ratio {s.ratio_name} spans [{G.min():.4g}, {G.max():.4g}], outside the bounds "
                          f"[{lo:.4g}, {hi:.4g}]")
    torque = (None, None, None)
    if max_torque is not None:
        from .torque import torque_check
        peak, at, text = torque_check(law, max_torque)
        torque = (peak, float(max_torque), at)
        if text:
            violations.append(text)
    return GearChecks(L, m, alpha, n, z1, n * z1, module_adjusted, p1, p2, float(G.min()), float(G.max()),
                      (float(t["r_driving"].min()), float(t["r_driving"].max())),
                      (float(t["r_driven"].min()), float(t["r_driven"].max())),
                      float(mu[i_mu]), s.at(i_mu), convexity, concave, rho_min, limit, violations, s.angle, *torque)


def curve_findings(t: dict, L: float, limit: float, mu, mu_max: float, ranges, at: float, names: dict, angle: str,
                   suffix: str = ""):
    """(convexity, concave ranges, smallest radius of curvature, violations) of both pitch curves from their
    closed-form terms ``t`` (:func:`pitch_terms`) on samples: convexity (min κ·L ≥ 0), undercut (|ρ| ≥ ``limit`` =
    m/sin²α) and the centrode pressure angle ``mu`` (samples, rad; max ``mu_max``, its largest at the angle
    ``at``). ``ranges(mask)`` → [(from, to)] of the sample angles; ``names`` the curves' names in messages;
    ``angle`` the angle's name ("crank angle q"); ``suffix`` appended to the ranges (" of each step")."""
    convexity, concave, rho_min, violations = {}, {}, {}, []
    for name in ("driving", "driven"):
        kappa = t[f"kappa_{name}"]
        convexity[name] = float(np.min(kappa) * L)
        concave[name] = ranges(kappa < 0)
        rho = np.abs(1.0 / np.where(kappa != 0, kappa, np.inf))
        rho_min[name] = float(np.min(rho))
        if concave[name]:
            violations.append(f"the {names[name]} pitch curve is concave for {angle} ∈ "
                              f"{ranges_text(concave[name])}{suffix} (min κ·L = {convexity[name]:.4g})")
        if (rho < limit).any():
            violations.append(f"undercut: the {names[name]} pitch curve's radius of curvature falls to "
                              f"{rho_min[name] * 1e3:.4g} mm < m/sin²α = {limit * 1e3:.4g} mm for {angle} ∈ "
                              f"{ranges_text(ranges(rho < limit))}{suffix}")
    if np.max(mu) > mu_max:
        violations.append(f"the centrode pressure angle reaches {math.degrees(np.max(mu)):.2f}° > "
                          f"{math.degrees(mu_max):.2f}° at {angle} = "
                          f"{math.degrees(at):.1f}° (over {ranges_text(ranges(mu > mu_max))}{suffix})")
    return convexity, concave, rho_min, violations


__all__ = ["GearChecks", "PitchSamples", "check_angle", "check_bounds", "check_bumps", "check_length",
           "curve_findings", "gear_checks", "perimeter", "pitch_samples", "pitch_terms", "ranges_text"]
