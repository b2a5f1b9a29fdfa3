"""Meshing check: roll two rigid tooth outlines through a full cycle and measure play, interference and ratio.

Set-up (the conventions of :mod:`assur.gears.pitch`): the driving outline turns about O1 = (0, 0) counter-clockwise
by φ, the driven outline about O2 = (L, 0) clockwise by θ(φ) + δ. For each driving angle φ of the scan the check
finds the **admissible interval** [δ_lo, δ_hi] of driven offsets δ around the law θ(φ) for which the two outlines
do not overlap:

- the polygons are the outlines as written (each checked first by :func:`assur.gears.outline.outline_defects`;
  the findings are in ``MeshReport.outline_defects`` and the summary's ``outline_valid``/``outline_defects``);
- exact events: rotating the driven gear by δ moves every driving vertex, seen from the driven gear, on a circle
  about O2, and every driven vertex, seen from the driving gear placed at δ = 0, on a circle about O2 the other
  way. Each circle's crossings with the other polygon's edges (solved exactly, segment by segment, for the pairs
  whose radial ranges and angular reach overlap) are the offsets at which that vertex enters or leaves the other
  gear's material. The first contact of two polygons moving apart or together is always a vertex on an edge, so from a free offset
  the admissible interval ends exactly at the nearest events on either side (no grid, no bisection);
- the law position δ = 0 is free when no vertex is inside the other polygon (read from its next event: a vertex
  that leaves next is inside). Otherwise the free offset nearest 0 is sought on a grid of ``grid`` offsets over
  ± half a pitch at the driven pitch point, and its interval again ends at the exact events; where no offset is
  free the position **interferes**, and its depth is the smallest, over the grid, of the largest arc by which a
  vertex would have to turn about the driven centre to leave the other gear (≤ ``tolerance``, default 0.2 % of
  the module, counts as touching).

The transmitted motion with the driving gear pushing (its leading flanks in contact) is θ(φ) + δ_lo(φ): the
driven gear lags as far as the outlines allow. Its ratio is taken over a fixed window of driving rotation (one
tooth pitch rolled along the pitch curves, by default), from the exact offsets at the window's ends: the mean
ratio ((θ + δ_lo)(φ + w) − (θ + δ_lo)(φ))/w, compared with the law's mean over the same window. It is a
function of φ alone (not of the scan's step), so its largest deviation converges as the scan is refined; a
difference quotient of neighbouring positions would not (a contact that moves to the next tooth makes δ_lo jump,
and the quotient of that jump grows as the step shrinks). The spread of δ_lo is the transmission error;
(δ_hi − δ_lo)·r2 is the circumferential backlash at the driven pitch point.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..errors import GearError
from .cache import cached
from .contact import depth_of, events, inside_any
from .errors import angle_ranges
from .raster import TWO_PI, periodic_interp, rasterise_min


@dataclass(frozen=True, slots=True)
class PolarOutline:
    """A closed outline star-shaped about the centre, sampled on uniform body angles: radius (M,), m
    (angle i = 2π·i/M)."""

    radius: np.ndarray

    @property
    def angle(self) -> np.ndarray:
        return np.arange(self.radius.size) * (TWO_PI / self.radius.size)

    @property
    def xy(self) -> np.ndarray:
        a = self.angle
        return np.stack([self.radius * np.cos(a), self.radius * np.sin(a)], axis=-1)

    def radius_at(self, a) -> np.ndarray:
        return periodic_interp(np.asarray(a, dtype=float), self.radius)

    def penetration(self, q) -> np.ndarray:
        """Depth of points q (..., 2) inside the outline along the centre's ray, m (> 0 inside)."""
        q = np.asarray(q, dtype=float)
        return self.radius_at(np.arctan2(q[..., 1], q[..., 0])) - np.hypot(q[..., 0], q[..., 1])


def polar_outline(xy, rays: int = 16384) -> PolarOutline:
    """A closed polygon (M, 2) (centre at the origin, star-shaped about it) as radii on ``rays`` uniform rays:
    per ray the nearest crossing of the polygon (the material seen from the centre)."""
    xy = np.asarray(xy, dtype=float)
    closed = np.concatenate([xy, xy[:1]])[None]
    out = np.full(int(rays), np.inf)
    rasterise_min(out, closed, np.ones(closed.shape[:2], dtype=bool))
    if not np.all(np.isfinite(out)):
        raise GearError("the outline does not surround its centre (some directions cross no edge)")
    return PolarOutline(out)


