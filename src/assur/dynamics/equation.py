"""The reduced equation of motion of one design, ready for an integrator: its terms as interpolants (or evaluated
on demand), the drive train, and the domain of the input where the equation holds.

The domain is the whole line for a crank whose mechanism assembles at every angle (the terms are 2π-periodic);
otherwise it is the interval around the start where every sample assembles, is not singular and has a finite,
positive J* below :data:`JSTAR_GROWTH` times its median (a dead centre of the input, where J* → ∞, or the
limit of assembly, ends it), intersected with a linear driver's working stroke. Each end carries the reason a
run stops there.
"""
from __future__ import annotations

import math
from bisect import bisect_right
from dataclasses import dataclass, field

import numpy as np

from ..errors import SpecError
from .motors import DriveTrain
from .reduced import check_one_input, reduced_terms
from .series import PeriodicSeries, fit_periodic, fit_table

TWO_PI = 2.0 * math.pi
#: samples of a turn the periodic fit starts from (unless a solved cycle gives its own grid), and the most
GRID_START, GRID_MAX = 256, 2048
#: samples of the table that replaces a series which does not converge (kinks), and of an interval's table
TABLE_TURN, TABLE_INTERVAL = 8192, 4097
#: the relative interpolation error at the grid's midpoints the fits aim at
FIT_TOLERANCE = 1e-11
#: the domain ends where J* exceeds this multiple of its median over the domain (a dead centre approaches)
JSTAR_GROWTH = 1e3
#: bisection steps refining a domain end (each halves the uncertainty of the input)
BISECTIONS = 48


@dataclass(frozen=True)
class Limit:
    """One end of the domain: the input ``q`` where the run stops, ``at`` where the mechanism degenerates (the
    dead centre, or the last input that assembles), and the ``reason`` ('end of stroke', 'dead centre',
    'cannot be assembled', 'zero inertia')."""
    q: float
    at: float
    reason: str


