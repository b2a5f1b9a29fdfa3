"""Pitch curves of a non-circular gear pair from a transmission law and a centre distance.

Geometry (one convention for the whole package):

- the driving gear turns about O1 = (0, 0) counter-clockwise by φ, the driven gear about O2 = (L, 0) clockwise by
  θ(φ); ``driving_turns = n``: the **driving** gear turns n times per driven turn (paper 001: n = 2), so the driven
  pitch curve is n times as long as the driving one;
- the pitch point lies on O1O2 at r1 = L·k/(1 + k) from O1, k = dθ/dφ, and r1 + r2 = L; rolling without slip
  r1 dφ = r2 dθ;
- body frames: the driving pitch point at rotation φ has body polar angle −φ (mod 2π); the driven one has body polar
  angle π + θ (mod 2π). So ``driving.radius_at(-phi) + driven.radius_at(pi + law(phi)) = L``.

Besides the two dataclasses of the shared interface (:class:`PitchCurve`, :class:`PitchPair`) this module checks
closure, finds corners (tangent jumps) and concave stretches, and flags undercut risk for a module.
:class:`PitchPair` was called ``GearPair`` (a deprecated alias, kept for one release): that name is now only
the gear pair of a mechanism, :class:`assur.model.gearing.GearPair`.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Callable

import numpy as np

from ..errors import GearError
from ..tolerances import DEFAULT as TOL
from .errors import angle_ranges
from .law import TWO_PI, TransmissionLaw, as_law

#: finite-difference step (rad) for derivatives of exactly known radius functions
_H = 1e-5
#: points used for perimeters
_PERIMETER_POINTS = 1 << 15


@dataclass(frozen=True, slots=True, eq=False)   # array fields: compare by identity
class PitchCurve:
    """One gear's closed pitch curve in its own body frame, centre at the origin.

    angle: (N,) body-frame polar angle, strictly increasing, covering [angle[0], angle[0] + 2π).
    radius: (N,) pitch radius r(angle) > 0, m.
    function: optional exact periodic r(a) (vectorised); without it ``radius_at`` interpolates the samples with a
    periodic cubic spline.
    """
    angle: np.ndarray
    radius: np.ndarray
    function: Callable | None = field(default=None, compare=False)
    _cache: dict = field(default_factory=dict, init=False, repr=False, compare=False)

    def __post_init__(self):
        object.__setattr__(self, "angle", np.asarray(self.angle, dtype=float))
        object.__setattr__(self, "radius", np.asarray(self.radius, dtype=float))

    def _spline(self):
        s = self._cache.get("spline")
        if s is None:
            from scipy.interpolate import CubicSpline
            a = np.append(self.angle, self.angle[0] + TWO_PI)
            r = np.append(self.radius, self.radius[0])
            s = self._cache["spline"] = CubicSpline(a, r, bc_type="periodic")
        return s

    def _wrap(self, a):
        a0 = self.angle[0]
        return a0 + np.mod(np.asarray(a, dtype=float) - a0, TWO_PI)

    def radius_at(self, a) -> np.ndarray:
        """r at any body angles a (...,) → (...), m (periodic)."""
        if self.function is not None:
            return np.asarray(self.function(np.mod(np.asarray(a, dtype=float), TWO_PI)), dtype=float)
        return self._spline()(self._wrap(a))

    def slope(self, a) -> np.ndarray:
        """dr/da at angles a (...,) → (...), m/rad (central difference for an exact function)."""
        if self.function is not None:
            a = np.asarray(a, dtype=float)
            return (self.radius_at(a + _H) - self.radius_at(a - _H)) / (2 * _H)
        return self._spline()(self._wrap(a), 1)

    def _second(self, a):
        if self.function is not None:
            a = np.asarray(a, dtype=float)
            h = 1e-3   # truncation ~h²r''''/12; noise of a spline law ~1e-13/h²
            return (self.radius_at(a + h) - 2 * self.radius_at(a) + self.radius_at(a - h)) / (h * h)
        return self._spline()(self._wrap(a), 2)

    def xy_at(self, a) -> np.ndarray:
        """Points of the curve at body angles a (...,) → (..., 2), m."""
        a = np.asarray(a, dtype=float)
        r = self.radius_at(a)
        return np.stack([r * np.cos(a), r * np.sin(a)], axis=-1)

    def xy(self, n: int | None = None) -> np.ndarray:
        """(n, 2) closed-curve points, not repeating the first (n=None: the stored samples), m."""
        if n is None:
            a, r = self.angle, self.radius
        else:
            key = ("xy", int(n))
            if key not in self._cache:      # kept: the writers and the plots ask for the same curve several times
                a = self.angle[0] + np.arange(n) * (TWO_PI / n)
                r = self.radius_at(a)
                self._cache[key] = np.stack([r * np.cos(a), r * np.sin(a)], axis=-1)
            return self._cache[key].copy()
        return np.stack([r * np.cos(a), r * np.sin(a)], axis=-1)

    @property
    def perimeter(self) -> float:
        """Arc length of the closed curve, m: a polyline through 2¹⁵ points (relative error ~1e-9; exact at corners)."""
        p = self._cache.get("perimeter")
        if p is None:
            pts = self.xy(_PERIMETER_POINTS)
            p = self._cache["perimeter"] = float(np.linalg.norm(np.roll(pts, -1, axis=0) - pts, axis=-1).sum())
        return p

    def curvature(self, a) -> np.ndarray:
        """Signed curvature (1/m) at angles a (...,) → (...); > 0 convex, < 0 concave.

        κ = (r² + 2r′² − r r″) / (r² + r′²)^{3/2}. Meaningless exactly at a corner (see :func:`find_corners`)."""
        r = self.radius_at(a)
        d1 = self.slope(a)
        d2 = self._second(a)
        return (r * r + 2 * d1 * d1 - r * d2) / (r * r + d1 * d1) ** 1.5

    def arc_length(self, a_from, a_to, points: int = 1025) -> np.ndarray:
        """Arc length from a_from to a_to (a_to ≥ a_from, same shape (...)), m, by Simpson's rule."""
        from scipy.integrate import simpson
        a_from = np.asarray(a_from, dtype=float)
        t = np.linspace(0.0, 1.0, points)
        a = a_from[..., None] + (np.asarray(a_to, dtype=float) - a_from)[..., None] * t
        ds = np.hypot(self.radius_at(a), self.slope(a))
        return simpson(ds, x=a, axis=-1)