def _as_outline(outline):
    if hasattr(outline, "penetration") and hasattr(outline, "xy"):
        return outline
    return polar_outline(outline)


@dataclass(frozen=True, slots=True)
class MeshReport:
    """Result of :func:`mesh_check`; arrays are (S,) over the scanned driving angles ``phi`` (rad)."""

    phi: np.ndarray
    theta_law: np.ndarray
    lower: np.ndarray            #: δ_lo, rad (NaN where the position interferes)
    upper: np.ndarray            #: δ_hi, rad (NaN where the position interferes)
    penetration: np.ndarray      #: smallest achievable radial penetration, m (≤ tolerance where admissible)
    interferes: np.ndarray       #: bool
    law_ratio: np.ndarray        #: k(φ) of the law
    actual_ratio: np.ndarray     #: mean d(θ + δ_lo)/dφ over the ratio window [φ, φ + w] (NaN where an end interferes)
    backlash: np.ndarray         #: (δ_hi − δ_lo)·r2, circumferential at the driven pitch point, m
    tolerance: float
    centre_distance: float
    outline_defects: tuple = ()  #: located findings of both outlines (:mod:`assur.gears.outline`); () if clean
    law_ratio_window: np.ndarray | None = None   #: the law's mean ratio over the same windows as actual_ratio
    ratio_window: float = 1.0    #: the window of the transmitted ratio, in pitches rolled (see mesh_check)
    uniform: bool = False        #: the scan is the uniform cycle (steps positions), not given angles

    def _sampling_error(self, rel):
        """The change of the largest ratio deviation when every other scan position is left out: an estimate of
        its sampling error (None for a scan that is not a uniform cycle of an even number of positions)."""
        if not self.uniform or rel.size < 4 or rel.size % 2 or not np.isfinite(rel).any():
            return None
        half = rel[::2]
        if not np.isfinite(half).any():
            return None
        return float(np.nanmax(np.abs(rel)) - np.nanmax(np.abs(half)))

    @property
    def any_interference(self) -> bool:
        return bool(self.interferes.any())

    def interference_ranges(self) -> str:
        """Driving-angle ranges (degrees, text) where the position interferes ("" if none)."""
        return angle_ranges(self.phi, self.interferes)

    def interference_theta_ranges(self) -> str:
        """The same ranges as driven angles θ (text)."""
        order = np.argsort(np.mod(self.theta_law, TWO_PI))
        return angle_ranges(np.mod(self.theta_law, TWO_PI)[order], self.interferes[order])

    def summary(self) -> dict:
        """Scalars of the check (SI units, angles in rad)."""
        ok = ~self.interferes
        law = self.law_ratio if self.law_ratio_window is None else self.law_ratio_window
        rel = self.actual_ratio / law - 1.0
        te = self.lower[ok] - np.nanmean(self.lower[ok]) if ok.any() else np.array([np.nan])
        worst = int(np.argmax(self.penetration))
        return {
            "positions": int(self.phi.size),
            "interfering_positions": int(self.interferes.sum()),
            "interference": self.any_interference,
            "interference_driving_ranges": self.interference_ranges(),
            "interference_driven_ranges": self.interference_theta_ranges() if self.any_interference else "",
            "max_penetration": float(self.penetration.max()) if self.any_interference else 0.0,
            "max_penetration_at_phi": float(self.phi[worst]) if self.any_interference else None,
            "backlash_min": float(np.nanmin(self.backlash)) if ok.any() else None,
            "backlash_max": float(np.nanmax(self.backlash)) if ok.any() else None,
            "law_ratio_min": float(self.law_ratio.min()),
            "law_ratio_max": float(self.law_ratio.max()),
            "actual_ratio_min": float(np.nanmin(self.actual_ratio)) if np.isfinite(self.actual_ratio).any() else None,
            "actual_ratio_max": float(np.nanmax(self.actual_ratio)) if np.isfinite(self.actual_ratio).any() else None,
            "max_ratio_deviation": float(np.nanmax(np.abs(rel))) if np.isfinite(rel).any() else None,
            "ratio_window_pitches": self.ratio_window,
            "max_ratio_deviation_sampling_error": self._sampling_error(rel),
            "transmission_error": float(np.nanmax(np.abs(te))) if ok.any() else None,
            "tolerance": self.tolerance,
            "outline_valid": not self.outline_defects,
            "outline_defects": list(self.outline_defects),
        }


