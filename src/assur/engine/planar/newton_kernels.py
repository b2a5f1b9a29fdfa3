"""The compiled backend for plans with Newton-solved groups: a whole batch solved in one numba kernel.

A plan whose groups include a triad or a larger group (:func:`assur.engine.planar.traced.covers` with
``newton=True``) is traced once (:mod:`.traced`, :mod:`.traced_newton`: the numpy backend's step executors and loop
equations on symbols) and wrapped by :func:`assur.kernels.newton_codegen.newton_source` in the numpy backend's
certified continuation: every sample continued from the sketch on its own
(:func:`assur.engine.planar.continuation.execute`, the default), or each design swept through its inputs
(:func:`assur.engine.planar.sweep.execute_cycle`, ``solve(..., sweep=True)``). So every sample follows the sketch's
assembly, certified as the numpy backend certifies it, and its valid flag and numbers are numpy's to round-off; the
one check not compiled (a sample's distance to the other assemblies of a group the certified reduction enumerates)
is numpy's own, on the few samples that need it (:func:`separate_by_reduction`).

Batch layout (:func:`layout`): the last batch axis is the samples of one sweep, the leading axes the designs (the
parameters must not vary along the last axis; if they do, every sample is a design of its own). The inputs may be
the same for every design or differ per design.

The generated sources depend only on the plan's structure (its steps, bodies and parameters' roles), never on its
numbers: the file's parameters, the seeds (the sketch's poses) and the tolerances are arguments, so a plan dragged in
the designer reuses its kernel.
"""
from __future__ import annotations

import math
import weakref
from dataclasses import dataclass

import numpy as np

from ...kernels import newton_codegen
from ...kernels.trace import SAMPLE, source
from . import traced

TWO_PI = 2.0 * math.pi


def covers(plan) -> bool:
    """True when the plan has a Newton-solved group and the Newton kernels trace it (one rotary input, no gears)."""
    return plan.has_newton_groups and traced.covers(plan, newton=True)


def structure_key(plan) -> tuple:
    """What a traced program of the plan depends on: its steps (kinds, bodies, points, branch signs, parameter
    indices), the geometry program, the slide lines, the names, the joints and bodies of its graph, the drivers'
    kinds — never its numbers (the file's parameters, the sketch, the tolerances are the kernels' arguments)."""
    g = plan.structure.graph
    return (plan.steps, repr(plan.geometry_program), repr(plan.lines), plan.point_names, plan.body_names,
            plan.param_names, tuple(plan.param_kind.tolist()), plan.input_kinds, plan.point_body, g.joints,
            tuple(tuple(b.points) for b in g.bodies), tuple((d.kind, getattr(d, "actuator", None))
                                                            for d in plan.mechanism.drivers))


#: (structure key, kind) → generated source: a plan of a known structure is not traced again (a designer's drag
#: compiles a new plan per move)
_SOURCES: dict = {}


def _memo(plan, kind: str, make):
    key = (structure_key(plan), kind)
    src = _SOURCES.get(key)
    if src is None:
        if len(_SOURCES) > 64:
            _SOURCES.clear()
        src = _SOURCES[key] = make()
    return src


def solve_source(plan, order: int, each: bool = True) -> str:
    """The source of the plan's Newton solve kernel: per point and then per body six rows (x, y of the value, of
    w1·d/dq and of w2·d²/dq² + w3·d/dq; the first 2·(order + 1) written) at every sample reached, and ``valid``
    (every group assembled and certified, every written value finite); a sample not reached is not valid. ``each``:
    every sample continued from the sketch on its own (the default continuation,
    :func:`assur.engine.planar.continuation.execute`), else the designs swept through their inputs
    (:func:`assur.engine.planar.sweep.execute_cycle`). Traced once per structure (:func:`structure_key`)."""
    return _memo(plan, f"solve_{order}_{'each' if each else 'sweep'}", lambda: _solve_source(plan, order, each))


