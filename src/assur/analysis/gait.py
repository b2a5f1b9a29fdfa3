"""Gait metrics of a walking leg from its foot path over one crank turn (no physics engine).

Definitions (spec 000 §6, shared with paper 004). The foot path P(q) over one input turn is
projected on the stride axis (``x = P·ground``) and the vertical axis (``v = P·up``, pointing
away from the ground side); the height is ``h = v − min v``.

- contact (support) arc: the crank angles of the two horizontal extremes (min x, max x) split
  the turn into two arcs; the contact arc is the one whose time-mean height is lower;
- step length: the x-range of the contact arc (= of the whole path);
- lift: the vertical extent of the whole path; sag: the vertical extent of the contact arc;
- duty factor: contact-arc width / 2π;
- support speed |v| = ω·|dP/dq| over the contact arc: max, min, time-mean and midrange;
  the same for the absolute horizontal component |v_x|; the horizontal acceleration range;
- the frame pivot's absolute path while the foot is planted (paper 004, Fig. 6 b–c):
  with the foot fixed, the body moves by the negative of the foot's relative displacement.

Extremes and arc ends are refined from a uniform sample by a bounded 1-D minimiser; speeds come
from the solver's exact derivatives, never from finite differences of the path.
Alternative support definitions: ``support="band"`` (samples with h ≤ ``band``) and
``support="antiphase"`` (two legs 180° apart: a leg supports while lower than the other).
"""
from __future__ import annotations

import math
from dataclasses import asdict, dataclass

import numpy as np
from scipy.integrate import simpson

from ..errors import SpecError, UnbuildableError
from .sampling import TWO_PI, Cycle, intervals, refine_extreme


@dataclass(frozen=True)
class Stats:
    max: float
    min: float
    mean: float
    midrange: float

    @staticmethod
    def of(values, q, vmax, vmin):
        mean = float(simpson(values, x=q) / (q[-1] - q[0])) if len(q) > 2 else float(np.mean(values))
        return Stats(float(vmax), float(vmin), mean, 0.5 * (float(vmax) + float(vmin)))


@dataclass(frozen=True)
class GaitMetrics:
    foot: str
    support: str
    omega: float                 # crank speed, rad/s
    contact_start: float         # input angle (rad) where the contact arc begins
    contact_end: float           # ... and ends (increasing input, may exceed 2π)
    step_length: float           # m
    lift: float                  # m
    sag: float                   # m
    duty_factor: float
    support_speed: Stats         # |v| over the contact arc, m/s
    support_vx: Stats            # |v_x| over the contact arc, m/s
    support_ax: tuple[float, float]   # (min, max) horizontal acceleration over the contact arc, m/s²
    samples: int

    @property
    def contact_ratio(self) -> float:
        """Contact/transfer time ratio = duty / (1 − duty)."""
        return self.duty_factor / (1.0 - self.duty_factor) if self.duty_factor < 1 else math.inf

    def as_dict(self) -> dict:
        d = asdict(self)
        d["support_ax"] = {"min": self.support_ax[0], "max": self.support_ax[1]}
        d["contact_ratio"] = self.contact_ratio
        return d


@dataclass(frozen=True)
class GaitCurves:
    """Sampled curves over one turn, for plots: q (n,), x, v, vx, vv, speed (n,), contact (n,) bool,
    and the body pivot's absolute path over the contact arc body_x, body_v (m,)."""
    q: np.ndarray
    x: np.ndarray
    v: np.ndarray
    vx: np.ndarray
    vv: np.ndarray
    speed: np.ndarray
    contact: np.ndarray
    body_q: np.ndarray
    body_x: np.ndarray
    body_v: np.ndarray


