"""Teeth along the exact pitch curve: the envelope of a straight-sided rack cutter rolled without slip.

Method (exact for any pitch curve, circular or not). The basic rack's pitch line rolls on the gear's pitch curve;
at contact arc length s the rack pitch line is tangent to the curve at P(s), rack abscissa u = s sits on P(s), and a
rack point (u, v) (u along the line in the rolling direction, v outward from the gear) lies in the gear's body frame
at

    X(u, v; s) = P(s) + (u − s)·T(s) + v·N(s)          T tangent, N outward normal of the pitch curve at P(s).

The instantaneous centre of the rack's motion relative to the gear is P(s) itself, so (fundamental law of gearing)
the point of a rack flank *line* that touches its envelope at s is the foot of the perpendicular from (s, 0) onto
that line — no differentiation and no discretisation error in the flank points. The other parts of the swept
boundary are the root (the envelope of the rack tip line, i.e. the pitch curve offset by −h_f), and the trochoids
traced by the rack's tip corners (the root fillets; where they cut a flank the gear is undercut). Where the pitch
curve has a corner the rack pivots about the corner point, which the path samples represent by extra states at the
same s with the tangent turning.

The gear outline is the blank (pitch curve offset by +h_a, the tip) minus everything the rack sweeps, computed
by polygon booleans (:mod:`assur.gears.cutting`): every cutter tooth in every rack state of its engagement window is
a polygon carrying the exact envelope points of that state, the union of all of them is subtracted from the blank.
The result is one simple polygon by construction; it is then checked (:mod:`assur.gears.outline`: simplicity,
point spacing ≤ m/8, slivers and needle-like notches, the number of teeth and their thickness on the pitch curve),
and the findings are carried in ``GearOutline.defects`` and the pair's notes, with their body angles. On a concave
stretch a straight rack cuts the neighbouring teeth as well (its teeth turn with the tangent); the outline is then
what such a rack would cut, and the thinned teeth are reported where they are.

Rack (the basic rack of ISO 53 without the tip radius): pitch p = π·m, pressure angle α, tooth of the cutter (= the
gear's space) w = p/2 + j_n/(2·cos α) wide on the pitch line (the pair's normal backlash j_n is taken equally from
both gears), cutter tip at v = −h_f = −(h_a* + c*)·m (the gear's root), gear tip at v = +h_a*·m.

The generating rack acts only near its contact: each cutter tooth while one of its flanks touches its envelope
(foot point between −h_f and h_a + c), a quarter pitch more for its tip corners; the rack's body is not modelled. A rack cannot follow a
corner of the pitch curve (the paper-001 law has kinks at the step boundaries); :func:`rounded_pair` rounds them
first, and the mesh check shows what the rounding costs.

Conventions (those of :mod:`assur.gears.pitch`): the driving gear turns counter-clockwise by φ with its pitch point
at body angle −φ, the driven gear clockwise by θ with its pitch point at π + θ. The driving gear has a tooth *space*
centred on its φ = 0 pitch point and the driven gear a *tooth* there, so the two outlines mesh in the position
φ = 0, θ = θ(0).
"""
from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass, field

import numpy as np

from ..errors import GearError
from ..tolerances import DEFAULT as TOL
from .errors import angle_ranges
from .pitch import Corner
from .cutting import cut_polygon, densify
from .cache import cached
from .outline import outline_defects, pitch_ring_angles
from .raster import TWO_PI, periodic_interp, wrap_angle
from .rounding import rounded_pair

#: largest distance between consecutive outline points, in modules
MAX_STEP = 0.125


