"""Gear checks of a co-designed walking-leg law (:mod:`assur.gears.codesign_law`): convexity, centrode pressure
angle, ratio range, undercut and tooth count of the motor/crank pair, all in closed form from g(q) = dτ/dq.

Pitch radii at centre distance L (k = dθ/dφ = 1/g, :mod:`assur.gears.pitch`): motor (driving) r1 = L/(1 + g),
crank (driven) r2 = L·g/(1 + g); primes are d/dq.

- driven curve, body angle α = π + σq: dr2/dα = σ·r2′, d²r2/dα² = r2″;
- driving curve, body angle α = −τ, dα/dq = −σg: dr1/dα = −σ·r1′/g, d²r1/dα² = (r1″·g − r1′·g′)/g³;
- polar curvature κ = (r² + 2r_α² − r·r_αα)/(r² + r_α²)^{3/2} (> 0 convex);
- centrode pressure angle μ: the angle between the common tangent of the pitch curves and the normal to the line of
  centres, tan μ = |r_α|/r; for both curves tan μ = |g′|/(g·(1 + g)) (r2′/r2 = g′/(g(1+g)), |r1′|/(g·r1) the same);
- both curves roll the same arc: perimeter = ∫₀^{2π} √(r2² + r2′²) dq (= ∫ √(r1²g² + r1′²) dq, since r1·g = r2 and
  r1′ = −r2′), so one tooth count z = round(perimeter/(π·m)) serves both, with the module adjusted to
  perimeter/(π·z);
- undercut: a rack of module m and pressure angle α cuts a stretch of pitch curve of radius of curvature ρ without
  undercut if |ρ| ≥ m/sin²α (the rule of :func:`assur.gears.pitch.curvature_report`).
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from ..errors import SpecError
from ..kernels.runs import cyclic_runs

TWO_PI = 2.0 * math.pi


def pitch_terms(g, dg, d2g, centre_distance: float) -> dict:
    """Closed-form pitch-curve quantities from g, g′, g″ (...) at centre distance L (m).

    Returns arrays (...): ``r_driving``, ``r_driven`` (m); ``kappa_driving``, ``kappa_driven`` (1/m, > 0 convex);
    ``numerator_driving``, ``numerator_driven`` (r² + 2r_α² − r·r_αα, m²); ``tan_pressure`` (tan μ)."""
    g, dg, d2g = (np.asarray(v, dtype=float) for v in (g, dg, d2g))
    L = float(centre_distance)
    a = 1.0 + g
    r1 = L / a
    r1p = -L * dg / a ** 2
    r1pp = -L * d2g / a ** 2 + 2.0 * L * dg ** 2 / a ** 3
    r2, r2p, r2pp = L - r1, -r1p, -r1pp
    d1 = r1p / g
    dd1 = (r1pp * g - r1p * dg) / g ** 3
    n1 = r1 * r1 + 2.0 * d1 * d1 - r1 * dd1
    n2 = r2 * r2 + 2.0 * r2p * r2p - r2 * r2pp
    return {"r_driving": r1, "r_driven": r2, "numerator_driving": n1, "numerator_driven": n2,
            "kappa_driving": n1 / (r1 * r1 + d1 * d1) ** 1.5, "kappa_driven": n2 / (r2 * r2 + r2p * r2p) ** 1.5,
            "tan_pressure": np.abs(dg) / (g * a)}


def _ranges(q, mask) -> list[tuple[float, float]]:
    """Cyclic runs of ``mask`` over the turn sampled at q (n,) as (q_from, q_to) rad in [0, 2π)."""
    return [(float(np.mod(q[a], TWO_PI)), float(np.mod(q[b], TWO_PI))) for a, b in cyclic_runs(mask)]


def ranges_text(ranges) -> str:
    """``"[a°, b°], …"`` of (q_from, q_to) pairs in rad."""
    return ", ".join(f"[{math.degrees(a):.1f}°, {math.degrees(b):.1f}°]" for a, b in ranges)


def perimeter(law, *, panels: int = 256, nodes: int = 8) -> float:
    """Arc length of either pitch curve per unit centre distance (multiply by L), by Gauss–Legendre quadrature over
    ``panels`` panels on the window and on the transfer separately (g is C² across their joints)."""
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


@dataclass(frozen=True)
class GearChecks:
    """Checks of the motor (driving) / crank (driven) pitch curves of a co-designed law at one centre distance.

    Angles are crank angles q (rad) unless named otherwise; radii in m."""
    centre_distance: float
    module_requested: float
    pressure_angle: float                 #: the rack's pressure angle α, rad
    teeth: int                            #: z, the same on both gears (they roll the same arc)
    module: float                         #: perimeter/(π·z), m
    perimeter: float                      #: of either pitch curve, m
    ratio_min: float                      #: min g = dτ/dq
    ratio_max: float                      #: max g
    radius_driving: tuple[float, float]   #: (min, max) pitch radius of the motor gear
    radius_driven: tuple[float, float]    #: (min, max) pitch radius of the crank gear
    max_pressure_angle: float             #: max centrode pressure angle μ, rad
    max_pressure_angle_at: float          #: crank angle of it, rad
    convexity: dict                       #: {"driving", "driven"}: min κ·L over the curve (≥ 0 convex)
    concave: dict                         #: {"driving", "driven"}: [(q_from, q_to)] where concave
    min_curvature_radius: dict            #: {"driving", "driven"}: min |ρ| over the curve, m
    undercut_limit: float                 #: m/sin²α with the adjusted module, m
    violations: list = field(default_factory=list)

    @property
    def ok(self) -> bool:
        """No violation."""
        return not self.violations

    @property
    def convex(self) -> dict:
        """{"driving", "driven"}: the curve is convex everywhere."""
        return {name: not ranges for name, ranges in self.concave.items()}


def _check_positive_length(name, value):
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


def gear_checks(law, centre_distance: float, *, module: float, pressure_angle: float = math.radians(20.0),
                max_pressure_angle: float = math.radians(30.0), ratio_bounds=None,
                points: int = 8192) -> GearChecks:
    """Check the gear pair of a :class:`~assur.gears.codesign_law.CodesignLaw` at ``centre_distance`` (m) for a rack
    of ``module`` (m) and ``pressure_angle`` (rad): convexity of both pitch curves, centrode pressure angle ≤
    ``max_pressure_angle``, g within ``ratio_bounds`` (optional (min, max)), no undercut with the module adjusted
    to a whole tooth count. Sampled at ``points`` crank angles from the window start (plus the joints)."""
    L = _check_positive_length("centre_distance", centre_distance)
    m = _check_positive_length("module", module)
    alpha = check_angle("pressure_angle", pressure_angle)
    mu_max = check_angle("max_pressure_angle", max_pressure_angle)
    lo, hi = check_bounds(ratio_bounds)
    q = law.q1 + np.linspace(0.0, TWO_PI, int(points), endpoint=False)
    q = np.sort(np.append(q, law.q2))
    g, dg, d2g = law.g(q), law.dg(q), law.d2g(q)
    t = pitch_terms(g, dg, d2g, L)
    length = perimeter(law) * L
    z = max(1, int(round(length / (math.pi * m))))
    module_adjusted = length / (math.pi * z)
    limit = module_adjusted / math.sin(alpha) ** 2
    mu = np.arctan(t["tan_pressure"])
    i_mu = int(np.argmax(mu))
    convexity, concave, rho_min, violations = curve_findings(
        t, L, limit, mu, mu_max, lambda mask: _ranges(q, mask), float(np.mod(q[i_mu], TWO_PI)),
        {"driving": "motor (driving)", "driven": "crank (driven)"}, "crank angle q")
    if g.min() < lo or g.max() > hi:
        violations.append(f"the ratio g = dτ/dq spans [{g.min():.4g}, {g.max():.4g}], outside the bounds "
                          f"[{lo:.4g}, {hi:.4g}]")
    return GearChecks(L, m, alpha, z, module_adjusted, length, float(g.min()), float(g.max()),
                      (float(t["r_driving"].min()), float(t["r_driving"].max())),
                      (float(t["r_driven"].min()), float(t["r_driven"].max())),
                      float(mu[i_mu]), float(np.mod(q[i_mu], TWO_PI)), convexity, concave, rho_min, limit, violations)


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


__all__ = ["GearChecks", "curve_findings", "check_angle", "check_bounds", "gear_checks", "perimeter", "pitch_terms", "ranges_text"]
