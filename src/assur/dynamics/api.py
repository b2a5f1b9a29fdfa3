"""``assur.simulate``: how the machine runs on its motor (forward dynamics of a one-input mechanism).

One design (``params`` (n_params,) or None) is integrated by :func:`~.integrate.integrate` with scipy's
``solve_ivp``; a batch of designs (``params`` (n_designs, n_params)) by the vectorised integrator of
:mod:`.population`. The motor is the file's ``[motor]`` unless ``motor`` is given (a
:class:`~assur.model.motor.Motor`, the keys of ``[motor]`` as a dict, or the text of ``--motor``); ``motor=False``
runs the mechanism freely, without one.
"""
from __future__ import annotations

import math

import numpy as np

from ..errors import SpecError
from ..model.motor import Motor
from .equation import build_equation
from .integrate import integrate
from .motors import drive_train
from .result import Simulation

TWO_PI = 2.0 * math.pi
#: output samples per turn, and their bounds over a run
SAMPLES_PER_TURN, MIN_SAMPLES, MAX_SAMPLES = 96, 1000, 200_000


def resolve_motor(plan, motor) -> Motor | None:
    """The Motor of a run: the file's (``motor`` None), none (``motor`` False), or ``motor`` given as a Motor,
    a dict of ``[motor]`` keys (file units) or the ``--motor`` text."""
    m = plan.mechanism
    if motor is None:
        return m.motor
    if motor is False:
        return None
    if isinstance(motor, Motor):
        return motor
    from ..io.motor_file import parse_motor_option, read_motor
    if isinstance(motor, str):
        return parse_motor_option(motor, m.units, m.drivers)
    if isinstance(motor, dict):
        from ..io.problems import Problems
        P = Problems()
        out = read_motor(dict(motor), P, m.units, m.drivers, path="motor")
        P.raise_if_any()
        return out
    raise SpecError([("motor", f"must be a Motor, a dict of [motor] keys or their text: {type(motor).__name__}")])


def _source(plan_or_cycle, params):
    """(plan, params, solved grid or None) of a plan or a solved cycle (a :class:`~assur.analysis.study.Study`:
    ``.plan``, ``.params``, ``.grid()``); its grid is used when it is the uniform grid of one turn from 0."""
    if hasattr(plan_or_cycle, "grid") and hasattr(plan_or_cycle, "plan"):
        cyc = plan_or_cycle
        if params is not None:
            raise SpecError([("params", "a solved cycle carries its own parameters: give params only with a plan")])
        grid = None
        if cyc.plan.n_inputs == 1 and cyc.plan.input_kinds[0] == "rotary" and getattr(cyc, "order", 2) >= 2:
            q, state = cyc.grid()
            q = np.asarray(q, dtype=float)
            if q.ndim == 1 and q.size >= 16 and np.allclose(q, TWO_PI * np.arange(q.size) / q.size, rtol=0,
                                                            atol=1e-15):
                grid = (q, state)
        return cyc.plan, np.asarray(cyc.params, dtype=float), grid
    plan = plan_or_cycle
    if not hasattr(plan, "input_kinds"):
        raise TypeError(f"simulate needs a plan from assur.compile (or a solved cycle), not {type(plan).__name__}")
    return plan, (plan.defaults if params is None else np.asarray(params, dtype=float)), None


#: a crank's run may start this many turns from the sketch's angle at most (farther, a turn is lost to round-off)
MAX_START_TURNS = 1000


def check_start(plan, q0, *, name: str = "q0", given=None) -> None:
    """SpecError (at ``name``, showing ``given``, default ``q0``) unless the start ``q0`` (SI: None, a number or one
    per design) is finite and, for a crank, within :data:`MAX_START_TURNS` turns of the sketch's angle."""
    if q0 is None:
        return
    q = np.asarray(q0, dtype=float) if not isinstance(q0, str) else np.array(math.nan)
    off = np.abs(q - float(plan.sketch_inputs[0])) if plan.input_kinds[0] == "rotary" else np.zeros(q.shape)
    if not (np.all(np.isfinite(q)) and np.all(off <= MAX_START_TURNS * TWO_PI)):
        what = (f"a finite angle within {MAX_START_TURNS} turns of the sketch's angle"
                if plan.input_kinds[0] == "rotary" else "a finite length")
        raise SpecError([(name, f"must be {what}: {(q0 if given is None else given)!r:.60}")])


