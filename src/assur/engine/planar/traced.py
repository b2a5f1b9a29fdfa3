"""A planar plan's kinematics traced for the compiled kernels: the numpy backend's own step executors, run once on
symbols.

:func:`trace_plan` runs the executors of :mod:`.steps` — the closed forms of :mod:`assur.kernels.planar` on the
jets of :mod:`assur.kernels.jet`, the same code the numpy backend runs on arrays — on one design and one input made
of tracer symbols (:mod:`assur.kernels.trace`): the design's parameters are the loads ``P[d, k]``, the input's
cosine and sine are ``c`` and ``s``, the radicand tolerance is ``tol``. The result is every point's position and
every body's orientation as jets of traced values, the validity flag and the groups' margins; the kernel generator
(:mod:`assur.kernels.codegen`) wraps them in loops. So a formula exists once: a change to a closed form changes the
numpy backend and every compiled kernel alike.

The traced plans (:func:`covers`): one rotary input, frame, crank and the RRR, RRP and RPR dyads without a driven
actuator (walking legs, four-bars, slider-cranks, slotted levers, passive cylinders), and with ``newton=True`` also
Newton-solved groups (triads and larger groups of revolute and passive prismatic pairs: :mod:`.traced_newton`). Others
(several inputs, gears, PRP and PPR dyads, driven actuators) are solved by the numpy backend.
"""
from __future__ import annotations

from dataclasses import dataclass
from types import SimpleNamespace

import numpy as np

from ...kernels.jet import Jet
from ...kernels.trace import DESIGN, SAMPLE, C, Tracer, isfinite, where
from .steps import EXECUTORS, Context
from .traced_newton import trace_group

#: the step kinds a traced kernel covers
TRACED_KINDS = ("frame", "crank", "RRR", "RRP", "RPR")


def covers(plan, newton: bool = False) -> bool:
    """True when the plan's steps can be traced into a compiled kernel (see the module's docstring); with ``newton``
    Newton-solved groups are traced too."""
    if plan.n_inputs != 1 or plan.input_kinds[0] != "rotary" or getattr(plan, "gear_slots", ()):
        return False
    for st in plan.steps:
        if st.kind == "newton" and newton:       # one rotary input: no driven actuator's length equation
            continue
        if st.kind not in TRACED_KINDS:
            return False
        if st.kind in ("RRR", "RRP") and st.side_a.actuator is not None:
            return False
        if st.kind == "RRR" and st.side_b.actuator is not None:
            return False
    return True


class _Params:
    """One design's parameter row as traced loads (``P[d, k]``; ``row`` names another array), indexed like
    ``params (..., n_params)``."""

    def __init__(self, tracer: Tracer, n: int, row: str = "P[d, {}]"):
        self.tracer, self.shape, self.row = tracer, (n,), row

    def __getitem__(self, key):
        k = key[-1] if isinstance(key, tuple) else key
        return self.tracer.load(self.row.format(int(k)), DESIGN)


class _TracedPlan:
    """The plan as the traced executors read it: its records and tables, with its length scale the kernel argument
    ``ls`` (a number of the design's sketch, so never a constant of a kernel's source)."""

    def __init__(self, plan, tracer: Tracer):
        self._plan = plan
        self.length_scale = tracer.free("ls")

    def __getattr__(self, name):
        return getattr(self._plan, name)


class TracedContext(Context):
    """A :class:`~.steps.Context` on symbols: one design (``P[d, k]``), one input sample (its cosine ``c`` and sine
    ``s``, with dq = 1, d²q = 0), the tolerance ``tol``; constants are jets with zero derivatives that cost
    nothing, and the closed forms' margins are collected. ``row``: the parameters' load (default ``P[d, k]``); the
    plan's length scale is the free name ``ls``;
    ``groups``: the Newton-solved groups traced so far (:class:`.traced_newton.TracedGroup`)."""

    def __init__(self, plan, tracer: Tracer, order: int, row: str = "P[d, {}]"):
        self.tracer = tracer
        tol = SimpleNamespace(radicand=tracer.free("tol"))
        super().__init__(_TracedPlan(plan, tracer), _Params(tracer, plan.n_params, row), [None] * plan.n_inputs, order,
                         tol)
        self.margins = []
        self.groups, self.group_steps = [], []

    def const(self, v):
        return Jet(v, 0.0 if self.order >= 1 else None, 0.0 if self.order >= 2 else None)

    def turn(self, k: int, sense: int, factor) -> Jet:
        """e = exp(i·sense·q)·factor from the input's cosine and sine, and its derivatives by q: i·sense·e and −e
        (a swap and signs: what numpy's jet gives, exactly, at the cost of one complex product)."""
        e = C(self.tracer.free("c", SAMPLE), self.tracer.free("s", SAMPLE) * float(sense)) * factor
        d = C(-e.imag * float(sense), e.real * float(sense))
        return Jet(e, d if self.order >= 1 else None, -e if self.order >= 2 else None)


@dataclass
class KinematicsTrace:
    """A plan traced on symbols: ``pos`` (point name → complex Jet), ``orient`` (per body, its e = exp(iθ) as a
    complex Jet), ``valid`` (a traced boolean: every group assembled), ``margins`` (the closed forms' margins, in
    solve order: each ≥ 0 where its group assembles). The values of a sample that does not assemble are the
    toggle's continuation, meaningless: the kernels mask them with ``valid``. ``groups``: the Newton-solved groups'
    pieces (:class:`.traced_newton.TracedGroup`), in solve order."""
    tracer: Tracer
    pos: dict
    orient: list
    valid: object
    margins: list
    groups: list = ()

    def deficit(self):
        """The groups' summed shortfall past their toggles, Σ max(−margin, 0): a group past its toggle continues at
        it (:func:`assur.kernels.planar._tolerant_radicand`), so the groups it feeds add their own shortfall; a NaN
        margin (a design whose geometry is not physical) adds nothing."""
        total = 0.0
        for m in self.margins:
            total = total + where(m < 0.0, -m, 0.0)
        return total

    def finite(self, *values):
        """``valid`` and every value given finite (a traced boolean)."""
        ok = self.valid
        for v in values:
            ok = ok & isfinite(v)
        return ok


def trace_plan(plan, order: int, row: str = "P[d, {}]", select: str | None = None) -> KinematicsTrace:
    """Run the plan's step executors on symbols (derivatives up to ``order`` by the input; the parameters loaded as
    ``row``; element-wise choices written as ``select``: :class:`~assur.kernels.trace.Tracer`) and return the traced
    state. The plan must be covered (:func:`covers`)."""
    tracer = Tracer(select=select)
    ctx = TracedContext(plan, tracer, order, row)
    with np.errstate(all="ignore"):
        for st in plan.steps:
            (trace_group if st.kind == "newton" else EXECUTORS[st.kind])(ctx, st)
    return KinematicsTrace(tracer, ctx.pos, [ctx.pose[b][1] for b in range(len(plan.body_names))], ctx.valid,
                           ctx.margins, ctx.groups)