@dataclass(frozen=True)
class Equation:
    """The reduced equation of one design (module docstring). ``mode``: 'series' (interpolants) or 'exact'
    (every evaluation solves the mechanism). ``fit``: the :class:`~.series.Fit` of the terms (None in exact
    mode); ``drive``: the drive train or None (a free motion)."""
    plan: object
    params: np.ndarray
    rotary: bool
    periodic: bool
    lower: Limit | None
    upper: Limit | None
    drive: DriveTrain | None
    mode: str = "series"
    fit: object = None
    friction: bool = False
    notes: tuple[str, ...] = field(default_factory=tuple)

    @property
    def extra_inertia(self) -> float:
        return 0.0 if self.drive is None else self.drive.inertia

    def exact(self, q) -> np.ndarray:
        """(..., 4) J*, J*′, Q_applied, Q_opposing at q (...), solving the mechanism."""
        return reduced_terms(self.plan, self.params, np.asarray(q, dtype=float), backend="numpy").stacked()

    def terms(self, q):
        """(J* + motor inertia, dJ*/dq, Q_applied, Q_opposing) at q (...), each (...)."""
        if self.mode == "exact":
            t = self.exact(q)
            return t[..., 0] + self.extra_inertia, t[..., 1], t[..., 2], t[..., 3]
        series = self.fit.series
        if np.ndim(q) == 0 and isinstance(series, PeriodicSeries):     # the integrator's scalar evaluation
            k, columns = self._scalar_form
            v = (np.exp(1j * (float(q) - series.start) * k) @ columns).real
            return v[0] + self.extra_inertia, v[1], v[2], v[3]
        if np.ndim(q) == 0:
            return self._table_scalar(float(q))
        value, slope = series(q, derivative=True)
        return value[..., 0] + self.extra_inertia, slope[..., 0], value[..., 2], value[..., 3]

    def _table_scalar(self, q: float):
        """:meth:`terms` of a table at one input, in plain floats (the table's interpolation written out on Python
        lists: the integrator's evaluation)."""
        nodes, vals, knots, pieces, periodic, lo = self._scalar_table
        n = len(nodes)
        if periodic:
            q = lo + (q - lo) % TWO_PI
            i = min(max(bisect_right(nodes, q) - 1, 0), n - 1)
            j = (i + 1) % n
            h = (nodes[j] if j else lo + TWO_PI) - nodes[i]
        else:
            i = min(max(bisect_right(nodes, q) - 1, 0), n - 2)
            j = i + 1
            h = nodes[j] - nodes[i]
        s = (q - nodes[i]) / h
        a0, a1 = vals[i]
        b0, b1 = vals[j]
        d, ha1, hb1 = b0 - a0, h * a1, h * b1
        c2 = 3.0 * d - 2.0 * ha1 - hb1
        c3 = ha1 + hb1 - 2.0 * d
        J = a0 + s * (ha1 + s * (c2 + s * c3))
        dJ = (ha1 + s * (2.0 * c2 + 3.0 * s * c3)) / h
        k = min(max(bisect_right(knots, q) - 1, 0), len(knots) - 2)
        x = q - knots[k]
        p0, p1, p2, p3, r0, r1, r2, r3 = pieces[k]
        return J + self.extra_inertia, dJ, ((p0 * x + p1) * x + p2) * x + p3, ((r0 * x + r1) * x + r2) * x + r3

    @property
    def _scalar_table(self):
        """The table as Python lists (nodes, (J, J′) per node, the forces' spline knots and pieces), on first use."""
        form = self.__dict__.get("_table_lists")
        if form is None:
            t = self.fit.series
            sp = t.forces
            c = sp.c
            pieces = [tuple(float(v) for v in (c[0, k, 0], c[1, k, 0], c[2, k, 0], c[3, k, 0],
                                               c[0, k, 1], c[1, k, 1], c[2, k, 1], c[3, k, 1])) for k in range(c.shape[1])]
            form = ([float(x) for x in t.nodes], [(float(a), float(b)) for a, b in t.values[:, :2]],
                    [float(x) for x in sp.x], pieces, bool(t.periodic), float(t.nodes[0]))
            object.__setattr__(self, "_table_lists", form)
        return form

    @property
    def _scalar_form(self):
        """(k (K + 1,), columns (K + 1, 4)): the harmonics of J*, dJ*/dq, Q_applied, Q_opposing, kept on first use."""
        form = self.__dict__.get("_form")
        if form is None:
            c = self.fit.series.coefficients
            k = np.arange(c.shape[0])
            form = (k, np.ascontiguousarray(np.stack([c[:, 0], 1j * k * c[:, 0], c[:, 2], c[:, 3]], axis=1)))
            object.__setattr__(self, "_form", form)
        return form

    def motor(self, qdot):
        """(Q_motor, motor effort, motor speed) at the input speeds ``qdot`` (...); zeros without a motor."""
        if self.drive is None:
            z = np.zeros_like(np.asarray(qdot, dtype=float))
            return z, z, z
        return self.drive.generalised(qdot)

    def acceleration(self, q, qdot):
        """q̈ (...) of the equation at (q, q̇) without friction."""
        J, dJ, Qa, Qo = self.terms(q)
        if self.drive is None:
            Qm = 0.0
        elif np.ndim(qdot) == 0 and self.drive.motor.efficiency == 1.0:
            Qm = self.drive.ratio * float(self.drive.effort(self.drive.ratio * float(qdot)))
        else:
            Qm = self.drive.generalised(qdot)[0]
        return (Qm + Qa + np.sign(qdot) * Qo - 0.5 * dJ * qdot * qdot) / J

    def potential(self, q):
        """V(q) = −∫ Q_applied dq from the start of the grid, or None when Q_applied has a mean over a turn (the
        loads then do net work each turn and have no potential)."""
        if self.mode == "exact":
            return None
        s = self.fit.series
        if self.periodic:
            mean = float(s.mean()[2])
            if abs(mean) > 1e-12 * max(float(self.fit.scale[2]), 1e-300):
                return None
        if isinstance(s, PeriodicSeries):
            return -s.antiderivative(q)[..., 2]
        return -s.integral(q, 2)

    def contains(self, q) -> bool:
        lo = -math.inf if self.lower is None else self.lower.q
        hi = math.inf if self.upper is None else self.upper.q
        return lo <= q <= hi


