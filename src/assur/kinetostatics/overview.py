"""The forces of one working cycle of a file, as the command line, the analysis and the report show them.

:func:`force_cycle` solves the forces over one crank turn (a uniform grid of ``steps`` inputs) or over a
linear driver's working stroke (``range`` in the file); :func:`force_summary` turns it into a JSON-ready dict
(SI): the design quantities of :func:`~.design.drive_summary`, the flywheel inertia for δ =
:data:`FLYWHEEL_DELTA`, the friction iterations and, for a walking module with ``[gait] weight``, the
module's driving torque (:func:`~.gait.gait_forces`). Reactions may be planar (…, 2) or spatial (…, 3).
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..engine.options import CYCLE_STEPS
from ..errors import SpecError, StructureError
from .api import forces
from .design import drive_summary
from .result import Forces

#: the coefficient of speed fluctuation δ = (ω_max − ω_min)/ω_mean for which the summary sizes a flywheel
FLYWHEEL_DELTA = 0.05


#: what the force analysis says of a file without masses, loads or a body weight (its forces are all zero)
NO_LOADS = ("the file has no masses or loads: every force is zero (give its links a mass, [[loads]] or a [gait] "
            "weight: docs/format.md, \"Forces\")")


def has_loads(mechanism) -> bool:
    """True when the file gives the force analysis something to carry: a mass, a load or a body weight."""
    d = mechanism.dynamics
    gait = mechanism.gait
    weight = gait is not None and getattr(gait, "weight", None) is not None
    return weight or (d is not None and (d.has_mass or bool(d.loads)))


def check_one_driver(plan) -> None:
    """StructureError unless the plan has a single driver."""
    if plan.n_inputs != 1:
        raise StructureError(f"the force analysis of a cycle needs one driver; the mechanism has {plan.n_inputs} "
                             f"({', '.join(plan.input_names)})")


def cycle_inputs(plan, steps: int = CYCLE_STEPS) -> tuple[np.ndarray, bool]:
    """(q (n,), turn): one crank turn (``turn`` True) or the linear driver's working stroke (SI)."""
    check_one_driver(plan)
    if plan.input_kinds[0] == "rotary":
        return np.linspace(0.0, 2.0 * math.pi, int(steps), endpoint=False), True
    d = plan.mechanism.drivers[0]
    if d.range is None:
        raise SpecError([(f"drivers.{d.name}.range", "a linear driver needs a working stroke (range = [start, "
                                                     "stop]) for a force cycle; or give inputs with --at")])
    return np.linspace(float(d.range[0]), float(d.range[1]), int(steps)), False


@dataclass(frozen=True)
class ForceCycle:
    """The forces of one cycle: ``q (n,)`` the inputs (SI), ``turn`` a crank turn (else a stroke),
    ``forces`` (n,), the :class:`~.design.DriveSummary` ``drive`` and the gait's forces or None."""
    q: np.ndarray
    turn: bool
    forces: Forces
    drive: object
    gait: object = None


def cycle_forces(cycle, *, friction: bool = False):
    """The :class:`~.result.Forces` over the run of ``cycle`` (a Cycle or Study of a one-driver plan, its State
    solved with order 2; nothing is solved again): one crank turn, or a linear driver's working stroke."""
    plan = cycle.plan
    check_one_driver(plan)
    d = plan.mechanism.drivers[0]
    if plan.input_kinds[0] != "rotary" and d.range is None:
        raise SpecError([(f"drivers.{d.name}.range", "a linear driver needs a working stroke (range = [start, "
                                                     "stop]) for a force cycle; or give inputs with --at")])
    q, state = cycle.grid()
    return forces(plan, cycle.params, q[:, None], friction=friction, state=state)