def _solve_source(plan, order: int, each: bool = True) -> str:
    t = traced.trace_plan(plan, order, row="p[{}]", select="select")
    w1, w2, w3 = (t.tracer.free(n) for n in ("w1", "w2", "w3"))
    jets = [t.pos[p] for p in plan.point_names] + t.orient
    rows, values = [], []
    for m, z in enumerate(jets):
        for xy, part in enumerate((np.real, np.imag)):
            v = part(z.v)
            rows.append((6 * m + xy, v))
            if order >= 1:
                rows.append((6 * m + 2 + xy, part(z.d) * w1))
            if order >= 2:
                rows.append((6 * m + 4 + xy, part(z.dd) * w2 + part(z.d) * w3))
            values.append(v)
    ok = t.finite(*[v for v in values if getattr(v, "level", 0) & SAMPLE])
    # then the groups' unknowns and certificates (:func:`solve`'s check of groups without a compiled separation)
    extra = [v for grp in t.groups for v in grp.solved] + [grp.certificate for grp in t.groups]
    rows += [(6 * len(jets) + i, v) for i, v in enumerate(extra)]
    # the last row: 1 where the sample is ambiguous (reached on two assemblies, one each way round), else 0
    flag = 6 * len(jets) + len(extra)
    epilogue = [f"out[{row}, d, u] = {source(v)}" for row, v in rows] + [f"valid[d, u] = {source(ok)} and sepok",
                                                                         f"out[{flag}, d, u] = 0.0"]
    return newton_codegen.newton_source(t.tracer, t.groups, [v for _, v in rows] + [ok], epilogue,
                                        ["valid[d, u] = False", f"out[{flag}, d, u] = 0.0"], valid=t.valid,
                                        generator="assur.engine.planar.newton_kernels.solve_source",
                                        signature="w1, w2, w3, out, valid", each=each,
                                        ambiguous=["valid[d, u] = False", f"out[{flag}, d, u] = 1.0"])


def seeds(plan) -> np.ndarray:
    """The Newton-solved groups' unknowns at the sketch (x, y, θ of each body, in solve order): their first seed."""
    return np.array([v for st in plan.newton_steps() for b in st.bodies for v in plan.sketch_poses[b]],
                    dtype=float)


@dataclass(frozen=True)
class _Fixed:
    """What every solve of one plan passes or reads alike (:func:`_fixed`): the seeds (the kernels never write them; a
    writeable array, as numba's signature of the cached kernels has it), the kernel's rows (``6·m`` of the points and
    bodies, then ``extra`` of the groups' unknowns and certificates) and whether the certified reduction enumerates
    any of its Newton-solved groups (else :func:`separate_by_reduction` has nothing to check). The kernel's last row
    (after ``extra``) flags the ambiguous samples."""
    seeds: np.ndarray
    m: int
    extra: int
    reduced: bool


#: plan → its :class:`_Fixed` (a plan is frozen; the entry goes with it)
_FIXED: "weakref.WeakKeyDictionary" = weakref.WeakKeyDictionary()
#: the ``fwd`` and ``bwd`` of a kernel of the default continuation, which visits the inputs in their own order
_NO_ORDER = np.zeros((1, 0), dtype=np.int64)


def _fixed(plan) -> _Fixed:
    """The plan's :class:`_Fixed`, made once per plan."""
    f = _FIXED.get(plan)
    if f is None:
        from .group_assemblies import group_method
        groups = tuple(plan.newton_steps())
        f = _FIXED[plan] = _Fixed(seeds(plan), len(plan.point_names) + len(plan.body_names),
                                  sum(3 * len(st.bodies) for st in groups) + len(groups),
                                  any(group_method(plan, st) == "reduction" for st in groups))
    return f


