"""The figure of a run on a motor: the input's speed against time at start-up, beside the kinetostatic estimate of
its steady fluctuation, and the motor's torque (and current) below.

Top: q̇(t) (rpm for a crank, the file's length unit per second for a linear input); the steady mean speed and 95 %
of it (the start-up time marked where the speed first reaches it); the simulated steady band [q̇_min, q̇_max] over
the last turn, and beside it the kinetostatic estimate's band ω̄·(1 ± δ_est/2) (a constant-speed force analysis
with a flywheel of the equation's mean inertia). Bottom: the motor's torque at its shaft (or force), and its current
on the right axis where it is known.
"""
from __future__ import annotations

import math

import numpy as np

from ..io.units import LENGTH
from .draw import mpl

RPM = 60.0 / (2.0 * math.pi)


def _speed_unit(plan):
    if plan.input_kinds[0] == "rotary":
        return RPM, "rpm"
    u = plan.mechanism.units.length
    return 1.0 / LENGTH[u], f"{u}/s"


def startup_figure(run, *, dpi: int = 100):
    """The figure of a :class:`~assur.dynamics.cycle.MotorRun` (or a bare Simulation)."""
    sim = getattr(run, "simulation", run)
    est = getattr(run, "estimate", None)
    _, plt = mpl()
    plan = sim.plan
    f, unit = _speed_unit(plan)
    motor = sim.effort is not None
    fig, axes = plt.subplots(2 if motor else 1, 1, figsize=(7.5, 5.6 if motor else 3.6), dpi=dpi, sharex=True,
                             squeeze=False, gridspec_kw={"height_ratios": [3, 2] if motor else [1]})
    ax = axes[0, 0]
    ax.plot(sim.t, sim.speed * f, color="C0", lw=1.2, label="simulated speed")
    w = sim.mean_speed
    if math.isfinite(w):
        ax.axhline(w * f, color="0.35", lw=0.8, ls="--", label=f"steady mean {w * f:.4g} {unit}")
        if sim.steady:
            ts = sim.startup_time
            ax.axhline(0.95 * w * f, color="0.6", lw=0.6, ls=":")
            if math.isfinite(ts):
                ax.axvline(ts, color="C3", lw=0.8, ls=":")
                ax.annotate(f"95 % at {ts:.3g} s", (ts, 0.95 * w * f), xytext=(6, -14), textcoords="offset points",
                            color="C3", fontsize=8)
        lo, hi = sim.last_extremes
        t0 = sim.turns[-1].start if sim.turns else sim.t[0]
        if sim.steady and math.isfinite(sim.startup_time):       # the steady bands from the end of the start-up
            t0 = min(t0, sim.startup_time)
        ax.fill_between([t0, sim.t[-1]], lo * f, hi * f, color="C0", alpha=0.15, lw=0,
                        label=f"simulated δ = {sim.delta:.4g}")
        if est is not None:
            d = est["delta_estimate"]
            ws = est["speed"] * np.sign(w)
            band = ws * f * (1 - d / 2), ws * f * (1 + d / 2)
            ax.hlines(band, t0, sim.t[-1], colors="C1", lw=1.2,
                      label=f"kinetostatic estimate δ ≈ {d:.4g} (difference {est['difference']:+.3g})")
    ax.set_ylabel(f"speed of {plan.input_names[0]} [{unit}]")
    ax.legend(loc="lower right", fontsize=8)
    ax.grid(alpha=0.3)
    ax.set_title(f"{plan.mechanism.name or 'mechanism'}: start-up on the motor", fontsize=10)
    if motor:
        ax2 = axes[1, 0]
        eff = "torque [N·m]" if not sim.equation.drive.motor.pushes else "force [N]"
        ax2.plot(sim.t, sim.motor_torque, color="C2", lw=1.0, label=f"motor {eff.split()[0]}")
        ax2.set_ylabel(f"motor {eff}")
        ax2.grid(alpha=0.3)
        if sim.current is not None:
            ax3 = ax2.twinx()
            ax3.plot(sim.t, sim.current, color="C4", lw=0.8, alpha=0.8, ls="--")
            ax3.set_ylabel("current [A]", color="C4")
        axes[-1, 0].set_xlabel("time [s]")
    else:
        ax.set_xlabel("time [s]")
    fig.tight_layout()
    return fig


__all__ = ["startup_figure"]