class _Foot:
    def __init__(self, plan, params, foot, ground, up):
        self.cycle = Cycle(plan, params)
        self.i = plan.point_index(foot)
        self.g = np.asarray(ground, dtype=float)
        self.u = np.asarray(up, dtype=float)
        self.omega = float(plan.speeds[0])

    def eval(self, q):
        s = self.cycle.state(q)
        P = s.pos[..., self.i, :]
        dP = s.dpos_dq[..., self.i, :, 0]
        d2P = s.d2pos_dq2[..., self.i, :, 0, 0]
        return s.valid, P @ self.g, P @ self.u, dP @ self.g, dP @ self.u, d2P @ self.g, np.hypot(*np.moveaxis(dP, -1, 0))

    def x(self, q):
        return self.eval(np.atleast_1d(q))[1][0]

    def v(self, q):
        return self.eval(np.atleast_1d(q))[2][0]

    def speed(self, q):
        return abs(self.omega) * self.eval(np.atleast_1d(q))[6][0]

    def vx(self, q):
        return abs(self.omega * self.eval(np.atleast_1d(q))[3][0])


def _resolve(plan, foot, ground, up):
    g = plan.mechanism.gait
    if foot is None:
        if g is None:
            raise SpecError([("gait.foot", "the mechanism names no foot point; add [gait] foot = \"P\"")])
        foot = g.foot
    if ground is None:
        ground = g.ground if g is not None else (1.0, 0.0)
    if up is None:
        up = g.up_vector if g is not None else (-ground[1], ground[0])
    return foot, ground, up


def gait_metrics(plan, params=None, *, foot=None, ground=None, up=None, steps: int = 720,
                 support: str = "arc", band: float | None = None) -> GaitMetrics:
    """Gait metrics of one leg (see the module docstring). Raises UnbuildableError if the crank
    cannot turn fully."""
    return _gait(plan, params, foot, ground, up, steps, support, band)[0]


def gait_curves(plan, params=None, *, foot=None, ground=None, up=None, steps: int = 720,
                support: str = "arc", band: float | None = None) -> GaitCurves:
    return _gait(plan, params, foot, ground, up, steps, support, band)[1]


