"""The motor torque a co-designed gear drive asks of its motor, and its limit (issue 25 C2: the co-designed leg
needs about 11× the peak torque of the plain leg, because the crank races through the shortened transfer).

The leg alone gives it (no geared file is solved). For a one-crank mechanism the force analysis is linear in the
crank's acceleration and in the square of its speed (d'Alembert: every body's acceleration is J·q̈ + J′·q̇²; gravity
and the file's loads depend on q alone, a load that opposes a point's velocity on the sense of q̇ alone), so the
crank torque is

    T_c(q, q̇, q̈) = a(q)·q̈ + b(q)·q̇² + c(q)

for q̇ of the crank's sense σ; :func:`crank_torque_terms` reads a, b, c off three force solves of the leg
(:func:`assur.forces`) at q̇ = s, 2s and (q̇, q̈) = (s, s²), s = σ·ω. A motor turning uniformly at ω_m through the
pair drives the crank at q̇ = σ·ω_m/g and q̈ = −ω_m²·g′/g³ (g = dτ/dq, :mod:`assur.codesign.law`), and an ideal
gear pair passes the power on, T_m·ω_m = T_c·q̇, so

    T_m = σ·T_c/g,    |T_m| = |T_c|/g.

That is the motor torque of the geared mechanism file's force analysis (``assur forces``) to round-off; the tests
check it there independently. :func:`drive_cost` is the before/after summary of two solved runs (the plain leg's
crank turn and the geared leg's motor turn, :class:`~assur.analysis.study.Study`).
"""
from __future__ import annotations

import math

import numpy as np

from ..errors import SpecError
from ..kinetostatics.api import forces
from ..engine import solve
from .law import motor_speed

TWO_PI = 2.0 * math.pi
#: crank angles at which the peak of a finished design is looked for, before it is refined
CHECK_SAMPLES = 4096
#: the searches hold the peak on their samples this fraction inside the limit, so that the peak between their
#: samples (found by :func:`peak_torque` when the design is checked) stays within it
SEARCH_SAFETY = 1e-3


def carries_loads(mechanism) -> bool:
    """Whether the leg's own force analysis has a motor torque to speak of: a mass or a load (a body weight alone
    loads the walking module's shaft, not the leg's crank)."""
    d = mechanism.dynamics
    return d is not None and (d.has_mass or bool(d.loads))


def check_max_torque(max_torque, plan) -> float:
    """The torque limit (N·m) as a float > 0, else SpecError naming ``max_torque``; also when the leg has no mass
    and no load (its motor torque is zero whatever the gears)."""
    if isinstance(max_torque, bool) or not isinstance(max_torque, (int, float, np.floating, np.integer)) \
            or not np.isfinite(max_torque) or max_torque <= 0:
        raise SpecError([("max_torque", f"must be a finite torque > 0 N·m: {max_torque!r}")])
    if plan is None or not carries_loads(plan.mechanism):
        raise SpecError([("max_torque", "the leg has no masses and no loads, so its motor torque is zero whatever "
                                        "the gears: give its links masses (docs/forces.md) to limit the torque")])
    return float(max_torque)


def crank_torque_terms(plan, params, q) -> np.ndarray:
    """(3, n): a, b, c of the crank torque T_c = a·q̈ + b·q̇² + c (N·m per rad/s², per (rad/s)², N·m) of the leg
    ``plan`` at ``params`` and crank inputs q (n,), for a crank turning in the sense of the plan's speed (module
    docstring). Samples the force analysis cannot carry (a toggle) are NaN."""
    q = np.asarray(q, dtype=float).reshape(-1)
    speed = float(plan.speeds[0])
    s = (-1.0 if speed < 0 else 1.0) * (abs(speed) if speed else 1.0)
    rates = np.array([[s, 0.0], [2.0 * s, 0.0], [s, s * s]])                       # (q̇, q̈) of the three solves
    inputs = np.repeat(q[None, :, None], 3, axis=0)                                # (3, n, 1)
    speeds = np.repeat(rates[:, None, :1], q.size, axis=1)
    accels = np.repeat(rates[:, None, 1:], q.size, axis=1)
    state = solve(plan, params, inputs, speeds=speeds, accels=accels, order=2, backend="numpy")
    t1, t2, t3 = np.asarray(forces(plan, params, inputs, state=state, backend="numpy").driver, dtype=float)[..., 0]
    b = (t2 - t1) / (3.0 * s * s)
    return np.stack([(t3 - t1) / (s * s), b, t1 - b * s * s])


