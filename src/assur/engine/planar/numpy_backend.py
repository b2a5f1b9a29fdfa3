"""The planar numpy backend: every group on whole arrays of jets, and the wrapping of any backend's
arrays into a :class:`~assur.engine.state.State`."""
from __future__ import annotations

import warnings

import numpy as np

from ...errors import UnbuildableWarning
from ...kernels.jet import Jet
from ..options import input_rates, report_unbuildable
from ..state import State, _Once
from .continuation import execute
from .sweep import execute_cycle


def solve_numpy(plan, params, inputs, shape, speeds, accels, order, on_unbuildable, tol, method,
                sweep: bool = False) -> State:
    """Solve on whole arrays of jets, one pass per input direction (and one per pair of inputs for
    the mixed second derivatives). ``params (..., n_params)``, ``inputs (..., n_inputs)`` broadcast
    to ``shape``. ``sweep``: the inputs along the last batch axis are one turn of the crank, Newton-solved
    groups swept through them in turn (:func:`~assur.engine.planar.sweep.execute_cycle`)."""
    n = plan.n_inputs
    names = plan.point_names
    n_bodies = len(plan.body_names)

    def run(direction):
        q = []
        for k in range(n):
            d = np.full(inputs.shape[:-1], float(direction[k])) if order >= 1 else None
            dd = np.zeros(inputs.shape[:-1]) if order >= 2 else None
            q.append(Jet(inputs[..., k], d, dd))
        return (execute_cycle if sweep else execute)(plan, plan.steps, params, q, order, tol, method)

    def stack(ctx, attr):
        """(..., n_points + n_bodies) complex: point positions, then body orientations e = exp(iθ)."""
        jets = [ctx.pos[p] for p in names] + [ctx.pose[b][1] for b in range(n_bodies)]
        out = np.empty(shape + (len(jets),), dtype=complex)
        for i, j in enumerate(jets):
            out[..., i] = getattr(j, attr)           # broadcast by the assignment
        return out

    eye = np.eye(n)
    passes = [run(eye[k]) for k in range(n)] if order >= 1 and n > 0 else [run(np.zeros(n))]
    base = passes[0]
    z = stack(base, "v")
    valid = np.broadcast_to(base.valid, shape) & np.all(np.isfinite(z), axis=-1)
    dz = d2z = None
    if order >= 1:
        dz = np.stack([stack(p, "d") for p in passes], axis=-1)             # (..., n_points + n_bodies, n_inputs)
    if order >= 2:
        d2z = np.empty(shape + (z.shape[-1], n, n), dtype=complex)
        for i in range(n):
            d2z[..., i, i] = stack(passes[i], "dd")
        for i in range(n):
            for j in range(i + 1, n):
                mixed = run(eye[i] + eye[j])
                d2z[..., i, j] = d2z[..., j, i] = 0.5 * (stack(mixed, "dd") - d2z[..., i, i] - d2z[..., j, j])
    ambiguous = None if base.ambiguous is None else np.broadcast_to(base.ambiguous, shape)
    return finish(plan, params, inputs, shape, z, dz, d2z, valid, speeds, accels, on_unbuildable,
                  ambiguous=ambiguous)


def finish(plan, params, inputs, shape, z, dz, d2z, valid, speeds, accels, on_unbuildable,
           complete=None, xyz=None, xyz_time: bool = False, ambiguous=None) -> State:
    """NaN out the unbuildable samples, report them as asked, and wrap the arrays in a State.
    ``xyz``: the compiled backend's (pos, first, second) float views instead of z, dz, d2z;
    ``complete``: a callable returning the full state (body orientations) where the backend gave
    points only; ``ambiguous`` (...) bool or None: the samples on two assemblies (``State.ambiguous``)."""
    n = plan.n_inputs
    # invalid samples: NaN everywhere, never finite garbage
    inv = ~valid
    if xyz is None and inv.any():
        cnan = complex(np.nan, np.nan)   # both coordinates NaN (a plain nan would give nan + 0j)
        z = np.where(inv[..., None], cnan, z)
        if dz is not None:
            dz = np.where(inv[..., None, None], cnan, dz)
        if d2z is not None:
            d2z = np.where(inv[..., None, None, None], cnan, d2z)
    n_bad = report_unbuildable(plan, inputs, valid, on_unbuildable, stacklevel=5, ambiguous=ambiguous)
    qdot, qddot = input_rates(plan, speeds, accels)
    full_inputs = inputs if inputs.shape[:-1] == shape else np.broadcast_to(inputs, shape + (n,))
    state = State(plan=plan, inputs=full_inputs, valid=valid, n_unbuildable=n_bad,
                  qdot=qdot, qddot=qddot, params=params, _z=z, _dz=dz, _d2z=d2z,
                  _complete=None if complete is None else _Once(complete), _xyz=xyz, _xyz_time=xyz_time,
                  _ambiguous=ambiguous)
    if on_unbuildable == "warn":
        singular = state.singular
        if singular is not None and singular.any():
            warnings.warn(f"{int(np.count_nonzero(singular))} samples are at a singular position (a toggle or a "
                          "change point, where two assemblies meet): their velocities are not finite "
                          "(state.singular)", UnbuildableWarning, stacklevel=4)
    return state