# -- result objects --------------------------------------------------------------------------------
@dataclass(frozen=True, slots=True)
class ToothParameters:
    """The cutter: module m (m), pressure angle α (rad), coefficients of addendum h_a*, clearance c*, and the
    pair's normal backlash j_n (m)."""

    module: float
    pressure_angle: float = math.radians(20.0)
    addendum: float = 1.0
    clearance: float = 0.25
    backlash: float = 0.0
    tip_radius: float = 0.0        #: radius of the rack's tip corners, in modules (ISO 53 profile A: 0.38)
    profile_shift: float = 0.0     #: x: the driving gear is cut with the rack moved out by x·m, the driven by −x·m
    print_clearance: float = 0.0   #: each flank moved into its tooth by this much along the pitch curve, m

    @property
    def pitch(self) -> float:
        """Circular pitch π·m, m."""
        return math.pi * self.module

    @property
    def addendum_height(self) -> float:
        return self.addendum * self.module

    @property
    def dedendum_height(self) -> float:
        return (self.addendum + self.clearance) * self.module

    @property
    def space_width(self) -> float:
        """Width of the cutter tooth (= the gear's tooth space) on the pitch line, m."""
        return 0.5 * self.pitch + 0.5 * self.backlash / math.cos(self.pressure_angle)

    def rack(self, shift: float = 0.0) -> "Rack":
        """The cutter for a gear cut with profile shift coefficient ``shift`` (the rack moved out by shift·m)."""
        m = self.module
        ta = math.tan(self.pressure_angle)
        return Rack(module=m, alpha=self.pressure_angle,
                    half_width=0.5 * self.space_width + self.print_clearance - shift * m * ta,
                    v_tip=-self.dedendum_height + shift * m, v_top=self.addendum_height + self.clearance * m + shift * m,
                    v_blank=self.addendum_height + shift * m, tip_radius=self.tip_radius * m)

    def thickness(self, shift: float = 0.0) -> float:
        """Designed tooth thickness along the pitch curve of a gear cut with profile shift ``shift``, m."""
        return self.pitch - 2.0 * self.rack(shift).half_width

    def check(self) -> None:
        problems = []
        if not (self.module > 0 and math.isfinite(self.module)):
            problems.append(f"module must be > 0: {self.module!r}")
        if not (0 < self.pressure_angle < math.radians(45)):
            problems.append(f"pressure angle must be in (0°, 45°): {math.degrees(self.pressure_angle):.3f}°")
        if not (self.addendum > 0):
            problems.append(f"addendum coefficient must be > 0: {self.addendum!r}")
        if not (self.clearance >= 0):
            problems.append(f"clearance coefficient must be ≥ 0: {self.clearance!r}")
        if not (self.backlash >= 0):
            problems.append(f"backlash must be ≥ 0: {self.backlash!r}")
        if not (self.tip_radius >= 0 and math.isfinite(self.tip_radius)):
            problems.append(f"tip radius coefficient must be ≥ 0: {self.tip_radius!r}")
        if not (abs(self.profile_shift) < 1 and math.isfinite(self.profile_shift)):
            problems.append(f"profile shift coefficient must lie in (−1, 1): {self.profile_shift!r}")
        if not (self.print_clearance >= 0 and math.isfinite(self.print_clearance)):
            problems.append(f"print clearance must be ≥ 0: {self.print_clearance!r}")
        if problems:
            raise GearError("; ".join(problems))
        sa = math.sin(self.pressure_angle)
        rack = self.rack()
        land = rack.half_width + rack.v_tip * math.tan(self.pressure_angle)
        if land <= 0:
            raise GearError(f"the rack cutter comes to a point before the root: tip land {2e3 * land:.4f} mm ≤ 0 "
                            f"(module {1e3 * self.module:g} mm, pressure angle "
                            f"{math.degrees(self.pressure_angle):g}°, dedendum "
                            f"{self.addendum + self.clearance:g}·m, backlash {1e3 * self.backlash:g} mm, print "
                            f"clearance {1e3 * self.print_clearance:g} mm)")
        rho = rack.tip_radius
        if rho > 0 and rho * (1 - sa) > self.clearance * self.module * (1 + 1e-3):   # ISO 53: 0.38 (≈ 0.37995)
            raise GearError(f"tip radius {self.tip_radius:g}·m too large: the rounded rack corner would reach "
                            f"{1e3 * rho * (1 - sa):.4f} mm above the root line, into the working depth (at most "
                            f"clearance·m = {1e3 * self.clearance * self.module:.4f} mm, i.e. tip radius ≤ "
                            f"{self.clearance / (1 - sa):.4f}·m)")
        if rho > 0 and land - rho * (1 - sa) / math.cos(self.pressure_angle) <= 0:
            raise GearError(f"tip radius {self.tip_radius:g}·m too large for the rack's tip land "
                            f"{2e3 * land:.4f} mm: both rounded corners do not fit (at most "
                            f"{land * math.cos(self.pressure_angle) / (1 - sa) / self.module:.4f}·m)")


