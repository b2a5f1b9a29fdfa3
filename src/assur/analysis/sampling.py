"""Sampling a mechanism: one input turn solved once and shared (:class:`Cycle`), the runs of inputs that
figures and tables show (:func:`sweep_inputs`), and roots on samples.

:data:`CYCLE_STEPS` is the one documented number of samples of a turn: ``assur analyze``, ``assur report``,
``assur plot`` and the traced path of ``assur animate`` sample one turn at it unless told otherwise, and
one :class:`Cycle` carries that solve to every analysis, figure and table of a command.
"""
from __future__ import annotations

import math

import numpy as np

from ..engine import solve
from ..engine.options import CYCLE_STEPS as _CYCLE_STEPS
from ..engine.plan import require_plan
from ..errors import SpecError, float_array
from ..tolerances import DEFAULT as TOL

TWO_PI = 2.0 * math.pi

#: Samples of one input turn shared by the analysis, the report, the figures and the animation's path.
CYCLE_STEPS = _CYCLE_STEPS


class Cycle:
    """One solved run of a plan at fixed parameters: the base of :class:`~assur.analysis.study.Study`.

    plan: a compiled plan; params: (n_params,) (default the plan's defaults); steps: samples of the run;
    ranges: one (start, stop) pair per input (SI) instead of the natural cycle. The run (:func:`sweep_inputs`) is
    one turn of a crank (``linspace(0, 2π, steps, endpoint=False)``), a linear driver's working stroke (endpoints
    included) or the ranges; its State is solved once, on first use, with order 2 and kept (:attr:`state`), so the
    analyses, figures and tables of one command share one solve. :meth:`state_at` solves any other inputs of the
    moving input (the refinements of roots and edges); :meth:`frames` gives positions for animations and tables,
    taken from the run where they fall on its samples.
    """

    def __init__(self, plan, params=None, steps: int = CYCLE_STEPS, *, ranges=None):
        require_plan(plan)
        if isinstance(steps, bool) or not isinstance(steps, (int, np.integer)):
            raise SpecError([("steps", f"must be a whole number of samples: {steps!r:.40}")])
        steps = int(steps)
        if steps < 2:
            raise SpecError([("steps", f"must be at least 2 samples: {steps}")])
        p = plan.defaults if params is None else float_array(params, "params", "numbers (the design parameters)")
        if p.shape != (plan.n_params,):
            raise SpecError([("params", f"must be one design of {plan.n_params} parameters: shape {p.shape}")])
        self.plan = plan
        self.params = np.array(p, dtype=float)
        self.params.setflags(write=False)
        self.steps = steps
        self.ranges = None if ranges is None else tuple(tuple(map(float, r)) for r in ranges)
        self.order = 2
        self._run = None
        self._state = None

    @classmethod
    def of(cls, source, params=None, steps: int = CYCLE_STEPS, *, ranges=None):
        """``source`` itself when it is an instance of this class (its own parameters and run), else a new one of
        the plan ``source``."""
        return source if isinstance(source, cls) else cls(source, params, steps, ranges=ranges)

    @classmethod
    def from_state(cls, state, params=None):
        """The run of a State already solved (order 2) over the uniform grid of one turn of a one-input plan:
        ``state.inputs`` must be ``linspace(0, 2π, n, endpoint=False)`` (n, 1). Nothing is solved again."""
        q = np.asarray(state.inputs, dtype=float)
        if q.ndim != 2 or q.shape[1] != 1 or not np.array_equal(
                q[:, 0], np.linspace(0.0, TWO_PI, len(q), endpoint=False)):
            raise SpecError([("state", "must be solved at the inputs linspace(0, 2π, n, endpoint=False), "
                                       f"shape (n, 1): {q.shape}")])
        if state.d2pos_dq2 is None:
            raise SpecError([("state", "must be solved with order = 2")])
        out = cls(state.plan, params, len(q))
        out._run, out._state = (q, 0, True), state
        return out

    # -- the run --------------------------------------------------------------------------------------
    def _sweep(self):
        if self._run is None:
            self._run = sweep_inputs(self.plan, self.steps, self.ranges)
        return self._run

    @property
    def inputs(self) -> np.ndarray:
        """(n, n_inputs) the run's inputs (SI)."""
        return self._sweep()[0]

    @property
    def moving(self) -> int:
        """The index of the input that moves over the run."""
        return self._sweep()[1]

    @property
    def cyclic(self) -> bool:
        """Whether the run is one full turn of a crank (endpoint excluded)."""
        return self._sweep()[2]

    @property
    def turn(self) -> bool:
        """Whether the run is one turn of the plan's only input, a crank: the cycle of the cycle analyses."""
        p = self.plan
        return p.n_inputs == 1 and p.input_kinds[0] == "rotary" and self.ranges is None

    @property
    def q(self) -> np.ndarray:
        """(n,) the moving input over the run (rad or m)."""
        return self.inputs[:, self.moving]

    @property
    def state(self):
        """The run's State (n,), solved once with order 2."""
        if self._state is None:
            self._state = solve(self.plan, self.params, self.inputs, order=self.order)
        return self._state

    def grid(self):
        """(q (n,), State (n,)): the moving input over the run and the run's State."""
        return self.q, self.state

    def state_at(self, q, order: int | None = None):
        """The State at inputs ``q (...)`` of the moving input (any others held as in the run), solved with
        ``order`` (default 2)."""
        q = np.asarray(q, dtype=float)
        if self.plan.n_inputs == 1:
            inputs = q[..., None]
        else:
            inputs = np.broadcast_to(self.inputs[0], q.shape + (self.plan.n_inputs,)).copy()
            inputs[..., self.moving] = q
        return solve(self.plan, self.params, inputs, order=self.order if order is None else order)

    def frames(self, n: int):
        """(inputs (n, n_inputs), State (n,)) of ``n`` positions over the run (an animation, a table): every
        (steps/n)-th sample of the run when n divides the samples of a turn (nothing solved), else the run sampled
        afresh at ``n`` inputs (one solve)."""
        n = int(n)
        if n < 1:
            raise SpecError([("frames", f"must be a positive number of positions: {n}")])
        if n == self.steps:
            return self.inputs, self.state
        if self.cyclic and self.steps % n == 0:
            idx = np.arange(0, self.steps, self.steps // n)
            return self.inputs[idx], self.state.take(idx)
        inputs, _, _ = sweep_inputs(self.plan, n, self.ranges)
        return inputs, solve(self.plan, self.params, inputs, order=self.order)


def sweep_inputs(plan, steps: int, ranges=None):
    """Input samples ``(steps, n_inputs)`` (SI) for a plan, the index of the input on the x axis and
    whether the run is one full turn.

    Without ``ranges``: one turn of the crank (q from 0 to 2π, endpoint excluded), or a linear driver's
    working stroke (its ``range``, else the span of its table ``law``; endpoints included); with several
    inputs, the one crank whose speed is not zero turns and the inputs of speed 0 (settings) are
    held at their sketch values. ``ranges``: one ``(start, stop)`` pair per input (SI: rad or m);
    each input runs linearly from start to stop (endpoints included). Raises SpecError when the
    run is not determined (a linear input without a range, several moving inputs)."""
    n = plan.n_inputs
    steps = int(steps)
    if steps < 1:
        raise SpecError([("steps", f"must be a positive number of samples: {steps}")])
    if n == 0:
        raise SpecError([("drivers", "the mechanism has no driver; nothing to sweep")])
    if ranges is not None:
        ranges = [tuple(map(float, r)) for r in ranges]
        if len(ranges) != n:
            raise SpecError([("--range", f"give one range per input ({n}: {', '.join(plan.input_names)}), "
                                         f"in driver order: {len(ranges)} given")])
        q = np.stack([np.linspace(a, b, steps) for a, b in ranges], axis=-1)
        moving = next((k for k, (a, b) in enumerate(ranges) if a != b), 0)
        return q, moving, False
    if n == 1:
        d0 = plan.mechanism.drivers[0]
        stroke = getattr(d0, "range", None) or (getattr(d0, "law", None) and (min(d0.law.values), max(d0.law.values)))
        if plan.input_kinds[0] != "rotary" and stroke is not None:   # the driver's working stroke
            return np.linspace(stroke[0], stroke[1], steps)[:, None], 0, False
        if plan.input_kinds[0] != "rotary":
            raise SpecError([("--range", f"the linear input '{plan.input_names[0]}' has no natural cycle and its "
                                         f"stroke is not known: give --range START STOP "
                                         f"(in {plan.mechanism.units.length})")])
        q = np.linspace(0.0, TWO_PI, steps, endpoint=False)[:, None]
        return q, 0, True
    moving = [k for k in range(n) if plan.speeds[k] != 0]
    if len(moving) == 1 and plan.input_kinds[moving[0]] == "rotary":
        k = moving[0]
        q = np.tile(np.asarray(plan.sketch_inputs, dtype=float), (steps, 1))
        q[:, k] = np.linspace(0.0, TWO_PI, steps, endpoint=False)
        return q, k, True
    raise SpecError([("--range", f"the mechanism has {n} inputs ({', '.join(plan.input_names)}) and one turn of "
                                 f"them is not determined: give --range START STOP once per input, in driver order "
                                 f"(angles in {plan.mechanism.units.angle}, lengths in {plan.mechanism.units.length})")])


def tracked_point(plan) -> str:
    """The point a table or figure follows: the foot of a walking leg, else the last point of the file."""
    g = plan.mechanism.gait
    return g.foot if g is not None else plan.point_names[-1]


def sign_changes(q, values):
    """Indices i where values (n,) changes sign between q[i] and q[i+1] (cyclic)."""
    v = np.asarray(values)
    nxt = np.roll(v, -1)
    return np.nonzero(np.isfinite(v) & np.isfinite(nxt) & (np.sign(v) != np.sign(nxt)) & (v != 0))[0]


def root_between(f, a, b):
    """A root of the scalar function ``f`` on [a, b] (rad) to :attr:`~assur.tolerances.Tolerances.root_angle`
    (Brent's method), or the midpoint when f has no sign change there or is not defined inside (NaN)."""
    fa, fb = f(a), f(b)
    if not (np.isfinite(fa) and np.isfinite(fb)) or fa * fb > 0:
        return 0.5 * (a + b)
    from scipy.optimize import brentq   # imported on first use: scipy.optimize takes ~1 s to import
    try:
        return brentq(f, a, b, xtol=TOL.root_angle)
    except ValueError:                  # f is NaN somewhere inside (the mechanism not placed there)
        return 0.5 * (a + b)


def roots_between(f, a, b, xtol: float = 1e-14, rtol: float = 1e-14, max_iterations: int = 200):
    """Roots of a vectorised function on many brackets at once: ``f(x (k,)) -> (k,)`` is called once per
    iteration on every unfinished bracket (one batched solve instead of one per root). a, b: (k,) bracket ends
    with f(a)·f(b) < 0. The Illinois variant of false position, with a bisection step whenever it stalls, to
    |b − a| ≤ xtol + rtol·|x| (the tolerances of scipy's brentq). Returns (k,) roots."""
    a, b = np.array(a, dtype=float), np.array(b, dtype=float)
    k = a.size
    if k == 0:
        return a
    fa, fb = np.asarray(f(a), dtype=float), np.asarray(f(b), dtype=float)
    side = np.zeros(k, dtype=np.int8)                     # which end was kept last (-1: a, +1: b)
    done = (fa == 0) | (fb == 0)
    root = np.where(fa == 0, a, np.where(fb == 0, b, 0.5 * (a + b)))
    for _ in range(max_iterations):
        live = ~done
        if not live.any():
            break
        A, B, FA, FB = a[live], b[live], fa[live], fb[live]
        c = (A * FB - B * FA) / (FB - FA)
        width = np.abs(B - A)
        bad = ~np.isfinite(c) | (c <= np.minimum(A, B)) | (c >= np.maximum(A, B))
        c = np.where(bad, 0.5 * (A + B), c)
        fc = np.asarray(f(c), dtype=float)
        ia = np.flatnonzero(live)
        same_as_b = np.sign(fc) == np.sign(FB)
        # the new point replaces the end of the same sign; the kept end's value is halved when it is kept twice
        new_a = np.where(same_as_b, A, c)
        new_fa = np.where(same_as_b, FA, fc)
        new_b = np.where(same_as_b, c, B)
        new_fb = np.where(same_as_b, fc, FB)
        kept = np.where(same_as_b, -1, 1)
        twice = kept == side[ia]
        new_fa = np.where(twice & (kept == -1), 0.5 * new_fa, new_fa)
        new_fb = np.where(twice & (kept == 1), 0.5 * new_fb, new_fb)
        a[ia], fa[ia], b[ia], fb[ia], side[ia] = new_a, new_fa, new_b, new_fb, kept
        finished = (fc == 0) | (np.abs(new_b - new_a) <= xtol + rtol * np.abs(c)) | (width <= xtol + rtol * np.abs(c))
        root[ia] = c
        done[ia[finished]] = True
    return root
