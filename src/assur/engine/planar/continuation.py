"""Certified continuation of Newton-solved groups: every sample follows the sketch's assembly without a jump.

A group without a closed form has several assemblies at one input; which one Newton's method reaches depends on
where it starts. The solver therefore never starts far from where it is going: each *row* (a sample, or a design in
a sweep) walks from where it is known — the sketch, at the file's design and the sketch's inputs — to its target
along the straight line of inputs and parameters, in steps it controls (:class:`Walker`):

1. a predictor: the last step's secant (the first step: the last position);
2. a corrector: Newton's method on the loop equations (:func:`~assur.engine.planar.newton_group.solve_group`);
3. the step's certificate: the corrector converged; the dimensionless Jacobian determinant kept the sketch's sign
   and stayed clear of zero (``tolerances.newton_certify``); the correction moved no point of the group by more
   than ``tolerances.continuation_correction`` of the length scale; and, for a triad, the corrected assembly is
   the one of its at most six assemblies (:mod:`assur.kernels.triad`) nearest the prediction, with every other
   at least twice as far from the prediction.

A step that fails its certificate is retried at a quarter of its length, one that passes lets the next be twice as
long (never more than ``stage_angle`` of crank, ``stage_length`` of stroke, or a ``stages_for_new_design``-th of a
design change). A row whose step falls below ``min_step`` cannot be continued certifiably (a toggle: the input
cannot go further on this assembly; a singular position) and is unbuildable there, never possibly on another
assembly.

:func:`execute` continues every sample on its own from the sketch (the short way round; samples a crank cannot
reach that way, past a locked range, the long way), so a sample's result does not depend on the batch it is in or
on the step of a grid. A sample both ways reach must be the same assembly both ways: where the sketch's assembly
does not close after one turn of the crank but spans more than one (it locks at a toggle after more than a turn one
way or the other), the inputs both ways reach have two assemblies on it, one each way, and such a sample is
*ambiguous*: unbuildable, never one of them silently (else neighbouring samples, one reached each way, would jump
between them). A crank whose assembly closes (:func:`closes`: the walks half a turn each way meet on one assembly)
has no ambiguous sample, and its samples are not walked the long way. The samples of the file's design start at
the last whole step of crank before them (:class:`WholeSteps`: the design walked once from the sketch through
q_s ± k·``stage_angle``, kept with the plan), which depends on the plan, the tolerances and the way round only. After the last step each sample's group is
checked against its other assemblies (:mod:`assur.engine.planar.group_assemblies`): a sample closer to another
assembly than ``tolerances.assembly_separation`` of the length scale is unbuildable (at a singular position).
"""
from __future__ import annotations

import copy
import threading
import weakref
from dataclasses import replace

import numpy as np

from ...kernels.jet import Jet
from ...kernels.triad import triad_alone, triad_polynomial, triad_roots
from ...tolerances import DEFAULT
from .group_assemblies import (assembly_distances, before_group, group_assemblies, group_method, group_points,
                               take_rows, triad_layout, triad_legs)
from .newton_group import _residual_and_jacobian, alone_within, certificate_det
from .steps import Context, _run

#: the factors a step's length changes by after a failed or passed certificate
SHRINK, GROW = 0.25, 2.0
#: Newton iterations of a step's corrector
CORRECTOR_ITERATIONS = 8
#: the dimensionless determinant below which another group than a triad is checked against its other assemblies
SEPARATION_GATE = 1e-2
#: steps one row may try on one walk (a row that needs more cannot be certified: unbuildable)
MAX_STEPS = 1000


def newton_keys(steps, method):
    """The Newton-solved steps of a step list (with ``method='newton'`` every group)."""
    return [st for st in steps if st.kind == "newton" or (method == "newton" and st.kind not in ("frame", "crank",
                                                                                                   "gear"))]


