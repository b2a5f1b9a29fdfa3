"""The result of a forward-dynamics run (:class:`Simulation`) and its summary.

Arrays over the output samples (n,), SI: ``t`` (s), ``q`` (rad or m), ``speed`` q̇, ``accel`` q̈; with a motor
``effort`` (the motor's generalised force at the input, N·m or N), ``motor_torque`` (at the motor's own shaft,
N·m, or its rod, N), ``motor_speed`` (rad/s or m/s), ``power`` (the motor's mechanical power τ·ω_m, W) and
``current`` (A, where the motor's torque constant is known, else None); ``kinetic`` (J, ½·J*·q̇² with the
motor's inertia) and ``energy`` (kinetic + the potential of gravity and the loads, where they have one, else None).

The summary of a run to its steady state: ``mean_speed`` (2π/T of the last turn), ``delta`` (its coefficient of
speed fluctuation (q̇_max − q̇_min)/mean), ``startup_time`` (the first time the speed reaches 95 % of the steady
mean speed) and ``starts`` (the motor turns the mechanism through a whole turn).
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

#: the share of the steady mean speed that ends the start-up
STARTUP_SHARE = 0.95


@dataclass(frozen=True)
class Simulation:
    """One design's run (module docstring). ``events``: what the run met (:class:`~.integrate.Event`), ``stop``
    the event that ended it; ``turns``: the completed turns (:class:`~.integrate.Turn`); ``equation``: the
    :class:`~.equation.Equation` integrated (its ``fit`` holds the interpolation's measured error)."""
    plan: object
    params: np.ndarray
    equation: object
    t: np.ndarray
    q: np.ndarray
    speed: np.ndarray
    accel: np.ndarray
    effort: np.ndarray | None
    motor_torque: np.ndarray | None
    motor_speed: np.ndarray | None
    power: np.ndarray | None
    current: np.ndarray | None
    kinetic: np.ndarray
    energy: np.ndarray | None
    events: tuple
    stop: object
    turns: tuple
    method: str
    nfev: int
    run: object = field(repr=False, default=None)
    #: (min, max) speed over the last completed turn
    last_extremes: tuple = (math.nan, math.nan)

    # -- the summary ------------------------------------------------------------------------------------
    @property
    def steady(self) -> bool:
        """True when the run ended at its detected periodic steady state."""
        return self.stop is not None and self.stop.kind == "steady"

    @property
    def starts(self) -> bool:
        """True unless the motor could not turn the mechanism through a whole turn (or a stroke's end)."""
        return self.stop is None or self.stop.kind not in ("cannot start",)

    @property
    def mean_speed(self) -> float:
        """The mean speed 2π/T (rad/s) of the steady state (T the last turn's period plus the geometric tail of
        the periods' convergence, :func:`~.integrate.limit_period`); of the last turn when the run did not reach
        its steady state; NaN without a completed turn."""
        from .integrate import limit_period
        if not self.turns:
            return math.nan
        T = limit_period(self.turns) if self.steady else self.turns[-1].period
        return self.turns[-1].direction * 2.0 * math.pi / T

    @property
    def extremes(self) -> tuple[float, float]:
        """(min, max) speed over the last completed turn (rad/s); NaN without one."""
        return self.last_extremes

    @property
    def delta(self) -> float:
        """(q̇_max − q̇_min)/mean over the last completed turn, NaN without one."""
        lo, hi = self.last_extremes
        return (hi - lo) / abs(self.mean_speed) if self.turns else math.nan

    @property
    def startup_time(self) -> float:
        """The first time (s) the speed reaches 95 % of the steady mean speed; NaN unless the run reached its
        steady state (the dense output is searched, so the time is exact to the integration's tolerance)."""
        if not self.steady:
            return math.nan
        return crossing_time(self.run, STARTUP_SHARE * self.mean_speed)

    def forces(self, *, friction: bool | None = None):
        """Every joint's reaction over the samples: the force analysis at the simulated q, q̇ and q̈
        (:func:`assur.forces` with per-sample ``speeds`` and ``accels``); a Forces of shape (n,)."""
        from ..kinetostatics.api import forces
        fr = self.equation.friction if friction is None else friction
        return forces(self.plan, self.params, self.q[:, None], speeds=self.speed[:, None],
                      accels=self.accel[:, None], friction=fr)

    def summary(self) -> dict:
        """JSON-ready numbers of the run (SI)."""
        eq = self.equation
        fit = eq.fit
        out = {"stop": self.stop.kind if self.stop else None, "message": self.stop.message if self.stop else "",
               "time": float(self.t[-1]) if self.t.size else 0.0, "turns": len(self.turns), "starts": self.starts,
               "steady": self.steady, "mean_speed": _num(self.mean_speed), "delta": _num(self.delta),
               "startup_time": _num(self.startup_time), "method": self.method, "evaluations": self.nfev,
               "model": eq.mode, "domain": "turn" if eq.periodic else
               [eq.lower.q, eq.upper.q]}
        if fit is not None:
            out["interpolation"] = {"samples": int(fit.samples), "error": [float(e) for e in fit.error],
                                    "terms": ["J*", "dJ*/dq", "Q_applied", "Q_opposing"]}
        if self.effort is not None:
            out["effort_peak"] = _num(np.nanmax(np.abs(self.effort))) if self.effort.size else None
            out["motor_torque_peak"] = _num(np.nanmax(np.abs(self.motor_torque))) if self.effort.size else None
            out["power_peak"] = _num(np.nanmax(np.abs(self.power))) if self.effort.size else None
            if self.current is not None and self.current.size:
                out["current_peak"] = _num(np.nanmax(np.abs(self.current)))
        out["events"] = [{"kind": e.kind, "t": e.t, "q": e.q, "speed": e.speed, "message": e.message}
                         for e in self.events]
        return out


def _num(x):
    x = float(x)
    return x if math.isfinite(x) else None


def crossing_time(run, level: float) -> float:
    """The first time the run's speed reaches ``level`` (towards its sign), from the segments' dense outputs;
    0 when it starts there."""
    from scipy.optimize import brentq
    sign = 1.0 if level >= 0 else -1.0
    for t0, t1, sol in run.segments:
        if t1 <= t0:
            continue
        ts = np.linspace(t0, t1, 65)
        w = sign * (sol(ts)[1] - level)
        if w[0] >= 0:
            return float(t0)
        above = np.nonzero(w >= 0)[0]
        if above.size:
            j = int(above[0])
            return float(brentq(lambda t: sign * (sol(t)[1] - level), ts[j - 1], ts[j], xtol=1e-14 * max(1.0, t1)))
    return math.nan


__all__ = ["STARTUP_SHARE", "Simulation", "crossing_time"]