@dataclass(frozen=True, slots=True)
class Rack:
    """The cutter of one gear in the rolling frame (u along the pitch line, v outward from the gear, m): flanks
    u = u_c ± (half_width + v·tan α), tip line v = v_tip (the gear's root), top v = v_top, the gear's blank at
    v = v_blank (its tip), tip corners rounded with radius tip_radius."""

    module: float
    alpha: float
    half_width: float
    v_tip: float
    v_top: float
    v_blank: float
    tip_radius: float = 0.0


@dataclass(frozen=True, slots=True)
class GearOutline:
    """One gear's closed tooth outline in its body frame (centre at the origin).

    xy: (M, 2) counter-clockwise simple closed polygon (first point not repeated), m: the blank minus every
    position of the cutter (:mod:`assur.gears.cutting`), its edges split to at most ``max_step`` (m/8).
    ``undercut``: body-angle ranges (rad) where a working flank has an envelope cusp (the cutter's tip cuts the
    flank; text in ``undercut_text``). ``corners``: corners of the pitch curve. ``mirror``: True for the gear
    whose pitch point moves clockwise on its body (the driving gear). ``defects``: the located findings of
    :func:`assur.gears.outline.outline_defects` (empty for a clean outline)."""

    name: str
    teeth: int
    tooth: ToothParameters
    xy: np.ndarray
    perimeter: float
    undercut: tuple = ()
    undercut_text: str = ""
    corners: tuple = ()
    min_curvature_radius: float = math.inf
    mirror: bool = False
    defects: tuple = ()
    shift: float = 0.0

    @property
    def radius(self) -> np.ndarray:
        """(M,) distance of each outline vertex from the centre, m."""
        return np.hypot(self.xy[:, 0], self.xy[:, 1])

    @property
    def angle(self) -> np.ndarray:
        """(M,) body polar angle of each outline vertex, rad in [0, 2π)."""
        return np.mod(np.arctan2(self.xy[:, 1], self.xy[:, 0]), TWO_PI)

    @property
    def tip_radius(self) -> float:
        return float(self.radius.max())

    @property
    def root_radius(self) -> float:
        return float(self.radius.min())

    def radius_at(self, a) -> np.ndarray:
        """Distance from the centre to the outline along body directions a (...,): the first crossing of the
        polygon from the centre (exact ray casting), m."""
        return first_crossing(self.xy, a)


def first_crossing(xy, a, chunk: int = 256) -> np.ndarray:
    """Distance from the origin to the first crossing of the closed polygon xy (M, 2) along directions a (...),
    by exact ray–edge intersection (inf where the ray crosses nothing)."""
    a = np.asarray(a, dtype=float)
    flat = a.ravel()
    u = np.stack([np.cos(flat), np.sin(flat)], axis=-1)
    p, q = xy, np.roll(xy, -1, axis=0)
    e = q - p
    out = np.full(flat.size, np.inf)
    for i in range(0, flat.size, chunk):
        d = u[i:i + chunk, None, :]                                   # (c, 1, 2)
        den = d[..., 0] * e[None, :, 1] - d[..., 1] * e[None, :, 0]   # d × e
        with np.errstate(divide="ignore", invalid="ignore"):
            t = (p[None, :, 0] * e[None, :, 1] - p[None, :, 1] * e[None, :, 0]) / den    # along the ray
            w = (p[None, :, 0] * d[..., 1] - p[None, :, 1] * d[..., 0]) / den            # along the edge
        # a ray through a vertex meets both edges there: each end is kept within round-off (the nearest counts)
        hit = (den != 0) & (t > 0) & (w >= -1e-12) & (w <= 1 + 1e-12)
        out[i:i + chunk] = np.where(hit, t, np.inf).min(axis=1)
    return out.reshape(a.shape)


@dataclass(frozen=True, slots=True)
class GearTeeth:
    """Both gears of a pair cut by the same basic rack."""

    driving: GearOutline
    driven: GearOutline
    tooth: ToothParameters
    centre_distance: float
    driving_turns: int
    notes: tuple = field(default=())