class Walker:
    """Rows walked in certified steps from where they are to targets (module docstring).

    ``params (R, n_params)``, ``q (R, n_inputs)`` where the rows are now; ``x {step id: (R, 3k)}`` their groups'
    poses there and ``sign {step id: (R,)}`` the branch invariant to keep; ``alive (R,)``."""

    def __init__(self, plan, steps, tol, method, params, q, x, sign):
        self.plan, self.steps, self.tol, self.method = plan, steps, tol, method
        #: a step's corrector: a few Newton iterations (a prediction that needs more is too far: a shorter step)
        self.step_tol = replace(tol, newton_iterations=min(tol.newton_iterations, CORRECTOR_ITERATIONS))
        self.newton = newton_keys(steps, method)
        self.params, self.q = np.array(params, dtype=float), np.array(q, dtype=float)
        self.x = {k: np.array(v, dtype=float) for k, v in x.items()}
        self.sign = {k: np.array(v, dtype=float) for k, v in sign.items()}
        self.alive = np.all([np.all(np.isfinite(v), axis=-1) for v in self.x.values()], axis=0) \
            if self.x else np.ones(len(self.q), dtype=bool)

    @classmethod
    def at_sketch(cls, plan, steps, tol, method, rows: int):
        """``rows`` rows at the sketch: the file's design at the sketch's inputs, its groups solved from the sketch."""
        warm: dict = {}
        params = plan.defaults[None, :]
        q = [Jet.const(np.asarray([v]), 0) for v in plan.sketch_inputs]
        _run(plan, steps, params, q, 0, tol, method, warm)
        keys = [id(st) for st in newton_keys(steps, method)]
        x = {k: np.repeat(warm[k].reshape(1, -1), rows, axis=0) for k in keys}
        sign = {k: np.repeat(np.reshape(warm[(k, "det_sign")], (1,)), rows) for k in keys}
        return cls(plan, steps, tol, method, np.repeat(params, rows, axis=0),
                   np.repeat(plan.sketch_inputs[None, :], rows, axis=0), x, sign)

    def _h_max(self, dq, dp):
        """(R,) the longest step in t ∈ [0, 1] along dq (R, n_inputs), dp (R, n_params)."""
        tol, plan = self.tol, self.plan
        h = np.ones(len(dq))
        with np.errstate(divide="ignore"):
            for k, kind in enumerate(plan.input_kinds):
                stage = tol.stage_angle if kind == "rotary" else tol.stage_length * plan.length_scale
                h = np.minimum(h, stage / np.abs(dq[:, k]))
        moved = np.any(dp != 0, axis=-1)
        return np.where(moved, np.minimum(h, 1.0 / tol.stages_for_new_design), h)

    def _min_step(self, dq):
        """(R,) the shortest step in t: ``continuation_min_step`` of crank or of the length scale of stroke."""
        plan, tol = self.plan, self.tol
        span = np.zeros(len(dq))
        for k, kind in enumerate(plan.input_kinds):
            span = np.maximum(span, np.abs(dq[:, k]) / (1.0 if kind == "rotary" else plan.length_scale))
        with np.errstate(divide="ignore"):
            return np.where(span > 0, tol.continuation_min_step / span, 1e-12)

    def advance(self, params, q, rows=None, back=None):
        """Walk the rows ``rows`` (default all alive) to ``params (R, n_params)``, ``q (R, n_inputs)``
        (broadcastable); rows that cannot be certified die. Returns the alive mask (R,).

        ``back``: ``(x {step id: (R, 3k)}, q (R, n_inputs))``, a point each row passed before on the straight line
        to its target (its inputs NaN where none): the first step's secant goes through it (else the first
        prediction is the row's position)."""
        R = len(self.q)
        params = np.broadcast_to(np.asarray(params, dtype=float), (R, self.plan.n_params))
        q = np.broadcast_to(np.asarray(q, dtype=float), (R, self.plan.n_inputs))
        idx = np.flatnonzero(self.alive if rows is None else (self.alive & rows))
        if len(idx) == 0:
            return self.alive
        p0, q0 = self.params[idx], self.q[idx]
        dp, dq = params[idx] - p0, q[idx] - q0
        t = np.zeros(len(idx))
        h_max = self._h_max(dq, dp)
        h_min = self._min_step(dq)
        h = h_max.copy()
        x = {k: v[idx] for k, v in self.x.items()}
        last = {k: v.copy() for k, v in x.items()}           # the previous accepted point, for the secant
        t_last = np.full(len(idx), np.nan)
        if back is not None:
            bx, bq = back
            with np.errstate(all="ignore"):
                # where the row's target is along its first input: t of the point behind it on that line
                tb = (bq[idx, 0] - q0[:, 0]) / dq[:, 0]
            has = np.isfinite(tb) & (tb < 0.0)
            t_last[has] = tb[has]
            for k in last:
                last[k][has] = bx[k][idx[has]]
        todo = t < 1.0
        todo &= ~np.all(dq == 0, axis=-1) | np.any(dp != 0, axis=-1)
        dead = np.zeros(len(idx), dtype=bool)
        tries = np.zeros(len(idx), dtype=int)
        while True:
            act = np.flatnonzero(todo & ~dead)
            if len(act) == 0:
                break
            ta, ha = t[act], h[act]
            tn = np.minimum(ta + ha, 1.0)
            with np.errstate(all="ignore"):
                ratio = np.where(np.isfinite(t_last[act]), (tn - ta) / (ta - t_last[act]), 0.0)
            warm = {}
            pred = {}
            for k in x:
                pred[k] = x[k][act] + ratio[:, None] * (x[k][act] - last[k][act])
                warm[k] = pred[k].copy()
                warm[(k, "det_sign")] = self.sign[k][idx[act]]
            pa = p0[act] + tn[:, None] * dp[act]
            qa = q0[act] + tn[:, None] * dq[act]
            c = _run(self.plan, self.steps, pa, [Jet.const(qa[:, j], 0) for j in range(qa.shape[1])], 0, self.step_tol,
                     self.method, warm)
            ok = np.broadcast_to(np.asarray(c.valid, dtype=bool), (len(act),)).copy()
            for st in self.newton:
                k = id(st)
                # a body's angle is continued, never wrapped: θ within half a turn of its prediction
                warm[k][:, 2::3] = pred[k][:, 2::3] + np.remainder(warm[k][:, 2::3] - pred[k][:, 2::3] + np.pi,
                                                                   2 * np.pi) - np.pi
                ok &= np.all(np.isfinite(warm[k]), axis=-1)
                ok &= self._certify(c, st, pred[k], warm[k], len(act))

            good, bad = act[ok], act[~ok]
            for k in x:
                last[k][good] = x[k][good]
                x[k][good] = warm[k][ok]
            t_last[good] = t[good]
            t[good] = tn[ok]
            h[good] = np.minimum(h[good] * GROW, h_max[good])
            h[bad] *= SHRINK
            tries[act] += 1
            dead[bad[h[bad] < h_min[bad]]] = True
            dead[act[tries[act] > MAX_STEPS]] = True
            todo = t < 1.0
        for k in x:
            self.x[k][idx] = np.where(dead[:, None], np.nan, x[k])
        self.params[idx] = np.where(dead[:, None], self.params[idx], params[idx])
        self.q[idx] = np.where(dead[:, None], self.q[idx], q[idx])
        self.alive[idx[dead]] = False
        return self.alive

    def _certify(self, c, st, pred, x, n):
        """(n,) the step's certificate beyond convergence and the determinant (module docstring, 3)."""
        rows = np.arange(n)
        moved = np.max(np.abs(group_points(c, st, x, rows, n) - group_points(c, st, pred, rows, n)), axis=-1)
        ok = moved <= self.tol.continuation_correction * self.plan.length_scale
        if triad_layout(self.plan, st) is not None and np.any(ok):
            ok &= _nearest_triad_assembly(c, st, pred, x, n)
        return ok


