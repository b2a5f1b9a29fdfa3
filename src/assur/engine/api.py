"""The engine's two verbs: ``compile(mechanism) → plan`` and ``solve(plan, …) → state``, with one
dispatch on the plan's type and one check of the options for planar and spatial plans alike."""
from __future__ import annotations

import contextlib
import math
import sys

import numpy as np

from ..errors import SpecError
from ..model.mechanism import Mechanism
from ..tolerances import DEFAULT
from .options import (AUTO_CACHED_MIN_SAMPLES, AUTO_COMPILE_MIN_SAMPLES, AUTO_COMPILED_MIN_SAMPLES,
                      AUTO_NEWTON_COMPILE_MIN_SAMPLES, check_options, prepare_batch)
from .plan import PlanarPlan, SpatialPlan, require_mechanism, require_plan
from .planar import numba_backend
from .planar.compile import compile_planar
from .planar.numpy_backend import finish, solve_numpy
from .spatial.compile import compile_spatial
from .spatial.numpy_backend import solve_spatial

#: the compiler of each dimension
COMPILERS = {2: compile_planar, 3: compile_spatial}


def compile(m: Mechanism, *, tolerances=DEFAULT, structure=None):  # noqa: A001 - the public verb
    """Compile a mechanism into a solve plan (:class:`PlanarPlan` or :class:`SpatialPlan`, by its
    ``dimension``). Raises StructureError / SpecError with the location of every problem. ``structure``: the
    mechanism's ``assur.structure.assur.analyse(m)`` when the caller has it already (planar only)."""
    require_mechanism(m)
    if structure is not None and m.dimension == 2:
        return compile_planar(m, tolerances=tolerances, structure=structure)
    return COMPILERS[m.dimension](m, tolerances=tolerances)


def solve(plan, params=None, inputs=None, *, speeds=None, accels=None, order: int = 2,
          on_unbuildable: str = "nan", method: str = "closed", backend: str = "auto", tolerances=DEFAULT,
          sweep: bool = False):
    """Solve positions (and, with ``order`` ≥ 1/2, velocities and accelerations) of every point.

    Parameters
    ----------
    plan : PlanarPlan or SpatialPlan
    params : array_like (..., n_params), optional
        Design parameters (default: the file's).
    inputs : array_like (..., n_inputs), optional
        Input values (crank angles in rad, actuator lengths in m); for a single-input plan a scalar
        or a 1-D array is a batch of values. Leading axes broadcast against those of ``params``.
    speeds, accels : array_like (..., n_inputs), optional
        Input rates (default: the drivers' speeds, zero input acceleration).
    order : {0, 1, 2}
        Highest time derivative solved.
    on_unbuildable : {'nan', 'warn', 'raise'}
        Unassemblable samples are NaN with ``valid`` False; 'warn' also warns with the count,
        'raise' raises :class:`~assur.errors.UnbuildableError`.
    method : {'closed', 'newton'}
        The groups' closed forms, or the batched Newton oracle for every group.
    backend : {'auto', 'numpy', 'numba'}
        'numba' is the fused compiled loop (:mod:`assur.engine.planar.numba_backend`; plans and
        batches it does not cover fall back to numpy; spatial plans always use numpy), 'auto' uses it
        when numba is installed for batches of at least ``AUTO_COMPILED_MIN_SAMPLES`` samples whose kernel
        is compiled already (in this process or in the disk cache) — for a plan with Newton-solved groups from
        ``AUTO_CACHED_MIN_SAMPLES`` when besides numba is imported already (the kernel then costs nothing to
        start) — and compiles it first only for a batch of ``AUTO_COMPILE_MIN_SAMPLES`` (a compile costs
        seconds; ``AUTO_NEWTON_COMPILE_MIN_SAMPLES`` for a plan with Newton-solved groups, whose kernels follow
        the same certified continuation: :mod:`assur.engine.planar.newton_kernels`). Both give the same numbers
        (and the same valid samples) to round-off.
    sweep : bool
        The inputs along the last batch axis are one turn of the plan's single crank, the same for every design
        (a cycle): Newton-solved groups are then swept through the samples in turn instead of continued from the
        sketch one by one (:mod:`assur.engine.planar.sweep`; much faster, the same positions to the Newton
        tolerance). Ignored where it does not apply.

    Returns
    -------
    State or SpatialState
        ``pos (..., n_points, dim)``, ``vel``, ``acc``, ``dpos_dq``, ``d2pos_dq2``, ``valid (...)`` …
    """
    require_plan(plan)
    check_options(on_unbuildable, method, order, backend)
    params, inputs = prepare_batch(plan, params, inputs)
    shape = np.broadcast_shapes(params.shape[:-1], inputs.shape[:-1])
    if isinstance(plan, SpatialPlan):
        return solve_spatial(plan, params, inputs, shape, speeds, accels, order, on_unbuildable, tolerances, method)
    size = math.prod(shape)
    # an infinite or NaN input is a sample that cannot be assembled: its angle's cosine and remainder are NaN
    # without numpy's warnings
    with np.errstate(invalid="ignore") if not np.all(np.isfinite(inputs)) else contextlib.nullcontext():
        if method == "closed" and (backend == "numba" or (backend == "auto"
                                                          and _compiled_pays(plan, size, order, sweep))):
            state = _solve_compiled(plan, params, inputs, shape, speeds, accels, order, on_unbuildable, tolerances,
                                    required=backend == "numba", sweep=sweep)
            if state is not None:
                return state
        return solve_numpy(plan, params, inputs, shape, speeds, accels, order, on_unbuildable, tolerances, method,
                           sweep=sweep)


