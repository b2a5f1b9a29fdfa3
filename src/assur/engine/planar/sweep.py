"""Newton-solved groups over one turn of a crank, swept sample after sample.

:func:`assur.engine.planar.continuation.execute` continues every sample from the sketch on its own: right for any
batch, but a cycle of M samples of D designs then walks D·M paths. When the batch is one turn of a single crank —
the M inputs along the last batch axis, the same for every design, as a synthesis evaluation solves them —
:func:`execute_cycle` instead walks the D designs (:class:`~assur.engine.planar.continuation.Walker`, the same
certified steps)

1. from the file's design to each design at the sketch's crank angle;
2. forward through the samples by their angle past the sketch's, then backward from the sketch through the samples
   the forward sweep could not reach (past a dead point, as ``execute`` continues failed samples the long way
   round);
3. and solves the whole batch once more from those poses, for the derivatives and the branch certificate.

Every sample keeps the branch of the sketch; the positions equal ``execute``'s to the Newton tolerance wherever the
sketch's assembly closes after one turn. The forward sweep, once through the samples, walks on to the sketch's
angle a turn later: a design back on its own pose there closes; for any other the backward sweep visits every
sample it can reach, and a sample both sweeps reach on different assemblies is ambiguous, unbuildable, as
``execute`` flags it (an assembly that spans more than a turn without closing: a branch that needs two turns to
close is then ambiguous everywhere here, and where ``execute`` walks both ways to an input).
"""
from __future__ import annotations

import numpy as np

from ...kernels.jet import Jet
from .continuation import Walker, execute, newton_keys, same_assembly, separate
from .steps import Context, _run

TWO_PI = 2.0 * np.pi


def sweepable(plan, steps, q_jets, method) -> bool:
    """Whether :func:`execute_cycle` applies: Newton-solved groups and a single rotary input."""
    return bool(newton_keys(steps, method)) and len(q_jets) == 1 and plan.input_kinds[0] == "rotary"


def _angles(q_jets, shape):
    """The M crank angles of the last batch axis (the same for every design), or None."""
    q = np.broadcast_to(np.asarray(q_jets[0].v, dtype=float), shape)
    if q.ndim == 0:
        return None
    rows = q.reshape(-1, q.shape[-1])
    return rows[0] if np.all(rows == rows[0]) else None


def execute_cycle(plan, steps, params, q_jets, order, tol, method="closed") -> Context:
    """:func:`~assur.engine.planar.continuation.execute` for a batch whose inputs are crank angles along the last
    axis (module docstring); any other batch goes to ``execute``. params (..., 1, n_params) or (..., M, n_params)."""
    params = np.asarray(params, dtype=float)
    shape = np.broadcast_shapes(params.shape[:-1], np.shape(q_jets[0].v))
    q = _angles(q_jets, shape) if len(shape) else None
    if q is None or len(q) < 2 or not sweepable(plan, steps, q_jets, method):
        return execute(plan, steps, params, q_jets, order, tol, method)
    rows = params if params.ndim >= 2 else params[None, :]
    if not np.all(rows == rows[..., :1, :]):          # the designs must not vary along the samples' axis
        return execute(plan, steps, params, q_jets, order, tol, method)
    design = np.broadcast_to(rows[..., :1, :], shape[:-1] + (1, plan.n_params)).reshape(-1, plan.n_params)
    D, M = len(design), len(q)
    q_s = float(plan.sketch_inputs[0])
    # 1. the designs at the sketch's crank angle, continued from the file's parameters
    start = Walker.at_sketch(plan, steps, tol, method, D)
    start.advance(design, np.full((D, 1), q_s))
    keys = list(start.x)
    poses = {k: np.full((D, M, v.shape[-1]), np.nan) for k, v in start.x.items()}
    ahead = np.mod(q - q_s, TWO_PI)

    def sweep(order_, signed, todo, check=None):
        # ``check`` (D, M): samples reached before, walked to again to compare (rows that may not close)
        w = Walker(plan, steps, tol, method, start.params, start.q, start.x, start.sign)
        for j in order_:
            visit = todo[:, j] if check is None else todo[:, j] | check[:, j]
            if not visit.any():
                continue
            w.advance(design, np.full((D, 1), q_s + signed[j]))
            for k in keys:
                fill = todo[:, j] & w.alive
                poses[k][fill, j] = w.x[k][fill]
            if check is not None:
                there = check[:, j] & w.alive
                if there.any():
                    same = same_assembly(plan, tol, {k: poses[k][:, j] for k in keys}, w.x)
                    ambiguous[:, j] |= there & ~same
            todo[:, j] &= ~w.alive
            if not w.alive.any():
                break
        return todo, w

    ambiguous = np.zeros((D, M), dtype=bool)
    todo, forward = sweep(np.argsort(ahead, kind="stable"), ahead, np.repeat(start.alive[:, None], M, axis=1))
    # 2b. the assembly closes after a turn where the forward sweep, walked on to the sketch's angle a turn later,
    # is back on the design's pose there; elsewhere the backward sweep visits every sample, and a sample both
    # sweeps reach on different assemblies is ambiguous (continuation.execute)
    forward.advance(design, np.full((D, 1), q_s + TWO_PI))
    closed = forward.alive & same_assembly(plan, tol, start.x, forward.x)
    check = (start.alive & ~closed)[:, None] & ~todo
    if todo.any() or check.any():
        sweep(np.argsort(-(ahead - TWO_PI), kind="stable"), ahead - TWO_PI, todo, check)
    # 3. the whole batch from the swept poses: derivatives and the branch certificate
    final = {k: v.reshape(shape + v.shape[-1:]) for k, v in poses.items()}
    for k, v in start.sign.items():
        final[(k, "det_sign")] = np.repeat(v[:, None], M, axis=1).reshape(shape)
    c = _run(plan, steps, params, q_jets, order, tol, method, dict(final))
    reached = np.all(np.isfinite(poses[keys[0]]), axis=-1).reshape(shape) if keys else True
    c.valid = np.broadcast_to(np.asarray(c.valid, dtype=bool), shape) & reached & ~ambiguous.reshape(shape)
    c.ambiguous = ambiguous.reshape(shape)
    return separate(plan, steps, c, method, tol, shape, final)


__all__ = ["execute_cycle", "sweepable"]
