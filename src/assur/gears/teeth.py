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

The gear outline is the blank (pitch curve offset by +h_a, the tip) minus everything the rack sweeps. Teeth of a
non-circular gear lean with the pitch-curve normal (by tens of degrees near a corner), so a tooth is not
star-shaped about the gear centre; it is star-shaped about a **pole** on its own axis: the point 6·m (at most 0.6 of
the pitch radius) below the pitch point at the tooth centre, along the normal. Each tooth sector — from the root
point at the centre of one space (the pitch point there offset by −h_f) to the next — is sampled on uniform rays
from its pole: along each ray the material ends at the first swept point (the smallest pole distance among all
candidate curves crossing the ray, each candidate a polyline of exact envelope points from the cutter teeth on
either side) or at the tip curve, whichever comes first. The sectors joined in order give one closed polygon.

Rack (the basic rack of ISO 53 without the tip radius): pitch p = π·m, pressure angle α, tooth of the cutter (= the
gear's space) w = p/2 + j_n/(2·cos α) wide on the pitch line (the pair's normal backlash j_n is taken equally from
both gears), cutter tip at v = −h_f = −(h_a* + c*)·m (the gear's root), gear tip at v = +h_a*·m.

The generating rack acts only near its contact: the cutter teeth within a few pitches of the pitch point (their
flanks between −h_f and h_a + c, their tip lands and tip corners); its body beyond is not modelled (on a concave
stretch a real straight rack would also cut the neighbouring tips, which is why concave stretches are held to the
same curvature limit as convex ones by :func:`assur.gears.pitch.curvature_report`). A rack cannot follow a
corner of the pitch curve (the paper-001 law has kinks at the step boundaries); :func:`rounded_pair` rounds them
first, and the mesh check shows what the rounding costs.

Conventions (those of :mod:`assur.gears.pitch`): the driving gear turns counter-clockwise by φ with its pitch point
at body angle −φ, the driven gear clockwise by θ with its pitch point at π + θ. The driving gear has a tooth *space*
centred on its φ = 0 pitch point and the driven gear a *tooth* there, so the two outlines mesh in the position
φ = 0, θ = θ(0).
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from ..errors import GearError
from ..tolerances import DEFAULT as TOL
from .errors import angle_ranges
from .pitch import Corner
from .raster import TWO_PI, periodic_interp, rasterise_fans, wrap_angle
from .rounding import rounded_pair


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
        if problems:
            raise GearError("; ".join(problems))
        land = 0.5 * self.space_width - self.dedendum_height * math.tan(self.pressure_angle)
        if land <= 0:
            raise GearError(f"the rack cutter comes to a point before the root: tip land {2e3 * land:.4f} mm ≤ 0 "
                            f"(module {1e3 * self.module:g} mm, pressure angle "
                            f"{math.degrees(self.pressure_angle):g}°, dedendum "
                            f"{self.addendum + self.clearance:g}·m, backlash {1e3 * self.backlash:g} mm)")


@dataclass(frozen=True, slots=True)
class GearOutline:
    """One gear's closed tooth outline in its body frame (centre at the origin).

    xy: (M, 2) counter-clockwise closed polygon (first point not repeated), m. Per tooth sector k (Z sectors):
    ``poles`` (Z, 2), the sector's ray fan from angle ``ray_start`` (Z,) over ``ray_span`` (Z,) in R+1 uniform
    steps, and ``ray_length`` (Z, R+1) the outline's distance from the pole on each ray (see the module docstring).
    ``undercut``: body-angle ranges (rad) where a working flank has an envelope cusp (the cutter's tip cuts the
    flank; text in ``undercut_text``). ``corners``: corners of the pitch curve. ``mirror``: True for the gear
    whose pitch point moves clockwise on its body (the driving gear)."""

    name: str
    teeth: int
    tooth: ToothParameters
    xy: np.ndarray
    poles: np.ndarray
    ray_start: np.ndarray
    ray_span: np.ndarray
    ray_length: np.ndarray
    perimeter: float
    undercut: tuple = ()
    undercut_text: str = ""
    corners: tuple = ()
    min_curvature_radius: float = math.inf
    mirror: bool = False
    _lookup: dict = field(default_factory=dict, init=False, repr=False, compare=False)

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

    def _sectors(self):
        lk = self._lookup
        if not lk:
            # the start boundary of sector k is the ray from pole k through its first outline point (a root point)
            R = self.ray_length.shape[1] - 1
            first = self.poles + self.ray_length[:, 0, None] * np.stack(
                [np.cos(self.ray_start), np.sin(self.ray_start)], axis=-1)
            b = np.mod(np.arctan2(first[:, 1], first[:, 0]), TWO_PI)
            order = np.argsort(b)
            lk.update(order=order, boundary=b[order], rays=R)
        return lk

    def penetration(self, q) -> np.ndarray:
        """How deep points q (..., 2) (body frame, m) lie inside the outline, measured along the ray of the tooth
        sector that contains them (> 0 inside, < 0 outside by that distance), (...)."""
        q = np.asarray(q, dtype=float)
        lk = self._sectors()
        order, bnd, R = lk["order"], lk["boundary"], lk["rays"]
        z = order.size
        a = np.mod(np.arctan2(q[..., 1], q[..., 0]), TWO_PI)
        i = np.searchsorted(bnd, a, side="right") - 1                    # sector by the root boundaries' angles
        best = np.full(q.shape[:-1], -np.inf)
        found = np.zeros(q.shape[:-1], dtype=bool)
        for shift in (0, -1, 1):                                          # the boundary ray is not radial
            k = order[np.mod(i + shift, z)]
            d = q - self.poles[k]
            beta = np.mod(np.arctan2(d[..., 1], d[..., 0]) - self.ray_start[k], TWO_PI)
            inside = (beta <= self.ray_span[k]) & ~found
            x = np.clip(beta / self.ray_span[k], 0.0, 1.0) * R
            j = np.minimum(np.floor(x).astype(np.intp), R - 1)
            f = x - j
            rl = self.ray_length[k, j] * (1 - f) + self.ray_length[k, j + 1] * f
            pen = rl - np.hypot(d[..., 0], d[..., 1])
            best = np.where(inside, pen, best)
            found |= inside
        # below the poles no fan reaches: that is the gear's body (positive, by the distance below the pole)
        k = order[np.mod(i, z)]
        below = np.hypot(self.poles[k, 0], self.poles[k, 1]) - np.hypot(q[..., 0], q[..., 1])
        return np.where(found, best, np.abs(below))

    def radius_at(self, a) -> np.ndarray:
        """Distance from the centre to the outline along body directions a (...,) (the first crossing from the
        centre), m — by bisection on :meth:`penetration` (for plots and coarse checks)."""
        a = np.asarray(a, dtype=float)
        u = np.stack([np.cos(a), np.sin(a)], axis=-1)
        lo = np.full(a.shape, 0.999 * self.root_radius)
        hi = np.full(a.shape, 1.01 * self.tip_radius)
        for _ in range(48):
            mid = 0.5 * (lo + hi)
            inside = self.penetration(mid[..., None] * u) > 0
            lo = np.where(inside, mid, lo)
            hi = np.where(inside, hi, mid)
        return 0.5 * (lo + hi)


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
def _cut(radius_of, start: float, tooth: ToothParameters, teeth: int, *, rack_phase: float, samples: int,
         rays: int, max_turn: float, name: str = "gear"):
    """Cut one gear whose pitch curve r(ψ) is traversed counter-clockwise from body angle ``start`` (arc 0).

    Cutter teeth (the gear's spaces) are centred at u = (rack_phase + k)·p, k = 0 … teeth−1; gear tooth k lies
    between cutter teeth k and k+1. Returns (fans: poles (Z, 2), ray start (Z,), span (Z,), lengths (Z, R+1);
    undercut body angles (list); (smallest radius of curvature, corners, polyline perimeter))."""
    psi_v, pts = _pitch_polyline(radius_of, start, samples)
    path, turn, seg = _rolling_path(pts, max_turn)
    rc_min, corners = _curvature_check(name, turn, seg, tooth, psi_v, np.hypot(pts[:, 0], pts[:, 1]))
    p = tooth.pitch
    alpha = tooth.pressure_angle
    m = tooth.module
    ha, hf = tooth.addendum_height, tooth.dedendum_height
    w2 = 0.5 * tooth.space_width
    land = w2 - hf * math.tan(alpha)
    sa, ca = math.sin(alpha), math.cos(alpha)
    per = path.perimeter
    pitch = per / teeth                     # = p within the caller's tolerance: spread over the exact perimeter
    centres = (rack_phase + np.arange(teeth)) * pitch                            # (Z,)
    window = w2 + max(ha + tooth.clearance * m, hf) / (sa * ca) + p             # reach of a cutter tooth in s
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

    def place(u, v):
        return P + (u - s)[..., None] * T + np.asarray(v)[..., None] * N

    families, masks = [], []
    undercut = []
    for side in (-1.0, 1.0):   # left flank (u = uc − w/2 − v·tanα), right flank (u = uc + w/2 + v·tanα)
        a_u = uc + side * w2
        v_foot = side * (s - a_u) * sa * ca
        u_foot = a_u + side * v_foot * math.tan(alpha)
        ok = inside & (v_foot >= -hf) & (v_foot <= ha + tooth.clearance * m)
        X = place(u_foot, v_foot)
        families.append(X)
        masks.append(ok)
        undercut += _cusps(X, ok & (v_foot >= -ha - 1e-12 * m))
        families.append(place(uc + side * land, np.full_like(s, -hf)))   # tip corner: its trochoid (fillet)
        masks.append(inside)
    families.append(place(s, np.full_like(s, -hf)))                      # root: envelope of the tip land
    masks.append(inside & (np.abs(s - uc) <= land))
    families.append(P + ha * N)                                          # the blank's tip curve
    masks.append(inside)
    cand = np.stack(families, axis=1)                                    # (Z, F, K, 2) per cutter tooth
    cmask = np.stack(masks, axis=1)

    # tooth fans: tooth k between cutter teeth k and k+1; pole on the normal below the tooth centre
    def state_at(sv):
        """(point, normal) of the path at arc lengths sv (Z,) (the middle state of a corner's pivot)."""
        sv = np.mod(sv, per)
        lo = np.searchsorted(path.s, sv, side="left")
        hi = np.searchsorted(path.s, sv, side="right")
        j = np.where(hi > lo, (lo + hi - 1) // 2, np.maximum(lo - 1, 0))
        j = np.minimum(j, J - 1)
        frac = np.where(hi > lo, 0.0, (sv - path.s[j]) / np.maximum(seg_at(j), 1e-300))
        nxt = np.where(j + 1 < J, j + 1, 0)
        pt = path.point[j] + frac[:, None] * (path.point[nxt] - path.point[j])
        tu = path.tau[j] + frac * wrap_angle(path.tau[nxt] - path.tau[j])
        return pt, np.stack([np.sin(tu), -np.cos(tu)], axis=-1)

    def seg_at(j):
        nxt = np.where(j + 1 < J, j + 1, 0)
        return np.hypot(*(path.point[nxt] - path.point[j]).T)

    mid_pt, mid_n = state_at(centres + 0.5 * pitch)
    depth = np.minimum(6.0 * m, 0.6 * np.hypot(mid_pt[:, 0], mid_pt[:, 1]))
    poles = mid_pt - depth[:, None] * mid_n
    root_pt, root_n = state_at(centres)
    bound = root_pt - hf * root_n                                        # root points at the space centres
    b0 = bound - poles
    b1 = np.roll(bound, -1, axis=0) - poles
    ray0 = np.arctan2(b0[:, 1], b0[:, 0])
    span = np.mod(np.arctan2(b1[:, 1], b1[:, 0]) - ray0, TWO_PI)
    if np.any(span <= 0) or np.any(span >= math.pi):
        raise GearError(f"the module {1e3 * m:g} mm is too large for the pitch radius: a tooth sector cannot be "
                        f"laid out (smallest pitch radius {1e3 * float(np.hypot(*pts.T).min()):.3f} mm)")
    R = rays
    step = span / R
    lengths = np.full((teeth, R + 1), np.inf)
    nb = np.array([-1, 0, 1, 2])                                         # cutter teeth around tooth k
    rows = np.mod(np.arange(teeth)[:, None] + nb[None, :], teeth)        # (Z, 4)
    for z0 in range(0, teeth, 16):                                       # chunks of teeth (memory)
        zs = np.arange(z0, min(teeth, z0 + 16))
        xy = cand[rows[zs]].reshape(zs.size, -1, K, 2)
        ok = cmask[rows[zs]].reshape(zs.size, -1, K)
        sub = lengths[zs]
        rasterise_fans(sub, xy, ok, poles[zs], ray0[zs], step[zs])
        lengths[zs] = sub
    if not np.all(np.isfinite(lengths)):
        raise GearError("the tooth outline has directions without any boundary (the module is too large for the "
                        "pitch curve)")
    return (poles, ray0, span, lengths), undercut, (rc_min, corners, float(seg.sum()))


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
             rays: int = 160, max_turn: float = math.radians(0.25)) -> GearOutline:
    """Cut one gear with pitch curve r(ψ) (a vectorised callable, body angle ψ in rad → m).

    The rack rolls from body angle ``start`` counter-clockwise (``mirror=True``: clockwise, i.e. the curve is
    cut in the mirrored frame and mirrored back). ``space_at_start``: a tooth space (else a tooth) is centred on
    the start point. samples: pitch-polyline points (default 256 per tooth, at least 8192); rays: rays per tooth
    sector. The teeth are spread over the exact perimeter; the caller checks that ``teeth`` divides it
    (:func:`tooth_count`)."""
    tooth.check()
    if teeth < 3:
        raise GearError(f"tooth count of the {name} gear must be ≥ 3: {teeth}")
    samples = samples or max(8192, 256 * teeth)
    sign = -1.0 if mirror else 1.0
    r_frame = (lambda a: radius_of(-a)) if mirror else radius_of
    start_frame = sign * start
    (poles, ray0, span, lengths), cusps, (rc_min, corners, perimeter) = _cut(
        r_frame, start_frame, tooth, teeth, rack_phase=0.0 if space_at_start else 0.5, samples=samples,
        rays=rays, max_turn=max_turn, name=name)
    R = lengths.shape[1] - 1
    beta = ray0[:, None] + span[:, None] * (np.arange(R + 1) / R)[None, :]
    pts = poles[:, None, :] + lengths[..., None] * np.stack([np.cos(beta), np.sin(beta)], axis=-1)
    xy = pts[:, :-1, :].reshape(-1, 2)                          # the last ray of a sector = the next one's first
    if mirror:
        xy = xy[::-1] * np.array([1.0, -1.0])
        poles = poles[::-1] * np.array([1.0, -1.0])
        ray0, span, lengths = -(ray0 + span)[::-1], span[::-1], lengths[::-1, ::-1]
        cusps = [-c for c in cusps]
        corners = tuple(Corner(float(np.mod(-c.angle, TWO_PI)), c.radius, c.tangent_jump) for c in corners)
    rmin = float(np.min(radius_of(np.linspace(0, TWO_PI, 721))))
    runs = _angle_runs(cusps, tol=2.0 * tooth.pitch / rmin)
    text = ", ".join(f"[{_deg(lo)}, {_deg(hi)}]" for lo, hi in runs)
    return GearOutline(name=name, teeth=int(teeth), tooth=tooth, xy=xy, poles=poles, ray_start=ray0,
                       ray_span=span, ray_length=lengths, perimeter=perimeter, undercut=runs,
                       undercut_text=text, corners=corners, min_curvature_radius=rc_min, mirror=mirror)


def cut_pair(pair, *, module: float | None = None, teeth: int | None = None,
             pressure_angle: float = math.radians(20.0), addendum: float = 1.0, clearance: float = 0.25,
             backlash: float = 0.0, rel_tol: float = TOL.tooth_perimeter, samples: int | None = None,
             rays: int = 160) -> GearTeeth:
    """Cut both gears of a :class:`~assur.gears.pitch.GearPair` with one basic rack.

    module (m) and/or teeth (tooth count of the driving gear): the driving pitch perimeter must be π·m·z within
    ``rel_tol`` (else GearError naming the numbers); the driven gear gets z·driving_turns teeth. pressure_angle in
    rad, backlash = the pair's normal backlash j_n in m."""
    n = int(pair.driving_turns)
    p1, p2 = float(pair.driving.perimeter), float(pair.driven.perimeter)
    m, z1 = tooth_count(p1, module, teeth, name="driving", rel_tol=rel_tol)
    z2 = z1 * n
    exact2 = p2 / (math.pi * m)
    if abs(exact2 - z2) > rel_tol * exact2:
        raise GearError(f"tooth count: the driven pitch perimeter {1e3 * p2:.4f} mm holds {exact2:.4f} circular "
                        f"pitches, not {z2} = {z1}·{n} (driving teeth × driving turns)")
    tooth = ToothParameters(module=m, pressure_angle=pressure_angle, addendum=addendum, clearance=clearance,
                            backlash=backlash)
    theta0 = float(np.asarray(pair.law(0.0)))
    driving = cut_gear(pair.driving.radius_at, tooth, z1, name="driving", start=0.0, mirror=True,
                       space_at_start=True, samples=samples, rays=rays)
    driven = cut_gear(pair.driven.radius_at, tooth, z2, name="driven", start=math.pi + theta0, mirror=False,
                      space_at_start=False, samples=samples, rays=rays)
    notes = []
    for g in (driving, driven):
        if g.undercut:
            notes.append(f"{g.name} gear: working flanks undercut near body angle {g.undercut_text}")
        for c in g.corners:
            notes.append(f"{g.name} gear: pitch-curve corner at body angle {_deg(c.angle)}, tangent turns by "
                         f"{math.degrees(c.tangent_jump):+.1f}° ({c.kind})")
    return GearTeeth(driving=driving, driven=driven, tooth=tooth, centre_distance=float(pair.centre_distance),
                     driving_turns=n, notes=tuple(notes))


__all__ = ["GearOutline", "GearTeeth", "ToothParameters", "cut_gear", "cut_pair", "periodic_interp", "rounded_pair",
           "tooth_count"]