def _scales(plan):
    """The scales of the fit's errors: J* and dJ*/dq (per radian, or per length scale of a linear input) relative
    to the largest J*; Q_applied and Q_opposing relative to the largest of the two."""
    unit = 1.0 if plan.input_kinds[0] == "rotary" else plan.length_scale

    def scales(mag):
        J, Q = mag[0], max(mag[2], mag[3])
        return np.array([J, J / unit, Q, Q])
    return scales


def _good(t: np.ndarray, cap: float | None = None) -> np.ndarray:
    """(...) bool: the samples where the equation holds (finite terms, J* > 0, J* below ``cap``)."""
    with np.errstate(invalid="ignore"):
        ok = np.all(np.isfinite(t), axis=-1) & (t[..., 0] > 0)
        if cap is not None:
            ok &= t[..., 0] <= cap
    return ok


def _reason(eq_exact, q: float) -> str:
    """Why the equation fails at q: the mechanism does not assemble, is singular (a dead centre), or J* is 0."""
    from ..engine import solve
    st = solve(eq_exact.plan, eq_exact.params, np.array([[q]]), order=1, backend="numpy")
    if not bool(np.asarray(st.valid).reshape(-1)[0]):
        return "cannot be assembled"
    t = eq_exact.exact(np.array([q]))[0]
    if np.isfinite(t[0]) and t[0] <= 0:
        return "zero inertia"
    return "dead centre"


def _refine(exact, good_q: float, bad_q: float, cap) -> float:
    """The last input from ``good_q`` towards ``bad_q`` where the equation holds (bisection)."""
    for _ in range(BISECTIONS):
        mid = 0.5 * (good_q + bad_q)
        if _good(exact(np.array([mid])), cap)[0]:
            good_q = mid
        else:
            bad_q = mid
        if abs(bad_q - good_q) <= 1e-15 * max(1.0, abs(good_q)):
            break
    return good_q


def _run_around(ok: np.ndarray, i0: int, cyclic: bool) -> tuple[int, int]:
    """The first and last index of the run of True in ``ok`` that contains ``i0`` (indices may leave the array
    of a cyclic grid: unwrapped)."""
    n = ok.size
    lo = hi = i0
    while (lo - 1 >= 0 or cyclic) and ok[(lo - 1) % n] and hi - lo < n:
        lo -= 1
    while (hi + 1 < n or cyclic) and ok[(hi + 1) % n] and hi - lo < n:
        hi += 1
    return lo, hi


