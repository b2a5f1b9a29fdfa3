"""A compiled (numba) Dormand–Prince 5(4) run of many one-degree-of-freedom equations of motion at once.

Each design d integrates q̈ = (Q_m(q̇) + Q_a(q) + sign(q̇)·Q_o(q) − ½·J′(q)·q̇²)/J(q) from (q0[d], w0[d]) with its own
step size (mixed tolerance atol + rtol·|y|, the standard controller), its terms read from a periodic table of
values and slopes at n uniform inputs per turn (cubic Hermite; ``flat`` (D·n, 8): J, J′, Q_a, Q_o, then their
slopes), the motor from a characteristic code (``motor``: see :data:`MOTOR_CODES` and :func:`effort`). The designs
are independent and run one after the other (a parallel loop compiled three times slower for little gain on two
busy cores). Everything here is plain arrays and numbers: no plan, no names (the layer of kernels).

Per design it records its turns (q0 + 2πk crossed, located on the step's Hermite interpolant of q), the extreme
speeds of its last complete turn, the first time its speed reaches ``level[d]`` (NaN: not asked), samples at the
times ``grid`` (Hermite), and stops by ``STOP_*``: steady (the last four periods converged), stall (the speed falls
back through zero, or below ``creep``), cannot start (a stall before the first turn), turns, time, not steady, a
step too small.
"""
from __future__ import annotations

import math

import numpy as np

from .numba_target import configure

configure()                     # before numba is imported (numba_target's docstring)
from numba import njit  # noqa: E402

TWO_PI = 2.0 * math.pi
#: motor characteristic codes: none, constant, DC (stall, free speed), induction (breakdown torque, slip,
#: synchronous speed), table (rows in xs, ys), hydraulic (p·A, v_max)
MOTOR_CODES = {"none": 0, "constant": 1, "dc": 2, "induction": 3, "table": 4, "hydraulic": 5}
STOP_RUNNING, STOP_STEADY, STOP_STALL, STOP_CANNOT_START, STOP_TURNS, STOP_TIME, STOP_NOT_STEADY, STOP_SMALL, \
    STOP_DOES_NOT_TURN = range(9)
STOP_NAMES = ("running", "steady", "stall", "cannot start", "turns", "time", "not steady", "step too small",
              "does not turn")

_C2, _C3, _C4, _C5 = 1 / 5, 3 / 10, 4 / 5, 8 / 9
_A21 = 1 / 5
_A31, _A32 = 3 / 40, 9 / 40
_A41, _A42, _A43 = 44 / 45, -56 / 15, 32 / 9
_A51, _A52, _A53, _A54 = 19372 / 6561, -25360 / 2187, 64448 / 6561, -212 / 729
_A61, _A62, _A63, _A64, _A65 = 9017 / 3168, -355 / 33, 46732 / 5247, 49 / 176, -5103 / 18656
_B1, _B3, _B4, _B5, _B6 = 35 / 384, 500 / 1113, 125 / 192, -2187 / 6784, 11 / 84
_E1, _E3, _E4, _E5, _E6, _E7 = 71 / 57600, -71 / 16695, 71 / 1920, -17253 / 339200, 22 / 525, -1 / 40


@njit(cache=True, error_model="numpy")
def effort(code, p, xs, ys, w):
    """The motor's effort at its speed w: code and parameters ``p`` as :data:`MOTOR_CODES`."""
    if code == 1:
        return p[0]
    if code == 2:
        return p[0] * (1.0 - w / p[1])
    if code == 3:
        s = (p[2] - w) / p[2]
        if s == 0.0:
            return 0.0
        return 2.0 * p[0] / (s / p[1] + p[1] / s)
    if code == 4:
        n = xs.shape[0]
        if w <= xs[0]:
            return ys[0] + (w - xs[0]) * (ys[1] - ys[0]) / (xs[1] - xs[0])
        if w >= xs[n - 1]:
            return ys[n - 1] + (w - xs[n - 1]) * (ys[n - 1] - ys[n - 2]) / (xs[n - 1] - xs[n - 2])
        j = np.searchsorted(xs, w) - 1
        return ys[j] + (w - xs[j]) * (ys[j + 1] - ys[j]) / (xs[j + 1] - xs[j])
    if code == 5:
        r = w / p[1]
        return p[0] * (1.0 - r * abs(r))
    return 0.0


