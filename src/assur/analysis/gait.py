"""Gait metrics of a walking leg from its foot path over one crank turn (no physics engine).

Definitions (docs/papers/000.md §6, shared with paper 004). The foot path P(q) over one input turn is
projected on the stride axis (``x = P·ground``) and the vertical axis (``v = P·up``, pointing
away from the ground side); the height is ``h = v − min v``.

- contact (support) arc: the crank angles of the two horizontal extremes (min x, max x) split
  the turn into two arcs; the contact arc is the one whose time-mean height is lower;
- step length: the x-range of the contact arc (= of the whole path);
- lift: the vertical extent of the whole path; sag: the vertical extent of the contact arc;
- duty factor: contact-arc width / 2π;
- support speed |v| = ω·|dP/dq| over the contact arc: max, min, time-mean and midrange;
  the same for the absolute horizontal component |v_x|; the horizontal acceleration range;
- the horizontal-speed spread ``vx_spread[f]`` for the central fractions f = 0.8, 0.9 of the stride: (max − min)/mean
  of |v_x| over the inputs of the contact arc where the foot x lies in the central fraction f of the stride
  ``[x_min, x_max]``, with the window's exact ends (:func:`window_vx_spread`; :func:`central_vx_spread` is the
  same on samples alone, what synthesis screens vectorise); 0 for a foot that carries the body at constant speed;
- the frame pivot's absolute path while the foot is planted (paper 004, Fig. 6 b–c):
  with the foot fixed, the body moves by the negative of the foot's relative displacement.

Extremes and arc ends are refined from a uniform sample by a bounded 1-D minimiser; speeds come
from the solver's exact derivatives, never from finite differences of the path.
Alternative support definitions: ``support="band"`` (samples with h ≤ ``band``) and
``support="antiphase"`` (two legs 180° apart: a leg supports while lower than the other).

:func:`gait_metrics` and :func:`gait_curves` take a plan, a :class:`~assur.analysis.sampling.Cycle` (a solved
cycle shared with other analyses) or a State solved over the uniform grid of one turn.
:func:`population_gait` is the same definition on uniform samples only, vectorised over a population of designs
(what dimensional synthesis optimises).
"""
from __future__ import annotations

import math
from dataclasses import asdict, dataclass, field

import numpy as np
from scipy.integrate import simpson
from scipy.optimize import brentq

from ..engine import State, solve
from ..engine.options import ambiguous_note
from ..engine.plan import require_plan
from ..errors import SpecError, UnbuildableError
from ..kernels.arcs import arc_mask, in_arc, population_contact, sampled_arcs
from ..kernels.runs import cyclic_runs
from .sampling import TWO_PI, Cycle, roots_between


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
    vx_spread: dict = field(default_factory=dict)   # {"0.8": …, "0.9": …}: window_vx_spread of the contact arc

    @property
    def clearance(self) -> float:
        """How far the foot rises above the highest point of its support in the swing (m): lift − sag. Zero for a
        foot that retraces its support (a foot on a link hinged to the frame swings back along its own arc)."""
        return max(self.lift - self.sag, 0.0)      # lift ≥ sag: below zero only by round-off

    @property
    def contact_ratio(self) -> float:
        """Contact/transfer time ratio = duty / (1 − duty)."""
        return self.duty_factor / (1.0 - self.duty_factor) if self.duty_factor < 1 else math.inf

    def as_dict(self) -> dict:
        d = asdict(self)
        d["support_ax"] = {"min": self.support_ax[0], "max": self.support_ax[1]}
        d["contact_ratio"] = self.contact_ratio
        d["clearance"] = self.clearance
        return d

    def _repr_html_(self) -> str:
        from ..model.display import html_table
        units = {"omega": "rad/s", "contact_start": "rad", "contact_end": "rad", "step_length": "m", "lift": "m",
                 "sag": "m", "clearance": "m", "support_speed": "m/s", "support_vx": "m/s", "support_ax": "m/s²"}
        rows = [(k, getattr(self, k)) for k in self.__dataclass_fields__] + [("contact_ratio", self.contact_ratio),
                                                                             ("clearance", self.clearance)]
        return html_table(f"Gait metrics of {self.foot}", rows, units=units)


#: the central fractions of the stride whose horizontal-speed spread the gait metrics report
VX_FRACTIONS = (0.8, 0.9)