# -- small helpers ---------------------------------------------------------------------------------
def _deg(x):
    return f"{math.degrees(x):.1f}°"


# -- the rolling path ------------------------------------------------------------------------------
@dataclass(frozen=True, slots=True)
class _Path:
    s: np.ndarray      # (J,) arc length, non-decreasing, 0 … perimeter (endpoint excluded)
    point: np.ndarray  # (J, 2) pitch point P
    tau: np.ndarray    # (J,) tangent angle (unwrapped)
    perimeter: float


def _pitch_polyline(radius_of, start: float, samples: int):
    """Dense ccw polyline of the pitch curve r = radius_of(ψ) from body angle ``start``: (ψ (N,), P (N, 2))."""
    psi = start + np.arange(samples) * (TWO_PI / samples)
    r = np.asarray(radius_of(psi), dtype=float)
    if not np.all(np.isfinite(r)) or np.any(r <= 0):
        bad = ~(np.isfinite(r) & (r > 0))
        raise GearError(f"pitch radius ≤ 0 or not finite for body angle ∈ {angle_ranges(psi, bad)}")
    return psi, np.stack([r * np.cos(psi), r * np.sin(psi)], axis=-1)


def _rolling_path(points, max_turn: float) -> tuple[_Path, np.ndarray, np.ndarray]:
    """The rack's states along a closed ccw polyline: arc length, point, tangent angle; extra states where the
    tangent turns by more than ``max_turn`` between samples (corners). Also returns the turn (N,) at each sample
    (tangent of the outgoing chord minus that of the incoming one)."""
    nxt = np.roll(points, -1, axis=0)
    chord = nxt - points
    seg = np.hypot(chord[:, 0], chord[:, 1])
    s_vertex = np.concatenate([[0.0], np.cumsum(seg)[:-1]])
    perimeter = float(seg.sum())
    seg_dir = np.arctan2(chord[:, 1], chord[:, 0])             # direction of chord i (vertex i → i+1)
    turn = wrap_angle(seg_dir - np.roll(seg_dir, 1))                 # at vertex i: chord i−1 → chord i
    # tangent at a vertex of a smooth curve = mean of the two chords; through a corner the rack pivots from the
    # incoming to the outgoing chord direction, so each vertex gets k ≥ 1 states spread over its turn.
    prev_dir = seg_dir - turn
    k = np.maximum(1, np.ceil(np.abs(turn) / max_turn).astype(np.intp))
    if k.max() == 1:
        tau_v = prev_dir + 0.5 * turn
        tau = np.unwrap(tau_v)
        return _Path(s_vertex, points, tau, perimeter), turn, seg
    owner = np.repeat(np.arange(points.shape[0]), k)
    first = np.concatenate([[0], np.cumsum(k)[:-1]])
    j = np.arange(owner.size) - first[owner]
    frac = np.where(k[owner] == 1, 0.5, j / np.maximum(k[owner] - 1, 1))
    tau = np.unwrap(prev_dir[owner] + frac * turn[owner])
    return _Path(s_vertex[owner], points[owner], tau, perimeter), turn, seg


