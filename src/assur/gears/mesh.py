"""Meshing check: roll two rigid tooth outlines through a full cycle and measure play, interference and ratio.

Set-up (the conventions of :mod:`assur.gears.pitch`): the driving outline turns about O1 = (0, 0) counter-clockwise
by φ, the driven outline about O2 = (L, 0) clockwise by θ(φ) + δ. For each driving angle φ of the scan the check
finds the **admissible interval** [δ_lo, δ_hi] of driven offsets δ around the law θ(φ) for which the two outlines
do not overlap:

- overlap criterion: the largest *penetration* of any outline vertex of one gear (within ±``window`` pitches
  of the pitch point) into the other gear, measured along the other outline's ray through the vertex (a
  :class:`~assur.gears.teeth.GearOutline` is star-shaped about each tooth's pole, a :class:`PolarOutline` about
  the centre; "inside" means "closer to the pole than the outline on that ray"). Penetration ≤ ``tolerance``
  (default 0.2 % of the module) counts as touching, not overlapping; every ``vertex_stride``-th outline vertex
  is tested (default 2: about 80 per tooth of the envelope outlines);
- scan grid: ``offsets`` values of δ uniformly over ± half a pitch at the driven pitch point; the admissible run
  nearest δ = 0 is refined at both ends by bisection (16 halvings of a grid step by default). Where no grid value is admissible the
  smallest penetration over δ is found by golden-section search around the best grid value; if it is still above
  the tolerance, the position **interferes** (no placement of the driven gear avoids overlap) and that minimal
  penetration is its depth.

The transmitted motion with the driving gear pushing (its leading flanks in contact) is θ(φ) + δ_lo(φ): the
driven gear lags as far as the outlines allow. Its ratio dθ/dφ (central differences) is compared with the law's;
the spread of δ_lo is the transmission error; (δ_hi − δ_lo)·r2 is the circumferential backlash at the driven
pitch point.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..errors import GearError
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
    actual_ratio: np.ndarray     #: d(θ + δ_lo)/dφ = k + dδ_lo/dφ (NaN next to interfering positions)
    backlash: np.ndarray         #: (δ_hi − δ_lo)·r2, circumferential at the driven pitch point, m
    tolerance: float
    centre_distance: float

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
        rel = self.actual_ratio / self.law_ratio - 1.0
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
            "transmission_error": float(np.nanmax(np.abs(te))) if ok.any() else None,
            "tolerance": self.tolerance,
        }


class _Scene:
    """Vectorised penetration of the two outlines for driving angles φ (S,) and driven angles θ (S, G)."""

    def __init__(self, g1, g2, L, pitch, window, stride=1):
        self.g1, self.g2, self.L = g1, g2, float(L)
        xy1, xy2 = g1.xy[::stride], g2.xy[::stride]
        r1 = np.hypot(xy1[:, 0], xy1[:, 1])
        r2 = np.hypot(xy2[:, 0], xy2[:, 1])
        # a vertex can reach the other gear only if it is farther than L − (the other's largest radius) from its
        # own centre
        self.v1 = self._by_angle(xy1[r1 >= self.L - r2.max() - pitch])
        self.v2 = self._by_angle(xy2[r2 >= self.L - r1.max() - pitch])
        if not (self.v1[0].size and self.v2[0].size):
            raise GearError(f"the gears do not reach each other at the centre distance {self.L * 1e3:.6g} mm: the "
                            f"largest radii are {r1.max() * 1e3:.6g} mm and {r2.max() * 1e3:.6g} mm")
        self.k1 = self._half_count(self.v1, pitch, window)
        self.k2 = self._half_count(self.v2, pitch, window)

    @staticmethod
    def _by_angle(xy):
        a = np.mod(np.arctan2(xy[:, 1], xy[:, 0]), TWO_PI)
        o = np.argsort(a)
        return a[o], xy[o]

    @staticmethod
    def _half_count(v, pitch, window):
        """Vertices within ±window pitches (arc at the smallest radius) of any angle: a fixed half count."""
        a, xy = v
        rmin = float(np.min(np.hypot(xy[:, 0], xy[:, 1])))
        half = min(math.pi, window * pitch / rmin)
        a2 = np.concatenate([a, a + TWO_PI])
        counts = np.searchsorted(a2, a + 2 * half) - np.arange(a.size)
        return int(min(a.size // 2, math.ceil(counts.max() / 2) + 1))

    @staticmethod
    def _near(v, k, centre_angle):
        a, xy = v
        c = np.searchsorted(a, np.mod(centre_angle, TWO_PI))
        idx = np.mod(c[..., None] + np.arange(-k, k + 1), a.size)
        return xy[idx]

    def penetration(self, phi, theta):
        """Largest penetration (m; < 0: clear by that much), shape of theta (S, G)."""
        phi = np.asarray(phi, dtype=float)[:, None]
        th = np.asarray(theta, dtype=float)
        phi_b = np.broadcast_to(phi, th.shape)
        # driven vertices near its pitch point (body angle π + θ) → world → driving body frame
        q = self._near(self.v2, self.k2, math.pi + th)                    # (S, G, V, 2)
        c, s_ = np.cos(-th)[..., None], np.sin(-th)[..., None]            # driven body → world: rotate by −θ
        x = self.L + c * q[..., 0] - s_ * q[..., 1]
        y = s_ * q[..., 0] + c * q[..., 1]
        c1, s1 = np.cos(-phi_b)[..., None], np.sin(-phi_b)[..., None]     # world → driving body: rotate by −φ
        pen_a = self.g1.penetration(np.stack([c1 * x - s1 * y, s1 * x + c1 * y], axis=-1)).max(axis=-1)
        # driving vertices near its pitch point (body angle −φ) → world → driven body frame
        q = self._near(self.v1, self.k1, -phi_b)
        c1, s1 = np.cos(phi_b)[..., None], np.sin(phi_b)[..., None]
        x = c1 * q[..., 0] - s1 * q[..., 1] - self.L
        y = s1 * q[..., 0] + c1 * q[..., 1]
        c, s_ = np.cos(th)[..., None], np.sin(th)[..., None]              # world → driven body: rotate by +θ
        pen_b = self.g2.penetration(np.stack([c * x - s_ * y, s_ * x + c * y], axis=-1)).max(axis=-1)
        return np.maximum(pen_a, pen_b)


def mesh_check(driving, driven, pair, *, steps: int = 720, offsets: int = 33, window: float = 1.0,
               tolerance: float | None = None, pitch: float | None = None, chunk: int = 48,
               bisections: int = 16, vertex_stride: int = 2, phi=None) -> MeshReport:
    """Roll ``driving`` and ``driven`` outlines (GearOutline, PolarOutline or (M, 2) polygons star-shaped about
    the centre, body frames) at the
    pair's centre distance through the full cycle (driving φ over 0 … 2π·driving_turns, ``steps`` positions),
    or over the driving angles ``phi`` (rad) when given.

    pitch: the circular pitch (m) that sets the search range and window (default: the outlines' ``tooth.pitch``);
    tolerance: penetration counted as contact, m (default 0.2 % of the module). See the module docstring."""
    g1, g2 = _as_outline(driving), _as_outline(driven)
    if pitch is None:
        tooth = getattr(driving, "tooth", None)
        if tooth is None:
            raise GearError("give the circular pitch for outlines that carry no tooth parameters")
        pitch = tooth.pitch
    module = pitch / math.pi
    tol = 2e-3 * module if tolerance is None else float(tolerance)
    L = float(pair.centre_distance)
    n = int(pair.driving_turns)
    if phi is None:
        phi = np.arange(steps) * (TWO_PI * n / steps)
        periodic = True
    else:
        phi = np.asarray(phi, dtype=float).ravel()
        steps, periodic = phi.size, False
    theta = np.asarray(pair.law(phi), dtype=float)
    k = np.asarray(pair.ratio(phi), dtype=float)
    r2c = L / (1.0 + k)                                   # driven pitch radius at the contact point
    half = 0.5 * pitch / r2c                              # ± half a pitch at the driven pitch point, rad
    scene = _Scene(g1, g2, L, pitch, window, vertex_stride)
    lower = np.full(steps, np.nan)
    upper = np.full(steps, np.nan)
    pen_min = np.zeros(steps)
    grid = np.linspace(-1.0, 1.0, offsets)
    for a in range(0, steps, chunk):
        sl = slice(a, min(steps, a + chunk))
        ph, th, hw = phi[sl], theta[sl], half[sl]
        s = ph.size
        rows = np.arange(s)
        d = hw[:, None] * grid[None, :]                                       # (s, G)
        pen = scene.penetration(ph, th[:, None] + d)
        free = pen <= tol
        # seed: the free grid value nearest δ = 0, else the golden-section minimum around the best grid value
        dist = np.where(free, np.abs(np.arange(offsets) - (offsets - 1) / 2.0)[None, :], np.inf)
        seed_i = np.argmin(dist, axis=1)
        has = np.isfinite(dist[rows, seed_i])
        seed_i = np.where(has, seed_i, np.argmin(pen, axis=1))
        seed = d[rows, seed_i]
        seed_pen = pen[rows, seed_i]
        step = 2.0 * hw / (offsets - 1)
        no = np.flatnonzero(~has)
        if no.size:
            lo_d, hi_d = seed[no] - step[no], seed[no] + step[no]
            g = (math.sqrt(5) - 1) / 2

            def f(x):
                return scene.penetration(ph[no], (th[no] + x)[:, None])[:, 0]
            x1, x2 = hi_d - g * (hi_d - lo_d), lo_d + g * (hi_d - lo_d)
            f1, f2 = f(x1), f(x2)
            for _ in range(24):
                left = f1 < f2
                hi_d = np.where(left, x2, hi_d)
                lo_d = np.where(left, lo_d, x1)
                n1, n2 = hi_d - g * (hi_d - lo_d), lo_d + g * (hi_d - lo_d)
                x1, x2 = np.where(left, n1, x2), np.where(left, x1, n2)
                fn1, fn2 = f(x1), f(x2)
                f1, f2 = np.where(left, fn1, f2), np.where(left, f1, fn2)
            seed[no] = 0.5 * (lo_d + hi_d)
            seed_pen[no] = f(seed[no])
        found = seed_pen <= tol
        # outward on the grid to the first blocked value on either side (or ± one grid step from a golden
        # seed, whose grid neighbours are blocked), then bisection between the last free and first blocked δ
        idx = np.arange(offsets)[None, :]
        blocked = ~free
        left_block = np.where(blocked & (idx < seed_i[:, None]), idx, -1).max(axis=1)
        right_block = np.where(blocked & (idx > seed_i[:, None]), idx, offsets).min(axis=1)
        ends = []
        for side, bidx in ((-1.0, left_block), (1.0, right_block)):
            inside_i = np.clip(bidx - side, 0, offsets - 1).astype(np.intp)
            a_free = np.where(has, d[rows, inside_i], seed)
            edge = (bidx < 0) | (bidx >= offsets)
            b_block = np.where(has & ~edge, d[rows, np.clip(bidx, 0, offsets - 1)], a_free + side * step)
            b_block = np.where(has & edge, a_free + side * hw, b_block)
            for _ in range(bisections):
                mid = 0.5 * (a_free + b_block)
                ok = scene.penetration(ph, (th + mid)[:, None])[:, 0] <= tol
                a_free = np.where(ok, mid, a_free)
                b_block = np.where(ok, b_block, mid)
            ends.append(a_free)
        lower[sl] = np.where(found, ends[0], np.nan)
        upper[sl] = np.where(found, ends[1], np.nan)
        pen_min[sl] = np.where(found, np.minimum(seed_pen, tol), seed_pen)
    interferes = np.isnan(lower)
    pen_min = np.where(interferes, pen_min, np.minimum(pen_min, tol))
    # d(θ + δ_lo)/dφ = k(φ) + dδ_lo/dφ, the offset differentiated by central differences (exact k: no
    # finite-difference error of the law itself on a coarse scan)
    if periodic:
        ratio = k + (np.roll(lower, -1) - np.roll(lower, 1)) / (2.0 * (TWO_PI * n / steps))
    else:          # an explicit scan: derivative along the given angles
        ratio = k + np.gradient(lower, phi) if steps > 2 else np.full(steps, np.nan)
    backlash = (upper - lower) * r2c
    return MeshReport(phi=phi, theta_law=theta, lower=lower, upper=upper, penetration=pen_min, interferes=interferes,
                      law_ratio=k, actual_ratio=ratio, backlash=backlash, tolerance=tol, centre_distance=L)


__all__ = ["MeshReport", "PolarOutline", "mesh_check", "polar_outline"]
