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
from ..errors import SpecError, StructureError
from ..tolerances import DEFAULT as TOL

TWO_PI = 2.0 * math.pi

#: Samples of one input turn shared by the analysis, the report, the figures and the animation's path.
CYCLE_STEPS = 720


class Cycle:
    """A one-input plan over turns of its input, at fixed parameters ``params`` (n_params,).

    ``grid()`` gives the uniform grid of ``steps`` inputs over one turn, q = linspace(0, 2π, steps,
    endpoint=False) (steps,), and its State (steps,) solved with ``order``: solved on first use and kept,
    so the analyses, figures and tables of one command share one solve. ``state(q)`` solves any other
    inputs ``q (...)`` (refinements: roots, bisections), a State of shape q.shape.
    """

    def __init__(self, plan, params=None, order: int = 2, steps: int = CYCLE_STEPS):
        if plan.n_inputs != 1:
            raise StructureError(f"this analysis needs one input; the mechanism has {plan.n_inputs} "
                                 f"({', '.join(plan.input_names)})")
        self.plan = plan
        self.params = plan.defaults if params is None else np.asarray(params, dtype=float)
        self.order = order
        self.steps = int(steps)
        self._grid = None

    @classmethod
    def of(cls, source, params=None, steps: int = CYCLE_STEPS, order: int = 2) -> "Cycle":
        """``source`` itself when it is a Cycle (its parameters, grid and order; the other arguments are not
        used), else a new Cycle of the plan ``source``."""
        return source if isinstance(source, Cycle) else cls(source, params, order, steps)

    def state(self, q, order=None):
        """The State at inputs ``q (...)`` (rad), solved with ``order`` (default: the cycle's)."""
        return solve(self.plan, self.params, np.asarray(q, dtype=float)[..., None],
                     order=self.order if order is None else order)

    def grid(self, n: int | None = None, start: float = 0.0, stop: float = TWO_PI, endpoint: bool = False):
        """(q (n,), State (n,)) at ``n`` inputs from ``start`` to ``stop``; the default, the uniform grid of
        ``steps`` inputs over one turn, is solved once and kept."""
        n = self.steps if n is None else int(n)
        if (n, start, stop, endpoint) != (self.steps, 0.0, TWO_PI, False):
            q = np.linspace(start, stop, n, endpoint=endpoint)
            return q, self.state(q)
        if self._grid is None:
            q = np.linspace(0.0, TWO_PI, n, endpoint=False)
            self._grid = (q, self.state(q))
        return self._grid


def cycle_source(source, params=None, steps: int = CYCLE_STEPS):
    """(plan, params, steps) of an analysis of ``source``: a Cycle's own, else the plan ``source`` with the
    given ``params`` and ``steps``."""
    if isinstance(source, Cycle):
        return source.plan, source.params, source.steps
    return source, params, steps


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
    (Brent's method), or the midpoint when f has no sign change there."""
    fa, fb = f(a), f(b)
    if not (np.isfinite(fa) and np.isfinite(fb)) or fa * fb > 0:
        return 0.5 * (a + b)
    from scipy.optimize import brentq   # imported on first use: scipy.optimize takes ~1 s to import
    return brentq(f, a, b, xtol=TOL.root_angle)