# -- one gear ----------------------------------------------------------------------------------------
def _cut(polyline, tooth: ToothParameters, teeth: int, *, rack_phase: float, max_turn: float, name: str = "gear",
         shift: float = 0.0):
    """Cut one gear whose pitch curve, the polyline (ψ (N,), P (N, 2)) of :func:`_pitch_polyline`, is traversed
    counter-clockwise from its first point (arc 0).

    Cutter teeth (the gear's spaces) are centred at u = (rack_phase + k)·p, k = 0 … teeth−1; gear tooth k lies
    between cutter teeth k and k+1. Returns (outline (M, 2) ccw, :func:`assur.gears.cutting.cut_polygon`;
    undercut body angles (list); (smallest radius of curvature, corners, polyline perimeter))."""
    psi_v, pts = polyline
    path, turn, seg = _rolling_path(pts, max_turn)
    rc_min, corners = _curvature_check(name, turn, seg, tooth, psi_v, np.hypot(pts[:, 0], pts[:, 1]))
    p = tooth.pitch
    alpha = tooth.pressure_angle
    m = tooth.module
    rack = tooth.rack(shift)
    w2 = rack.half_width
    sa, ca = math.sin(alpha), math.cos(alpha)
    per = path.perimeter
    pitch = per / teeth                     # = p within the caller's tolerance: spread over the exact perimeter
    centres = (rack_phase + np.arange(teeth)) * pitch                            # (Z,)
    # engagement of a cutter tooth: its flanks touch their envelope (foot point between the cutter's tip and root
    # lines) for |s − u_c| ≤ w/2 + (h_a + c)/(sin α cos α); a quarter pitch more for the tip corners' fillets
    window = w2 + max(rack.v_top, -rack.v_tip) / (sa * ca) + 0.25 * p
    # the path three times (s − per, s, s + per) so windows can wrap
    J = path.s.size
    s3 = np.concatenate([path.s - per, path.s, path.s + per])
    idx3 = np.concatenate([np.arange(J)] * 3)
    j0 = np.searchsorted(s3, centres - window, side="left")
    j1 = np.searchsorted(s3, centres + window, side="right")
    K = int((j1 - j0).max())
    jj = j0[:, None] + np.arange(K)[None, :]                                     # (Z, K)
    inside = jj < j1[:, None]
    jj = np.minimum(jj, s3.size - 1)
    s = s3[jj]                                                                   # (Z, K)
    P = path.point[idx3[jj]]                                                     # (Z, K, 2)
    tau = path.tau[idx3[jj]]
    T = np.stack([np.cos(tau), np.sin(tau)], axis=-1)
    N = np.stack([T[..., 1], -T[..., 0]], axis=-1)
    uc = centres[:, None]

    undercut = []
    # the working flank: down to where the mating gear's tip reaches (its addendum, shifted the other way)
    reach = -(tooth.addendum_height - shift * m)
    for side in (-1.0, 1.0):   # left flank (u = uc − w/2 − v·tanα), right flank (u = uc + w/2 + v·tanα)
        a_u = uc + side * w2
        v_foot = side * (s - a_u) * sa * ca
        u_foot = a_u + side * v_foot * math.tan(alpha)
        ok = inside & (v_foot >= rack.v_tip) & (v_foot <= rack.v_top)
        X = P + (u_foot - s)[..., None] * T + v_foot[..., None] * N
        undercut += _cusps(X, ok & (v_foot >= reach - 1e-12 * m))
    tip_xy = path.point + rack.v_blank * np.stack([np.sin(path.tau), -np.cos(path.tau)], axis=-1)
    xy = cut_polygon(P, T, N, s, inside, centres, rack, tip_xy)
    return xy, undercut, (rc_min, corners, float(seg.sum()))


def _cusps(X, ok):
    """Body angles (list, rad) of envelope cusps — the flank's direction reverses — along the valid (``ok``
    (Z, K)) stretches of the polylines X (Z, K, 2)."""
    d = np.diff(X, axis=-2)
    both = ok[:, 1:] & ok[:, :-1]
    dot = np.einsum("zki,zki->zk", d[:, 1:], d[:, :-1])
    lens = np.hypot(d[..., 0], d[..., 1])
    meaningful = (lens[:, 1:] > 0) & (lens[:, :-1] > 0)
    cusp = both[:, 1:] & both[:, :-1] & meaningful & (dot < 0)
    out = []
    for z, k in zip(*np.nonzero(cusp)):
        pt = X[z, k + 1]
        out.append(float(np.arctan2(pt[1], pt[0])))
    return out


def _angle_runs(angles, tol):
    """Group angles (rad) into ranges (lo, hi) of points closer than tol."""
    if not angles:
        return ()
    a = np.sort(np.mod(np.asarray(angles), TWO_PI))
    runs = []
    lo = hi = a[0]
    for x in a[1:]:
        if x - hi <= tol:
            hi = x
        else:
            runs.append((float(lo), float(hi)))
            lo = hi = x
    runs.append((float(lo), float(hi)))
    return tuple(runs)