def central_vx_spread(x, vx, contact, fraction: float, x_min, x_max):
    """(max − min)/mean of |vx| over the samples with ``contact`` whose x lies in the central ``fraction`` of the
    stride ``[x_min, x_max]`` (``|x − (x_min + x_max)/2| ≤ fraction·(x_max − x_min)/2``), the sample mean.

    x, vx, contact: (..., M) stride coordinates, horizontal velocities and contact flags of M samples;
    x_min, x_max: (...,) the stride's ends. Returns (...,): NaN where no sample lies in the window."""
    x, vx = np.asarray(x, dtype=float), np.abs(np.asarray(vx, dtype=float))
    lo, hi = np.asarray(x_min, dtype=float)[..., None], np.asarray(x_max, dtype=float)[..., None]
    inside = np.asarray(contact, dtype=bool) & (np.abs(x - 0.5 * (lo + hi)) <= 0.5 * fraction * (hi - lo))
    count = np.count_nonzero(inside, axis=-1)
    with np.errstate(all="ignore"):
        vmax = np.where(inside, vx, -np.inf).max(axis=-1)
        vmin = np.where(inside, vx, np.inf).min(axis=-1)
        mean = np.where(inside, vx, 0.0).sum(axis=-1) / count
        return np.where(count > 0, (vmax - vmin) / mean, np.nan)


def _vx_spreads(x, vx, contact, x_min, x_max) -> dict:
    return {f"{f:g}": float(central_vx_spread(x, vx, contact, f, x_min, x_max)) for f in VX_FRACTIONS}


def window_vx_spread(F: "_Foot", qq, vals, x_min: float, x_max: float, fraction: float, critical=None) -> float:
    """(max − min)/mean of |v_x| over the inputs of the contact arc sampled at ``qq`` (n,) (increasing, every sample
    in contact; ``vals``: F's values there) where the foot lies in the central ``fraction`` of the stride
    ``[x_min, x_max]``, refined: the window's ends are the exact inputs where x(q) crosses
    ``centre ± fraction·(x_max − x_min)/2`` (roots between the samples), the extremes of |v_x| are taken at those
    ends and at the exact roots of its derivative inside, and the mean is the time mean (Simpson's rule over the
    samples and the exact ends). The sampled form (:func:`central_vx_spread`) misses the window's ends by up to one
    sample, where |v_x| changes fastest, so it underestimates the spread by a term of the order of the sample
    spacing; here only the mean's quadrature error is left. NaN if no sample lies in the window.

    F: an evaluator, ``F.eval(q (k,))`` → {"x", "dx", "absdx", "dabsdx"} (k,) each (x, its derivative by the
    sampling parameter, |dx| and its derivative); critical: (q (m,), |dx| (m,)) the roots of d|dx| and of dx on the
    arc with their values, when the caller has them (else they are found here)."""
    centre, half = 0.5 * (x_min + x_max), 0.5 * fraction * (x_max - x_min)
    d = vals["x"] - centre
    inside = np.abs(d) <= half
    idx = np.flatnonzero(inside)
    if idx.size == 0:
        return math.nan
    runs = np.split(idx, np.flatnonzero(np.diff(idx) > 1) + 1)
    # the outside neighbour of each run's first and last sample, where there is one and the foot is placed there (a
    # resampled input of a Newton-solved leg may not assemble: NaN): a bracket of the window's end
    brackets = [p for p in [(r[0] - 1, r[0]) for r in runs if r[0] > 0] + [(r[-1], r[-1] + 1) for r in runs
                                                                           if r[-1] + 1 < len(qq)]
                if np.isfinite(d[p[0]]) and np.isfinite(d[p[1]])]
    ends = {}
    for sign in (-1.0, 1.0):
        pairs = [p for p in brackets if np.sign(d[p[0] if not inside[p[0]] else p[1]]) == sign]
        if pairs:
            bound = centre + sign * half
            a, b = qq[[p[0] for p in pairs]], qq[[p[1] for p in pairs]]
            for p, r in zip(pairs, roots_between(lambda t, bound=bound: F.eval(t)["x"] - bound, a, b)):
                ends[p] = float(r)
    # the ends' values in one solve; the samples' are the caller's. An end where the foot is not placed is left out:
    # its run ends at its own sample
    keys = list(ends)
    end_q = np.array([ends[k] for k in keys])
    names = ("x", "dx", "absdx", "dabsdx")
    end_values = F.eval(end_q) if keys else {k: np.empty(0) for k in names}
    slot = {k: j for j, k in enumerate(keys) if np.isfinite(end_q[j]) and np.isfinite(end_values["absdx"][j])}
    if critical is None:
        crit_q = critical_points(F, ("dabsdx", "dx"), qq, vals)
        crit_v = F.eval(crit_q)["absdx"] if crit_q.size else np.empty(0)
    else:
        crit_q, crit_v = (np.asarray(c, dtype=float) for c in critical)
    total, duration, lo_vx, hi_vx = 0.0, 0.0, math.inf, -math.inf
    for r in runs:
        head = [slot[(r[0] - 1, r[0])]] if (r[0] - 1, r[0]) in slot else []     # else the run's own sample ends it
        tail = [slot[(r[-1], r[-1] + 1)]] if (r[-1], r[-1] + 1) in slot else []
        q = np.concatenate([end_q[head], qq[r], end_q[tail]])
        sub = {k: np.concatenate([end_values[k][head], vals[k][r], end_values[k][tail]]) for k in names}
        absdx = np.abs(sub["dx"])
        total += float(simpson(absdx, x=q)) if len(q) > 2 else float(np.trapezoid(absdx, q))
        duration += float(q[-1] - q[0])
        within = crit_v[(crit_q > q[0]) & (crit_q < q[-1])]
        candidates = np.concatenate([sub["absdx"][[0, -1]], within])   # |v_x| at the window's ends and inside
        lo_vx, hi_vx = min(lo_vx, float(np.nanmin(candidates))), max(hi_vx, float(np.nanmax(candidates)))
    mean = total / duration if duration > 0 else float(np.mean(np.abs(vals["dx"][idx])))
    return (hi_vx - lo_vx) / mean


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
    """The foot's stride/vertical coordinates and their exact derivatives at any inputs."""

    def __init__(self, cycle, foot, ground, up):
        self.cycle = cycle
        self.i = cycle.plan.point_index(foot)
        self.g = np.asarray(ground, dtype=float)
        self.u = np.asarray(up, dtype=float)
        self.omega = float(cycle.plan.speeds[0])

    def eval(self, q) -> dict:
        return self.values(self.cycle.state_at(np.atleast_1d(np.asarray(q, dtype=float))))

    def values(self, s) -> dict:
        """The foot's coordinates and derivatives in a State solved with order 2."""
        P = s.pos[..., self.i, :]
        dP = s.dpos_dq[..., self.i, :, 0]
        d2P = s.d2pos_dq2[..., self.i, :, 0, 0]
        norm = np.hypot(dP[..., 0], dP[..., 1])
        with np.errstate(invalid="ignore", divide="ignore"):   # NaN where unassembled or the foot stands still
            dspeed = np.sum(dP * d2P, axis=-1) / norm
        return {"valid": s.valid, "x": P @ self.g, "v": P @ self.u, "dx": dP @ self.g, "dv": dP @ self.u,
                "d2x": d2P @ self.g, "d2v": d2P @ self.u, "speed": norm,
                "dspeed": dspeed, "absdx": np.abs(dP @ self.g),
                "dabsdx": np.sign(dP @ self.g) * (d2P @ self.g)}

    def scalar(self, key):
        return lambda q: float(self.eval(q)[key][0])