def build_equation(plan, params=None, *, drive: DriveTrain | None = None, q0: float = 0.0, mode: str = "series",
                   friction: bool = False, state_grid=None, tolerance: float = FIT_TOLERANCE) -> Equation:
    """The equation of ``plan`` at ``params`` (n_params,) for a run starting at the input ``q0``.

    ``state_grid``: (q (n,), State (n,)) a solved uniform grid of one turn from 0 (a solved cycle's), used as the
    first grid of the periodic fit. ``mode`` 'series' fits the terms (error measured and reported in ``fit``),
    'exact' evaluates them on demand. SpecError when the run cannot start (q0 outside the domain)."""
    check_one_input(plan)
    if mode not in ("series", "exact"):
        raise SpecError([("mode", f"must be 'series' or 'exact': {mode!r}")])
    params = plan.defaults if params is None else np.asarray(params, dtype=float)
    rotary = plan.input_kinds[0] == "rotary"
    probe = Equation(plan, params, rotary, False, None, None, drive, "exact", friction=friction)
    exact = probe.exact
    notes = []
    if rotary:
        if state_grid is not None:
            qg, st = state_grid
            first = reduced_terms(plan, params, qg, state=st).stacked()
        else:
            qg = TWO_PI * np.arange(GRID_START) / GRID_START
            first = exact(qg)
        ok = _good(first)
        if ok.all():
            if mode == "exact":
                return Equation(plan, params, True, True, None, None, drive, "exact", None, friction)
            fit = fit_periodic(exact, float(qg[0]), qg.size, tol=tolerance, n_max=GRID_MAX, first=first,
                               scales=_scales(plan))
            if not np.all(fit.error <= tolerance):
                fit = fit_table(exact, float(qg[0]), TWO_PI, TABLE_TURN, periodic=True, scales=_scales(plan))
                notes.append(f"the terms do not converge as a Fourier series on {GRID_MAX} inputs (a load against "
                             f"velocity or a load law has kinks; a gear law is a spline): tabulated on {TABLE_TURN} "
                             f"inputs of the turn")
            return Equation(plan, params, True, True, None, None, drive, mode, fit, friction, tuple(notes))
        i0 = int(np.argmin(np.abs(((qg - q0 + math.pi) % TWO_PI) - math.pi)))
        base = q0 - ((q0 - qg[i0] + math.pi) % TWO_PI - math.pi)          # qg[i0] unwrapped next to q0
        step = TWO_PI / qg.size
        values = first
        cyclic = True
    else:
        d = plan.mechanism.drivers[0]
        if d.range is not None:
            lo, hi = sorted(float(x) for x in d.range)
        else:
            lo, hi = q0 - 2.0 * plan.length_scale, q0 + 2.0 * plan.length_scale
        if not lo <= q0 <= hi:
            raise SpecError([("q0", f"the start {q0:g} m is outside the working stroke {lo:g}…{hi:g} m of "
                                    f"driver {d.name!r}")])
        qg = np.linspace(lo, hi, 1025)
        values = exact(qg)
        i0 = int(np.argmin(np.abs(qg - q0)))
        base, step, cyclic = float(qg[i0]), float(qg[1] - qg[0]), False
        ok = _good(values)
        if ok.all():
            lower, upper = Limit(lo, lo, "end of stroke"), Limit(hi, hi, "end of stroke")
            return _interval(plan, params, drive, mode, friction, exact, lower, upper, tolerance, notes)
    ok = _good(values)
    if not ok[i0]:
        why = _reason(probe, float(q0))
        raise SpecError([("q0", f"the run cannot start at input {q0:.6g}: {why} there")])
    cap = JSTAR_GROWTH * float(np.median(values[ok, 0]))
    ok_cap = _good(values, cap)
    a, b = _run_around(ok_cap if ok_cap[i0] else ok, i0, cyclic)
    a_any, b_any = _run_around(ok, i0, cyclic)
    n = qg.size
    ends = []
    for idx, idx_any, direction in ((a, a_any, -1), (b, b_any, +1)):
        good_q = base + (idx - i0) * step
        if not cyclic and not 0 <= idx + direction < n:
            ends.append(Limit(good_q, good_q, "end of stroke"))
            continue
        stop = _refine(exact, good_q, good_q + direction * step, cap)
        last_any = base + (idx_any - i0) * step
        if not cyclic and not 0 <= idx_any + direction < n:
            ends.append(Limit(stop, last_any, f"J* grows beyond {JSTAR_GROWTH:g} times its median"))
            continue
        at = _refine(exact, max(last_any, stop) if direction > 0 else min(last_any, stop),
                     last_any + direction * step, None)
        ends.append(Limit(stop, at, _reason(probe, at + direction * 1e-9 * step)))
    lower, upper = ends
    if any(e.reason == "zero inertia" for e in ends):
        notes.append("J* vanishes at an end of the domain: give the moving links masses or the motor an inertia")
    return _interval(plan, params, drive, mode, friction, exact, lower, upper, tolerance, notes)


def _interval(plan, params, drive, mode, friction, exact, lower, upper, tolerance, notes) -> Equation:
    rotary = plan.input_kinds[0] == "rotary"
    if mode == "exact":
        return Equation(plan, params, rotary, False, lower, upper, drive, "exact", None, friction, tuple(notes))
    fit = fit_table(exact, lower.q, upper.q - lower.q, TABLE_INTERVAL, periodic=False, scales=_scales(plan))
    return Equation(plan, params, rotary, False, lower, upper, drive, mode, fit, friction, tuple(notes))


__all__ = ["Equation", "FIT_TOLERANCE", "JSTAR_GROWTH", "Limit", "build_equation"]