#: results of the polygon preparation (checks, simplification) of recent mesh checks, by content: the same
#: outline checked again (the sector scheme at two centre distances, a fine scan after the coarse one) reuses them
_MEMO: dict = {}
_MEMO_SIZE = 16


def _memo(kind, xy, params, compute):
    """``compute()`` once per (kind, content of the array xy, params); the few latest results are kept."""
    import hashlib
    key = (kind, xy.shape, hashlib.blake2b(np.ascontiguousarray(xy).tobytes(), digest_size=16).digest(), params)
    if key not in _MEMO:
        while len(_MEMO) >= _MEMO_SIZE:
            _MEMO.pop(next(iter(_MEMO)))
        _MEMO[key] = compute()
    return _MEMO[key]


def _polygon(outline, module):
    """The outline as a counter-clockwise polygon (M, 2) and its findings (:mod:`assur.gears.outline`)."""
    from .outline import outline_defects
    xy = np.asarray(outline.xy if hasattr(outline, "xy") else outline, dtype=float)
    name = f"{getattr(outline, 'name', 'outline')} outline" if hasattr(outline, "name") else "outline"
    if xy.ndim == 2 and xy.shape[0] >= 3:
        x, y = xy[:, 0], xy[:, 1]
        if np.sum(x * np.roll(y, -1) - np.roll(x, -1) * y) < 0:
            xy = xy[::-1]
    found = list(getattr(outline, "defects", ()))
    if not found:
        found = list(_memo("defects", xy, (module, name), lambda: tuple(
            outline_defects(xy, module, name=name, max_step=np.inf))))
    return xy, found


def _simplified(xy, tol):
    def compute():
        import shapely
        g = shapely.Polygon(xy).simplify(tol, preserve_topology=True)
        out = np.asarray(g.exterior.coords)[:-1]
        x, y = out[:, 0], out[:, 1]
        out = out if np.sum(x * np.roll(y, -1) - np.roll(x, -1) * y) > 0 else out[::-1]
        out.flags.writeable = False
        return out
    return _memo("simplified", np.asarray(xy, dtype=float), (tol,), compute)


