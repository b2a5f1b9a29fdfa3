"""Integrating the reduced equation of one design with scipy's ``solve_ivp``, turn by turn, with its events.

The run is a sequence of ``solve_ivp`` segments, each ending at a terminal event:

* ``turn``: the input completes a turn (q passes q_start ± 2π): the turn's period, mean speed, extreme speeds
  and δ are recorded; a run "to steady state" stops when the turns have converged (:func:`converged`);
* ``stall``: with a motor, the speed falls back through zero (the motor cannot carry the load: it stalls and
  the mechanism runs backwards), or decays below :data:`CREEP` of the motor's free speed (it creeps to a rest);
* ``limit``: the input reaches an end of the equation's domain (a dead centre, the limit of assembly, the end of
  a stroke): the run stops there with the input and the time;
* ``reversal`` (no motor): the speed changes sign (a pendulum); recorded, the run goes on.

Methods: 'DOP853' (explicit Runge–Kutta of order 8, the default), 'RK45', or an implicit one ('Radau', 'BDF',
'LSODA') for stiff cases; 'auto' picks Radau when the motor's damping makes the equation stiff (its time
constant J*/c below :data:`STIFF` of the time of a turn at the motor's free speed), else DOP853.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from ..errors import SpecError

TWO_PI = 2.0 * math.pi
METHODS = ("auto", "DOP853", "RK45", "Radau", "BDF", "LSODA")
#: a motor-driven run has stalled when its speed falls below this fraction of the motor's free input speed
CREEP = 1e-7
#: the equation counts as stiff when J*/c is below this fraction of a turn's time at the free speed
STIFF = 1e-3
#: a run to steady state stops when the period's remaining change, extrapolated from the last turns'
#: geometric convergence, is below this fraction of the period
STEADY = 1e-6
#: the most turns a run to steady state makes
MAX_TURNS = 5000


@dataclass(frozen=True)
class Event:
    """Something the run met: ``kind`` ('stall', 'reversal', 'limit', 'steady', 'not steady', 'cannot start'),
    the time ``t`` (s), input ``q`` and speed ``speed`` where it happened, and a sentence."""
    kind: str
    t: float
    q: float
    speed: float
    message: str


@dataclass(frozen=True)
class Turn:
    """One completed turn: its start and end times (s), direction (+1 forward), and the dense output that covers
    it (``sol``: an OdeSolution). ``period`` (s), ``mean_speed`` 2π/T (rad/s, signed)."""
    start: float
    end: float
    direction: int
    sol: object = field(repr=False, compare=False, default=None)

    @property
    def period(self) -> float:
        return self.end - self.start

    @property
    def mean_speed(self) -> float:
        return self.direction * TWO_PI / self.period


def limit_period(turns) -> float:
    """The steady period: the last turn's, plus the geometric tail of the last changes where they contract
    (Aitken's extrapolation); the last period when there are fewer than three turns."""
    if len(turns) < 3:
        return turns[-1].period if turns else math.nan
    T = [tr.period for tr in turns[-3:]]
    d1, d2 = T[1] - T[0], T[2] - T[1]
    r = d2 / d1 if d1 else 0.0
    return T[2] + (d2 * r / (1.0 - r) if abs(r) < 1 else 0.0)


@dataclass
class Run:
    """The raw run: the segments' dense outputs (each (t0, t1, OdeSolution)), its turns and events, and why
    it stopped (``stop``: an Event)."""
    segments: list = field(default_factory=list)
    turns: list = field(default_factory=list)
    events: list = field(default_factory=list)
    stop: Event | None = None
    method: str = "DOP853"
    nfev: int = 0

    @property
    def t_end(self) -> float:
        return self.segments[-1][1] if self.segments else 0.0

    def state(self, t):
        """(q, q̇) at the times ``t`` (m,), from the dense outputs."""
        t = np.atleast_1d(np.asarray(t, dtype=float))
        out = np.full((2, t.size), np.nan)
        for t0, t1, sol in self.segments:
            sel = (t >= t0) & (t <= t1)
            if sel.any():
                out[:, sel] = sol(t[sel]) if t1 > t0 else np.asarray(sol(t0))[:, None]
        return out


def choose_method(eq, method: str) -> str:
    """The integration method for ``eq`` (see the module docstring)."""
    if method not in METHODS:
        raise SpecError([("method", f"must be one of {', '.join(METHODS)}: {method!r}")])
    if method != "auto":
        return method
    if eq.drive is None or eq.friction:
        return "DOP853"
    c = eq.drive.damping()
    free = eq.drive.input_free_speed()
    if c <= 0 or not math.isfinite(free) or free <= 0:
        return "DOP853"
    J = float(np.nanmin(eq.terms(np.linspace(0, TWO_PI, 64) if eq.periodic else
                                 np.linspace(eq.lower.q, eq.upper.q, 64))[0]))
    return "Radau" if J / c < STIFF * TWO_PI / free else "DOP853"


def _rhs(eq):
    if eq.friction:
        from .friction import friction_acceleration

        def f(t, y):
            return np.array([y[1], friction_acceleration(eq, y[0], y[1])])
        return f

    def f(t, y):
        return np.array([y[1], float(eq.acceleration(y[0], y[1]))])
    return f


def _event(fun, terminal, direction):
    fun.terminal, fun.direction = terminal, direction
    return fun


def turn_extremes(eq, turn, samples: int = 96) -> tuple[float, float]:
    """(min, max) of q̇ over a completed turn."""
    return _extremes(eq, turn.sol, turn.start, turn.end, samples)


def _extremes(eq, sol, t0, t1, samples: int = 96):
    """(min, max) of q̇ over [t0, t1] from the dense output, each polished to the zero of q̈."""
    from scipy.optimize import brentq
    ts = np.linspace(t0, t1, samples)
    y = sol(ts)
    w = y[1]
    acc = np.asarray(eq.acceleration(y[0], y[1]), dtype=float) if not eq.friction else np.gradient(w, ts)
    out = []
    for pick in (np.argmin, np.argmax):
        i = int(pick(w))
        best = w[i]
        if 0 < i < samples - 1 and not eq.friction:
            for a, b in ((i - 1, i), (i, i + 1)):
                if acc[a] * acc[b] < 0:
                    def g(t):
                        yy = sol(t)
                        return float(eq.acceleration(yy[0], yy[1]))
                    tr = brentq(g, ts[a], ts[b], xtol=1e-14 * max(1.0, abs(t1)))
                    best = float(sol(tr)[1])
                    break
        out.append(float(best))
    return out[0], out[1]


def _covering(segments, t0, t1):
    """A callable dense output over [t0, t1] from the run's segments (a turn may span several)."""
    parts = [(a, b, sol) for a, b, sol in segments if b > t0 and a < t1]
    if len(parts) == 1:
        return parts[0][2]

    def sol(t):
        t = np.asarray(t, dtype=float)
        flat = np.atleast_1d(t)
        out = np.empty((2, flat.size))
        for a, b, part in parts:
            sel = (flat >= a) & (flat <= b)
            if sel.any():
                out[:, sel] = part(flat[sel])
        return out if t.ndim else out[:, 0]
    return sol


def converged(turns, tol: float = STEADY, noise: float = 0.0) -> bool:
    """Whether the turns have reached their periodic steady state: the last three periods change geometrically
    (ratio r < 1) and the change still to come, |ΔT|·r/(1 − r), plus the last change, is below ``tol``·T; or the
    last three changes are all below ``noise``·T (the integration's own error)."""
    if len(turns) < 4:
        return False
    T = [tr.period for tr in turns[-4:]]
    d1, d2, d3 = T[1] - T[0], T[2] - T[1], T[3] - T[2]
    if d3 == 0 or max(abs(d1), abs(d2), abs(d3)) <= noise * T[-1]:
        return True
    r = abs(d3 / d2) if d2 else math.inf
    r_prev = abs(d2 / d1) if d1 else math.inf
    if r >= 1 or r_prev >= 1:
        return abs(d3) <= 1e-3 * tol * T[-1]          # not (yet) contracting: only when already flat
    remaining = abs(d3) * (1.0 + r / (1.0 - r))
    return remaining <= tol * T[-1]


def integrate(eq, *, q0: float, speed0: float, time: float | None = None, turns: int | None = None,
              method: str = "auto", rtol: float = 1e-10, atol: float | None = None,
              max_turns: int = MAX_TURNS, max_time: float | None = None, steady: float = STEADY) -> Run:
    """Integrate ``eq`` from (q0, speed0) for ``time`` seconds, or ``turns`` turns, or (neither) to the periodic
    steady state of a motor-driven run. Returns the :class:`Run`."""
    from scipy.integrate import solve_ivp
    run = Run(method=choose_method(eq, method))
    motor = eq.drive is not None
    if time is None and turns is None and not motor:
        raise SpecError([("time", "a free motion (no motor) has no steady state to run to: give time= or cycles=")])
    if time is None and turns is None and not eq.periodic:
        raise SpecError([("time", "the mechanism does not turn fully, so it has no steady state to run to: "
                                  "give time=")])
    if turns is not None and not eq.periodic:
        raise SpecError([("cycles", "the mechanism does not turn fully (its input is limited to "
                                    f"{eq.lower.q:.6g}…{eq.upper.q:.6g}): give time= instead of cycles=")])
    if not eq.contains(q0):
        raise SpecError([("q0", f"the start {q0:.6g} lies outside the input range {eq.lower.q:.6g}…"
                                f"{eq.upper.q:.6g} where the mechanism can run")])
    forward = 1.0
    free = math.inf
    if motor:
        Q0 = float(eq.motor(np.array(0.0))[0])
        forward = 1.0 if Q0 >= 0 else -1.0
        free = eq.drive.input_free_speed()
    scale = abs(speed0) if speed0 else (free if math.isfinite(free) else 1.0)
    if atol is None:
        atol = rtol * max(scale, 1e-12)
    atol_vec = np.array([rtol * TWO_PI if eq.rotary else rtol * eq.plan.length_scale, atol])
    limit = time if time is not None else (max_time if max_time is not None else math.inf)
    fun = _rhs(eq)
    t, y = 0.0, np.array([float(q0), float(speed0)])
    turn_start, t_turn = float(q0), 0.0
    creep = CREEP * free if motor and math.isfinite(free) else 0.0
    # a segment ends at a terminal event or after this long (a run to steady state has no end time)
    segment = 1e3 * TWO_PI / free if math.isfinite(free) and free > 0 else \
        100.0 * TWO_PI / max(abs(speed0), 1e-3)
    while True:
        events, kinds = [], []
        if eq.periodic:
            events += [_event(lambda t, y, s=turn_start: y[0] - (s + TWO_PI), True, 1),
                       _event(lambda t, y, s=turn_start: y[0] - (s - TWO_PI), True, -1)]
            kinds += ["turn+", "turn-"]
        else:
            events += [_event(lambda t, y: y[0] - eq.lower.q, True, -1),
                       _event(lambda t, y: y[0] - eq.upper.q, True, 1)]
            kinds += ["lower", "upper"]
        if motor:
            events.append(_event(lambda t, y: forward * y[1], True, -1))
            kinds.append("stall")
            if creep > 0 and forward * y[1] > creep:
                events.append(_event(lambda t, y: forward * y[1] - creep, True, -1))
                kinds.append("creep")
        else:      # a free motion asked for turns stops at its first reversal: it swings, it will not turn
            moving = y[1] if y[1] else float(eq.acceleration(y[0], 0.0))
            if moving == 0:
                run.stop = Event("rest", t, float(y[0]), 0.0, f"the mechanism rests in equilibrium at q = {y[0]:.6g}")
                return run
            events.append(_event(lambda t, y: y[1], turns is not None, -1 if moving > 0 else 1))
            kinds.append("reversal")
        t_stop = min(limit, t + segment)
        sol = solve_ivp(fun, (t, t_stop), y, method=run.method, events=events, dense_output=True, rtol=rtol,
                        atol=atol_vec)
        run.nfev += int(sol.nfev)
        if sol.status == -1:
            raise SpecError([("simulate", f"the integration failed at t = {t:.6g} s: {sol.message}")])
        run.segments.append((t, float(sol.t[-1]), sol.sol))
        if not motor:
            for te, ye in zip(sol.t_events[-1], sol.y_events[-1]):
                if te > t:
                    run.events.append(Event("reversal", float(te), float(ye[0]), 0.0,
                                            f"the speed changes sign at q = {ye[0]:.6g}, t = {te:.6g} s"))
        hit = [(float(te[0]), k, ye[0]) for te, ye, k in zip(sol.t_events, sol.y_events, kinds)
               if len(te) and (k != "reversal" or turns is not None)]
        t, y = float(sol.t[-1]), sol.y[:, -1].copy()
        if sol.status == 0:                       # reached t_stop
            if t >= limit:
                run.stop = Event("time", t, float(y[0]), float(y[1]), f"ran {t:.6g} s")
                return run
            continue
        te, kind, ye = min(hit, key=lambda h: h[0])
        t, y = te, np.asarray(ye, dtype=float)
        if kind == "reversal":
            run.stop = Event("reversal", t, float(y[0]), 0.0,
                             f"the mechanism swings back at q = {y[0]:.6g}, t = {t:.6g} s after {len(run.turns)} "
                             f"turns: it has not the energy to turn (asked for {turns})")
            return run
        if kind.startswith("turn"):
            direction = 1 if kind == "turn+" else -1
            run.turns.append(Turn(t_turn, t, direction, _covering(run.segments, t_turn, t)))
            turn_start, t_turn = turn_start + direction * TWO_PI, t
            if turns is not None and len(run.turns) >= turns:
                run.stop = Event("turns", t, float(y[0]), float(y[1]), f"ran {len(run.turns)} turns")
                return run
            if time is None and turns is None:
                if converged(run.turns, steady, 100.0 * rtol):
                    run.stop = Event("steady", t, float(y[0]), float(y[1]),
                                     f"reached its periodic steady state after {len(run.turns)} turns ({t:.6g} s)")
                    return run
                if len(run.turns) >= max_turns:
                    run.stop = Event("not steady", t, float(y[0]), float(y[1]),
                                     f"did not settle to a periodic steady state in {max_turns} turns ({t:.6g} s)")
                    return run
            continue
        if kind in ("stall", "creep"):
            Qm = float(eq.motor(np.array(0.0))[0])
            Qa = float(eq.terms(np.array(y[0]))[2])
            where = f"q = {y[0]:.6g}, t = {t:.6g} s"
            started = bool(run.turns) or forward * speed0 > 0
            if not started:
                kind = "cannot start"
                msg = (f"the motor cannot start the mechanism: it stalls at {where} before a turn (the motor gives "
                       f"{Qm:.4g} at rest, the load needs {-Qa:.4g} there)")
            elif kind == "stall":
                msg = f"the motor stalls at {where}: the speed falls to zero and the load drives the mechanism back"
            else:
                kind = "stall"
                msg = (f"the motor stalls at {where}: the mechanism creeps to rest (speed below {CREEP:g} of the "
                       f"motor's free speed) where the motor's {Qm:.4g} at rest balances the load {-Qa:.4g}")
            run.stop = Event(kind, t, float(y[0]), float(y[1]), msg)
            run.events.append(run.stop)
            return run
        end = eq.lower if kind == "lower" else eq.upper
        what = {"dead centre": f"a dead centre at q = {end.at:.6g}",
                "cannot be assembled": f"the limit of assembly (the mechanism cannot be assembled beyond "
                                       f"q = {end.at:.6g})",
                "end of stroke": "the end of the working stroke",
                "zero inertia": f"J* = 0 at q = {end.at:.6g}"}.get(end.reason, end.reason)
        run.stop = Event("limit", t, float(y[0]), float(y[1]),
                         f"the run stops at q = {y[0]:.6g}, t = {t:.6g} s, speed {y[1]:.6g}: {what}")
        run.events.append(run.stop)
        return run


__all__ = ["Event", "METHODS", "Run", "Turn", "choose_method", "converged", "integrate", "limit_period",
           "turn_extremes"]