def _triad_certificate_data(c, st, n):
    """A triad's data for its certificates at n samples of ``c``: ``(w, Q, ell, ti, joints)``, as
    :func:`.group_assemblies.triad_legs`, the ternary's index among the group's bodies, and a function giving the
    ternary's three joints (m, 3) of group poses (m, 3k) with their rows' ``w`` (m, 3)."""
    t, legs, w, Q, ell = triad_legs(c, st, n)
    ti = st.bodies.index(t)

    def joints(y, w):
        return (y[:, 3 * ti] + 1j * y[:, 3 * ti + 1])[:, None] + np.exp(1j * y[:, 3 * ti + 2])[:, None] * w

    return w, Q, ell, ti, joints


def _root_joints(w, Q, ell):
    """(m, 6, 3) the ternary's joints in every assembly of the triad's polynomial, NaN where it has fewer."""
    phi, p = triad_roots(w, Q, ell)                                              # phi, p: (m, 6)
    return p[..., None] + np.exp(1j * phi)[..., None] * w[:, None, :]


def _alone(w, Q, ell, theta):
    """(m,) a lower bound (m) on the distance from the ternary's orientation ``theta`` (m,) to every other assembly of
    the triad, from its polynomial's coefficients, no root found (:func:`assur.kernels.triad.triad_alone`)."""
    coeff, _ = triad_polynomial(w, Q, ell)
    return triad_alone(coeff, theta, w)


