"""``assur.forces(plan, params, inputs, …)``: kinetostatics of a batch, by Assur groups.

The state is solved (or taken) with order 2; the applied loads (gravity, d'Alembert inertia, the
file's loads, extra point loads such as a walking leg's ground reaction) go on the bodies; the groups
are solved from the last back to the drivers (:mod:`.groups`). ``method="matrix"`` solves the global
Newton–Euler matrix of every moving body at once instead: the test oracle and the fallback.
Friction (optional) is a fixed-point iteration on the reactions.
"""
from __future__ import annotations

import numpy as np

import math

from ..engine import solve
from ..engine.options import AUTO_COMPILE_MIN_SAMPLES, AUTO_COMPILED_MIN_SAMPLES
from ..engine.plan import SpatialPlan, require_plan
from ..errors import SpecError, one_of
from ..tolerances import DEFAULT
from . import kernel as K
from .groups import body_rows, solve_rows
from .loads import add_items, applied_items, friction_loads
from .program import program_of
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
    point_loads : sequence of (point, force) or (point, force, link), optional
        Extra forces (N, frame coordinates, arrays (..., 2) broadcasting to the batch), each acting at a
        point on ``link`` or, without one, on the one body there or the slider there (the rule of a file's
        ``[[loads]]``, docs/format.md), e.g. a foot's ground reaction (:func:`assur.kinetostatics.gait_forces`).
    state : State, optional
        An already solved state of the same plan, params and inputs (order 2).
    method : {'groups', 'matrix'}
        Group by group with the dyads' closed forms, or the global Newton–Euler matrix.

    Returns
    -------
    Forces
        See :mod:`assur.kinetostatics.result` for the shapes and the sign convention.
    """
    require_plan(plan)
    if not one_of(backend, ("auto", "numpy", "numba")):
        raise SpecError([("backend", f"must be one of auto, numpy, numba: {backend!r}")])
    if not one_of(method, METHODS):
        raise SpecError([("method", f"must be one of {', '.join(METHODS)}: {method!r}")])
    point_loads = _check_point_loads(plan, point_loads)
    if isinstance(plan, SpatialPlan):
        dyn = plan.mechanism.dynamics
        if point_loads:
            raise SpecError([("point_loads", "extra point loads are not modelled for spatial mechanisms: give them "
                                             "as [[loads]] in the file")])
        if friction and dyn is not None and dyn.friction.any:
            raise SpecError([("dynamics.friction", "friction is not modelled for spatial mechanisms (planar only)")])
        from .spatial import spatial_forces
        return spatial_forces(plan, params, inputs, speeds=speeds, accels=accels, state=state,
                              tolerances=tolerances)
    if state is None:
        state = solve(plan, params, inputs, speeds=speeds, accels=accels, order=2, backend=backend,
                      tolerances=tolerances)
    elif state.acc is None:
        raise SpecError([("state", "the force analysis needs accelerations: solve the state with order=2")])
    shape = state.shape
    n = math.prod(shape)
    if n == 0:
        raise SpecError([("inputs", f"no sample to analyse: the batch is empty (shape {shape}); give at least one "
                                    "input value")])
    tables, prog = force_tables(plan), program_of(plan)
    with_friction = bool(friction) and tables.dynamics.friction.any
    plain = prog.compiled_ok and prog.loads_in_kernel and not point_loads and not with_friction and method == "groups"
    from . import compiled
    if plain and backend != "numpy" and (backend == "numba" or n >= AUTO_COMPILE_MIN_SAMPLES or (
            n >= AUTO_COMPILED_MIN_SAMPLES and compiled.kernel_ready(plan, prog))):
        out = compiled.solve_compiled(prog, state, required=backend == "numba")
        if out is not None:
            return _result(plan, state, *out, iterations=0, converged=True, method=method, tol=tolerances)
    return _solve_numpy(plan, tables, prog, state, point_loads, with_friction, method, tolerances)


def _check_point_loads(plan, point_loads):
    """``point_loads`` as a list of (point, force) or (point, force, link) tuples, else SpecError naming the entry
    (a point the plan does not have included)."""
    if point_loads is None or (isinstance(point_loads, (list, tuple)) and not point_loads):
        return None
    if isinstance(point_loads, (str, bytes, dict)) or not hasattr(point_loads, "__iter__"):
        raise SpecError([("point_loads", f"must be a list of (point, force) or (point, force, link): "
                                         f"{point_loads!r:.60}")])
    out = []
    for j, entry in enumerate(point_loads):
        if (not isinstance(entry, (list, tuple)) or len(entry) not in (2, 3) or not isinstance(entry[0], str)
                or (len(entry) == 3 and not isinstance(entry[2], str))):
            raise SpecError([(f"point_loads[{j}]", f"must be (point, force) or (point, force, link) with names as "
                                                   f"text: {entry!r:.60}")])
        if entry[0] not in plan.point_names:
            raise SpecError([(f"point_loads[{j}]", f"unknown point {entry[0]!r} (known: {', '.join(plan.point_names)})")])
        from ..errors import float_array
        float_array(entry[1], f"point_loads[{j}]", "a force (N): [fx, fy] numbers")
        out.append(tuple(entry))
    return out


def state_rows(state, n):
    """The state's points as rows: z, v, a (n_points, N) complex, and the parameters (n_params, N or 1)."""
    def rows(x):
        x = np.reshape(x, (n,) + x.shape[-2:])
        return (x[..., 0] + 1j * x[..., 1]).T
    params = np.asarray(state.params, dtype=float)
    if params.ndim == 1:
        p = params[:, None]
    else:
        p = np.broadcast_to(params, state.shape + params.shape[-1:]).reshape(n, -1).T
    return rows(state.pos), rows(state.vel), rows(state.acc), p