def critical_points(F, dkeys, qq, vals) -> np.ndarray:
    """The exact roots of each derivative ``F[dkey]`` (dkeys) between the grid samples ``qq`` where it changes sign,
    refined together (:func:`~assur.analysis.sampling.roots_between`), and the samples where it is exactly 0."""
    out = []
    for k in dkeys:
        dv = vals[k]
        idx = np.nonzero(np.sign(dv[:-1]) * np.sign(dv[1:]) < 0)[0]
        out += list(roots_between(lambda t, k=k: F.eval(t)[k], qq[idx], qq[idx + 1]))
        out += list(qq[np.nonzero(dv == 0)[0]])
    return np.array(out, dtype=float)


def _extremes(F: _Foot, key: str, dkey: str, qq, vals, lo: float, hi: float):
    """(min, max) of F[key] over [lo, hi]: candidates are the ends and the exact roots of its
    derivative F[dkey] between the grid samples (:func:`critical_points`)."""
    cands = np.concatenate([[lo, hi], critical_points(F, (dkey,), qq, vals)])
    values = F.eval(cands)[key]     # a refined root where the foot is not placed is NaN: left out
    return float(np.nanmin(values)), float(np.nanmax(values))


def _extreme_location(F: _Foot, key: str, dkey: str, q, vals, which: str) -> tuple[float, float]:
    """(q, value) of the global min or max of F[key] over a full cyclic grid, refined by a root of F[dkey]."""
    i = int(np.argmin(vals[key]) if which == "min" else np.argmax(vals[key]))
    step = q[1] - q[0]
    f = F.scalar(dkey)
    best = (float(q[i]), float(vals[key][i]))
    for a in (q[i] - step, q[i]):
        b = a + step
        fa, fb = f(a), f(b)
        if np.isfinite(fa) and np.isfinite(fb) and fa * fb <= 0:
            try:
                r = brentq(f, a, b, xtol=1e-14, rtol=1e-14) if fa * fb < 0 else (a if fa == 0 else b)
            except ValueError:      # the foot is not placed somewhere inside (an uncertified position): the grid's
                continue            # sample stands
            val = float(F.eval(r)[key][0])
            if (which == "min" and val <= best[1]) or (which == "max" and val >= best[1]):
                best = (float(r) % TWO_PI, val)
    return best


