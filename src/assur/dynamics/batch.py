"""Running a population's equations: the compiled route (:mod:`assur.kernels.dopri`) where numba is installed, else the vectorised numpy route (:func:`~.population.integrate_population`); both give the
same numbers to the integration's tolerance.

The compiled route runs twice: the first run finds each design's end and steady mean speed; the second, the same
deterministic run, records the first time the speed reaches 95 % of that mean and the samples at the output times.
"""
from __future__ import annotations

import math
import sys
from importlib.util import find_spec

import numpy as np

from .population import (PopulationResult, _limit_period, _resample, integrate_population, population_equation,
                         startup_times)
from .result import STARTUP_SHARE

TWO_PI = 2.0 * math.pi


def compiled_available() -> bool:
    """Whether numba is installed (the ``fast`` extra) and its kernels may run (numba is not imported here: where it
    is already, whether its target is safe, :func:`assur.kernels.numba_target.configure`)."""
    if find_spec("numba") is None:
        return False
    if "numba" in sys.modules:
        from ..kernels.numba_target import configure
        return configure()
    return True


def motor_code(drive):
    """(code, parameters, table speeds, table efforts, ratio, efficiency, inertia) of a drive train (None: none)."""
    from ..kernels.dopri import MOTOR_CODES
    empty = np.zeros(2)
    if drive is None:
        return MOTOR_CODES["none"], np.zeros(3), empty, empty, 1.0, 1.0, 0.0
    mo = drive.motor
    p, xs, ys = np.zeros(3), empty, empty
    if mo.kind in ("torque", "force"):
        code, p[0] = MOTOR_CODES["constant"], mo.torque if mo.kind == "torque" else mo.force
    elif mo.kind == "dc":
        code, (p[0], p[1]) = MOTOR_CODES["dc"], drive.dc_constants()
    elif mo.kind == "induction":
        code, p[:] = MOTOR_CODES["induction"], (mo.breakdown_torque, mo.breakdown_slip, mo.synchronous_speed)
    elif mo.kind == "table":
        code = MOTOR_CODES["table"]
        xs, ys = (np.array(c, dtype=float) for c in zip(*mo.table))
    else:
        code, p[0], p[1] = MOTOR_CODES["hydraulic"], mo.pressure * mo.area, drive.free_speed()
    return code, p, xs, ys, float(drive.ratio), float(mo.efficiency), float(drive.inertia)


def _compiled(eq, q0, w0, atol_w, rtol, t_limit, turns_limit, steady, noise, max_turns, creep, forward, level, grid):
    from ..kernels.dopri import run
    D = q0.size
    table = eq.table
    flat = table.flat()
    n = table.table.shape[1]
    code, p, xs, ys, ratio, eta, extra = motor_code(eq.drive)
    stop = np.zeros(D, np.int64)
    t_end, crossing = np.zeros(D), np.zeros(D)
    turns, steps = np.zeros(D, np.int64), np.zeros(D, np.int64)
    periods, extremes = np.zeros((D, 4)), np.zeros((D, 2))
    samples = np.zeros((D, grid.size, 3))
    run(flat, n, float(table.start), eq.valid, code, p, xs, ys, ratio, eta, extra, q0, w0, atol_w, rtol, t_limit,
        turns_limit, steady, noise, max_turns, creep, forward, level, grid, stop, t_end, turns, periods, extremes,
        crossing, samples, steps)
    return stop, t_end, turns, periods, extremes, crossing, samples, steps