def _gait(plan, params, foot, ground, up, steps, support, band):
    if support not in ("arc", "band", "antiphase"):
        raise SpecError([("support", f"must be 'arc', 'band' or 'antiphase': {support!r}")])
    if steps < 16:
        raise SpecError([("steps", f"must be at least 16: {steps}")])
    foot, ground, up = _resolve(plan, foot, ground, up)
    F = _Foot(plan, params, foot, ground, up)
    q = np.linspace(0.0, TWO_PI, steps, endpoint=False)
    valid, x, v, dx, dv, d2x, dnorm = F.eval(q)
    if not np.all(valid):
        bad = q[~valid]
        raise UnbuildableError(
            f"the crank cannot turn fully: {np.count_nonzero(~valid)} of {steps} positions cannot be assembled "
            f"(from {np.degrees(bad.min()):.1f}° to {np.degrees(bad.max()):.1f}°); no gait metrics",
            int(np.count_nonzero(~valid)), steps)
    w = abs(F.omega)
    # refined vertical extremes of the whole path
    _, vmin = refine_extreme(F.v, q, v, int(np.argmin(v)), +1)
    _, vmax = refine_extreme(F.v, q, v, int(np.argmax(v)), -1)
    lift = vmax - vmin
    qa, xa = refine_extreme(F.x, q, x, int(np.argmin(x)), +1)
    qb, xb = refine_extreme(F.x, q, x, int(np.argmax(x)), -1)
    step_length = xb - xa
    if support == "arc":
        # the two arcs between the horizontal extremes; the contact arc has the lower mean height
        arcs = []
        for start, end in ((qa, qb), (qb, qa)):
            width = (end - start) % TWO_PI
            qq = start + np.linspace(0.0, width, steps)
            vals = F.eval(qq)
            arcs.append((float(simpson(vals[2] - vmin, x=qq) / width), start, width, qq, vals))
        arcs.sort(key=lambda a: a[0])
        _, start, width, qq, vals = arcs[0]
        _, xs, vs, dxs, dvs, d2xs, dns = vals
        lo, hi = start, start + width
        _, smin = refine_extreme(F.v, qq, vs, int(np.argmin(vs)), +1, lo, hi)
        _, smax = refine_extreme(F.v, qq, vs, int(np.argmax(vs)), -1, lo, hi)
        sag = smax - smin
        speed = w * dns
        _, spmax = refine_extreme(F.speed, qq, speed, int(np.argmax(speed)), -1, lo, hi)
        _, spmin = refine_extreme(F.speed, qq, speed, int(np.argmin(speed)), +1, lo, hi)
        vxa = np.abs(w * dxs)
        _, vxmax = refine_extreme(F.vx, qq, vxa, int(np.argmax(vxa)), -1, lo, hi)
        _, vxmin = refine_extreme(F.vx, qq, vxa, int(np.argmin(vxa)), +1, lo, hi)
        ax = w * w * d2xs
        metrics = GaitMetrics(foot, "arc", F.omega, float(start), float(start + width), float(step_length),
                              float(lift), float(sag), float(width / TWO_PI),
                              Stats.of(speed, qq, spmax, spmin), Stats.of(vxa, qq, vxmax, vxmin),
                              (float(ax.min()), float(ax.max())), steps)
        contact = ((q - start) % TWO_PI) <= width
        body_q = qq
        P0 = np.array([xs[0], vs[0]])
        body_x, body_v = P0[0] - xs, P0[1] - vs
    else:
        h = v - vmin
        if support == "band":
            if band is None or not band > 0:
                raise SpecError([("band", f"support='band' needs a positive band height (m): {band!r}")])
            contact = h <= band
        else:
            shifted = F.eval(q + math.pi)[2] - vmin
            contact = h < shifted
        if not contact.any():
            raise SpecError([("band", "no sample lies in the support band")])
        runs = intervals(contact)
        first, last = max(runs, key=lambda r: (r[1] - r[0]) % steps)
        start = q[first]
        width = ((q[last] - q[first]) % TWO_PI) + (q[1] - q[0])
        speed, vxa = w * dnorm[contact], np.abs(w * dx[contact])
        qc = np.sort(((q[contact] - start) % TWO_PI)) + start
        order = np.argsort((q[contact] - start) % TWO_PI)
        metrics = GaitMetrics(foot, support, F.omega, float(start), float(start + width),
                              float(np.ptp(x[contact])), float(lift), float(np.ptp(v[contact])),
                              float(np.count_nonzero(contact) / steps),
                              Stats(float(speed.max()), float(speed.min()), float(speed.mean()),
                                    0.5 * float(speed.max() + speed.min())),
                              Stats(float(vxa.max()), float(vxa.min()), float(vxa.mean()),
                                    0.5 * float(vxa.max() + vxa.min())),
                              (float((w * w * d2x[contact]).min()), float((w * w * d2x[contact]).max())), steps)
        body_q = qc
        xs, vs = x[contact][order], v[contact][order]
        body_x, body_v = xs[0] - xs, vs[0] - vs
    curves = GaitCurves(q, x, v, F.omega * dx, F.omega * dv, w * dnorm, contact, body_q, body_x, body_v)
    return metrics, curves


@dataclass(frozen=True)
class ModuleMetrics:
    """A walking module: identical legs at crank phase offsets. ``feet_on_ground`` over the cycle."""
    phases: tuple[float, ...]
    min_feet: int
    max_feet: int
    mean_feet: float
    airborne_fraction: float     # share of the cycle with no foot on the ground

    def as_dict(self) -> dict:
        d = asdict(self)
        d["phases"] = list(self.phases)
        return d


def module_timeline(metrics: GaitMetrics, phases, steps: int = 720):
    """Number of feet on the ground at each input angle: (q (steps,), count (steps,))."""
    q = np.linspace(0.0, TWO_PI, steps, endpoint=False)
    width = metrics.contact_end - metrics.contact_start
    count = np.zeros(steps, dtype=int)
    for ph in phases:
        count += (((q + ph - metrics.contact_start) % TWO_PI) <= width).astype(int)
    return q, count


def module_metrics(metrics: GaitMetrics, phases, steps: int = 720) -> ModuleMetrics:
    _, count = module_timeline(metrics, phases, steps)
    return ModuleMetrics(tuple(float(p) for p in phases), int(count.min()), int(count.max()), float(count.mean()),
                         float(np.mean(count == 0)))
