"""Time laws of the inputs: q(t), q̇(t), q̈(t), and solving a mechanism along them.

A time law gives, at times ``t (...)`` (s), an input's value, rate and acceleration (SI: m, m/s,
m/s² for a linear actuator; rad, rad/s, rad/s² for a crank). :class:`ConstantSpeed` is the paper-002
case s1 = V1·t; :class:`TableLaw` interpolates a programmed motion (a table of times and values) by
a C² cubic spline or a monotone PCHIP, both from scipy. :func:`solve_in_time` hands q, q̇ and q̈ to
the engine, whose chain rule gives every velocity and acceleration (ε = q̇²·d²θ/dq² + q̈·dθ/dq).
"""
from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from ..errors import SpecError

INTERPOLATIONS = ("cubic", "pchip")


@dataclass(frozen=True)
class ConstantSpeed:
    """q(t) = start + speed·t on [t_start, t_end]."""
    start: float
    speed: float
    t_start: float = 0.0
    t_end: float = 1.0

    @classmethod
    def over(cls, start: float, speed: float, stroke: tuple[float, float]) -> "ConstantSpeed":
        """The run at ``speed`` (≠ 0) from q = stroke[0] to stroke[1], with t = 0 where q = ``start``."""
        if not (np.isfinite(speed) and speed != 0):
            raise SpecError([("speed", f"a time axis needs a nonzero finite speed: {speed!r}")])
        t0, t1 = ((q - start) / speed for q in stroke)
        return cls(float(start), float(speed), float(min(t0, t1)), float(max(t0, t1)))

    def __call__(self, t):
        """(q, q̇, q̈) at times ``t (...)``, each (...)."""
        t = np.asarray(t, dtype=float)
        return self.start + self.speed * t, np.full(t.shape, self.speed), np.zeros(t.shape)


@dataclass(frozen=True)
class TableLaw:
    """q(t) through the table ``(times, values)``; ``interpolation``: 'cubic' (scipy CubicSpline,
    not-a-knot ends: continuous acceleration) or 'pchip' (scipy PchipInterpolator: no overshoot
    between monotone table values; the acceleration jumps at the knots). Outside the table's times
    the law is NaN (never extrapolated)."""
    times: tuple[float, ...]
    values: tuple[float, ...]
    interpolation: str = "cubic"
    _spline: object = field(init=False, repr=False, compare=False, default=None)

    def __post_init__(self):
        t = np.asarray(self.times, dtype=float)
        v = np.asarray(self.values, dtype=float)
        problems = []
        if t.ndim != 1 or len(t) < 2 or not np.all(np.isfinite(t)):
            problems.append(("law.time", f"must be at least 2 finite times: {self.times!r}"))
        elif np.any(np.diff(t) <= 0):
            i = int(np.argmax(np.diff(t) <= 0)) + 1
            problems.append((f"law.time[{i}]", f"times must increase strictly: {t[i - 1]:g} then {t[i]:g}"))
        if v.shape != t.shape or not np.all(np.isfinite(v)):
            problems.append(("law.length", f"needs one finite value per time: {len(v)} values for {len(t)} times"))
        if self.interpolation not in INTERPOLATIONS:
            problems.append(("law.interpolation", f"must be 'cubic' or 'pchip': {self.interpolation!r}"))
        if problems:
            raise SpecError(problems)
        from scipy.interpolate import CubicSpline, PchipInterpolator
        spline = CubicSpline(t, v) if self.interpolation == "cubic" else PchipInterpolator(t, v)
        object.__setattr__(self, "_spline", spline)

    @classmethod
    def of(cls, table) -> "TableLaw":
        """From a :class:`~assur.model.mechanism.TimeTable` of a mechanism file."""
        return cls(tuple(table.times), tuple(table.values), table.interpolation)

    @property
    def t_start(self) -> float:
        return float(self.times[0])

    @property
    def t_end(self) -> float:
        return float(self.times[-1])

    def __call__(self, t):
        t = np.asarray(t, dtype=float)
        inside = (t >= self.t_start) & (t <= self.t_end)
        out = [np.where(inside, self._spline(t, nu), np.nan) for nu in (0, 1, 2)]
        return out[0], out[1], out[2]


def driver_law(plan, k: int = 0, stroke=None):
    """The time law of input ``k`` from the mechanism file: its table law if the driver has one,
    else constant speed (the driver's ``speed``) over ``stroke`` (default: the driver's ``range``),
    with t = 0 at the sketch input. SpecError when no run is defined."""
    d = plan.mechanism.drivers[k]
    law = getattr(d, "law", None)
    if law is not None and stroke is None:
        return TableLaw.of(law)
    stroke = stroke if stroke is not None else getattr(d, "range", None)
    if stroke is None:
        raise SpecError([(f"drivers[{k}].range", f"the linear input '{d.name}' has no stroke: give range = "
                                                 f"[START, STOP] in the file or --range")])
    return ConstantSpeed.over(float(plan.sketch_inputs[k]), float(plan.speeds[k]), stroke)


def solve_in_time(plan, laws, t, params=None, *, order: int = 2, on_unbuildable: str = "nan"):
    """Solve ``plan`` at times ``t (n,)`` along ``laws`` (one time law per input, or one law for a
    one-input plan). Returns the engine's :class:`~assur.engine.state.State` of shape (n,) (or
    ``params.shape[:-1]`` broadcast against (n,)), with ``vel``, ``acc``, ``body_omega`` and
    ``body_alpha`` at the laws' rates and accelerations."""
    from ..engine import solve
    if callable(laws):
        laws = [laws]
    laws = list(laws)
    if len(laws) != plan.n_inputs:
        raise SpecError([("laws", f"need one time law per input ({plan.n_inputs}: {', '.join(plan.input_names)}): "
                                  f"{len(laws)} given")])
    t = np.asarray(t, dtype=float)
    qs = [law(t) for law in laws]
    q = np.stack([x[0] for x in qs], axis=-1)
    qd = np.stack([x[1] for x in qs], axis=-1)
    qdd = np.stack([x[2] for x in qs], axis=-1)
    return solve(plan, params, q, speeds=qd, accels=qdd, order=order, on_unbuildable=on_unbuildable,
                 backend="numpy")