def run_designs(eq, *, q0, speed0, time=None, turns=None, rtol: float = 1e-8, samples: int = 0,
                steady: float = 1e-6, max_turns: int = 1000, compiled: bool | None = None) -> dict:
    """Run every design of a :class:`~.population.PopulationEquation` from (q0 (D,), speed0) for ``time`` s, ``turns``
    turns or to the steady state. Returns per design (D,): ``stop`` (names), ``t_end``, ``turns``, ``mean_speed``
    (the steady period's extrapolation, else the last turn's), ``delta``, ``startup`` (to 95 % of a steady mean,
    NaN otherwise), ``steps``, ``forward``; with ``samples`` > 0 also ``t (samples,)`` and ``q``, ``speed``, ``accel``
    (D, samples)."""
    from ..errors import SpecError
    from .integrate import CREEP
    from .population import NOISE
    D = eq.valid.size
    q0 = np.broadcast_to(np.asarray(q0, dtype=float), (D,)).copy()
    w0 = np.broadcast_to(np.asarray(speed0, dtype=float), (D,)).copy()
    motor = eq.drive is not None
    if time is None and turns is None and not motor:
        raise SpecError([("time", "a free motion (no motor) has no steady state to run to: give time= or cycles=")])
    use = compiled_available() if compiled is None else compiled
    if compiled and "numba" in sys.modules and not compiled_available():   # numba's target is not safe
        from ..kernels.numba_target import UNSAFE
        raise RuntimeError(UNSAFE)
    if not use:
        r = integrate_population(eq, q0=q0, speed0=w0, time=time, turns=turns, rtol=rtol, max_turns=max_turns,
                                 steady=steady)
        is_steady = np.array([s == "steady" for s in r["stop"]])
        level = np.where(is_steady, STARTUP_SHARE * r["mean_speed"], np.nan)
        out = {k: r[k] for k in ("stop", "t_end", "turns", "mean_speed", "delta", "forward")}
        out["startup"] = startup_times(r["history"], level, r["forward"])
        out["steps"] = r["steps"]
        if samples:
            tg = np.linspace(0.0, float(np.nanmax(r["t_end"])) if D else 0.0, samples)
            out["t"] = tg
            out["q"], out["speed"], out["accel"] = _resample(r["history"], tg, D)
        return out
    from ..kernels.dopri import STOP_NAMES
    free = eq.drive.input_free_speed() if motor else math.inf
    forward = -1.0 if motor and float(eq.drive.generalised(np.array(0.0))[0]) < 0 else 1.0
    creep = CREEP * free if motor and math.isfinite(free) else 0.0
    ref = np.where(np.abs(w0) > 0, np.abs(w0), free if math.isfinite(free) else 1.0)
    atol_w = rtol * ref
    t_limit = math.inf if time is None else float(time)
    turns_limit = -1 if turns is None else int(turns)
    args = (eq, q0, w0, atol_w, rtol, t_limit, turns_limit, steady, NOISE * rtol, max_turns, creep, forward)
    stop, t_end, n_turns, periods, extremes, _, _, steps = _compiled(*args, np.full(D, np.nan), np.zeros(0))
    names = tuple(STOP_NAMES[s] for s in stop)
    has_turn = n_turns > 0
    with np.errstate(all="ignore"):
        T = np.where(stop == STOP_NAMES.index("steady"), _limit_period(periods), periods[:, 3])
        mean = np.where(has_turn, forward * TWO_PI / T, np.nan)
        delta = np.where(has_turn, (extremes[:, 1] - extremes[:, 0]) / np.abs(mean), np.nan)
    is_steady = np.array([s == "steady" for s in names])
    level = np.where(is_steady, STARTUP_SHARE * mean, np.nan)
    grid = np.linspace(0.0, float(np.max(t_end)) if D else 0.0, samples) if samples else np.zeros(0)
    out = {"stop": names, "t_end": t_end, "turns": n_turns, "mean_speed": mean, "delta": delta, "steps": steps,
           "forward": forward}
    if samples or np.isfinite(level).any():
        _, _, _, _, _, crossing, sampled, _ = _compiled(*args, level, grid)
        out["startup"] = np.where(is_steady, crossing, np.nan)
        if samples:
            out["t"] = grid
            out["q"], out["speed"], out["accel"] = (np.ascontiguousarray(sampled[..., k]) for k in range(3))
    else:
        out["startup"] = np.full(D, np.nan)
    return out


def simulate_population(plan, params, drive, *, time=None, cycles=None, q0=None, speed0=None, samples=None,
                        state=None, rtol: float = 1e-8, compiled: bool | None = None) -> PopulationResult:
    """The batch route of :func:`assur.simulate` (see :class:`PopulationResult`)."""
    params = np.asarray(params, dtype=float)
    eq = population_equation(plan, params, drive, state=state)
    D = params.shape[0]
    q0 = np.broadcast_to(float(plan.sketch_inputs[0]) if q0 is None else q0, (D,)).astype(float)
    if speed0 is None:
        speed0 = 0.0 if drive is not None else float(plan.speeds[0])
    r = run_designs(eq, q0=q0, speed0=speed0, time=time, turns=cycles, rtol=rtol, samples=samples or 1000,
                    compiled=compiled)
    steady = np.array([s == "steady" for s in r["stop"]])
    starts = np.array([s not in ("cannot start", "does not turn") for s in r["stop"]])
    w = r["speed"]
    effort = torque = power = current = None
    if drive is not None:
        effort, torque, mspeed = (np.asarray(x, dtype=float) for x in drive.generalised(w))
        power = torque * mspeed
        current = drive.current(torque)
    return PopulationResult(plan, params, r["t"], r["q"], w, r["accel"], effort, torque, power, current,
                            r["mean_speed"], r["delta"], r["startup"], starts, steady, r["turns"], r["stop"],
                            r["t_end"], r["steps"], eq.tail)


__all__ = ["compiled_available", "motor_code", "run_designs", "simulate_population"]