def force_cycle(cycle, *, friction: bool = False, run_forces=None) -> ForceCycle:
    """The forces over the run of ``cycle`` (:func:`cycle_forces`, or ``run_forces`` when already computed) with
    the drive summary and, for a walking module with a body weight, the gait forces (from ``cycle.gait``, the exact
    contact arc of a Study; the legs are the run's samples shifted by their phases)."""
    plan = cycle.plan
    f = cycle_forces(cycle, friction=friction) if run_forces is None else run_forces
    q = cycle.q
    turn = plan.input_kinds[0] == "rotary"
    drive = drive_summary(f, q, turn=turn)
    g = plan.mechanism.gait
    gait = None
    if plan.dimension == 2 and turn and g is not None and getattr(g, "weight", None) is not None:
        from .gait import gait_forces
        metrics = getattr(cycle, "gait", None)
        if metrics is not None:
            gait = gait_forces(cycle, metrics, joint_friction=friction)
    return ForceCycle(q, turn, f, drive, gait)


def _norm(a, batch_ndim: int) -> np.ndarray:
    """|a| over the vector axis when ``a`` has one beyond the batch, else |a|."""
    a = np.asarray(a, dtype=float)
    with np.errstate(invalid="ignore"):
        return np.sqrt(np.sum(a * a, axis=-1)) if a.ndim > batch_ndim else np.abs(a)


def _peak(a) -> float:
    a = np.asarray(a, dtype=float)
    return float(np.nanmax(a)) if np.isfinite(a).any() else math.nan


def _joint_key(f: Forces, k: int) -> str:
    return f"{f.pair_names[k]} ({f.pair_bodies[k][0]}–{f.pair_bodies[k][1]})"


def force_summary(cycle: ForceCycle, *, friction: bool = False) -> dict:
    """The JSON-ready summary (SI; NaN where a sample is singular) of a :class:`ForceCycle`."""
    f, q = cycle.forces, cycle.q
    plan = f.plan
    nb = len(f.shape)
    rotary = plan.input_kinds[0] == "rotary"
    out = {"driver": plan.input_names[0], "effort": "torque" if rotary else "force",
           "effort_unit": "N·m" if rotary else "N", "cycle": "turn" if cycle.turn else "stroke",
           "start": float(q[0]), "stop": float(q[-1]), "samples": int(q.size),
           "singular": int(np.sum(f.singular)), "unassembled": int(np.sum(~np.asarray(f.state.valid)))}
    d = cycle.drive
    if d is not None:
        out.update({k: getattr(d, k) for k in ("speed", "peak", "rms", "mean", "power_peak", "power_mean",
                                                "energy", "energy_fluctuation")})
        out["flywheel_delta"] = FLYWHEEL_DELTA
        out["flywheel_inertia"] = d.flywheel_inertia(FLYWHEEL_DELTA) if d.rotary and d.speed else None
    out["shaking_force_peak"] = _peak(_norm(f.frame_force, nb))
    out["shaking_moment_peak"] = _peak(_norm(f.frame_moment, nb))
    mags = _norm(f.reactions, nb + 1)
    out["joint_peaks"] = {_joint_key(f, k): _peak(mags[..., k]) for k in f.joint_pairs}
    if f.gears:
        out["gears"] = {name: {"tooth_force_peak": _peak(np.abs(g["tooth_force"])),
                               "torque_peak": _peak(np.abs(g["torque"]))} for name, g in f.gears.items()}
    if friction:
        out["friction"] = {"iterations": int(f.iterations), "converged": bool(f.converged)}
    if not has_loads(plan.mechanism):
        out = {"note": NO_LOADS, **out}
    g = cycle.gait
    if g is not None:
        M = np.asarray(g.module_driver, dtype=float)
        ok = np.isfinite(M)
        out["gait"] = {"weight": g.weight, "legs": len(g.phases), "friction": g.friction,
                       "module_peak": _peak(np.abs(M)),
                       "module_rms": float(np.sqrt(np.mean(M ** 2))) if ok.all() else math.nan,
                       "module_mean": float(np.mean(M)) if ok.all() else math.nan}
    return out