def _distances(roots, z):
    """(n, 6) the largest distance of a joint between each root and ``z (n, 3)``, inf where there is no root."""
    d = np.max(np.abs(roots - z[:, None, :]), axis=-1)
    return np.where(np.isfinite(d), d, np.inf)


def _nearest_triad_assembly(c, st, pred, x, n):
    """(n,) whether ``x`` is the triad's assembly nearest the prediction ``pred`` and every other is at least twice
    as far from the prediction (the roots of its polynomial, unpolished: good to far below the margin).

    Where the bound of :func:`_alone` puts every other assembly at least 3·d + 2·10⁻⁶·scale from x (d: x's distance
    from the prediction), that holds without finding a root: the assembly within 10⁻⁶·scale of x, if any, is x's own,
    at most d + 10⁻⁶·scale from the prediction, and every other is at least 2·(d + 10⁻⁶·scale) from it. The roots
    decide the other samples."""
    w, Q, ell, ti, joints = _triad_certificate_data(c, st, n)
    jx, jp = joints(x, w), joints(pred, w)
    scale = c.plan.length_scale
    with np.errstate(invalid="ignore"):
        proven = _alone(w, Q, ell, x[:, 3 * ti + 2]) >= 3.0 * np.max(np.abs(jx - jp), axis=-1) + 2e-6 * scale
    out = np.ones(n, dtype=bool)
    rest = np.flatnonzero(~proven)
    if rest.size:
        roots = _root_joints(w[rest], Q[rest], ell[rest])
        dp, dx = _distances(roots, jp[rest]), _distances(roots, jx[rest])
        mine = np.argmin(dx, axis=-1)
        d_mine = np.take_along_axis(dp, mine[:, None], axis=-1)[:, 0]
        others = np.where(np.arange(6)[None, :] == mine[:, None], np.inf, dp)
        is_root = np.take_along_axis(dx, mine[:, None], axis=-1)[:, 0] <= 1e-6 * scale
        out[rest] = ~is_root | (2.0 * d_mine <= np.min(others, axis=-1))
    return out


def _broadcast_batch(plan, params, q_jets):
    shape = np.broadcast_shapes(np.shape(params)[:-1], *(np.shape(qj.v) for qj in q_jets))
    P = np.broadcast_to(params, shape + (plan.n_params,)).reshape(-1, plan.n_params)
    Q = np.stack([np.broadcast_to(qj.v, shape).ravel() for qj in q_jets], axis=-1) if q_jets else \
        np.zeros((int(np.prod(shape)), 0))
    return shape, P, Q


