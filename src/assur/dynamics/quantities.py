"""The dynamic quantities a synthesis may name (``dynamics.*``), for a population of designs at once.

Each design runs from rest at its sketch input on the template's ``[motor]`` to its periodic steady state
(:mod:`.population`: the vectorised integrator on the designs' Fourier terms, sampled on the synthesis' own cycle
grid). Per design (SI):

* ``dynamics.startup_time``: the time (s) to 95 % of the steady mean speed (NaN unless it reaches a steady state);
* ``dynamics.mean_speed``: the steady mean speed 2π/T (rad/s);
* ``dynamics.delta``: the steady coefficient of speed fluctuation (max − min)/mean over the last turn;
* ``dynamics.starts``: 1 when the motor brings the design to its steady state, 0 when it cannot start it, stalls,
  or the design does not turn fully.
"""
from __future__ import annotations

import numpy as np

from ..errors import SpecError
from .batch import run_designs
from .motors import drive_train
from .population import population_equation

#: the quantities and what they mean
DYNAMICS_QUANTITIES = {
    "dynamics.startup_time": "time from rest to 95 % of the steady mean speed on the template's [motor] (s)",
    "dynamics.mean_speed": "steady mean speed of the input on the template's [motor] (angle unit per second)",
    "dynamics.delta": "steady coefficient of speed fluctuation (max − min)/mean on the template's [motor]",
    "dynamics.starts": "1 when the template's [motor] brings the design from rest to a steady state, else 0",
}


def check_dynamics(plan) -> str | None:
    """Why ``dynamics.*`` cannot be computed for ``plan`` (a sentence), or None."""
    m = plan.mechanism
    if m.motor is None:
        return "needs a [motor] in the template mechanism (docs/dynamics.md)"
    if plan.n_inputs != 1 or plan.input_kinds[0] != "rotary":
        return "needs a mechanism with one crank (its designs run to a steady state turn after turn)"
    return None


def population_quantities(plan, params, state=None, *, rtol: float = 1e-8, compiled: bool | None = None) -> dict:
    """{quantity: (D,) array} of the designs ``params (D, n_params)`` (SI; ``state``: their solved cycle grid
    (D, M) at q = 2πj/M with order 2, or None to solve it here; ``compiled``: the integrator's route, None for the
    compiled one where numba is installed)."""
    why = check_dynamics(plan)
    if why is not None:
        raise SpecError([("dynamics", why)])
    params = np.asarray(params, dtype=float)
    D = params.shape[0]
    drive = drive_train(plan.mechanism.motor, plan)
    with np.errstate(all="ignore"):
        eq = population_equation(plan, params, drive, state=state)
        finite = np.all(np.isfinite(params), axis=1)
        eq = type(eq)(eq.plan, eq.series, eq.table, eq.valid & finite, eq.drive, eq.tail)
        q0 = np.full(D, float(plan.sketch_inputs[0]))
        r = run_designs(eq, q0=q0, speed0=0.0, rtol=rtol, compiled=compiled)
    steady = np.array([s == "steady" for s in r["stop"]])
    return {"dynamics.startup_time": np.where(steady, r["startup"], np.nan),
            "dynamics.mean_speed": np.where(steady, r["mean_speed"], np.nan),
            "dynamics.delta": np.where(steady, r["delta"], np.nan),
            "dynamics.starts": steady.astype(float)}


__all__ = ["DYNAMICS_QUANTITIES", "check_dynamics", "population_quantities"]