@dataclass(frozen=True, slots=True, eq=False)   # array fields: compare by identity
class PitchPair:
    """A pair of rolling pitch curves at centre distance L (see the module docstring for conventions).

    phi: (N,) driving rotation over the full cycle 0 … 2π·driving_turns (endpoint excluded);
    theta: (N,) driven rotation θ(φ), 0 … 2π. ``transmission`` (optional) is the exact law.
    """
    centre_distance: float
    driving_turns: int
    phi: np.ndarray
    theta: np.ndarray
    driving: PitchCurve
    driven: PitchCurve
    transmission: TransmissionLaw | None = field(default=None, compare=False)

    def law(self, phi) -> np.ndarray:
        """θ(φ) at any φ (...,) → (...), rad (periodic continuation beyond one cycle)."""
        if self.transmission is not None:
            return self.transmission.theta(phi)
        phi = np.asarray(phi, dtype=float)
        cycle = TWO_PI * self.driving_turns
        j = np.floor(phi / cycle)
        u = phi - j * cycle
        grid = np.append(self.phi, cycle)
        vals = np.append(self.theta, self.theta[0] + TWO_PI)
        return j * TWO_PI + np.interp(u, grid, vals)

    def ratio(self, phi) -> np.ndarray:
        """dθ/dφ = r1/r2 at any φ (...,) → (...)."""
        if self.transmission is not None:
            return self.transmission.ratio(phi)
        phi = np.asarray(phi, dtype=float)
        return self.driving.radius_at(-phi) / self.driven.radius_at(math.pi + self.law(phi))

    def contact_radii(self, phi) -> tuple[np.ndarray, np.ndarray]:
        """(r1, r2) at the pitch point for driving rotations φ (...,), m."""
        phi = np.asarray(phi, dtype=float)
        return self.driving.radius_at(-phi), self.driven.radius_at(math.pi + self.law(phi))