def _solve_numpy(plan, tables, prog, state, point_loads, with_friction, method, tol):
    shape = state.shape
    n = math.prod(shape)
    z, v, a, p = state_rows(state, n)
    nb = tables.n_bodies
    F0, M0 = np.zeros((nb, n), complex), np.zeros((nb, n))
    q0 = np.broadcast_to(state.inputs, shape + (plan.n_inputs,)).reshape(n, -1)[:, 0]
    if not prog.loads_in_kernel or point_loads:        # loads that vary need the bodies' motion first
        orient, omega, alpha = body_rows(prog, z, v, a, p)
        with np.errstate(all="ignore"):
            add_items(applied_items(tables, prog, z, v, a, p, orient, omega, alpha, q0, point_loads, shape,
                                    kernel_loads=False), F0, M0)
    lam, orient, omega, alpha, cond = solve_rows(prog, z, v, a, p, F0.copy(), M0.copy(), method=method,
                                                length_scale=plan.length_scale)
    iterations, converged = 0, True
    if with_friction:
        converged = False
        for iterations in range(1, tol.friction_iterations + 1):
            F, M = F0.copy(), M0.copy()
            with np.errstate(all="ignore"):
                friction_loads(tables, prog, z, v, p, orient, omega, lam, F, M)
            new, orient, omega, alpha, cond = solve_rows(prog, z, v, a, p, F, M, method=method,
                                                        length_scale=plan.length_scale)
            with np.errstate(invalid="ignore"):
                change = np.nanmax(np.abs(new - lam), initial=0.0)
                size = np.nanmax(np.abs(new), initial=0.0)
            lam = new
            if change <= tol.friction_change * max(size, 1e-300):
                converged = True
                break
    n_pairs, n_slides = prog.pr.shape[0], int(np.sum(prog.slide_of >= 0))
    reac, slides = np.empty((n_pairs, 2, n)), np.empty((n_slides, 2, n))
    frame, driver = np.empty((3, n)), np.empty((plan.n_inputs, n))
    with np.errstate(all="ignore"):
        K.outputs(prog.pr, prog.ln, prog.drv, prog.sense, prog.slide_of, z, p, orient, lam, reac, slides, frame,
                  driver)
    reac, driver, gears, cams = np.moveaxis(reac, -1, 0), driver.T.copy(), None, None
    slides = np.moveaxis(slides, -1, 0)
    if plan.cam_slots:                               # before the gears: a cam's drive may be a gear's torque
        from .camming import cam_forces
        with np.errstate(all="ignore"):
            cams = cam_forces(plan, tables, state, lam, reac, slides, driver, prog.slide_of)
    if plan.gear_slots:
        from .gearing import gear_forces
        inputs = np.broadcast_to(state.inputs, shape + (plan.n_inputs,)).reshape(n, -1)
        with np.errstate(all="ignore"):
            gears = gear_forces(plan, tables, z, inputs, lam, reac, driver)
    return _result(plan, state, reac, slides, frame.T, driver, cond,
                   lam.T, iterations=iterations, converged=converged, method=method, tol=tol, gears=gears, cams=cams)


def _result(plan, state, reac, slides, frame, driver, cond, lam, *, iterations, converged, method, tol,
            gears=None, cams=None) -> Forces:
    """The Forces of flat arrays (N, …): singular samples (a group's condition below the tolerance, or a
    non-finite unknown) and unassembled ones are NaN."""
    shape = state.shape
    valid = np.asarray(state.valid).reshape(-1)
    with np.errstate(invalid="ignore"):
        singular = valid & ~(cond >= tol.force_condition)
        singular |= valid & ~np.all(np.isfinite(lam), axis=-1)
    bad = ~valid | singular
    if bad.any():
        for arr in (reac, slides, frame, driver):
            arr[bad] = np.nan
    qdot = np.asarray(state.qdot, dtype=float)
    driver = driver.reshape(shape + (plan.n_inputs,))
    power = np.einsum("...k,...k->...", driver, np.broadcast_to(qdot, driver.shape))
    tables, prog = force_tables(plan), program_of(plan)
    names = plan.body_names
    n_pairs = len(tables.pairs)
    rows = tuple(int(k) for k in np.flatnonzero(prog.slide_of >= 0))
    return Forces(plan=plan, inputs=np.broadcast_to(state.inputs, shape + (plan.n_inputs,)), qdot=qdot,
                  pair_kinds=tuple(fp.kind for fp in tables.pairs), pair_names=tuple(fp.name for fp in tables.pairs),
                  pair_bodies=tuple((names[fp.earlier], names[fp.later]) for fp in tables.pairs),
                  reactions=reac.reshape(shape + (n_pairs, 2)), driver=driver, power=power,
                  frame_force=frame[:, :2].reshape(shape + (2,)), frame_moment=frame[:, 2].reshape(shape),
                  condition=np.where(valid, cond, np.nan).reshape(shape), valid=(valid & ~singular).reshape(shape),
                  singular=singular.reshape(shape), iterations=iterations, converged=converged, method=method,
                  state=state, slides=(rows, slides.reshape(shape + (len(rows), 2))),
                  gears={name: {k: np.where(bad, np.nan, v).reshape(shape) for k, v in g.items()}
                         for name, g in (gears or {}).items()},
                  cams={name: {k: (np.where(bad, False, v) if v.dtype == bool else np.where(bad, np.nan, v)).reshape(shape)
                               for k, v in g.items()} for name, g in (cams or {}).items()})