class _Side:
    """One gear's polygon for the scan: vertices and edges (start, end) sorted by body angle, and the fixed
    number of them that a window of ± ``half`` rad around any angle holds."""

    def __init__(self, xy, keep, half):
        nxt = np.roll(xy, -1, axis=0)
        r = np.hypot(xy[:, 0], xy[:, 1])
        self.rmin = float(r.min())
        self.rmax = float(r.max())
        vk = keep(r)
        ek = vk | keep(np.hypot(nxt[:, 0], nxt[:, 1]))
        self.v = self._sorted(xy[vk], xy[vk])
        self.e = self._sorted(xy[ek], np.concatenate([xy[ek], nxt[ek]], axis=1))
        self.kv = self._count(self.v[0], half)
        self.ke = self._count(self.e[0], 2.0 * half)   # the edges a point's circle may cross lie farther out

    @staticmethod
    def _sorted(at, data):
        a = np.mod(np.arctan2(at[:, 1], at[:, 0]), TWO_PI)
        o = np.argsort(a)
        return a[o], data[o]

    @staticmethod
    def _count(a, half):
        if a.size == 0:
            return 0
        a2 = np.concatenate([a, a + TWO_PI])
        counts = np.searchsorted(a2, a + 2 * half) - np.arange(a.size)
        return int(min(a.size // 2, math.ceil(counts.max() / 2) + 1))

    @staticmethod
    def near(sorted_, k, centre_angle):
        a, data = sorted_
        c = np.searchsorted(a, np.mod(centre_angle, TWO_PI))
        idx = np.mod(c[..., None] + np.arange(-k, k + 1), a.size)
        return data[idx]


def _rot(xy, ang):
    c, s = np.cos(ang), np.sin(ang)
    return np.stack([c * xy[..., 0] - s * xy[..., 1], s * xy[..., 0] + c * xy[..., 1]], axis=-1)


class _Scanner:
    """The admissible offset interval [δ_lo, δ_hi] (and the least penetration) at any driving angles, for two
    polygons at a centre distance (the body of :func:`mesh_check`)."""

    def __init__(self, s1, s2, pair, L, pitch, window, tol, chunk, grid):
        self.pair, self.L, self.pitch, self.tol, self.chunk, self.grid = pair, L, pitch, tol, chunk, grid
        R1 = float(np.hypot(*s1.T).max())
        R2 = float(np.hypot(*s2.T).max())
        # a driving point can touch the driven gear only within R2 of O2, so farther than L − R2 from O1 (and the
        # driven points likewise); the windows: ± (window + ½) pitch around the pitch points (the δ range is ± ½
        # pitch)
        reach = (window + 0.5) * pitch
        self.g1 = _Side(s1, lambda r: r >= L - R2, reach / max(L - R2, 0.2 * R1))
        self.g2 = _Side(s2, lambda r: r >= L - R1, reach / max(L - R1, 0.2 * R2))
        if not (self.g1.v[0].size and self.g2.v[0].size):
            raise GearError(f"the gears do not reach each other at the centre distance {L * 1e3:.6g} mm: the "
                            f"largest radii are {R1 * 1e3:.6g} mm and {R2 * 1e3:.6g} mm")

    def search_range(self, phi):
        """(θ(φ), k(φ), driven pitch radius at the contact, ± half a pitch there in rad) at driving angles phi."""
        theta = np.asarray(self.pair.law(phi), dtype=float)
        k = np.asarray(self.pair.ratio(phi), dtype=float)
        r2c = self.L / (1.0 + k)
        return theta, k, r2c, 0.5 * self.pitch / r2c

    def _overlapping(self, rows, evA, enA, baseA, rhoA, evB, enB, baseB, rhoB, w):
        """The rows whose law position overlaps: the free offset nearest it, else the least overlap (offset NaN
        if that is deeper than the tolerance); returns (offset (R,), penetration (R,) m). The overlap changes only
        at events, so the candidates of a row are the midpoints between its consecutive events (exact) and a grid
        of ``grid`` offsets over ±w; the rows are padded to the same number of candidates (NaN, never chosen)."""
        cands = []
        for row in rows:
            evs = np.concatenate([evA[row].ravel(), evB[row].ravel()])
            evs = np.unique(evs[np.isfinite(evs)])
            cands.append(np.concatenate([0.5 * (evs[:-1] + evs[1:]), w[row] * np.linspace(-1.0, 1.0, self.grid)]))
        cand = np.full((rows.size, max(c.size for c in cands)), np.nan)
        for i, c in enumerate(cands):
            cand[i, :c.size] = c
        far = np.array([2.0 * np.max(np.abs(c)) for c in cands]) + 1e-300
        depth = np.maximum(depth_of(evA[rows], enA[rows], baseA[rows], rhoA[rows], cand, far),
                           depth_of(evB[rows], enB[rows], baseB[rows], rhoB[rows], cand, far))           # (R, G), m
        depth = np.where(np.isnan(cand), np.inf, depth)
        free = depth <= 0.0
        nearest = np.argmin(np.where(free, np.abs(cand), np.inf), axis=1)     # the first of the nearest free
        least = np.argmin(depth, axis=1)                                      # the first of the least deep
        r = np.arange(rows.size)
        has_free = free.any(axis=1)
        pen = np.where(has_free, 0.0, depth[r, least])
        centre = np.where(has_free, cand[r, nearest], np.where(pen <= self.tol, cand[r, least], np.nan))
        return centre, pen

    def __call__(self, phi):
        """(δ_lo, δ_hi, least penetration) at driving angles phi (S,): NaN offsets where the position interferes."""
        phi = np.asarray(phi, dtype=float)
        steps = phi.size
        theta, _, _, W = self.search_range(phi)
        g1, g2, chunk = self.g1, self.g2, self.chunk
        lower = np.full(steps, np.nan)
        upper = np.full(steps, np.nan)
        pen_min = np.zeros(steps)
        Lv = np.array([self.L, 0.0])
        for c0 in range(0, steps, chunk):
            sl = slice(c0, min(steps, c0 + chunk))
            ph, th, w = phi[sl], theta[sl], W[sl]
            # driving vertices and edges near its pitch point (body angle −φ), into the driven frame at δ = 0
            q = _Side.near(g1.v, g1.kv, -ph)                                  # (S, V1, 2)
            q = _rot(_rot(q, ph[:, None]) - Lv, th[:, None])
            e1 = _Side.near(g1.e, g1.ke, -ph)                                 # (S, E1, 4)
            a1 = _rot(_rot(e1[..., :2], ph[:, None]) - Lv, th[:, None])
            b1 = _rot(_rot(e1[..., 2:], ph[:, None]) - Lv, th[:, None])
            v = _Side.near(g2.v, g2.kv, math.pi + th)                         # (S, V2, 2) driven body frame
            e2 = _Side.near(g2.e, g2.ke, math.pi + th)
            evA, enA = events(q, e2[..., :2], e2[..., 2:], 1.0, w)           # driving points vs driven edges
            evB, enB = events(v, a1, b1, -1.0, w)                            # driven points vs driving edges
            baseA = np.hypot(q[..., 0], q[..., 1]) < g2.rmin                  # below the other's root: inside
            vw = _rot(v, -th[:, None]) + Lv                                    # driven points in the world
            baseB = np.hypot(vw[..., 0], vw[..., 1]) < g1.rmin
            rhoA, rhoB = np.hypot(q[..., 0], q[..., 1]), np.hypot(v[..., 0], v[..., 1])
            S = ph.size
            free0 = ~(inside_any(evA, enA, baseA) | inside_any(evB, enB, baseB))
            lo = np.full(S, np.nan)
            hi = np.full(S, np.nan)
            pen = np.zeros(S)
            centre = np.zeros(S)
            # the law position overlaps: the free offset nearest it, else the least overlap. The overlap changes
            # only at events, so the candidates are the midpoints between consecutive events (exact) and a grid
            rows = np.flatnonzero(~free0)
            if rows.size:
                centre[rows], pen[rows] = self._overlapping(rows, evA, enA, baseA, rhoA, evB, enB, baseB, rhoB, w)
            ok = np.isfinite(centre)
            rel = np.concatenate([evA.reshape(S, -1), evB.reshape(S, -1)], axis=1) - centre[:, None]
            for out, side in ((lo, -1.0), (hi, 1.0)):
                with np.errstate(invalid="ignore"):
                    cand = np.where(side * rel > 0, side * rel, np.inf).min(axis=1)
                out[:] = np.where(ok, centre + side * np.minimum(cand, w), np.nan)
            touching = ok & (pen > 0)
            lo[touching] = hi[touching] = centre[touching]
            lower[sl], upper[sl], pen_min[sl] = lo, hi, pen
        return lower, upper, pen_min


def mesh_check(driving, driven, pair, *, steps: int = 720, window: float = 1.0, tolerance: float | None = None,
               pitch: float | None = None, chunk: int = 24, grid: int = 65, phi=None, simplify: float = 5e-4,
               ratio_window: float | None = None) -> MeshReport:
    """Roll the ``driving`` and ``driven`` outlines (GearOutline, PolarOutline or (M, 2) simple polygons, body
    frames, as written) at the pair's centre distance through the full cycle (driving φ over 0 … 2π·driving_turns,
    ``steps`` positions), or over the driving angles ``phi`` (rad) when given.

    The polygons themselves are checked: each outline's findings (:func:`assur.gears.outline.outline_defects`) are
    reported in ``outline_defects``; for the scan each polygon is simplified within ``simplify``·m (1 µm for
    m = 2 mm). pitch: the circular pitch (m) that sets the search range (default: the outlines' ``tooth.pitch``);
    window: the features looked at, in pitches either side of the pitch points beyond the half-pitch search range;
    tolerance: circumferential penetration counted as contact, m (default 0.2 % of the module).

    The transmitted ratio at φ is the mean over a fixed window of driving rotation, not a difference quotient of
    neighbouring scan positions: ``ratio_window`` = the driving rotation (rad) that rolls ``ratio_window`` pitches
    along the pitch curves (default 1: one tooth pitch, w = p/r1(φ)); the ratio at φ is the mean over [φ, φ + w]
    from the exact offsets at both ends (one more scan), so it does not depend on the sampling and its largest deviation
    converges as the scan is refined; ``ratio_window=0``: no ratio (NaN; an interference scan). See the module
    docstring. The report is kept in the disk cache of :mod:`assur.gears.cache`."""
    if pitch is None:
        tooth = getattr(driving, "tooth", None)
        if tooth is None:
            raise GearError("give the circular pitch for outlines that carry no tooth parameters")
        pitch = tooth.pitch
    module = pitch / math.pi
    tol = 2e-3 * module if tolerance is None else float(tolerance)
    ratio_window = 1.0 if ratio_window is None else float(ratio_window)
    if not ratio_window >= 0:
        raise GearError(f"the ratio window must be ≥ 0 pitches (0: no transmitted ratio): {ratio_window!r}")
    L = float(pair.centre_distance)
    n = int(pair.driving_turns)
    uniform = phi is None
    if phi is None:
        phi = np.arange(steps) * (TWO_PI * n / steps)
    else:
        phi = np.asarray(phi, dtype=float).ravel()
        steps = phi.size
    # the disk cache (assur.gears.cache) key: the outlines as given and the law at every angle the scans look at
    law_at = lambda a: (np.asarray(pair.law(a), dtype=float), np.asarray(pair.ratio(a), dtype=float))  # noqa: E731
    at_phi = law_at(phi)
    ends = law_at(phi + ratio_window * pitch / (L - L / (1.0 + at_phi[1]))) if ratio_window > 0 else ()
    key = (_outline_key(driving), _outline_key(driven), pitch, tol, ratio_window, window, chunk, grid, simplify,
           uniform, L, n, phi, at_phi, ends)

    def compute():
        xy1, f1 = _polygon(driving, module)
        xy2, f2 = _polygon(driven, module)
        scan = _Scanner(_simplified(xy1, simplify * module), _simplified(xy2, simplify * module), pair, L, pitch,
                        window, tol, chunk, grid)
        theta, k, r2c, _ = scan.search_range(phi)
        lower, upper, pen_min = scan(phi)
        interferes = np.isnan(lower)
        # the mean ratio over the window [φ, φ + w], w = ratio_window·p/r1(φ): (θ + δ_lo) at both ends, exact
        if ratio_window > 0:
            wdw = ratio_window * pitch / (L - r2c)          # driving rotation that rolls ratio_window pitches at φ
            lo_end = scan(phi + wdw)[0]
            d_law = np.asarray(pair.law(phi + wdw), dtype=float) - theta
            ratio = (d_law + lo_end - lower) / wdw
            law_window = d_law / wdw
        else:          # no transmitted ratio asked for (an interference scan): two scans fewer
            ratio = np.full(steps, np.nan)
            law_window = k
        backlash = (upper - lower) * r2c
        return MeshReport(phi=phi, theta_law=theta, lower=lower, upper=upper, penetration=pen_min,
                          interferes=interferes, law_ratio=k, actual_ratio=ratio, backlash=backlash, tolerance=tol,
                          centre_distance=L, outline_defects=tuple(f1 + f2), law_ratio_window=law_window,
                          ratio_window=ratio_window, uniform=uniform)
    return cached("mesh-check", key, compute, _pack_report, lambda arrays, meta: MeshReport(
        **arrays, **{**meta, "outline_defects": tuple(meta["outline_defects"])}))


def _outline_key(outline):
    """What of an outline the mesh check sees: its polygon as given, its name and its findings."""
    xy = np.asarray(outline.xy if hasattr(outline, "xy") else outline, dtype=float)
    return xy, getattr(outline, "name", None), tuple(getattr(outline, "defects", ()))


def _pack_report(r: MeshReport):
    """The arrays and JSON data of a report for :func:`assur.gears.cache.cached`."""
    arrays = {f: getattr(r, f) for f in ("phi", "theta_law", "lower", "upper", "penetration", "interferes",
                                         "law_ratio", "actual_ratio", "backlash", "law_ratio_window")}
    meta = {f: getattr(r, f) for f in ("tolerance", "centre_distance", "ratio_window", "uniform")}
    return {k: v for k, v in arrays.items() if v is not None}, {**meta, "outline_defects": list(r.outline_defects)}


__all__ = ["MeshReport", "PolarOutline", "mesh_check", "polar_outline"]