class WholeSteps:
    """The file's design walked from the sketch in whole steps of its one crank, one way round: its groups' poses at
    the inputs q_s + way·k·``stage_angle`` (k = 0, 1, …), each walked from the one before by :meth:`Walker.advance`
    (the secant through the one before that). They depend on the plan, the tolerances, the method and the way only,
    so every sample of that design starts its walk at the last whole step before its input, and its result is the
    same in any batch and after any call before it. Extended on demand and kept per plan (:func:`whole_steps`; it
    holds no reference to the plan, which the cache keeps weakly).

    ``x[k]``: {step id: (1, 3k)} at the k-th step, NaN from the first step that cannot be reached."""

    def __init__(self, plan, steps, tol, method, way: float):
        self.tol, self.method, self.way = tol, method, way
        self.sketch, self.stage = float(plan.sketch_inputs[0]), float(tol.stage_angle)
        start = Walker.at_sketch(plan, steps, tol, method, 1)
        self.sign = start.sign
        self.x = [start.x]
        self.alive = bool(start.alive[0])
        self.closes = None          # whether the design's assembly closes after a turn (:func:`closes`), once known
        self.lock = threading.Lock()

    def q(self, k):
        """(...) the input at the k-th whole step (rad)."""
        return self.sketch + self.way * np.asarray(k) * self.stage

    def upto(self, plan, steps, n: int) -> list:
        """The poses of the whole steps 0 … n of ``plan`` (the one this was made for; walked now where they are not
        yet)."""
        with self.lock:
            while len(self.x) <= n:
                k = len(self.x)
                if not self.alive:
                    self.x.append({key: np.full_like(v, np.nan) for key, v in self.x[0].items()})
                    continue
                w = Walker(plan, steps, self.tol, self.method, plan.defaults[None, :], np.array([[self.q(k - 1)]]),
                           self.x[k - 1], self.sign)
                back = (self.x[k - 2], np.array([[self.q(k - 2)]])) if k >= 2 else None
                self.alive = bool(w.advance(plan.defaults[None, :], np.array([[self.q(k)]]), back=back)[0])
                self.x.append({key: v.copy() for key, v in w.x.items()})
            return self.x[:n + 1]


#: the whole steps of a plan's file's design: {plan: {(tolerances, method, way): WholeSteps}}
_WHOLE_STEPS: "weakref.WeakKeyDictionary" = weakref.WeakKeyDictionary()
_WHOLE_LOCK = threading.Lock()


def whole_steps(plan, steps, tol, method, way: float) -> WholeSteps:
    """The plan's :class:`WholeSteps` one way round: kept while the plan lives for its own steps, made afresh for
    others (a compile's first steps)."""
    if steps is not plan.steps:
        return WholeSteps(plan, steps, tol, method, way)
    key = (tol, method, way)
    with _WHOLE_LOCK:
        per_plan = _WHOLE_STEPS.setdefault(plan, {})
        if key not in per_plan:
            per_plan[key] = WholeSteps(plan, steps, tol, method, way)
        return per_plan[key]


def _at_sketch(plan, steps, tol, method, rows: int) -> Walker:
    """:meth:`Walker.at_sketch`, from the sketch's solve the plan keeps with its whole steps (:func:`whole_steps`)
    where the steps are the plan's own: the same numbers without solving the sketch again."""
    if steps is not plan.steps:
        return Walker.at_sketch(plan, steps, tol, method, rows)
    kept = whole_steps(plan, steps, tol, method, 1.0)
    return Walker(plan, steps, tol, method, np.repeat(plan.defaults[None, :], rows, axis=0),
                  np.repeat(plan.sketch_inputs[None, :], rows, axis=0),
                  {k: np.repeat(v, rows, axis=0) for k, v in kept.x[0].items()},
                  {k: np.repeat(v, rows) for k, v in kept.sign.items()})


def _start_on_whole_steps(plan, steps, tol, method, walker, P, target, among=None):
    """Move the walker's rows of the file's design (a plan with one crank), of those ``among`` (R,) (default all),
    to the last whole step of crank before their ``target`` (R, 1) (:class:`WholeSteps`); the rest stay where they
    are. Returns the ``back`` points of :meth:`Walker.advance` (None where no row moved)."""
    if plan.input_kinds != ("rotary",) or not walker.x:
        return None
    d = target[:, 0] - plan.sketch_inputs[0]
    stage = tol.stage_angle
    with np.errstate(invalid="ignore"):
        n = np.where(np.isfinite(d), np.ceil(np.abs(d) / stage) - 1.0, 0.0)
    rows = np.all(P == plan.defaults, axis=-1) & walker.alive & (n >= 1) & (True if among is None else among)
    if not rows.any():
        return None
    bx = {k: np.full_like(v, np.nan) for k, v in walker.x.items()}
    bq = np.full(walker.q.shape, np.nan)
    for way in (1.0, -1.0):
        mine = np.flatnonzero(rows & (np.sign(d) == way))
        if not len(mine):
            continue
        cache = whole_steps(plan, steps, tol, method, way)
        k = n[mine].astype(int)
        x = cache.upto(plan, steps, int(k.max()))
        for key in walker.x:
            stack = np.concatenate([xi[key] for xi in x], axis=0)           # (k_max + 1, 3k)
            walker.x[key][mine] = stack[k]
            bx[key][mine] = stack[k - 1]
        walker.q[mine, 0] = cache.q(k)
        bq[mine, 0] = cache.q(k - 1)
    walker.alive = np.all([np.all(np.isfinite(v), axis=-1) for v in walker.x.values()], axis=0)
    return bx, bq