def motor_torque(terms, g, dg, omega: float, sense: int) -> np.ndarray:
    """T_m (n,), N·m: the motor torque of a pair with ratio g = dτ/dq and g′ (n,) at the samples of ``terms``
    (:func:`crank_torque_terms`), the motor turning uniformly at ``omega`` (rad/s) and the crank in ``sense``."""
    a, b, c = terms
    qd = sense * omega / g
    qdd = -(omega ** 2) * dg / g ** 3
    return sense * (a * qdd + b * qd * qd + c) / g


def _motor_speed(law) -> float:
    """ω_m of a leg's law: the plan's crank speed times the motor turns per crank turn (the crank's mean speed is the
    plan's: :func:`~assur.codesign.law.motor_speed`)."""
    return motor_speed(law.foot, law.driving_turns)


def peak_torque(law, *, samples: int = CHECK_SAMPLES) -> tuple[float, float]:
    """(peak |T_m| (N·m), the crank angle of it (rad, in [0, 2π))) of a leg's co-designed ``law``: the largest of
    ``samples`` crank angles over a turn, refined by a bounded scalar search between its neighbours."""
    from scipy.optimize import minimize_scalar
    foot = law.foot
    plan, params = foot.plan, foot.params
    omega = _motor_speed(law)

    def torque(q):
        return np.abs(motor_torque(crank_torque_terms(plan, params, q), law.g(q), law.dg(q), omega, law.sense))

    q = law.q1 + np.linspace(0.0, TWO_PI, int(samples), endpoint=False)
    values = torque(q)
    if not np.isfinite(values).any():
        return math.nan, math.nan
    i = int(np.nanargmax(values))
    step = TWO_PI / int(samples)
    best = minimize_scalar(lambda x: -float(torque(np.array([x]))[0]), bounds=(q[i] - step, q[i] + step),
                           method="bounded", options={"xatol": 1e-10})
    peak, at = (float(-best.fun), float(best.x)) if -best.fun >= values[i] else (float(values[i]), float(q[i]))
    return peak, float(np.mod(at, TWO_PI))


def torque_check(law, max_torque) -> tuple[float, float, str]:
    """(peak, crank angle of it, violation text or "") of a leg's co-designed ``law`` against ``max_torque`` (N·m).
    SpecError (``max_torque``) for a bad limit, a law that is not a leg's, or a leg without masses and loads."""
    foot = getattr(law, "foot", None)
    if getattr(foot, "plan", None) is None or not hasattr(law, "q1"):
        raise SpecError([("max_torque", "a torque limit needs a walking leg's co-designed law (with its "
                                        "mechanism): the wheel-step drive has no motor torque model")])
    limit = check_max_torque(max_torque, foot.plan)
    peak, at = peak_torque(law)
    if not peak <= limit:
        return peak, at, (f"the motor torque reaches {peak:.5g} N·m > the limit {limit:.5g} N·m (by "
                          f"{peak - limit:.2g} N·m) at crank angle q = {math.degrees(at):.1f}°")
    return peak, at, ""


def drive_cost(before, after) -> dict | None:
    """The drive's before/after cost from two solved runs (:class:`~assur.analysis.study.Study`): the plain leg
    (a uniform crank) and the geared leg (a uniform motor), one turn each. {"before", "after"}: {"driver", "peak",
    "rms" (N·m), "joint_peaks" ({joint: peak |reaction|, N})}; None when the leg carries no mass and no load."""
    if not carries_loads(before.plan.mechanism):
        return None
    out = {}
    for key, study in (("before", before), ("after", after)):
        s = study.force_summary
        out[key] = {"driver": s["driver"], "peak": s.get("peak"), "rms": s.get("rms"),
                    "joint_peaks": dict(s.get("joint_peaks", {}))}
    return out


__all__ = ["CHECK_SAMPLES", "SEARCH_SAFETY", "carries_loads", "check_max_torque", "crank_torque_terms", "drive_cost",
           "motor_torque", "peak_torque", "torque_check"]
