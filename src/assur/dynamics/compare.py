"""The simulated speed fluctuation beside the kinetostatic estimate of a flywheel's designer.

The force analysis sizes a flywheel from one turn at a *constant* speed ω (:mod:`assur.kinetostatics.design`):
with a motor of constant torque Q̄ (the turn's mean), the work the flywheel stores and gives back is
ΔE = max − min of ∫(Q − Q̄) dq, and a constant inertia I then keeps the speed within δ ≈ ΔE/(I·ω²). Beside a
simulation's steady state this estimate is taken at the simulated mean speed ω̄, with I the constant inertia the
equation carries: the motor's rotor and flywheel plus the mean of the mechanism's own J* over the turn.

Its approximations, which the difference to the simulated δ measures: the speed is taken constant in the
inertia torques (an error of order δ); the motor's torque is taken constant, where a real motor's torque falls as
its speed rises and so damps the fluctuation (a DC motor of slope c = T_s/ω₀ at the input reduces a harmonic of
frequency nω̄ by 1/√(1 + (c/(n·I·ω̄))²)); J* is replaced by its mean.
"""
from __future__ import annotations

import math

import numpy as np

from ..kinetostatics.api import forces
from ..kinetostatics.design import drive_summary

#: samples of the turn on which the estimate's forces are solved
ESTIMATE_STEPS = 720


def kinetostatic_estimate(sim, steps: int = ESTIMATE_STEPS) -> dict | None:
    """The kinetostatic δ estimate at the simulation's steady mean speed, beside the simulated δ (SI): ``speed``,
    ``energy_fluctuation`` ΔE, ``inertia`` I, ``delta_estimate``, ``delta`` (simulated), ``difference`` (simulated −
    estimate) and ``damping`` (the motor's c/(I·ω̄), the estimate's neglected term). None unless the run turned a
    whole turn of a crank."""
    eq = sim.equation
    if not eq.rotary or not eq.periodic or not sim.turns:
        return None
    w = abs(float(sim.mean_speed))
    q = np.linspace(0.0, 2.0 * math.pi, int(steps), endpoint=False)
    f = forces(sim.plan, sim.params, q[:, None], speeds=[w])
    summary = drive_summary(f, q, turn=True)
    J = eq.terms(q)[0]
    inertia = float(np.mean(J))
    estimate = summary.energy_fluctuation / (inertia * w * w)
    damping = eq.drive.damping() / (inertia * w) if eq.drive is not None else 0.0
    return {"speed": w, "energy_fluctuation": float(summary.energy_fluctuation), "inertia": inertia,
            "delta_estimate": float(estimate), "delta": float(sim.delta),
            "difference": float(sim.delta - estimate), "damping": float(damping)}


__all__ = ["kinetostatic_estimate"]
