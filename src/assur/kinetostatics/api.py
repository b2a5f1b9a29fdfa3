"""``assur.forces(plan, params, inputs, …)``: kinetostatics of a batch, by Assur groups.

The state is solved (or taken) with order 2; the applied loads (gravity, d'Alembert inertia, the
file's loads, extra point loads such as a walking leg's ground reaction) go on the bodies; the groups
are solved from the last back to the drivers (:mod:`.groups`). ``method="matrix"`` solves the global
Newton–Euler matrix of every moving body at once instead: the test oracle and the fallback.
Friction (optional) is a fixed-point iteration on the reactions.
"""
from __future__ import annotations

import numpy as np

from ..engine import solve
from ..engine.plan import PlanarPlan, SpatialPlan
from ..errors import SpecError
from ..tolerances import DEFAULT
from .groups import Wrenches, solve_group_linear, solve_groups
from .loads import apply_body_loads, friction_loads, point_body
from .motion import motion as body_motion
from .result import Forces
from .tables import force_tables

METHODS = ("groups", "matrix")


def forces(plan, params=None, inputs=None, *, speeds=None, accels=None, friction: bool = False,
           point_loads=None, state=None, method: str = "groups", backend: str = "auto", tolerances=DEFAULT):
    """Reactions, driving efforts and power of every sample of a batch.

    Parameters
    ----------
    plan : PlanarPlan or SpatialPlan
    params : array_like (..., n_params), optional
        Design parameters (default: the file's).
    inputs : array_like (..., n_inputs), optional
        Inputs, as for :func:`assur.solve` (a 1-D array is a batch of a one-input plan's inputs).
    speeds, accels : array_like (n_inputs,), optional
        Input rates (default: the drivers' speeds, no input acceleration): they set the inertia loads.
    friction : bool
        Include the file's Coulomb friction (``[dynamics]`` friction radii and coefficients).
    point_loads : sequence of (point, force), optional
        Extra forces (N, frame coordinates, arrays (..., 2) broadcasting to the batch), each acting at a
        point on its earliest-solved body, e.g. a foot's ground reaction (:func:`assur.kinetostatics.gait_forces`).
    state : State, optional
        An already solved state of the same plan, params and inputs (order 2).
    method : {'groups', 'matrix'}
        Group by group with the dyads' closed forms, or the global Newton–Euler matrix.

    Returns
    -------
    Forces
        See :mod:`assur.kinetostatics.result` for the shapes and the sign convention.
    """
    if method not in METHODS:
        raise SpecError([("method", f"must be one of {', '.join(METHODS)}: {method!r}")])
    if isinstance(plan, SpatialPlan):
        from .spatial import spatial_forces
        return spatial_forces(plan, params, inputs, speeds=speeds, accels=accels, state=state,
                              tolerances=tolerances)
    if not isinstance(plan, PlanarPlan):
        raise TypeError(f"forces needs a plan from assur.compile, not {type(plan).__name__}")
    if state is None:
        state = solve(plan, params, inputs, speeds=speeds, accels=accels, order=2, backend=backend,
                      tolerances=tolerances)
    params = np.broadcast_to(state.params, state.shape + (plan.n_params,))
    tables = force_tables(plan)
    mo = body_motion(tables, state, params)
    inputs = np.broadcast_to(state.inputs, state.shape + (plan.n_inputs,))

    def one_pass(previous=None):
        W = Wrenches(tables, mo, params, state.shape)
        apply_body_loads(W, inputs)
        for point, force in point_loads or ():
            f = np.asarray(force, dtype=float)
            W.add(point_body(tables, point), f[..., 0] + 1j * f[..., 1], mo.z[..., plan.point_index(point)])
        if previous is not None:
            friction_loads(W, previous)
        if method == "groups":
            cond = solve_groups(W)
        else:
            bodies = tuple(range(1, tables.n_bodies))
            cond = solve_group_linear(W, bodies, list(tables.pairs))
        return W, cond

    W, cond = one_pass()
    iterations, converged = 0, True
    if friction and tables.dynamics.friction.any:
        converged = False
        lam = _stack(W)
        for iterations in range(1, tolerances.friction_iterations + 1):
            W, cond = one_pass(W)
            new = _stack(W)
            with np.errstate(invalid="ignore"):
                change = np.nanmax(np.abs(new - lam), initial=0.0)
                size = np.nanmax(np.abs(new), initial=0.0)
            lam = new
            if change <= tolerances.friction_change * max(size, 1e-300):
                converged = True
                break
    return _result(plan, tables, W, mo, state, cond, iterations, converged, method, tolerances)