def pitch_pair(law=None, centre_distance: float = None, *, ratio=None, driving_turns: int | None = None,
               samples: int = 2048) -> PitchPair:
    """Both pitch curves of the pair that realises ``law`` at ``centre_distance`` (m).

    law: a :class:`TransmissionLaw` (e.g. :class:`WheelStepLaw`), a vectorised callable θ(φ) over [0, 2π·n], or a
    table (φ_i, θ_i) over one driving turn; or ``ratio=`` a callable k(φ). driving_turns: the driving gear's turns
    per driven turn (default: the law's own, or 1). samples: points per driving turn; the pair holds
    N = samples·n samples over the cycle.

    Raises GearError naming the quantity and angle range: centre distance not finite/positive; ratio ≤ 0 (a pitch
    radius ≤ 0); the law or the driving curve does not close."""
    if centre_distance is None or isinstance(centre_distance, bool) or not np.isfinite(centre_distance) \
            or centre_distance <= 0:
        raise GearError(f"the centre distance must be a finite length > 0 m: {centre_distance!r}")
    if not isinstance(samples, (int, np.integer)) or samples < 16:
        raise GearError(f"samples must be a whole number ≥ 16: {samples!r}")
    tl = as_law(law, ratio=ratio, driving_turns=driving_turns)
    n = tl.driving_turns
    L = float(centre_distance)
    phi = np.arange(samples * n) * (TWO_PI / samples)
    theta = tl.theta(phi)
    k = tl.ratio(phi)
    bad = ~(np.isfinite(k) & (k > 0))
    if bad.any():
        raise GearError(f"pitch radius of the driving gear ≤ 0 (speed ratio dθ/dφ ≤ 0) for φ ∈ "
                        f"{angle_ranges(phi, bad)}")
    if abs(tl.theta(TWO_PI * n) - TWO_PI) > TOL.law_closure:
        raise GearError(f"the law does not close: θ(2π·{n}) = {math.degrees(tl.theta(TWO_PI * n)):.4f}°, must be 360°")
    r1 = L * k / (1.0 + k)
    r2 = L - r1
    # driving curve: one driving turn; body angle −φ
    a1 = np.mod(-phi[:samples], TWO_PI)
    o1 = np.argsort(a1)
    # driven curve: the whole cycle; body angle π + θ
    a2 = np.mod(math.pi + theta, TWO_PI)
    o2 = np.argsort(a2)

    def r_driving(a):
        kk = tl.ratio(-np.asarray(a, dtype=float))
        return L * kk / (1.0 + kk)

    def r_driven(b):
        kk = tl.ratio_of_theta(np.asarray(b, dtype=float) - math.pi)
        return L / (1.0 + kk)

    driving = PitchCurve(a1[o1], r1[:samples][o1], function=r_driving)
    driven = PitchCurve(a2[o2], r2[o2], function=r_driven)
    return PitchPair(L, n, phi, theta, driving, driven, transmission=tl)


# ---------------------------------------------------------------------------------------------------------------
# checks and reports


@dataclass(frozen=True, slots=True)
class ClosureReport:
    """How well the two pitch curves close and roll (all from the curves, not assumed)."""
    law_end: float                 #: θ(2π·n), rad (must be 2π)
    centre_distance_error: float   #: max |r1 + r2 − L| over the cycle, m
    driving_perimeter: float       #: m
    driven_perimeter: float        #: m
    perimeter_ratio: float         #: driven / driving (must be driving_turns)
    rolling_error: float           #: max |arc driven − arc driving| over the sample steps, relative to the step arc


def closure_report(pair: PitchPair, steps: int = 64) -> ClosureReport:
    """Closure and rolling check: r1 + r2 = L, θ(2πn) = 2π, driven/driving perimeter = n, equal arc elements."""
    phi = np.linspace(0.0, TWO_PI * pair.driving_turns, steps + 1)
    r1, r2 = pair.contact_radii(phi)
    theta = pair.law(phi)
    arc1 = pair.driving.arc_length(-phi[1:], -phi[:-1])
    arc2 = pair.driven.arc_length(math.pi + theta[:-1], math.pi + theta[1:])
    return ClosureReport(
        law_end=float(pair.law(TWO_PI * pair.driving_turns)),
        centre_distance_error=float(np.max(np.abs(r1 + r2 - pair.centre_distance))),
        driving_perimeter=pair.driving.perimeter,
        driven_perimeter=pair.driven.perimeter,
        perimeter_ratio=pair.driven.perimeter / pair.driving.perimeter,
        rolling_error=float(np.max(np.abs(arc2 - arc1) / arc1)))