def _curvature_check(name, turn, seg, tooth, psi_of_vertex, radius_of_vertex):
    """Smallest radius of curvature of the smooth parts (corners excluded) and the corners of a pitch polyline.

    Raises GearError when |radius of curvature| < tooth depth (h_a + h_f) anywhere on a smooth part: the root
    or tip offset folds, no tooth fits there ("module too large for the curvature")."""
    # chord-by-chord turning; a corner is a turn much larger than its neighbours' (a kink of the curve)
    ds = 0.5 * (seg + np.roll(seg, 1))
    curvature = turn / ds                                        # (N,) at the vertices, 1/m
    a = np.abs(turn)
    local = np.maximum(np.roll(a, 1), np.roll(a, -1))
    corner = (a > math.radians(0.5)) & (a > 4.0 * np.median(a) + 1e-12) & (a > 2.0 * local)
    near_corner = corner | np.roll(corner, 1) | np.roll(corner, -1) | np.roll(corner, 2) | np.roll(corner, -2)
    corners = tuple(Corner(float(np.mod(psi_of_vertex[i], TWO_PI)), float(radius_of_vertex[i]), float(turn[i]))
                    for i in np.flatnonzero(corner))
    smooth = ~near_corner
    with np.errstate(divide="ignore"):
        rc = np.where(smooth, 1.0 / np.abs(curvature), np.inf)
    depth = tooth.addendum_height + tooth.dedendum_height
    bad = rc < depth
    if bad.any():
        raise GearError(f"{name} gear: the module {1e3 * tooth.module:g} mm is too large for the curvature of "
                        f"its pitch curve: radius of curvature {1e3 * rc[bad].min():.3f} mm < tooth depth "
                        f"{1e3 * depth:.3f} mm for body angle ∈ {angle_ranges(np.mod(psi_of_vertex, TWO_PI), bad)}")
    return float(rc.min()) if np.isfinite(rc.min()) else math.inf, corners


# -- public API --------------------------------------------------------------------------------------
def tooth_count(perimeter: float, module: float | None, teeth: int | None, *, name: str = "driving",
                rel_tol: float = TOL.tooth_perimeter) -> tuple[float, int]:
    """(module, teeth) consistent with a pitch perimeter: perimeter = π·m·z.

    Give either (module derived from z) or both (checked to ``rel_tol``); GearError names the numbers."""
    if teeth is not None:
        if isinstance(teeth, bool) or int(teeth) != teeth or teeth < 3:
            raise GearError(f"tooth count of the {name} gear must be a whole number ≥ 3: {teeth!r}")
        teeth = int(teeth)
    if module is None:
        if teeth is None:
            raise GearError("give the module, the tooth count, or both")
        return perimeter / (math.pi * teeth), teeth
    if not (module > 0 and math.isfinite(module)):
        raise GearError(f"module must be > 0: {module!r}")
    exact = perimeter / (math.pi * module)
    if teeth is None:
        teeth = int(round(exact))
        if teeth < 3 or abs(exact - teeth) > rel_tol * exact:
            raise GearError(f"tooth count: the {name} pitch perimeter {1e3 * perimeter:.4f} mm is not a whole "
                            f"number of circular pitches π·m = {1e3 * math.pi * module:.4f} mm ({exact:.4f} "
                            f"teeth); use m = {1e3 * perimeter / (math.pi * max(3, round(exact))):.5f} mm for "
                            f"{max(3, round(exact))} teeth, or change the centre distance")
        return module, teeth
    if abs(exact - teeth) > rel_tol * exact:
        raise GearError(f"tooth count {teeth} does not divide the {name} pitch perimeter "
                        f"{1e3 * perimeter:.4f} mm into circular pitches π·m = {1e3 * math.pi * module:.4f} mm "
                        f"(perimeter / (π·m) = {exact:.4f}); use m = {1e3 * perimeter / (math.pi * teeth):.5f} mm "
                        f"for {teeth} teeth, or {round(exact)} teeth")
    return module, teeth