def resolve_gait(plan, foot=None, ground=None, up=None) -> tuple[str, tuple, tuple]:
    """(foot point name, ground direction (2,), up direction (2,)) of a plan's gait: each given value, else the
    mechanism's ``[gait]`` table, else the x axis as ground and its left normal as up. SpecError when no foot is
    named anywhere."""
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
    cannot turn fully.

    plan: a plan (solved here at ``params``, default its defaults), a :class:`~assur.analysis.sampling.Cycle`
    (its plan and parameters; the uniform grid of ``steps`` samples comes from ``cycle.grid(steps)``), or a
    State of one plan solved with order 2 at the inputs ``linspace(0, 2π, n, endpoint=False)`` (n, 1) and at
    ``params`` (then n replaces ``steps``). foot, ground, up: as :func:`resolve_gait`."""
    return _gait(plan, params, foot, ground, up, steps, support, band)[0]


def gait_curves(plan, params=None, *, foot=None, ground=None, up=None, steps: int = 720,
                support: str = "arc", band: float | None = None) -> GaitCurves:
    """Sampled gait curves of one leg over one turn, for plots (arguments as :func:`gait_metrics`)."""
    return _gait(plan, params, foot, ground, up, steps, support, band)[1]


def gait_metrics_and_curves(plan, params=None, *, foot=None, ground=None, up=None, steps: int = 720,
                            support: str = "arc", band: float | None = None) -> tuple[GaitMetrics, GaitCurves]:
    """:func:`gait_metrics` and :func:`gait_curves` from one computation (arguments as :func:`gait_metrics`)."""
    return _gait(plan, params, foot, ground, up, steps, support, band)


def _grid(source, params, steps):
    """(cycle, q (n,), state at q) of a plan (its turn solved here once, at ``params`` and ``steps``), a Cycle or
    Study (its own run), or a State solved over the uniform grid of one turn (nothing solved)."""
    if isinstance(source, State):
        cycle = Cycle.from_state(source, params)
    else:
        cycle = Cycle.of(source, params, steps)
    q, state = cycle.grid()
    return cycle, q, state


def _gait(plan, params, foot, ground, up, steps, support, band):
    if support not in ("arc", "band", "antiphase"):
        raise SpecError([("support", f"must be 'arc', 'band' or 'antiphase': {support!r}")])
    if isinstance(plan, State):
        steps = len(plan.inputs)
    elif isinstance(plan, Cycle):
        steps = plan.steps
    else:
        require_plan(plan)
    if isinstance(steps, bool) or not isinstance(steps, (int, np.integer)) or steps < 16:
        raise SpecError([("steps", f"must be at least 16: {steps}")])
    foot, ground, up = resolve_gait(plan.plan if isinstance(plan, (State, Cycle)) else plan, foot, ground, up)
    cycle, q, state = _grid(plan, params, steps)
    F = _Foot(cycle, foot, ground, up)
    vals = F.values(state)
    valid = vals["valid"]
    if not np.all(valid):
        bad = q[~valid]
        n_amb = int(np.count_nonzero(state.ambiguous))
        amb = f"; {ambiguous_note(n_amb)}" if n_amb else ""
        raise UnbuildableError(
            f"the crank cannot turn fully: {np.count_nonzero(~valid)} of {steps} positions cannot be assembled "
            f"(from {np.degrees(bad.min()):.1f}° to {np.degrees(bad.max()):.1f}°{amb}); no gait metrics",
            int(np.count_nonzero(~valid)), steps)
    x, v, dx = vals["x"], vals["v"], vals["dx"]
    w = abs(F.omega)
    # exact extremes of the whole path (roots of the exact derivatives)
    vmin = _extreme_location(F, "v", "dv", q, vals, "min")[1]
    vmax = _extreme_location(F, "v", "dv", q, vals, "max")[1]
    lift = vmax - vmin
    qa, xa = _extreme_location(F, "x", "dx", q, vals, "min")
    qb, xb = _extreme_location(F, "x", "dx", q, vals, "max")
    step_length = xb - xa
    if support == "arc":
        # the two arcs between the horizontal extremes; the contact arc has the lower mean height (decided on the
        # turn's samples; only the contact arc is sampled afresh, at ``steps`` inputs from its start to its end)
        arcs = []
        for start, end in ((qa, qb), (qb, qa)):
            width = (end - start) % TWO_PI
            inside = in_arc(q, start, width)
            arcs.append((float(np.mean(v[inside] - vmin)) if inside.any() else math.inf, start, width))
        arcs.sort(key=lambda a: a[0])
        _, start, width = arcs[0]
        qq = start + np.linspace(0.0, width, steps)
        av = F.eval(qq)
        lo, hi = start, start + width
        smin, smax = _extremes(F, "v", "dv", qq, av, lo, hi)
        sag = smax - smin
        spmin, spmax = _extremes(F, "speed", "dspeed", qq, av, lo, hi)
        crit_q = critical_points(F, ("dabsdx", "dx"), qq, av)       # |v_x|'s extremes: the arc's and the windows'
        crit_v = F.eval(np.concatenate([[lo, hi], crit_q]))["absdx"]
        vxmin, vxmax = float(np.nanmin(crit_v)), float(np.nanmax(crit_v))
        ax = w * w * av["d2x"]
        metrics = GaitMetrics(foot, "arc", F.omega, float(start), float(start + width), float(step_length),
                              float(lift), float(sag), float(width / TWO_PI),
                              Stats.of(w * av["speed"], qq, w * spmax, w * spmin),
                              Stats.of(w * av["absdx"], qq, w * vxmax, w * vxmin),
                              (float(ax.min()), float(ax.max())), steps,
                              {f"{f:g}": window_vx_spread(F, qq, av, xa, xb, f, (crit_q, crit_v[2:]))
                               for f in VX_FRACTIONS})
        contact = in_arc(q, start, width)
        body_q = qq
        xs, vs = av["x"], av["v"]
        body_x, body_v = xs[0] - xs, vs[0] - vs
    else:
        h = v - vmin
        if support == "band":
            if band is None or not band > 0:
                raise SpecError([("band", f"support='band' needs a positive band height (m): {band!r}")])
            contact = h <= band
        else:
            shifted = F.eval(q + math.pi)["v"] - vmin
            contact = h < shifted
        if not contact.any():
            raise SpecError([("band", "no sample lies in the support band")])
        runs = cyclic_runs(contact)
        first, last = max(runs, key=lambda r: (r[1] - r[0]) % steps)
        start = q[first]
        width = ((q[last] - q[first]) % TWO_PI) + (q[1] - q[0])
        speed, vxa = w * vals["speed"][contact], np.abs(w * dx[contact])
        order = np.argsort((q[contact] - start) % TWO_PI)
        d2x = vals["d2x"][contact]
        metrics = GaitMetrics(foot, support, F.omega, float(start), float(start + width),
                              float(np.ptp(x[contact])), float(lift), float(np.ptp(v[contact])),
                              float(np.count_nonzero(contact) / steps),
                              Stats(float(speed.max()), float(speed.min()), float(speed.mean()),
                                    0.5 * float(speed.max() + speed.min())),
                              Stats(float(vxa.max()), float(vxa.min()), float(vxa.mean()),
                                    0.5 * float(vxa.max() + vxa.min())),
                              (float((w * w * d2x).min()), float((w * w * d2x).max())), steps,
                              _vx_spreads(x, w * dx, contact, x[contact].min(), x[contact].max()))
        body_q = np.sort((q[contact] - start) % TWO_PI) + start
        xs, vs = x[contact][order], v[contact][order]
        body_x, body_v = xs[0] - xs, vs[0] - vs
    curves = GaitCurves(q, x, v, F.omega * dx, F.omega * vals["dv"], w * vals["speed"], contact, body_q,
                        body_x, body_v)
    return metrics, curves


def population_gait(pos, valid, dpos_dq=None, *, ground, up, omega: float = 1.0, scale: float = 1.0) -> dict:
    """Gait quantities of n designs from uniform samples of their foot paths over one turn, vectorised.

    The definitions of the module docstring on the samples alone (no refinement): the contact arc is the arc
    between the samples of smallest and largest x whose sample-mean height is lower.
    pos: (n, M, 2) foot positions at M uniform inputs over one turn; valid: (n, M) bool; dpos_dq: (n, M, 2) their
    derivatives by the input, or None; ground, up: (2,) directions; omega: the input speed magnitude (rad/s);
    scale: a factor on every length (e.g. SI → the file's unit).
    Returns ``{"step", "lift", "sag", "duty", "top", "clearance"}`` (top: the path's largest height ``P·up``, a
    coordinate; clearance: lift − sag, how far the foot rises above its support in the swing) and, with ``dpos_dq``,
    ``{"speed_mean", "speed_spread",
    "vx_spread", "vx_spread_90"}`` (the last two: :func:`central_vx_spread` at the fractions 0.8 and 0.9 of the
    sampled stride), each (n,) in ``scale`` units (speeds per second; duty a fraction), NaN for a design with an
    invalid sample."""
    g, u = np.asarray(ground, dtype=float), np.asarray(up, dtype=float)
    x, v = pos @ g * scale, pos @ u * scale
    M = x.shape[1]
    ia, ib, start, width = sampled_arcs(x, v)
    contact = arc_mask(start, width, M)
    out = {"step": np.take_along_axis(x, ib[:, None], 1)[:, 0] - np.take_along_axis(x, ia[:, None], 1)[:, 0],
           "lift": np.max(v, axis=1) - np.min(v, axis=1),   # NaN where a sample failed
           "sag": np.where(contact, v, -np.inf).max(axis=1) - np.where(contact, v, np.inf).min(axis=1),
           "duty": np.count_nonzero(contact, axis=1) / M,
           "top": np.max(v, axis=1)}
    out["clearance"] = out["lift"] - out["sag"]
    if dpos_dq is not None:
        speed = np.linalg.norm(dpos_dq, axis=-1) * omega * scale
        smax = np.where(contact, speed, -np.inf).max(axis=1)
        smin = np.where(contact, speed, np.inf).min(axis=1)
        smean = np.where(contact, speed, 0).sum(axis=1) / np.count_nonzero(contact, axis=1)
        out["speed_mean"] = smean
        out["speed_spread"] = (smax - smin) / smean
        vx = dpos_dq @ g * omega * scale
        x_min = np.take_along_axis(x, ia[:, None], 1)[:, 0]
        x_max = np.take_along_axis(x, ib[:, None], 1)[:, 0]
        out["vx_spread"] = central_vx_spread(x, vx, contact, 0.8, x_min, x_max)
        out["vx_spread_90"] = central_vx_spread(x, vx, contact, 0.9, x_min, x_max)
    bad = ~np.all(valid, axis=1)
    return {key: np.where(bad, np.nan, val) for key, val in out.items()}


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

    def _repr_html_(self) -> str:
        from ..model.display import dataclass_table
        return dataclass_table(self, "Walking module", units={"phases": "rad"})


def module_timeline(metrics: GaitMetrics, phases, steps: int = 720):
    """Number of feet on the ground at each input angle: (q (steps,), count (steps,))."""
    q = np.linspace(0.0, TWO_PI, steps, endpoint=False)
    return q, feet_on_ground(metrics, phases, q).sum(axis=1)


def module_metrics(metrics: GaitMetrics, phases, steps: int = 720) -> ModuleMetrics:
    _, count = module_timeline(metrics, phases, steps)
    return ModuleMetrics(tuple(float(p) for p in phases), int(count.min()), int(count.max()), float(count.mean()),
                         float(np.mean(count == 0)))


def legs_state(plan, phases, q, params=None, order: int = 2):
    """All legs of a walking module in one batched solve: the legs are a batch axis.

    q: (n,) crank angles; phases: (n_legs,) offsets (rad). Returns a State of shape (n, n_legs):
    leg k is at crank angle q + phases[k]."""
    q = np.asarray(q, dtype=float)
    ph = np.asarray(phases, dtype=float)
    return solve(plan, params, (q[:, None] + ph[None, :])[..., None], order=order)


def feet_on_ground(metrics: GaitMetrics, phases, q):
    """(n, n_legs) bool: leg k's foot is in its contact arc at crank angle q + phases[k]."""
    q = np.asarray(q, dtype=float)[:, None] + np.asarray(phases, dtype=float)[None, :]
    return in_arc(q, metrics.contact_start, metrics.contact_end - metrics.contact_start)