@dataclass(frozen=True, slots=True)
class Corner:
    """A tangent discontinuity of a pitch curve."""
    angle: float        #: body polar angle of the vertex, rad
    radius: float       #: m
    tangent_jump: float  #: signed turn of the tangent at the vertex, rad (> 0 convex vertex, < 0 re-entrant)

    @property
    def kind(self) -> str:
        return "convex" if self.tangent_jump > 0 else "re-entrant"


def _heading(curve, a_from, a_to):
    p, q = curve.xy_at(a_from), curve.xy_at(a_to)
    return np.arctan2(q[..., 1] - p[..., 1], q[..., 0] - p[..., 0])


def _refine_corner(curve, lo, hi, reach, iterations=40):
    """Locate a tangent discontinuity inside [lo, hi] by repeated quartering (the vertex with the largest chord
    turn keeps the corner), then measure its jump: on each side the tangent heading (a 2e-6 rad chord) at distances
    reach, 2·reach, 3·reach is extrapolated quadratically to the corner (error O(reach³), free of the corner)."""
    for _ in range(iterations):
        q = np.linspace(lo, hi, 5)
        h = _heading(curve, q[:-1], q[1:])
        turn = np.abs(np.angle(np.exp(1j * (h[1:] - h[:-1]))))
        k = int(np.argmax(turn)) + 1
        lo, hi = q[k - 1], q[k + 1]
        if hi - lo < 1e-13:
            break
    a, d, tiny = 0.5 * (lo + hi), reach, 1e-6
    wrap = lambda x: np.angle(np.exp(1j * x))  # noqa: E731
    tangent = lambda x: _heading(curve, x - tiny, x + tiny)  # noqa: E731

    def one_sided(sign):
        t1, t2, t3 = (tangent(a + sign * n * d) for n in (1, 2, 3))
        return t1 - 3.0 * wrap(t2 - t1) + wrap(t3 - t1)   # quadratic extrapolation to the corner: 3t1 − 3t2 + t3

    right, left = one_sided(+1.0), one_sided(-1.0)
    return a, float(wrap(right - left))


def find_corners(curve: PitchCurve, *, points: int = 8192, min_jump: float = math.radians(1.0)) -> list[Corner]:
    """Corners of a closed pitch curve: vertices of a dense polyline whose turning angle stands out.

    The polyline (``points`` uniform body angles) turns by about κ·ds per vertex where the curve is smooth; a corner
    adds its whole tangent jump at one vertex (or splits it between neighbours, which are merged). A vertex is a
    corner when its turning exceeds ``min_jump`` and 50× the median turning. The corner is then located to ~1e-12
    rad by repeated quartering and its jump measured from one-sided tangents extrapolated from 2e-3…6e-3 rad away
    (for a curve interpolated from samples: 3 sample spacings away, since the spline rounds the corner there)."""
    a = curve.angle[0] + np.arange(points) * (TWO_PI / points)
    pts = curve.xy(points)
    seg = np.roll(pts, -1, axis=0) - pts                     # segment i: vertex i → i+1
    heading = np.arctan2(seg[:, 1], seg[:, 0])
    turn = np.angle(np.exp(1j * (heading - np.roll(heading, 1))))   # turning at vertex i
    typical = np.median(np.abs(turn))
    flagged = set(np.flatnonzero(np.abs(turn) > max(min_jump, 50 * typical)).tolist())
    step = TWO_PI / points
    if curve.function is not None:
        reach = 2e-3
    else:
        reach = 3.0 * float(np.max(np.diff(np.append(curve.angle, curve.angle[0] + TWO_PI))))
    corners, used = [], set()
    for i in sorted(flagged):
        if i in used:
            continue
        group = [i]
        while (group[-1] + 1) % points in flagged:
            group.append((group[-1] + 1) % points)
        while (group[0] - 1) % points in flagged and (group[0] - 1) % points not in group:
            group.insert(0, (group[0] - 1) % points)
        used.update(group)
        centre = group[int(np.argmax(np.abs(turn[group])))]
        where, jump = _refine_corner(curve, a[centre] - step, a[centre] + step, reach)
        corners.append(Corner(angle=float(np.mod(where, TWO_PI)), radius=float(curve.radius_at(where)),
                              tangent_jump=jump))
    return sorted(corners, key=lambda c: c.angle)