@njit(inline="always", cache=True, error_model="numpy")
def _hermite_at(a0, a1, b0, b1, h, s):
    """The cubic Hermite interpolant (values a0, b0, slopes a1, b1 over a step h) at the fraction s, in Horner form."""
    ha1, hb1, d = h * a1, h * b1, b0 - a0
    return a0 + s * (ha1 + s * ((3.0 * d - 2.0 * ha1 - hb1) + s * (ha1 + hb1 - 2.0 * d)))


@njit(cache=True, error_model="numpy")
def _accel(flat, base, n, start, q, w, code, p, xs, ys, ratio, eta, extra):
    h = TWO_PI / n
    x = (q - start) / h
    i = math.floor(x)
    s = x - i
    i = int(i) % n
    j = (i + 1) % n
    ra, rb = base + i, base + j
    # J and its slope (the derivative of its Hermite interpolant), Q_applied and Q_opposing: no arrays
    a0, b0, ha1, hb1 = flat[ra, 0], flat[rb, 0], h * flat[ra, 4], h * flat[rb, 4]
    d = b0 - a0
    c2 = 3.0 * d - 2.0 * ha1 - hb1
    c3 = ha1 + hb1 - 2.0 * d
    J = a0 + s * (ha1 + s * (c2 + s * c3)) + extra
    dJ = (ha1 + s * (2.0 * c2 + 3.0 * s * c3)) / h
    Qa = _hermite_at(flat[ra, 2], flat[ra, 6], flat[rb, 2], flat[rb, 6], h, s)
    Qo = _hermite_at(flat[ra, 3], flat[ra, 7], flat[rb, 3], flat[rb, 7], h, s)
    wm = ratio * w
    tau = effort(code, p, xs, ys, wm)
    Q = ratio * tau * (eta if tau * wm >= 0.0 else 1.0 / eta)
    sg = 1.0 if w > 0 else (-1.0 if w < 0 else 0.0)
    return (Q + Qa + sg * Qo - 0.5 * dJ * w * w) / J


@njit(cache=True, error_model="numpy")
def _herm(ya, da, yb, db, h, s):
    return (2 * s ** 3 - 3 * s ** 2 + 1) * ya + (s ** 3 - 2 * s ** 2 + s) * h * da + (-2 * s ** 3 + 3 * s ** 2) * yb \
        + (s ** 3 - s ** 2) * h * db


@njit(cache=True, error_model="numpy")
def _cross(ya, da, yb, db, h, target):
    """The fraction of a step where its Hermite interpolant reaches ``target`` (Newton from the chord)."""
    s = (target - ya) / (yb - ya) if yb != ya else 1.0
    s = min(max(s, 0.0), 1.0)
    for _ in range(8):
        f = _herm(ya, da, yb, db, h, s) - target
        d = (6 * s * s - 6 * s) * ya + (3 * s * s - 4 * s + 1) * h * da + (-6 * s * s + 6 * s) * yb \
            + (3 * s * s - 2 * s) * h * db
        if d == 0:
            break
        s = min(max(s - f / d, 0.0), 1.0)
    return s


@njit(cache=True, error_model="numpy")
def _converged(T, tol, noise):
    d1, d2, d3 = T[1] - T[0], T[2] - T[1], T[3] - T[2]
    if not (math.isfinite(d1) and math.isfinite(d2) and math.isfinite(d3)):
        return False
    if d3 == 0.0 or max(abs(d1), max(abs(d2), abs(d3))) <= noise * T[3]:
        return True
    r = abs(d3 / d2) if d2 != 0 else math.inf
    rp = abs(d2 / d1) if d1 != 0 else math.inf
    if r < 1 and rp < 1:
        return abs(d3) * (1.0 + r / (1.0 - r)) <= tol * T[3]
    return abs(d3) <= 1e-3 * tol * T[3]