def layout(plan, params: np.ndarray, inputs: np.ndarray, shape: tuple):
    """The batch as designs × sweeps: ``(designs (D, n_params), q (Dq, N), split)`` where the batch ``shape`` is
    ``(D…, N)`` and q holds the inputs of every design (Dq = 1 when they are the same for all); ``split``: True when
    the batch's last axis is the sweep, False when every sample is a design of its own (the parameters vary along the
    last axis, or the batch has no axis)."""
    n_params = params.shape[-1]
    q = np.broadcast_to(inputs[..., 0], shape)
    p_shape = (1,) * (len(shape) + 1 - params.ndim) + params.shape[:-1]
    if len(shape) and p_shape[-1] == 1:
        designs = np.broadcast_to(params.reshape(p_shape + (n_params,))[..., 0, :], shape[:-1] + (n_params,))
        rows = q.reshape(-1, shape[-1])
        i_shape = (1,) * (len(shape) + 1 - inputs.ndim) + inputs.shape[:-1]
        if all(k == 1 for k in i_shape[:-1]):
            rows = rows[:1]
        return designs.reshape(-1, n_params), rows, True
    designs = np.broadcast_to(params, shape + (n_params,)).reshape(-1, n_params)
    return designs, q.reshape(-1, 1), False


def arguments(plan, designs: np.ndarray, q: np.ndarray, tol, each: bool = False) -> tuple:
    """The kernel's first arguments (:data:`assur.kernels.newton_codegen.NEWTON_ARGS`) for designs (D, n_params)
    walked through the inputs q (Dq, N): the orders in which :func:`assur.engine.planar.sweep.execute_cycle` visits
    them (with ``each`` none: that kernel visits them in their own order), and the tolerances of the numpy backend's
    continuation (:mod:`assur.engine.planar.continuation`: its corrector's iteration cap, its shortest step and
    largest correction) and of
    :func:`assur.engine.planar.newton_group.solve_group`. With ``each`` (a kernel of :func:`solve_source` with
    ``each``) ``ahead`` is each input's angle from the sketch's the short way, in [−π, π), as
    :func:`assur.engine.planar.continuation.execute` computes it."""
    from .continuation import CORRECTOR_ITERATIONS
    q_s = float(plan.sketch_inputs[0])
    if each:           # the inputs visited in their own order: no fwd, bwd
        ahead = (q_s + np.remainder(q - q_s + np.pi, TWO_PI) - np.pi) - q_s
        fwd = bwd = _NO_ORDER
    else:
        ahead = np.mod(q - q_s, TWO_PI)
        fwd = np.argsort(ahead, axis=-1, kind="stable")
        bwd = np.argsort(-(ahead - TWO_PI), axis=-1, kind="stable")
    scale = plan.length_scale
    return (np.require(designs, dtype=float, requirements=["C", "W"]), np.ascontiguousarray(plan.defaults, dtype=float),
            _fixed(plan).seeds, float(np.cos(q_s)), float(np.sin(q_s)), q_s, np.cos(q), np.sin(q), ahead, fwd, bwd,
            int(tol.stages_for_new_design), float(tol.stage_angle), float(tol.radicand), float(scale),
            tol.newton_residual * scale, 1e3 * tol.newton_residual * scale, float(tol.newton_certify),
            int(tol.newton_iterations), int(min(tol.newton_iterations, CORRECTOR_ITERATIONS)),
            float(tol.continuation_min_step), float(tol.continuation_correction), float(tol.assembly_separation))


def sweeps(plan, params: np.ndarray, inputs: np.ndarray, shape: tuple) -> bool:
    """Whether ``solve(..., sweep=True)`` sweeps this batch (:func:`assur.engine.planar.sweep.execute_cycle`): the
    same two or more inputs along the last axis for every design, the designs constant along it; else it continues
    every sample on its own as the default does."""
    designs, q, split = layout(plan, params, inputs, shape)
    return split and q.shape[0] == 1 and q.shape[-1] >= 2


