"""Newton-solved groups over one turn of a crank, swept sample after sample.

:func:`assur.engine.planar.steps.execute` continues every sample from the sketch on its own, in stages: right for
any batch, but a cycle of M samples then costs some twenty full-batch solves. When the batch is one turn of a
single crank — the M inputs along the last batch axis, the same for every design, as a synthesis evaluation
solves them — :func:`execute_cycle` instead

1. continues each design's parameters from the file's at the sketch's crank angle (the same
   ``stages_for_new_design`` stages, on the designs alone);
2. sweeps the crank forward through the samples in turn (each warm-started from the one before, with steps of at
   most ``stage_angle``), then backward from the sketch through the samples the forward sweep could not reach
   (past a dead point, as ``execute`` continues failed samples the long way round);
3. solves the whole batch once more from those poses, for the derivatives and the branch certificate.

Every sample keeps the branch of the sketch (the sign of the group's equilibrated Jacobian determinant, as in
:func:`~assur.engine.planar.newton_group.solve_group`); the positions equal ``execute``'s to the Newton
tolerance.
"""
from __future__ import annotations

import numpy as np

from ...kernels.jet import Jet
from .steps import Context, _run, execute

TWO_PI = 2.0 * np.pi


def sweepable(plan, steps, q_jets, method) -> bool:
    """Whether :func:`execute_cycle` applies: Newton-solved groups and a single rotary input."""
    newton = method == "newton" or any(st.kind == "newton" for st in steps)
    return newton and len(q_jets) == 1 and plan.input_kinds[0] == "rotary"


def _angles(q_jets, shape):
    """The M crank angles of the last batch axis (the same for every design), or None."""
    q = np.broadcast_to(np.asarray(q_jets[0].v, dtype=float), shape)
    if q.ndim == 0:
        return None
    rows = q.reshape(-1, q.shape[-1])
    return rows[0] if np.all(rows == rows[0]) else None


def execute_cycle(plan, steps, params, q_jets, order, tol, method="closed") -> Context:
    """:func:`~assur.engine.planar.steps.execute` for a batch whose inputs are crank angles along the last axis
    (module docstring); any other batch goes to ``execute``. params (..., 1, n_params) or (..., M, n_params)."""
    params = np.asarray(params, dtype=float)
    shape = np.broadcast_shapes(params.shape[:-1], np.shape(q_jets[0].v))
    q = _angles(q_jets, shape) if len(shape) else None
    if q is None or len(q) < 2 or not sweepable(plan, steps, q_jets, method):
        return execute(plan, steps, params, q_jets, order, tol, method)
    rows = params if params.ndim >= 2 else params[None, :]
    if not np.all(rows == rows[..., :1, :]):          # the designs must not vary along the samples' axis
        return execute(plan, steps, params, q_jets, order, tol, method)
    design = rows[..., :1, :]
    keys = [id(st) for st in steps if st.kind == "newton" or method == "newton"]
    q_s = float(plan.sketch_inputs[0])
    # 1. the designs at the sketch's crank angle, continued from the file's parameters
    dp = design - plan.defaults
    stages = tol.stages_for_new_design if np.any(dp != 0) else 1
    warm: dict = {}
    at_sketch = [Jet.const(np.float64(q_s), 0)]
    for i in range(1, stages + 1):
        _run(plan, steps, plan.defaults + (i / stages) * dp, at_sketch, 0, tol, method, warm)
    start = dict(warm)
    # 2. forward through the samples by their angle past the sketch's, then backward for what failed
    M = len(q)
    ahead = np.mod(q - q_s, TWO_PI)
    poses = {k: np.full(shape + warm[k].shape[-1:], np.nan) for k in keys}

    def sweep(order_, signed, todo):
        w = dict(start)
        last = 0.0
        for j in order_:
            if not todo[j]:
                continue
            target = signed[j]
            n_sub = max(1, int(np.ceil(abs(target - last) / tol.stage_angle)))
            for s in range(1, n_sub + 1):
                t = last + (target - last) * s / n_sub
                _run(plan, steps, design, [Jet.const(np.float64(q_s + t), 0)], 0, tol, method, w)
            last = target
            for k in keys:
                x = w[k][..., 0, :]
                poses[k][..., j, :] = np.where(np.isfinite(poses[k][..., j, :]), poses[k][..., j, :], x)
            todo[j] = bool(np.any(~np.isfinite(poses[keys[0]][..., j, 0]))) if keys else False
        return todo

    todo = sweep(np.argsort(ahead, kind="stable"), ahead, np.ones(M, dtype=bool))
    if todo.any():
        behind = ahead - TWO_PI
        sweep(np.argsort(-behind, kind="stable"), behind, todo)
    # 3. the whole batch from the swept poses: derivatives and the branch certificate
    final = {k: np.broadcast_to(v, shape + v.shape[-1:]).copy() for k, v in poses.items()}
    final.update({k: v for k, v in start.items() if k not in keys})
    return _run(plan, steps, params, q_jets, order, tol, method, final)


__all__ = ["execute_cycle", "sweepable"]