def same_assembly(plan, tol, xa: dict, xb: dict) -> np.ndarray:
    """(R,) whether the group poses ``xa``, ``xb`` ({step id: (R, 3k)}) are one assembly: every body's origin within
    ``tolerances.assembly_separation`` of the length scale and its angle within as much (as an arc at the length
    scale; whole turns apart are the same angle). False where either is not finite."""
    lim = tol.assembly_separation * plan.length_scale
    out = None
    for k in xa:
        d = np.array(xb[k], dtype=float) - xa[k]
        d[..., 2::3] = (np.remainder(d[..., 2::3] + np.pi, 2 * np.pi) - np.pi) * plan.length_scale
        with np.errstate(invalid="ignore"):
            ok = np.all(np.abs(d) <= lim, axis=-1)
        out = ok if out is None else out & ok
    return out


def closes(plan, steps, tol, method) -> bool:
    """Whether the file's design's assembly closes after one turn of its crank: its whole steps walked half a turn
    each way from the sketch (:class:`WholeSteps`) reach the opposite angle on one assembly (then every input has
    one assembly on it, whichever way it is walked to). Kept with the plan's whole steps."""
    ccw = whole_steps(plan, steps, tol, method, 1.0)
    if ccw.closes is None:
        ends = [_half_turn(plan, steps, tol, method, way) for way in (1.0, -1.0)]
        ccw.closes = bool(all(e is not None for e in ends) and same_assembly(plan, tol, *ends)[0])
    return ccw.closes


def _half_turn(plan, steps, tol, method, way: float):
    """The file's design's group poses ({step id: (1, 3k)}) half a turn from the sketch one way round, or None
    where that walk cannot be certified."""
    ws = whole_steps(plan, steps, tol, method, way)
    k = int(np.ceil(np.pi / ws.stage - 1e-9))
    x = ws.upto(plan, steps, k)
    if not all(np.all(np.isfinite(v)) for v in x[k - 1].values()):
        return None
    if abs(k * ws.stage - np.pi) <= 1e-12:
        end = x[k]
    else:                                            # the last whole step passes the opposite angle: walk to it
        w = Walker(plan, steps, tol, method, plan.defaults[None, :], np.array([[ws.q(k - 1)]]), x[k - 1], ws.sign)
        back = (x[k - 2], np.array([[ws.q(k - 2)]])) if k >= 2 else None
        w.advance(plan.defaults[None, :], np.array([[ws.sketch + way * np.pi]]), back=back)
        end = w.x
    return end if all(np.all(np.isfinite(v)) for v in end.values()) else None


def _may_not_close(plan, steps, tol, method, P) -> np.ndarray:
    """(R,) the rows of designs ``P (R, n_params)`` whose assembly may not close after a turn: all but the file's
    design's where it closes (:func:`closes`; other designs are not walked a turn for it)."""
    rows = np.ones(len(P), dtype=bool)
    if steps is plan.steps:
        mine = np.all(P == plan.defaults, axis=-1)
        if mine.any() and closes(plan, steps, tol, method):
            rows &= ~mine
    return rows


def _short_way(plan, Q):
    """(R, n_inputs) the inputs ``Q`` with every rotary one taken the short way round from the sketch's."""
    rotary = np.array([k == "rotary" for k in plan.input_kinds])
    q_s = plan.sketch_inputs
    return np.where(rotary, q_s + (Q - q_s + np.pi) % (2 * np.pi) - np.pi, Q)


