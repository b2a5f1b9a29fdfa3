"""A solved cycle's mechanism run on its motor: what the report, the designer and the command line show.

:func:`cycle_simulation` takes a solved cycle (an :class:`~assur.analysis.study.Study`, or anything with ``.plan``,
``.params`` and ``.grid()``; a plan works too) and returns a :class:`MotorRun`: the :class:`~.result.Simulation` to its steady
state (or for the time or turns asked), the kinetostatic δ estimate beside it (:mod:`.compare`) and every joint's
reaction over the run (the force analysis at the simulated speed and acceleration). None when the file has no
motor and none is given.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from .api import resolve_motor, simulate
from .compare import kinetostatic_estimate


@dataclass(frozen=True)
class MotorRun:
    """A run and what is derived from it: ``simulation``, ``estimate`` (dict or None), ``forces`` (a Forces over
    the run's samples, or None when the force analysis does not apply)."""
    simulation: object
    estimate: dict | None
    forces: object | None

    def joint_peaks(self) -> dict:
        """{joint label: peak reaction magnitude over the run (N)}."""
        f = self.forces
        if f is None:
            return {}
        with np.errstate(invalid="ignore"):
            mags = f.magnitudes
        out = {}
        for k in f.joint_pairs:
            col = mags[..., k]
            key = f"{f.pair_names[k]} ({f.pair_bodies[k][0]}–{f.pair_bodies[k][1]})"
            out[key] = float(np.nanmax(col)) if np.isfinite(col).any() else math.nan
        return out

    def summary(self) -> dict:
        """JSON-ready numbers (SI): the run's summary, the estimate and the joints' peak reactions."""
        out = self.simulation.summary()
        if self.estimate is not None:
            out["kinetostatic"] = dict(self.estimate)
        out["joint_peaks"] = {k: (v if math.isfinite(v) else None) for k, v in self.joint_peaks().items()}
        return out


def run_forces(sim):
    """The reactions over a run's samples, or None where the force analysis does not apply (several samples
    singular are NaN, as the force analysis gives them)."""
    from ..errors import AssurError
    try:
        return sim.forces()
    except AssurError:
        return None


def cycle_simulation(cycle, *, motor=None, time: float | None = None, cycles: int | None = None,
                     q0=None, speed0=None, friction: bool = False, method: str = "auto") -> MotorRun | None:
    """The :class:`MotorRun` of a solved cycle (module docstring); None when there is no motor."""
    plan = cycle.plan if hasattr(cycle, "grid") else cycle
    mot = resolve_motor(plan, motor)
    if mot is None:
        return None
    sim = simulate(cycle, motor=mot, time=time, cycles=cycles, q0=q0, speed0=speed0, friction=friction,
                   method=method)
    return MotorRun(sim, kinetostatic_estimate(sim), run_forces(sim))


__all__ = ["MotorRun", "cycle_simulation", "run_forces"]