def cut_gear(radius_of, tooth: ToothParameters, teeth: int, *, name: str = "gear", start: float = 0.0,
             mirror: bool = False, space_at_start: bool = True, samples: int | None = None,
             max_turn: float = math.radians(0.25), shift: float = 0.0) -> GearOutline:
    """Cut one gear with pitch curve r(ψ) (a vectorised callable, body angle ψ in rad → m).

    The rack rolls from body angle ``start`` counter-clockwise (``mirror=True``: clockwise, i.e. the curve is
    cut in the mirrored frame and mirrored back). ``space_at_start``: a tooth space (else a tooth) is centred on
    the start point. samples: pitch-polyline points = rack states (default 128 per tooth, at least 4096). The
    outline is checked by :func:`assur.gears.outline.outline_defects` (findings in ``defects``). The teeth are
    spread over the exact perimeter; the caller checks that ``teeth`` divides it (:func:`tooth_count`). shift: the
    profile shift coefficient this gear is cut with (:meth:`ToothParameters.rack`).

    The outline is kept in the disk cache of :mod:`assur.gears.cache`, keyed by the pitch curve as sampled here
    (the only way the cut sees it) and every parameter."""
    tooth.check()
    if teeth < 3:
        raise GearError(f"tooth count of the {name} gear must be ≥ 3: {teeth}")
    samples = samples or max(4096, 128 * teeth)
    sign = -1.0 if mirror else 1.0
    r_frame = (lambda a: radius_of(-a)) if mirror else radius_of
    polyline = _pitch_polyline(r_frame, sign * start, samples)
    r_coarse = np.asarray(radius_of(np.linspace(0, TWO_PI, 721)), dtype=float)     # for the undercut grouping
    r_ring = np.asarray(radius_of(pitch_ring_angles(teeth)), dtype=float)          # for the tooth checks
    key = (polyline, r_coarse, r_ring, dataclasses.astuple(tooth), int(teeth), name, bool(mirror),
           bool(space_at_start), float(max_turn), float(shift))

    def compute():
        return _cut_gear(polyline, r_coarse, r_ring, tooth, teeth, name=name, mirror=mirror,
                         space_at_start=space_at_start, max_turn=max_turn, shift=shift)

    def unpack(arrays, meta):
        return GearOutline(name=name, teeth=int(teeth), tooth=tooth, xy=arrays["xy"], perimeter=meta["perimeter"],
                           undercut=tuple(tuple(float(x) for x in u) for u in arrays["undercut"]),
                           undercut_text=meta["undercut_text"],
                           corners=tuple(Corner(*(float(x) for x in c)) for c in arrays["corners"]),
                           min_curvature_radius=meta["min_curvature_radius"], mirror=mirror,
                           defects=tuple(meta["defects"]), shift=shift)
    return cached("gear-outline", key, compute, _pack_outline, unpack)


def _pack_outline(g: GearOutline):
    """The arrays and JSON data of an outline for :func:`assur.gears.cache.cached`."""
    return ({"xy": g.xy, "undercut": np.array(g.undercut, dtype=float).reshape(-1, 2),
             "corners": np.array([(c.angle, c.radius, c.tangent_jump) for c in g.corners], dtype=float).reshape(-1, 3)},
            {"perimeter": g.perimeter, "undercut_text": g.undercut_text,
             "min_curvature_radius": g.min_curvature_radius, "defects": list(g.defects)})


def _cut_gear(polyline, r_coarse, r_ring, tooth, teeth, *, name, mirror, space_at_start, max_turn, shift):
    """The body of :func:`cut_gear`, from the sampled pitch curve: the polyline of the cut (in the mirrored frame
    when ``mirror``), the radii at 721 uniform angles and at :func:`assur.gears.outline.pitch_ring_angles`."""
    xy, cusps, (rc_min, corners, perimeter) = _cut(
        polyline, tooth, teeth, rack_phase=0.0 if space_at_start else 0.5, max_turn=max_turn, name=name,
        shift=shift)
    if mirror:
        xy = xy[::-1] * np.array([1.0, -1.0])
        xy = np.roll(xy, -int(np.argmin(np.mod(np.arctan2(xy[:, 1], xy[:, 0]), TWO_PI))), axis=0)
        cusps = [-c for c in cusps]
        corners = tuple(Corner(float(np.mod(-c.angle, TWO_PI)), c.radius, c.tangent_jump) for c in corners)
    xy = densify(xy, MAX_STEP * tooth.module)
    rmin = float(np.min(r_coarse))
    runs = _angle_runs(cusps, tol=2.0 * tooth.pitch / rmin)
    text = ", ".join(f"[{_deg(lo)}, {_deg(hi)}]" for lo, hi in runs)
    defects = outline_defects(xy, tooth.module, teeth=teeth, name=f"{name} gear", max_step=MAX_STEP * tooth.module,
                              thickness=tooth.thickness(shift), pitch_radius=r_ring)
    return GearOutline(name=name, teeth=int(teeth), tooth=tooth, xy=xy, perimeter=perimeter, undercut=runs,
                       undercut_text=text, corners=corners, min_curvature_radius=rc_min, mirror=mirror,
                       defects=tuple(defects), shift=shift)