def _walk_long_way(plan, steps, tol, method, walker, P, short, rows):
    """Walk the walker's ``rows (R,)`` (at the sketch) to the inputs ``short (R, n_inputs)`` the long way round (a
    turn the other way on every rotary input not at the sketch's angle), starting the file's design at its whole
    steps. Returns the rows that arrived (R,)."""
    rotary = np.array([k == "rotary" for k in plan.input_kinds])
    d = short - plan.sketch_inputs
    longer = np.where(rotary & (d != 0), short - np.copysign(2 * np.pi, d), short)
    back = _start_on_whole_steps(plan, steps, tol, method, walker, P, longer, among=rows)
    return walker.advance(P, longer, rows=rows, back=back) & rows


def execute(plan, steps, params, q_jets, order, tol, method="closed", ambiguity=True) -> Context:
    """Run the steps on input jets ``q_jets`` (per input, a Jet of shape (...)); Newton-solved groups continued from
    the sketch to every sample in certified steps (module docstring), a crank the short way round first, then the
    long way for the samples that failed. The samples of the file's design start at the last whole step of crank
    before them (:class:`WholeSteps`). ``ambiguity``: the samples the short way reached walked the long way too where
    the assembly may not close (False: the compile-time helpers below, at and next to the sketch)."""
    keys = newton_keys(steps, method)
    if not (keys and len(q_jets)):
        return _run(plan, steps, params, q_jets, order, tol, method, {})
    shape, P, Q = _broadcast_batch(plan, params, q_jets)
    R = len(Q)
    walker = _at_sketch(plan, steps, tol, method, R)
    rotary = np.array([k == "rotary" for k in plan.input_kinds])
    short = _short_way(plan, Q)
    start = (walker.params.copy(), walker.q.copy(), {k: v.copy() for k, v in walker.x.items()},
             {k: v.copy() for k, v in walker.sign.items()})
    back = _start_on_whole_steps(plan, steps, tol, method, walker, P, short)
    alive = walker.advance(P, short, back=back).copy()
    # the samples the short way reached are walked the long way too where the crank's assembly may not close (a
    # single crank: every sample away from the sketch's angle but those of the file's design when it closes), to
    # find the ambiguous ones (at the sketch's angle the long way is no walk)
    check = alive & np.any(short != plan.sketch_inputs, axis=-1)
    if ambiguity and plan.input_kinds == ("rotary",) and check.any():
        check &= _may_not_close(plan, steps, tol, method, P)
    else:
        check[:] = False
    ambiguous = np.zeros(R, dtype=bool)
    if rotary.any() and (check.any() or not alive.all()):
        other = Walker(plan, steps, tol, method, *start)
        again = _walk_long_way(plan, steps, tol, method, other, P, short, ~alive | check)
        take = ~alive & again
        for k in walker.x:
            walker.x[k][take] = other.x[k][take]
        ambiguous = check & again & ~same_assembly(plan, tol, walker.x, other.x)
        alive = (alive | take) & ~ambiguous
    final = {k: v.reshape(shape + v.shape[-1:]) for k, v in walker.x.items()}
    for k, v in walker.sign.items():
        final[(k, "det_sign")] = v.reshape(shape)
    c = _run(plan, steps, params, q_jets, order, tol, method, final)
    c.valid = np.broadcast_to(np.asarray(c.valid, dtype=bool), shape) & alive.reshape(shape)
    c.ambiguous = ambiguous.reshape(shape)
    return separate(plan, steps, c, method, tol, shape, final)