def assemblies(plan, inputs=None, params=None, *, tolerances=DEFAULT) -> list:
    """Every real assembly of the mechanism at each input: all combinations of its groups' assemblies (a dyad's two
    closed-form branches, a triad's polynomial roots, any other group's certified one-parameter reduction; docs/
    assemblies.md).

    Parameters
    ----------
    plan : PlanarPlan
    inputs : array_like (..., n_inputs), optional
        Input values (default: the sketch's); for a single-input plan a scalar or a 1-D array is a batch of values.
    params : array_like (n_params,), optional
        One design (default: the file's).

    Returns
    -------
    list of list of :class:`~assur.engine.planar.assemblies.Assembly`
        One list per input (the batch flattened in C order), each assembly with its branch identity, its positions
        ``pos (n_points, 2)``, its bodies' orientations ``angles (n_bodies,)``, whether it is the one :func:`solve` returns there (``sketch``), its loop closure and
        whether the enumeration certified it.
    """
    from .planar.assemblies import enumerate_assemblies
    if not isinstance(plan, PlanarPlan):
        raise SpecError([("plan", "assemblies are enumerated for planar mechanisms (a spatial R–S–S dyad has its two "
                                  "branches: SpatialPlan.with_branch)")])
    params, inputs = prepare_batch(plan, params, inputs)
    if params.shape != (plan.n_params,):
        raise SpecError([("params", f"must be one design of {plan.n_params} parameters: shape {params.shape}")])
    flat = inputs.reshape(-1, plan.n_inputs)
    state = solve(plan, params, flat, order=0, tolerances=tolerances)
    solved, angles = state.pos, state.body_angle
    return [enumerate_assemblies(plan, params, q, tolerances, solved[i], angles[i]) for i, q in enumerate(flat)]


def _compiled_pays(plan, size: int, order: int, sweep: bool = False) -> bool:
    """backend="auto": the compiled kernel for a batch of ``size`` samples when it costs nothing to start and the
    batch is large enough to gain from it (compiled already, in this process or the disk cache, from
    ``AUTO_COMPILED_MIN_SAMPLES`` samples; a plan with Newton-solved groups, whose numpy path costs a thousand times
    more, from ``AUTO_CACHED_MIN_SAMPLES`` once numba is imported), or when the batch alone wins back a first compile (engine/options.py). A plan
    with Newton-solved groups costs numpy about a thousand times more per sample: its kernel is compiled first from
    ``AUTO_NEWTON_COMPILE_MIN_SAMPLES`` samples."""
    if size >= (AUTO_NEWTON_COMPILE_MIN_SAMPLES if numba_backend.newton_covers(plan) else AUTO_COMPILE_MIN_SAMPLES):
        return numba_backend.available()
    newton = numba_backend.newton_covers(plan)
    if size < (AUTO_CACHED_MIN_SAMPLES if newton and "numba" in sys.modules else AUTO_COMPILED_MIN_SAMPLES):
        return False
    return numba_backend.kernel_ready(plan, False, order, sweep)