def cut_pair(pair, *, module: float | None = None, teeth: int | None = None,
             pressure_angle: float = math.radians(20.0), addendum: float = 1.0, clearance: float = 0.25,
             backlash: float = 0.0, rel_tol: float = TOL.tooth_perimeter, samples: int | None = None,
             tip_radius: float = 0.0, profile_shift: float = 0.0, print_clearance: float = 0.0,
             states_per_tooth: int | None = None) -> GearTeeth:
    """Cut both gears of a :class:`~assur.gears.pitch.PitchPair` with one basic rack.

    module (m) and/or teeth (tooth count of the driving gear): the driving pitch perimeter must be π·m·z within
    ``rel_tol`` (else GearError naming the numbers); the driven gear gets z·driving_turns teeth. pressure_angle in
    rad, backlash = the pair's normal backlash j_n in m; tip_radius (in modules), profile_shift (x: the driving gear
    is cut with +x, the driven with −x, which keeps the centre distance) and print_clearance (m) as in
    :class:`ToothParameters`. samples: rack states per gear (default :func:`cut_gear`'s); states_per_tooth: rack
    states per tooth pitch instead (at least 4096 per gear)."""
    n = int(pair.driving_turns)
    p1, p2 = float(pair.driving.perimeter), float(pair.driven.perimeter)
    m, z1 = tooth_count(p1, module, teeth, name="driving", rel_tol=rel_tol)
    z2 = z1 * n
    exact2 = p2 / (math.pi * m)
    if abs(exact2 - z2) > rel_tol * exact2:
        raise GearError(f"tooth count: the driven pitch perimeter {1e3 * p2:.4f} mm holds {exact2:.4f} circular "
                        f"pitches, not {z2} = {z1}·{n} (driving teeth × driving turns)")
    tooth = ToothParameters(module=m, pressure_angle=pressure_angle, addendum=addendum, clearance=clearance,
                            backlash=backlash, tip_radius=tip_radius, profile_shift=profile_shift,
                            print_clearance=print_clearance)
    theta0 = float(np.asarray(pair.law(0.0)))
    s1 = s2 = samples
    if states_per_tooth is not None and samples is None:
        s1, s2 = max(4096, int(states_per_tooth) * z1), max(4096, int(states_per_tooth) * z2)
    driving = cut_gear(pair.driving.radius_at, tooth, z1, name="driving", start=0.0, mirror=True,
                       space_at_start=True, samples=s1, shift=profile_shift)
    driven = cut_gear(pair.driven.radius_at, tooth, z2, name="driven", start=math.pi + theta0, mirror=False,
                      space_at_start=False, samples=s2, shift=-profile_shift)
    notes = []
    for g in (driving, driven):
        if g.undercut:
            notes.append(f"{g.name} gear: working flanks undercut near body angle {g.undercut_text}")
        notes.extend(f"outline defect: {d}" for d in g.defects)
        for c in g.corners:
            notes.append(f"{g.name} gear: pitch-curve corner at body angle {_deg(c.angle)}, tangent turns by "
                         f"{math.degrees(c.tangent_jump):+.1f}° ({c.kind})")
    return GearTeeth(driving=driving, driven=driven, tooth=tooth, centre_distance=float(pair.centre_distance),
                     driving_turns=n, notes=tuple(notes))


__all__ = ["GearOutline", "GearTeeth", "Rack", "ToothParameters", "cut_gear", "cut_pair", "periodic_interp", "rounded_pair",
           "tooth_count"]
