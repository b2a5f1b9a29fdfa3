"""The reduced equation of many designs integrated at once: a vectorised Dormand–Prince 5(4) with error control.

Every design carries its own step size, time and state; one iteration advances every active design by one
attempted step (the same arithmetic on arrays (n_designs,)), accepting or rejecting each by its own error
estimate (mixed tolerance ``atol + rtol·|y|``, the standard step controller). The terms are the designs'
trigonometric interpolants (:class:`~.series.PeriodicSeries` of samples on a uniform grid of one turn, from one
batched solve and one batched force analysis), so only designs whose mechanism turns fully are integrated; the
others are reported as not starting (``turns_fully`` False).

Per design the run records its turns (the crossing of q₀ + 2πk, located on the step's cubic Hermite
interpolant), each turn's extreme speeds (the step ends and the interior zero of q̈, on the same interpolant),
and stops at its periodic steady state (:func:`~.integrate.converged` on the periods), at a stall (the speed falls
back through zero, or below :data:`~.integrate.CREEP` of the motor's free speed) or at the time limit.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..errors import SpecError
from .integrate import CREEP
from .reduced import check_one_input, reduced_terms
from .series import PeriodicSeries, PeriodicTable

TWO_PI = 2.0 * math.pi
#: the Dormand–Prince 5(4) tableau (c, A rows, b of order 5, b − b̂ the error weights)
_C = np.array([0.0, 1 / 5, 3 / 10, 4 / 5, 8 / 9, 1.0, 1.0])
_A = [[], [1 / 5], [3 / 40, 9 / 40], [44 / 45, -56 / 15, 32 / 9],
      [19372 / 6561, -25360 / 2187, 64448 / 6561, -212 / 729],
      [9017 / 3168, -355 / 33, 46732 / 5247, 49 / 176, -5103 / 18656],
      [35 / 384, 0.0, 500 / 1113, 125 / 192, -2187 / 6784, 11 / 84]]
_E = np.array([71 / 57600, 0.0, -71 / 16695, 71 / 1920, -17253 / 339200, 22 / 525, -1 / 40])
_A_ROWS = [np.array(row, dtype=float) for row in _A]
#: a population's run to steady state stops when the periods' remaining change is below this share
POPULATION_STEADY = 1e-6
#: period changes below this multiple of the relative tolerance are the integration's own error, not convergence
NOISE = 100.0
#: samples of the turn on which a population's terms are sampled (unless a solved grid is given)
POPULATION_GRID = 128


@dataclass(frozen=True)
class PopulationEquation:
    """The terms of D designs: ``series`` (their Fourier coefficients (D, K + 1, 4)) and ``table``
    (:class:`~.series.PeriodicTable`: J* and J*′ from the series, the forces from a periodic cubic spline through
    their samples), ``valid (D,)`` the designs that turn fully with a positive J*, ``drive``
    (its inertia is added to J*), ``tail (D,)`` the magnitude of the last kept harmonic relative to its term's
    largest (an estimate of the series' truncation error)."""
    plan: object
    series: PeriodicSeries
    table: PeriodicTable
    valid: np.ndarray
    drive: object
    tail: np.ndarray

    def terms(self, q, rows):
        """(J, dJ, Qa, Qo) each (m,) at q (m,) of the designs ``rows`` (m,)."""
        value, slope = self.table(q, rows)
        extra = 0.0 if self.drive is None else self.drive.inertia
        return value[:, 0] + extra, slope[:, 0], value[:, 2], value[:, 3]

    def acceleration(self, q, w, rows):
        J, dJ, Qa, Qo = self.terms(q, rows)
        Qm = 0.0 if self.drive is None else self.drive.generalised(w)[0]
        return (Qm + Qa + np.sign(w) * Qo - 0.5 * dJ * w * w) / J


def population_equation(plan, params, drive, *, state=None, samples: int = POPULATION_GRID) -> PopulationEquation:
    """The :class:`PopulationEquation` of the designs ``params (D, n_params)``. ``state``: their solved grid
    (D, M) at q = 2πj/M (order 2), e.g. a synthesis cycle; else the grid is solved here."""
    check_one_input(plan)
    if plan.input_kinds[0] != "rotary":
        raise SpecError([("params", "a batch of designs runs cranks that turn fully; the input is linear")])
    params = np.asarray(params, dtype=float)
    M = samples if state is None else state.shape[-1]
    q = TWO_PI * np.arange(M) / M
    with np.errstate(all="ignore"):
        t = reduced_terms(plan, params[:, None, :], np.broadcast_to(q, (params.shape[0], M)), state=state)
        values = t.stacked()
        valid = np.all(t.valid, axis=1) & np.all(t.inertia > 0, axis=1)
    values = np.where(valid[:, None, None], values, 0.0)
    values[~valid, :, 0] = 1.0
    J = np.abs(values[..., 0]).max(axis=1)
    Q = np.maximum(np.abs(values[..., 2]).max(axis=1), np.abs(values[..., 3]).max(axis=1))
    scaled = values / np.stack([J, J, np.maximum(Q, 1e-300), np.maximum(Q, 1e-300)], axis=-1)[:, None, :]
    series = PeriodicSeries.from_samples(scaled, 0.0)
    coef = series.coefficients * np.stack([J, J, Q, Q], axis=-1)[:, None, :]
    tail = np.max(np.abs(series.coefficients[:, -1, :]), axis=-1)
    series = PeriodicSeries(0.0, coef)
    table = PeriodicTable.from_series(series)
    # the forces by a periodic cubic spline through their samples: local at the kinks of a load against velocity
    # (a truncated Fourier series rings there, and the step control follows the ringing)
    from scipy.interpolate import CubicSpline
    n = table.table.shape[1]
    spline = CubicSpline(np.append(q, TWO_PI), np.concatenate([values[:, :, 2:], values[:, :1, 2:]], axis=1),
                         axis=1, bc_type="periodic")
    fine = TWO_PI * np.arange(n) / n
    table.table[:, :, 2:, 0] = spline(fine)
    table.table[:, :, 2:, 1] = spline(fine, 1)
    return PopulationEquation(plan, series, table, valid, drive, tail)


@dataclass(frozen=True)
class PopulationResult:
    """The runs of D designs. Arrays over the common output times ``t (n,)``: ``q``, ``speed``, ``accel``
    (D, n) (NaN after a design's run ended); with a motor ``effort``, ``motor_torque``, ``power`` (D, n) and
    ``current`` (D, n) or None. Per design (D,): ``mean_speed``, ``delta`` (of the last turn), ``startup_time``
    (to 95 % of the steady mean speed, NaN unless steady), ``starts``, ``steady``, ``turns`` (completed),
    ``stop`` ('steady', 'stall', 'cannot start', 'time', 'turns', 'not steady', 'does not turn'), ``t_end``,
    ``steps`` (accepted steps: per design on the compiled route, the vectorised iterations on numpy's) and
    ``tail`` (the magnitude of each design's last kept Fourier harmonic, relative)."""
    plan: object
    params: np.ndarray
    t: np.ndarray
    q: np.ndarray
    speed: np.ndarray
    accel: np.ndarray
    effort: np.ndarray | None
    motor_torque: np.ndarray | None
    power: np.ndarray | None
    current: np.ndarray | None
    mean_speed: np.ndarray
    delta: np.ndarray
    startup_time: np.ndarray
    starts: np.ndarray
    steady: np.ndarray
    turns: np.ndarray
    stop: tuple
    t_end: np.ndarray
    steps: object
    tail: np.ndarray


def integrate_population(eq: PopulationEquation, *, q0, speed0, time=None, turns=None, rtol=1e-8,
                         max_turns: int = 1000, steady: float = POPULATION_STEADY, record: bool = True):
    """The vectorised run of every valid design of ``eq`` (module docstring). Returns a dict of per-design
    arrays and, with ``record``, ``history``: every accepted step as rows (design, t, q, q̇, q̈), sorted by design
    and time."""
    D = eq.valid.size
    motor = eq.drive is not None
    if time is None and turns is None and not motor:
        raise SpecError([("time", "a free motion (no motor) has no steady state to run to: give time= or cycles=")])
    free = eq.drive.input_free_speed() if motor else math.inf
    forward = 1.0
    if motor and float(eq.drive.generalised(np.array(0.0))[0]) < 0:
        forward = -1.0
    creep = CREEP * free if motor and math.isfinite(free) else 0.0
    t = np.zeros(D)
    q = np.broadcast_to(np.asarray(q0, dtype=float), (D,)).copy()
    w = np.broadcast_to(np.asarray(speed0, dtype=float), (D,)).copy()
    ref = np.where(np.abs(w) > 0, np.abs(w), free if math.isfinite(free) else 1.0)
    atol = np.stack([np.full(D, rtol * TWO_PI), rtol * ref], axis=0)
    active = eq.valid.copy()
    rows_all = np.arange(D)
    a = np.zeros(D)
    a[active] = eq.acceleration(q[active], w[active], rows_all[active])
    # the first step: a few thousandths of a turn at the reference speed
    h = np.full(D, 2e-3 * TWO_PI / np.maximum(ref, 1e-9))
    target = q + forward * TWO_PI
    turn_start = np.zeros(D)
    periods = np.full((D, 4), np.nan)
    n_turns = np.zeros(D, np.int64)
    wmin, wmax = w.copy(), w.copy()
    last_extremes = np.full((D, 2), np.nan)
    stop = np.array(["does not turn" if not v else "" for v in eq.valid], dtype=object)
    limit_t = np.inf if time is None else float(time)
    hist = [(np.flatnonzero(active), t[active], q[active], w[active], a[active])] if record else None
    steps = 0
    while active.any():
        steps += 1
        rows = rows_all[active]
        hh = np.minimum(h[rows], limit_t - t[rows])
        y0q, y0w = q[rows], w[rows]
        kq, kw = np.empty((7, rows.size)), np.empty((7, rows.size))
        kq[0], kw[0] = y0w, a[rows]
        for s in range(1, 7):
            coef = _A_ROWS[s]
            qs, ws = y0q + hh * (coef @ kq[:s]), y0w + hh * (coef @ kw[:s])
            kq[s], kw[s] = ws, eq.acceleration(qs, ws, rows)
        q1, w1, a1 = qs, ws, kw[6]
        eq_err = hh * (_E @ kq)
        ew_err = hh * (_E @ kw)
        sq = atol[0, rows] + rtol * np.maximum(np.abs(y0q), np.abs(q1))
        sw = atol[1, rows] + rtol * np.maximum(np.abs(y0w), np.abs(w1))
        with np.errstate(invalid="ignore"):
            err = np.sqrt(0.5 * ((eq_err / sq) ** 2 + (ew_err / sw) ** 2))
        ok = np.isfinite(err) & (err <= 1.0)
        factor = np.where(err > 0, np.clip(0.9 * np.where(err > 0, err, 1.0) ** -0.2, 0.2, 5.0), 5.0)
        factor = np.where(np.isfinite(factor), factor, 0.2)
        h[rows] = hh * np.where(ok, factor, np.minimum(factor, 0.9))
        acc_rows = rows[ok]
        if acc_rows.size:
            t0, qa, wa, aa = t[acc_rows], y0q[ok], y0w[ok], kw[0, ok]
            dt = hh[ok]
            qb, wb, ab = q1[ok], w1[ok], a1[ok]
            # the turn's speed extremes: the step ends and the interior zero of q̈ (linear in the step)
            inside = np.flatnonzero(aa * ab < 0)
            w_ext = wb.copy()
            if inside.size:
                s_ext = aa[inside] / (aa[inside] - ab[inside])
                w_ext[inside] = _hermite(wa[inside], aa[inside], wb[inside], ab[inside], dt[inside], s_ext, None)
            wmin[acc_rows] = np.minimum.reduce([wmin[acc_rows], wb, w_ext])
            wmax[acc_rows] = np.maximum.reduce([wmax[acc_rows], wb, w_ext])
            # a completed turn
            crossed = forward * (qb - target[acc_rows]) >= 0
            if crossed.any():
                cr = acc_rows[crossed]
                s = _crossing(qa[crossed], wa[crossed], qb[crossed], wb[crossed], dt[crossed], target[cr])
                tc = t0[crossed] + s * dt[crossed]
                periods[cr] = np.roll(periods[cr], -1, axis=1)
                periods[cr, -1] = tc - turn_start[cr]
                turn_start[cr] = tc
                target[cr] += forward * TWO_PI
                n_turns[cr] += 1
                last_extremes[cr] = np.stack([wmin[cr], wmax[cr]], axis=1)
                wmin[cr], wmax[cr] = wb[crossed], wb[crossed]
            t[acc_rows], q[acc_rows], w[acc_rows], a[acc_rows] = t0 + dt, qb, wb, ab
            # ends
            done = np.zeros(acc_rows.size, bool)
            if motor:
                stalled = forward * wb <= 0
                crept = (forward * wb < creep) & (forward * wa >= creep)
                for mask, why in ((stalled | crept, "stall"),):
                    if mask.any():
                        idx = acc_rows[mask]
                        stop[idx] = np.where(n_turns[idx] > 0, why, "cannot start")
                        done |= mask
            if time is None and turns is None:
                conv = _converged(periods[acc_rows], steady, NOISE * rtol) & ~done
                stop[acc_rows[conv]] = "steady"
                done |= conv
                many = (n_turns[acc_rows] >= max_turns) & ~done
                stop[acc_rows[many]] = "not steady"
                done |= many
            if turns is not None:
                fin = (n_turns[acc_rows] >= turns) & ~done
                stop[acc_rows[fin]] = "turns"
                done |= fin
            if time is not None:
                fin = (t[acc_rows] >= limit_t * (1 - 1e-15)) & ~done
                stop[acc_rows[fin]] = "time"
                done |= fin
            active[acc_rows[done]] = False
        if record and acc_rows.size:
            hist.append((acc_rows, t[acc_rows], q[acc_rows], w[acc_rows], a[acc_rows]))
        tiny = h[rows] < 1e-14 * np.maximum(t[rows], 1e-3)
        if tiny.any():
            stop[rows[tiny]] = "step too small"
            active[rows[tiny]] = False
    T = periods[:, -1]
    mean = np.where(n_turns > 0, forward * TWO_PI / _limit_period(periods), np.nan)
    delta = (last_extremes[:, 1] - last_extremes[:, 0]) / np.abs(mean)
    if record:         # the accepted steps of every design, in order: (design, t, q, q̇, q̈), sorted by design
        rows, *cols = (np.concatenate(c) for c in zip(*hist))
        order = np.argsort(rows, kind="stable")
        hist = (rows[order],) + tuple(c[order] for c in cols)
    return {"t_end": t, "q": q, "speed": w, "turns": n_turns, "stop": tuple(stop), "mean_speed": mean,
            "delta": np.where(n_turns > 0, delta, np.nan), "period": T, "history": hist, "steps": steps,
            "forward": forward}


def _hermite(ya, da, yb, db, h, s, _):
    """The cubic Hermite interpolant of y (values ya, yb and slopes da, db at the ends of steps of length h) at
    the fractions s of the steps."""
    h00, h10 = 2 * s ** 3 - 3 * s ** 2 + 1, s ** 3 - 2 * s ** 2 + s
    h01, h11 = -2 * s ** 3 + 3 * s ** 2, s ** 3 - s ** 2
    return h00 * ya + h10 * h * da + h01 * yb + h11 * h * db


def _crossing(qa, wa, qb, wb, h, target):
    """The fraction s of each step where the Hermite interpolant of q reaches ``target`` (Newton from the chord)."""
    with np.errstate(all="ignore"):
        s = np.clip((target - qa) / (qb - qa), 0.0, 1.0)
        for _ in range(6):
            f = _hermite(qa, wa, qb, wb, h, s, None) - target
            d = (6 * s ** 2 - 6 * s) * qa + (3 * s ** 2 - 4 * s + 1) * h * wa + (-6 * s ** 2 + 6 * s) * qb \
                + (3 * s ** 2 - 2 * s) * h * wb
            s = np.clip(s - np.where(d != 0, f / d, 0.0), 0.0, 1.0)
    return np.where(np.isfinite(s), s, 1.0)


def _converged(periods, tol, noise):
    """(m,) bool: the rows of the last four periods (m, 4) that have converged (:func:`~.integrate.converged`;
    ``noise``: the share of a period below which changes are the integration's own error)."""
    d = np.diff(periods, axis=1)
    with np.errstate(all="ignore"):
        r = np.abs(d[:, 2] / d[:, 1])
        r_prev = np.abs(d[:, 1] / d[:, 0])
        contracting = (r < 1) & (r_prev < 1)
        remaining = np.abs(d[:, 2]) * (1.0 + r / (1.0 - r))
        T = periods[:, 3]
        ok = np.where(contracting, remaining <= tol * T, np.abs(d[:, 2]) <= 1e-3 * tol * T)
        ok |= np.max(np.abs(d), axis=1) <= noise * T
    return np.all(np.isfinite(periods), axis=1) & (ok | (d[:, 2] == 0))


def _limit_period(periods):
    """The steady period: the last one, corrected by the geometric tail of the last changes where they contract."""
    d = np.diff(periods, axis=1)
    with np.errstate(all="ignore"):
        r = d[:, 2] / d[:, 1]
        tail = np.where((np.abs(r) < 1) & np.isfinite(r), d[:, 2] * r / (1.0 - r), 0.0)
    return periods[:, 3] + tail


def startup_times(hist, level, forward: float = 1.0):
    """(D,) the first time each design's speed reaches ``level (D,)`` (on the cubic Hermite interpolant of the
    speed between its recorded steps; NaN when it never does). ``hist``: the run's (design, t, q, q̇, q̈) rows
    sorted by design and time."""
    rows, T, _, W, A = hist
    D = level.shape[0]
    out = np.full(D, np.nan)
    with np.errstate(invalid="ignore"):
        reached = forward * (W - level[rows]) >= 0
    hit = np.flatnonzero(reached)
    if not hit.size:
        return out
    designs, first = np.unique(rows[hit], return_index=True)
    i = hit[first]
    at_start = (i == 0) | (rows[np.maximum(i - 1, 0)] != designs)
    out[designs[at_start]] = T[i[at_start]]
    j, d = i[~at_start], designs[~at_start]
    h = T[j] - T[j - 1]
    s = _crossing(W[j - 1], A[j - 1], W[j], A[j], h, level[d])
    out[d] = T[j - 1] + s * h
    return out


def _resample(hist, tg, D):
    """(q, w, a) (D, n) at the times ``tg`` (n,): the cubic Hermite interpolant of each design's accepted steps
    (NaN after its run ended)."""
    rows, T, Q, W, A = hist
    out = [np.full((D, tg.size), np.nan) for _ in range(3)]
    starts = np.searchsorted(rows, np.arange(D + 1))
    for d in range(D):
        lo, hi = starts[d], starts[d + 1]
        if hi - lo < 2:
            continue
        td = T[lo:hi]
        sel = tg <= td[-1]
        j = lo + np.clip(np.searchsorted(td, tg[sel], side="right") - 1, 0, hi - lo - 2)
        h = T[j + 1] - T[j]
        s = (tg[sel] - T[j]) / h
        out[0][d, sel] = _hermite(Q[j], W[j], Q[j + 1], W[j + 1], h, s, None)
        out[1][d, sel] = _hermite(W[j], A[j], W[j + 1], A[j + 1], h, s, None)
        out[2][d, sel] = A[j] + s * (A[j + 1] - A[j])
    return out


__all__ = ["PopulationEquation", "PopulationResult", "integrate_population", "population_equation",
           "startup_times"]