def separate(plan, steps, c, method, tol, shape, x):
    """Flag the samples whose Newton-solved groups are closer to another of their assemblies than
    ``tolerances.assembly_separation`` of the length scale (module docstring). A triad's assemblies are its
    polynomial's roots, at every sample; another group's (the certified reduction, costlier) are enumerated where
    its dimensionless determinant is below :data:`SEPARATION_GATE` (two assemblies that close meet at a singular
    position, where the determinant vanishes about as fast as their distance) and the uniqueness ball of
    :func:`.newton_group.alone_within` does not prove the sample alone. Groups without an enumeration are left to
    the determinant's certificate."""
    n = int(np.prod(shape))
    valid = np.broadcast_to(np.asarray(c.valid, dtype=bool), shape).ravel().copy()
    sep = tol.assembly_separation * plan.length_scale
    for st in newton_keys(steps, method):
        method_ = group_method(plan, st) if st.kind == "newton" else None
        if method_ is None or not valid.any():
            continue
        rows = np.flatnonzero(valid)
        flat = before_group(take_rows(_flat(c, shape), rows, n), st)
        xs = np.reshape(x[id(st)], (n, -1))[rows]
        m = len(rows)
        if method_ == "triad":
            # the second nearest assembly (the nearest is the sample's own), from the roots where the bound on the
            # coefficients does not already put every other beyond the separation
            w, Q, ell, ti, joints = _triad_certificate_data(flat, st, m)
            second = np.full(m, np.inf)
            rest = np.flatnonzero(~(_alone(w, Q, ell, xs[:, 3 * ti + 2]) > sep))
            if rest.size:
                roots = _root_joints(w[rest], Q[rest], ell[rest])
                second[rest] = np.sort(_distances(roots, joints(xs[rest], w[rest])), axis=-1)[:, 1]
        else:
            F, J = _residual_and_jacobian(flat, st, xs, (m,))
            gated = np.abs(certificate_det(flat, st, J)) < SEPARATION_GATE
            near = np.flatnonzero(gated & ~alone_within(flat, st, xs, F, J, sep))
            second = np.full(m, np.inf)
            if len(near) and np.ndim(flat.params) <= 1:
                sub = take_rows(flat, near, m)
                poses, found, _, _, enumerated = group_assemblies(sub, st, len(near), tol)
                second[near] = assembly_distances(sub, st, xs[near], poses, found)[1]
                second[near[~enumerated]] = 0.0      # its other assemblies unknown: not certified, unbuildable
        valid[rows[second <= sep]] = False
    c.valid = valid.reshape(shape)
    return c


def _flat(c, shape):
    """A copy of the context with its values flattened to one batch axis (positions only)."""
    n = int(np.prod(shape))

    def flat(v):
        v = np.asarray(v)
        return v if v.ndim == 0 else np.broadcast_to(v, shape).reshape(n)

    out = copy.copy(c)
    out.pos = {p: Jet(flat(z.v)) for p, z in c.pos.items()}
    out.pose = {b: (Jet(flat(o.v)), Jet(flat(e.v))) for b, (o, e) in c.pose.items()}
    out.q = [Jet(flat(q.v)) for q in c.q]
    out.w = {k: flat(v) for k, v in c.w.items()}
    out.lines = [tuple(flat(a) for a in rec) for rec in c.lines]
    out.valid = flat(c.valid)
    params = np.asarray(c.params)
    out.params = params if params.ndim <= 1 else np.broadcast_to(params, shape + params.shape[-1:]).reshape(n, -1)
    return out


def context_at(plan, steps, params, inputs, tol=DEFAULT) -> Context:
    """The context after running ``steps`` (positions only) at one design ``params (n_params,)`` and one
    input vector ``inputs (n_inputs,)``."""
    q = [Jet.const(np.asarray(inputs[k], dtype=float), 0) for k in range(len(inputs))]
    return execute(plan, steps, np.asarray(params, dtype=float), q, 0, tol, ambiguity=False)


def run_steps(plan, steps, params, inputs, order=0, upto=None, origins=False, tol=DEFAULT):
    """Compile-time helper: after the first ``upto`` steps, (positions by point name, body
    orientations e by body — or (o, e) pairs with ``origins`` —, validity), complex values."""
    q = [Jet.const(np.asarray(inputs[k], dtype=float), order) for k in range(len(inputs))]
    c = execute(plan, steps[:upto], np.asarray(params, dtype=float), q, order, tol, ambiguity=False)
    poses = {b: ((o.v, e.v) if origins else e.v) for b, (o, e) in c.pose.items()}
    return {p: z.v for p, z in c.pos.items()}, poses, c.valid