def simulate(plan, *, time: float | None = None, cycles: int | None = None, motor=None, q0: float | None = None,
             speed0: float | None = None, params=None, method: str = "auto", rtol: float = 1e-10,
             mode: str = "series", friction: bool = False, samples: int | None = None, steady: float | None = None,
             backend: str = "auto"):
    """Run the mechanism of ``plan`` on its motor.

    Parameters
    ----------
    plan : PlanarPlan or SpatialPlan (one input), or a solved cycle (``assur.Study``: its solved turn is reused)
    time : float, optional
        Seconds to run. ``cycles``: turns of the input to run instead. Neither: to the periodic steady state
        (a motor-driven crank), detected from the convergence of the turns' periods.
    motor : Motor, dict, str or False, optional
        The motor (default: the file's ``[motor]``); False: none, the mechanism moves freely from ``speed0``.
    q0, speed0 : float, optional
        The start: input (default: the sketch's) and its rate (default: rest with a motor; the driver's file
        speed without one).
    params : array_like (n_params,) or (n_designs, n_params), optional
        Design parameters; a 2-D array runs the designs as a batch (:mod:`.population`).
    method : {'auto', 'DOP853', 'RK45', 'Radau', 'BDF', 'LSODA'}
        The integrator ('auto': DOP853, or Radau for a stiff motor). ``rtol``: its relative tolerance.
    mode : {'series', 'exact'}
        Interpolate the equation's terms (their measured error in ``result.equation.fit.error``) or evaluate them
        exactly at every step (slower).
    friction : bool
        Include the file's Coulomb joint friction (evaluated exactly at every step; slow).
    samples : int, optional
        Output samples, 2 to 200 000 (default: 96 per turn, at least 1000).
    steady : float, optional
        A run to steady state stops when the period's remaining change is below this share of the period
        (default :data:`~.integrate.STEADY`).
    backend : {'auto', 'numpy', 'numba'}
        A batch's integrator: compiled (numba, where installed: 'auto') or vectorised numpy; the same numbers to
        the tolerance.

    Returns
    -------
    Simulation, or PopulationResult for a batch of designs.
    """
    plan, params, grid = _source(plan, params)
    mot = resolve_motor(plan, motor)
    if time is not None and cycles is not None:
        raise SpecError([("time", "give time or cycles, not both")])
    if time is not None and not (math.isfinite(time) and time > 0):
        raise SpecError([("time", f"must be a positive number of seconds: {time!r}")])
    if cycles is not None and (int(cycles) != cycles or cycles < 1):
        raise SpecError([("cycles", f"must be a positive whole number of turns: {cycles!r}")])
    if friction and plan.dimension != 2:
        raise SpecError([("friction", "friction is modelled for planar mechanisms only")])
    check_start(plan, q0)
    if samples is not None and (isinstance(samples, bool) or not isinstance(samples, (int, np.integer))
                                or not 2 <= samples <= MAX_SAMPLES):
        raise SpecError([("samples", f"must be a whole number from 2 to {MAX_SAMPLES}: {samples!r:.40}")])
    drive = None if mot is None else drive_train(mot, plan)
    if params.ndim == 2:
        from .batch import simulate_population
        if friction or mode != "series":
            raise SpecError([("params", "a batch of designs runs on interpolated terms without friction")])
        if backend not in ("auto", "numpy", "numba"):
            raise SpecError([("backend", f"must be one of auto, numpy, numba: {backend!r}")])
        return simulate_population(plan, params, drive, time=time, cycles=cycles, q0=q0, speed0=speed0,
                                   samples=samples, compiled=None if backend == "auto" else backend == "numba")
    if params.ndim != 1 or params.shape[0] != plan.n_params:
        raise SpecError([("params", f"must be ({plan.n_params},) or (n_designs, {plan.n_params}): "
                                    f"shape {params.shape}")])
    q0 = float(plan.sketch_inputs[0]) if q0 is None else float(q0)
    if speed0 is None:
        speed0 = 0.0 if drive is not None else float(plan.speeds[0])
    if friction and (plan.mechanism.dynamics is None or not plan.mechanism.dynamics.friction.any):
        raise SpecError([("friction", "the file gives no friction ([dynamics] joint_friction_radius, "
                                      "slide_friction)")])
    eq = build_equation(plan, params, drive=drive, q0=q0, mode=mode, friction=friction, state_grid=grid)
    if drive is None and not np.any(eq.terms(np.array([q0]))[0] > 0):
        raise SpecError([("dynamics", "the mechanism has no inertia: give its links masses (or a motor with a rotor "
                                      "or flywheel inertia)")])
    from .integrate import STEADY
    run = integrate(eq, q0=q0, speed0=float(speed0), time=time, turns=cycles, method=method, rtol=rtol,
                    steady=STEADY if steady is None else steady)
    return assemble(plan, params, eq, run, samples)


def assemble(plan, params, eq, run, samples=None) -> Simulation:
    """The :class:`Simulation` of a raw run: the output samples and the motor's quantities along them."""
    t_end = run.t_end
    n = samples or int(min(MAX_SAMPLES, max(MIN_SAMPLES, SAMPLES_PER_TURN * (len(run.turns) + 1))))
    t = np.linspace(0.0, t_end, n) if t_end > 0 else np.zeros(1)
    q, w = run.state(t)
    if eq.friction:
        from .friction import friction_acceleration
        acc = np.array([friction_acceleration(eq, a, b) for a, b in zip(q, w)])
    else:
        acc = np.asarray(eq.acceleration(q, w), dtype=float)
    J = eq.terms(q)[0]
    kinetic = 0.5 * J * w * w
    V = eq.potential(q)
    energy = None if V is None or eq.friction else kinetic + V
    effort = torque = mspeed = power = current = None
    if eq.drive is not None:
        effort, torque, mspeed = (np.asarray(x, dtype=float) for x in eq.drive.generalised(w))
        power = torque * mspeed
        current = eq.drive.current(torque)
    from .integrate import turn_extremes
    extremes = turn_extremes(eq, run.turns[-1]) if run.turns else (math.nan, math.nan)
    return Simulation(plan, params, eq, t, q, w, acc, effort, torque, mspeed, power, current, kinetic, energy,
                      tuple(run.events), run.stop, tuple(run.turns), run.method, run.nfev, run, extremes)


__all__ = ["assemble", "resolve_motor", "simulate"]