@njit(cache=True, error_model="numpy")
def run(flat, n, start, valid, code, p, xs, ys, ratio, eta, extra, q0, w0, atol_w, rtol, t_limit, turns_limit,
        steady, noise, max_turns, creep, forward, level, grid, stop, t_end, turns, periods, extremes, crossing,
        samples, steps):
    """Integrate every design (module docstring). Outputs, written per design d: ``stop (D,)`` int, ``t_end``,
    ``turns (D,)`` int, ``periods (D, 4)`` the last four, ``extremes (D, 2)`` (min, max) speed over the last
    complete turn, ``crossing (D,)`` the first time the speed reaches ``level[d]``, ``samples (D, G, 3)`` (q, q̇, q̈)
    at the ``grid`` times (NaN after the run ended), ``steps (D,)`` accepted steps. ``turns_limit`` < 0 and
    ``t_limit`` = inf: run to the steady state."""
    D = q0.shape[0]
    G = grid.shape[0]
    for d in range(D):
        for g in range(G):
            samples[d, g, 0] = np.nan
            samples[d, g, 1] = np.nan
            samples[d, g, 2] = np.nan
        crossing[d] = np.nan
        if not valid[d]:
            stop[d] = STOP_DOES_NOT_TURN
            continue
        base = d * n
        t = 0.0
        q = q0[d]
        w = w0[d]
        a = _accel(flat, base, n, start, q, w, code, p, xs, ys, ratio, eta, extra)
        ref = atol_w[d] / rtol
        h = 2e-3 * TWO_PI / max(ref, 1e-9)
        target = q + forward * TWO_PI
        turn_start = 0.0
        nt = 0
        wmin, wmax = w, w
        for k in range(4):
            periods[d, k] = np.nan
        extremes[d, 0] = np.nan
        extremes[d, 1] = np.nan
        gi = 0
        while gi < G and grid[gi] <= 0.0:
            samples[d, gi, 0] = q
            samples[d, gi, 1] = w
            samples[d, gi, 2] = a
            gi += 1
        if level[d] == level[d] and forward * (w - level[d]) >= 0:
            crossing[d] = 0.0
        result = STOP_RUNNING
        accepted = 0
        while result == STOP_RUNNING:
            hh = min(h, t_limit - t)
            k1q, k1w = w, a
            q2, w2 = q + hh * _A21 * k1q, w + hh * _A21 * k1w
            k2q, k2w = w2, _accel(flat, base, n, start, q2, w2, code, p, xs, ys, ratio, eta, extra)
            q3 = q + hh * (_A31 * k1q + _A32 * k2q)
            w3 = w + hh * (_A31 * k1w + _A32 * k2w)
            k3q, k3w = w3, _accel(flat, base, n, start, q3, w3, code, p, xs, ys, ratio, eta, extra)
            q4 = q + hh * (_A41 * k1q + _A42 * k2q + _A43 * k3q)
            w4 = w + hh * (_A41 * k1w + _A42 * k2w + _A43 * k3w)
            k4q, k4w = w4, _accel(flat, base, n, start, q4, w4, code, p, xs, ys, ratio, eta, extra)
            q5 = q + hh * (_A51 * k1q + _A52 * k2q + _A53 * k3q + _A54 * k4q)
            w5 = w + hh * (_A51 * k1w + _A52 * k2w + _A53 * k3w + _A54 * k4w)
            k5q, k5w = w5, _accel(flat, base, n, start, q5, w5, code, p, xs, ys, ratio, eta, extra)
            q6 = q + hh * (_A61 * k1q + _A62 * k2q + _A63 * k3q + _A64 * k4q + _A65 * k5q)
            w6 = w + hh * (_A61 * k1w + _A62 * k2w + _A63 * k3w + _A64 * k4w + _A65 * k5w)
            k6q, k6w = w6, _accel(flat, base, n, start, q6, w6, code, p, xs, ys, ratio, eta, extra)
            q1 = q + hh * (_B1 * k1q + _B3 * k3q + _B4 * k4q + _B5 * k5q + _B6 * k6q)
            w1 = w + hh * (_B1 * k1w + _B3 * k3w + _B4 * k4w + _B5 * k5w + _B6 * k6w)
            a1 = _accel(flat, base, n, start, q1, w1, code, p, xs, ys, ratio, eta, extra)
            eq_ = hh * (_E1 * k1q + _E3 * k3q + _E4 * k4q + _E5 * k5q + _E6 * k6q + _E7 * w1)
            ew_ = hh * (_E1 * k1w + _E3 * k3w + _E4 * k4w + _E5 * k5w + _E6 * k6w + _E7 * a1)
            sq = rtol * TWO_PI + rtol * max(abs(q), abs(q1))
            sw = atol_w[d] + rtol * max(abs(w), abs(w1))
            err = math.sqrt(0.5 * ((eq_ / sq) ** 2 + (ew_ / sw) ** 2))
            if not math.isfinite(err):
                err = 1e10
            factor = min(5.0, max(0.2, 0.9 * err ** -0.2)) if err > 0 else 5.0
            if err > 1.0:
                h = hh * min(factor, 0.9)
                if h < 1e-14 * max(t, 1e-3):
                    result = STOP_SMALL
                continue
            accepted += 1
            # samples at the grid's times inside the step
            while gi < G and grid[gi] <= t + hh:
                s = (grid[gi] - t) / hh
                samples[d, gi, 0] = _herm(q, w, q1, w1, hh, s)
                samples[d, gi, 1] = _herm(w, a, w1, a1, hh, s)
                samples[d, gi, 2] = a + s * (a1 - a)
                gi += 1
            # the speed first reaching the level
            if level[d] == level[d] and crossing[d] != crossing[d] and forward * (w1 - level[d]) >= 0:
                crossing[d] = t + hh * _cross(w, a, w1, a1, hh, level[d])
            # the extreme speeds of the turn
            w_ext = w1
            if a * a1 < 0:
                w_ext = _herm(w, a, w1, a1, hh, a / (a - a1))
            wmin = min(wmin, min(w1, w_ext))
            wmax = max(wmax, max(w1, w_ext))
            if forward * (q1 - target) >= 0:
                tc = t + hh * _cross(q, w, q1, w1, hh, target)
                for k in range(3):
                    periods[d, k] = periods[d, k + 1]
                periods[d, 3] = tc - turn_start
                turn_start = tc
                target += forward * TWO_PI
                nt += 1
                extremes[d, 0] = wmin
                extremes[d, 1] = wmax
                wmin, wmax = w1, w1
            w_prev = w
            t, q, w, a = t + hh, q1, w1, a1
            h = hh * factor
            if code != 0 and forward * w <= 0:
                result = STOP_STALL if nt > 0 else STOP_CANNOT_START
            elif code != 0 and creep > 0 and forward * w < creep <= forward * w_prev:
                result = STOP_STALL if nt > 0 else STOP_CANNOT_START
            elif turns_limit < 0 and t_limit == math.inf and nt >= 4 and _converged(periods[d], steady, noise):
                result = STOP_STEADY
            elif turns_limit < 0 and t_limit == math.inf and nt >= max_turns:
                result = STOP_NOT_STEADY
            elif turns_limit >= 0 and nt >= turns_limit:
                result = STOP_TURNS
            elif t >= t_limit * (1 - 1e-15):
                result = STOP_TIME
        stop[d] = result
        t_end[d] = t
        turns[d] = nt
        steps[d] = accepted


__all__ = ["MOTOR_CODES", "STOP_NAMES", "effort", "run"]