def _solve_compiled(plan, params, inputs, shape, speeds, accels, order, on_unbuildable, tol, required, sweep=False):
    """The compiled backend, or None where it does not apply (numba missing and not required,
    a plan or batch layout it does not cover)."""
    if not (required or numba_backend.available()):
        return None
    if numba_backend.newton_covers(plan):
        return _solve_newton(plan, params, inputs, shape, speeds, accels, order, on_unbuildable, tol, sweep)
    n = plan.n_inputs
    qdot = plan.speeds if speeds is None else np.asarray(speeds, dtype=float)
    qddot = np.zeros(n) if accels is None else np.asarray(accels, dtype=float)
    if qdot.shape != (n,) or qddot.shape != (n,):      # rates per sample: the numpy backend's
        return None
    # one scalar nonzero speed: the kernel writes velocities and accelerations directly
    time_mode = qdot.shape == (1,) and qddot.shape == (1,) and qdot[0] != 0
    rates = (qdot[0], qdot[0] ** 2, qddot[0]) if time_mode else (1.0, 1.0, 0.0)
    compiled = numba_backend.solve_compiled(plan, params, inputs, tol.radicand, rates, order=order, shape=shape)
    if compiled is None:
        return None
    buffer, (pos, first, second), valid = compiled   # valid includes "every position is finite"
    if not valid.all():
        buffer[:, ~valid.reshape(buffer.shape[1:])] = np.nan
    xyz = (pos, first if order >= 1 else None, second if order >= 2 else None)

    def complete():
        """The numpy backend's full state (body orientations), solved on first use."""
        return solve(plan, params, inputs, speeds=qdot, accels=qddot, order=order, backend="numpy", tolerances=tol)

    return finish(plan, params, inputs, shape, None, None, None, valid, speeds, accels, on_unbuildable,
                  complete=complete, xyz=xyz, xyz_time=time_mode)


def _solve_newton(plan, params, inputs, shape, speeds, accels, order, on_unbuildable, tol, sweep=False):
    """A plan with Newton-solved groups by its compiled sweep (:func:`numba_backend.solve_newton`): the points'
    values, velocities and accelerations (at one scalar nonzero speed; else the analogues) as the State's float
    views; the bodies' orientations from the same buffer on first use."""
    qdot = plan.speeds if speeds is None else np.asarray(speeds, dtype=float)
    qddot = np.zeros(plan.n_inputs) if accels is None else np.asarray(accels, dtype=float)
    time_mode = qdot.shape == (1,) and qddot.shape == (1,) and qdot[0] != 0
    w, a = (float(qdot[0]), float(qddot[0])) if time_mode else (1.0, 0.0)
    buffer, (pos, first, second), valid, ambiguous = numba_backend.solve_newton(plan, params, inputs, tol, shape,
                                                                     (w, w * w, a), sweep)
    if not valid.all():
        buffer[:, ~valid.reshape(buffer.shape[1:])] = np.nan
    n = len(plan.point_names)
    xyz = (pos[..., :n, :], first[..., :n, :] if order >= 1 else None, second[..., :n, :] if order >= 2 else None)

    def complete():
        """The full state (points and body orientations, complex, with their analogues) from the kernel's buffer:
        nothing solved again."""
        z, dz, d2z = (v[..., 0] + 1j * v[..., 1] for v in (pos, first, second))
        if time_mode:
            dz = dz / w
            d2z = (d2z - dz * a) / (w * w)
        return finish(plan, params, inputs, shape, z, dz[..., None] if order >= 1 else None,
                      d2z[..., None, None] if order >= 2 else None, valid, speeds, accels, "nan",
                      ambiguous=ambiguous)

    return finish(plan, params, inputs, shape, None, None, None, valid, speeds, accels, on_unbuildable,
                  complete=complete, xyz=xyz, xyz_time=time_mode, ambiguous=ambiguous)