def _stack(W) -> np.ndarray:
    return np.stack([np.asarray(v, dtype=float) * np.ones(W.shape) for v in W.lam], axis=-1)


def _result(plan, tables, W, mo, state, cond, iterations, converged, method, tol) -> Forces:
    shape = state.shape
    lam = _stack(W)
    singular = np.asarray(state.valid) & ~(cond >= tol.force_condition)
    singular |= np.asarray(state.valid) & ~np.all(np.isfinite(lam), axis=-1)
    ok = np.asarray(state.valid) & ~singular
    n = len(tables.pairs)
    reactions = np.full(shape + (n, 2), np.nan)
    couples = np.zeros(shape + (n,))
    normal = np.full(shape + (n,), np.nan)
    frame_f = np.zeros(shape, complex)
    frame_m = np.zeros(shape)
    for k, fp in enumerate(tables.pairs):
        basis = W.basis(fp)
        f = sum(lam[..., c] * b[0] for c, b in zip(fp.columns, basis))
        mom = sum(lam[..., c] * b[1] for c, b in zip(fp.columns, basis))
        if fp.kind == "R":
            reactions[..., k, 0], reactions[..., k, 1] = lam[..., fp.columns[0]], lam[..., fp.columns[1]]
        elif fp.kind == "P":
            nf = lam[..., fp.columns[0]] * basis[0][0]
            reactions[..., k, 0], reactions[..., k, 1] = nf.real, nf.imag
            normal[..., k] = lam[..., fp.columns[0]]
            couples[..., k] = lam[..., fp.columns[1]]
        else:
            reactions[..., k, :] = 0.0
            couples[..., k] = lam[..., fp.columns[0]]
        if fp.earlier == 0:
            frame_f = frame_f - f
            frame_m = frame_m - mom
    driver = np.empty(shape + (plan.n_inputs,))
    for i, k in enumerate(tables.driver_pairs):
        fp = tables.pairs[k]
        if fp.kind == "T":
            sense = next(st.sense for st in plan.crank_steps() if st.input == i)
            driver[..., i] = sense * lam[..., fp.columns[0]]
        else:
            driver[..., i] = lam[..., fp.columns[2]]
    qdot = np.asarray(state.qdot, dtype=float)
    power = np.einsum("...k,...k->...", driver, np.broadcast_to(qdot, driver.shape))
    bad = ~ok

    def masked(a, extra):
        return np.where(bad.reshape(shape + (1,) * extra), np.nan, a)

    names = plan.body_names
    return Forces(plan=plan, inputs=np.broadcast_to(state.inputs, shape + (plan.n_inputs,)), qdot=qdot,
                  pair_kinds=tuple(fp.kind for fp in tables.pairs), pair_names=tuple(fp.name for fp in tables.pairs),
                  pair_bodies=tuple((names[fp.earlier], names[fp.later]) for fp in tables.pairs),
                  reactions=masked(reactions, 2), couples=masked(couples, 1), normal=masked(normal, 1),
                  driver=masked(driver, 1), power=masked(power, 0),
                  frame_force=masked(np.stack([frame_f.real, frame_f.imag], axis=-1), 1),
                  frame_moment=masked(frame_m, 0), condition=np.where(np.asarray(state.valid), cond, np.nan),
                  valid=ok, singular=singular, iterations=iterations, converged=converged, method=method,
                  state=state)
