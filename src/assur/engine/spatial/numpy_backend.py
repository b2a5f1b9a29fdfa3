"""The spatial numpy backend: the plan's steps on whole arrays of jets, wrapped in a
:class:`~assur.engine.state.SpatialState`."""
from __future__ import annotations

import warnings

import numpy as np

from ...errors import UnbuildableWarning
from ...kernels import spatial as V
from ...kernels.jet import Jet
from .. import options
from ..options import input_rates, report_unbuildable
from ..state import SpatialState
from .steps import execute_newton, run


def _causes(status) -> dict:
    """Per dyad point, (samples its solver failed at, the reasons), for the unbuildable message."""
    out = {}
    for point, st in status.items():
        failed = ~V.assembled(st)
        reasons = sorted({V.STATUS_TEXT[int(k)] for k in np.unique(st[failed])})
        out[point] = (failed, reasons)
    return out


def unbuildable_message(plan, inputs, valid, status) -> str:
    """'k of n samples cannot be assembled (…): the dyad solving B: crank 100°…140°; …'."""
    return options.unbuildable_message(plan, inputs, valid, _causes(status))


def solve_spatial(plan, params, inputs, shape, speeds, accels, order: int, on_unbuildable: str, tolerances,
                  method: str) -> SpatialState:
    """Solve a spatial plan on a prepared batch (:func:`assur.engine.api.solve` checks the options and
    prepares ``params (..., n_params)`` and ``inputs (..., n_inputs)``, broadcast to ``shape``;
    ``method='newton'`` is the loop-closure oracle). Unassemblable samples are NaN with ``valid`` False."""
    n = plan.n_inputs
    names = plan.point_names
    nb = len(plan.body_names)

    def one_pass(direction):
        q = [Jet(inputs[..., k], np.full(inputs.shape[:-1], float(direction[k])) if order >= 1 else None,
                 np.zeros(inputs.shape[:-1]) if order >= 2 else None) for k in range(n)]
        if method == "newton":
            return execute_newton(plan, params, q, order, tolerances)
        return run(plan, params, q, order, tolerances)

    def part(x, attr):
        if isinstance(x, Jet):
            y = getattr(x, attr)
            return y if y is not None else np.zeros_like(x.v)
        return np.asarray(x, dtype=float) if attr == "v" else np.zeros_like(np.asarray(x, dtype=float))

    def stack(ctx, attr):
        pts = np.stack([np.broadcast_to(part(ctx.pos[p], attr), shape + (3,)) for p in names], axis=-2)
        frames = np.stack([np.stack([np.broadcast_to(part(a, attr), shape + (3,)) for a in ctx.frames[b]], axis=-1)
                           for b in range(nb)], axis=-3)
        return pts, frames

    eye = np.eye(n)
    passes = [one_pass(eye[k]) for k in range(n)] if order >= 1 and n > 0 else [one_pass(np.zeros(n))]
    base = passes[0]
    pos, frames = stack(base, "v")
    valid = np.broadcast_to(base.valid, shape) & np.all(np.isfinite(pos), axis=(-1, -2))
    d1 = d2 = f1 = f2 = None
    if order >= 1:
        s1 = [stack(p, "d") for p in passes]
        d1 = np.stack([s[0] for s in s1], axis=-1)
        f1 = np.stack([s[1] for s in s1], axis=-1)
    if order >= 2:
        d2 = np.empty(pos.shape + (n, n))
        f2 = np.empty(frames.shape + (n, n))
        for i in range(n):
            d2[..., i, i], f2[..., i, i] = stack(passes[i], "dd")
        for i in range(n):
            for j in range(i + 1, n):
                mp, mf = stack(one_pass(eye[i] + eye[j]), "dd")
                d2[..., i, j] = d2[..., j, i] = 0.5 * (mp - d2[..., i, i] - d2[..., j, j])
                f2[..., i, j] = f2[..., j, i] = 0.5 * (mf - f2[..., i, i] - f2[..., j, j])
    inv = ~valid
    if inv.any():
        for a in (pos, frames, d1, d2, f1, f2):
            if a is not None:
                a[inv] = np.nan
    status = {p: np.broadcast_to(s, shape) for p, s in base.status}
    full_inputs = np.broadcast_to(inputs, shape + (n,))
    n_bad = report_unbuildable(plan, full_inputs, valid, on_unbuildable, causes=_causes(status) if on_unbuildable != "nan" else None,
                               stacklevel=4)
    at_branch = [p for p, s_ in status.items() if np.any((s_ == V.BRANCH_POINT) & valid)]
    if at_branch and on_unbuildable == "warn":
        warnings.warn(f"{', '.join(at_branch)}: some samples are at a branch point (the two assemblies meet, "
                      "μ_T = 0; velocities there are infinite)", UnbuildableWarning, stacklevel=2)
    qdot, qddot = input_rates(plan, speeds, accels)
    return SpatialState(plan=plan, inputs=full_inputs, valid=valid, n_unbuildable=n_bad, qdot=qdot, qddot=qddot,
                        params=params,
                        pos=pos, dpos_dq=d1, d2pos_dq2=d2, body_frame=frames, dframe_dq=f1, d2frame_dq2=f2,
                        status=status)