def solve(plan, params: np.ndarray, inputs: np.ndarray, tol, order: int, shape: tuple, kernel, rates=(1.0, 1.0, 0.0),
          each: bool = True):
    """Run the plan's Newton solve kernel ``kernel`` (:func:`solve_source` with ``each``, loaded by the caller) on a
    batch: ``(buffer (6·m + …, D, N), (pos, first, second), valid, ambiguous)``, the first three as
    :func:`.numba_backend.solve_compiled` gives them, here for the m = n_points + n_bodies points and bodies (pos,
    first, second: shape + (m, 2) float views: the value, w1·d/dq and w2·d²/dq² + w3·d/dq for ``rates = (w1, w2,
    w3)``), then :func:`separate_by_reduction`; ``ambiguous`` (shape) the samples on two assemblies
    (``State.ambiguous``)."""
    designs, q, split = layout(plan, params, inputs, shape)
    D, N = designs.shape[0], q.shape[-1]
    fixed = _fixed(plan)
    m = fixed.m
    out = np.empty((6 * m + fixed.extra + 1, D, N))
    valid = np.empty((D, N), dtype=np.bool_)
    kernel(*arguments(plan, designs, q, tol, each), *(float(w) for w in rates), out, valid)
    if params.ndim <= 1 and fixed.reduced:
        separate_by_reduction(plan, params, inputs, shape, tol, out[6 * m:-1].reshape((-1,) + shape),
                              valid.reshape(shape))
    rows = out[:6 * m].reshape((m, 6) + shape)
    n = len(shape)
    axes = tuple(range(2, 2 + n)) + (0, 1)
    views = tuple(rows[:, 2 * j:2 * j + 2].transpose(axes) for j in range(3))
    return out, views, valid.reshape(shape), out[-1].reshape(shape) > 0.5


def separate_by_reduction(plan, params, inputs, shape, tol, extra, valid):
    """The numpy backend's last check of one design's samples that the kernels leave out
    (:func:`assur.engine.planar.continuation.separate`): a group whose assemblies the certified one-parameter
    reduction enumerates (not a triad's polynomial, which the kernels check) is flagged where its sample is closer to
    another assembly than ``tolerances.assembly_separation``; numpy looks only where the group's dimensionless
    determinant is below ``continuation.SEPARATION_GATE``, and only for one design (params (n_params,)). Those
    samples are checked here by numpy's own function, from the kernel's poses; ``valid`` is updated in place.
    ``extra (n_unknowns + n_groups, *shape)``: the kernel's rows of the groups' unknowns and certificates."""
    from .continuation import SEPARATION_GATE, Walker, separate
    from .group_assemblies import group_method
    from .steps import _run
    from ...kernels.jet import Jet
    groups = plan.newton_steps()
    starts = np.cumsum([0] + [3 * len(st.bodies) for st in groups])
    certs = extra[starts[-1]:]
    flagged = np.zeros(shape, dtype=bool)
    for g, st in enumerate(groups):
        if group_method(plan, st) == "reduction":
            flagged |= valid & (np.abs(certs[g]) < SEPARATION_GATE)
    if not flagged.any():
        return
    idx = np.nonzero(flagged)
    q = np.broadcast_to(inputs[..., 0], shape)[idx]
    sign = Walker.at_sketch(plan, plan.steps, tol, "closed", 1).sign
    warm = {}
    for g, st in enumerate(groups):
        warm[id(st)] = np.stack([extra[i][idx] for i in range(starts[g], starts[g + 1])], axis=-1)
        warm[(id(st), "det_sign")] = np.repeat(sign[id(st)], len(q))
    final = {k: v for k, v in warm.items() if not isinstance(k, tuple)}
    c = _run(plan, plan.steps, params, [Jet.const(q, 0)], 0, tol, "closed", warm)
    c.valid = np.broadcast_to(np.asarray(c.valid, dtype=bool), q.shape).copy()
    c = separate(plan, plan.steps, c, "closed", tol, q.shape, final)
    valid[idx] = np.asarray(c.valid, dtype=bool)