@dataclass(frozen=True, slots=True)
class CurvatureReport:
    """Convexity and cutting limits of one pitch curve, sampled away from its corners."""
    corners: list                 #: [Corner]
    min_convex_radius: float      #: smallest radius of curvature where convex, m (inf if none)
    min_convex_angle: float       #: body angle of it, rad
    concave_ranges: str           #: body-angle ranges where the curve is concave ("" if convex)
    min_concave_radius: float     #: smallest |radius of curvature| where concave, m (inf if none)
    undercut_ranges: str          #: ranges where |radius of curvature| < the undercut limit of the module ("" if none)
    undercut_limit: float         #: m/sin²α for the given module and pressure angle (nan if none given)


def curvature_report(curve: PitchCurve, *, module: float | None = None, pressure_angle: float = math.radians(20.0),
                     points: int = 4096) -> CurvatureReport:
    """Corners, concave stretches and undercut risk of a pitch curve.

    Undercut criterion: a rack-generated tooth of module m and pressure angle α on a stretch of pitch curve with
    radius of curvature ρ is free of undercut if ρ ≥ m/sin²α (the circular-gear limit z ≥ 2/sin²α applied to the
    osculating circle); concave stretches are held to the same limit on |ρ| (an internal-gear-like flank needs a
    cutter smaller than |ρ|). Samples within 3 grid steps of a corner are ignored (the curvature is a Dirac there)."""
    corners = find_corners(curve)
    a = curve.angle[0] + np.arange(points) * (TWO_PI / points)
    near = np.zeros(points, dtype=bool)
    for c in corners:
        d = np.abs(np.angle(np.exp(1j * (a - c.angle))))
        near |= d < 3.5 * TWO_PI / points
    kappa = curve.curvature(a)
    rho = np.where(kappa != 0, 1.0 / np.where(kappa != 0, kappa, 1.0), np.inf)
    convex = (kappa > 0) & ~near
    concave = (kappa < 0) & ~near
    ordered = np.argsort(np.mod(a, TWO_PI))
    a_sorted = np.mod(a, TWO_PI)[ordered]
    if convex.any():
        i = np.argmin(np.where(convex, rho, np.inf))
        min_cv, min_cv_a = float(rho[i]), float(np.mod(a[i], TWO_PI))
    else:
        min_cv, min_cv_a = math.inf, math.nan
    min_cc = float(np.min(np.abs(rho[concave]))) if concave.any() else math.inf
    if module is not None:
        limit = module / math.sin(pressure_angle) ** 2
        risky = (np.abs(rho) < limit) & ~near
        undercut = angle_ranges(a_sorted, risky[ordered])
    else:
        limit, undercut = math.nan, ""
    return CurvatureReport(corners=corners, min_convex_radius=min_cv, min_convex_angle=min_cv_a,
                           concave_ranges=angle_ranges(a_sorted, concave[ordered]), min_concave_radius=min_cc,
                           undercut_ranges=undercut, undercut_limit=limit)


def check_module(pair: PitchPair, module: float, pressure_angle: float = math.radians(20.0)) -> None:
    """Raise GearError if the module is too large for the pitch-curve curvature of either gear (see
    :func:`curvature_report`), naming the gear and the body-angle range."""
    if not (np.isfinite(module) and module > 0):
        raise GearError(f"the module must be a finite length > 0 m: {module!r}")
    for name, curve in (("driving", pair.driving), ("driven", pair.driven)):
        rep = curvature_report(curve, module=module, pressure_angle=pressure_angle)
        if rep.undercut_ranges:
            raise GearError(f"module {module * 1e3:.4g} mm is too large for the curvature of the {name} pitch curve: "
                            f"its radius of curvature is below m/sin²α = {rep.undercut_limit * 1e3:.4g} mm for body "
                            f"angle ∈ {rep.undercut_ranges}")


def speed_law(pair: PitchPair, phi) -> np.ndarray:
    """Driven angular speed per unit driving speed, θ̇/φ̇ = k(φ), (...) → (...)."""
    return pair.ratio(phi)


def __getattr__(name: str):
    """``GearPair``: the deprecated name of :class:`PitchPair` (warns with a DeprecationWarning)."""
    if name == "GearPair":
        import warnings
        warnings.warn("assur.gears.pitch.GearPair is deprecated: use PitchPair (a pair of pitch curves; GearPair "
                      "names a mechanism's gear pair, assur.model.gearing.GearPair)", DeprecationWarning, stacklevel=2)
        return PitchPair
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
