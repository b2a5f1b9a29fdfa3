"""The compiled backend: run a planar plan's op table in one fused numba loop.

The plan carries its op table (``plan.ops``, ``plan.slots``: :mod:`assur.engine.planar.optable`),
written at compile time; a plan without one (several inputs, PRP/PPR, driven actuators, Newton
groups) and a batch that is not laid out as designs × inputs return ``None`` here and the numpy
backend solves them. numba is imported only when this backend runs. The generated kernels and the
last set of per-design constants are cached per plan outside the (frozen) plan, in weak-keyed
dictionaries, so they go with the plan.
"""
from __future__ import annotations

import logging
import weakref

import numpy as np

from ...kernels import codegen
from ..plan import PlanarPlan
from .optable import slot_constants

#: plan → {kernel key: loaded kernel}
_KERNELS: "weakref.WeakKeyDictionary" = weakref.WeakKeyDictionary()
#: plan → (designs bytes, G): the last small set of per-design constants
_MEMO: "weakref.WeakKeyDictionary" = weakref.WeakKeyDictionary()
#: populations up to this many numbers memoise their constants (repeated solves of one design)
MEMO_MAX_VALUES = 4096
#: an INFO record "compiling a kernel for this mechanism (once, cached in …)" before numba compiles a kernel
#: that is not in its disk cache yet (the command line prints it; silent for a library user by default)
LOG = logging.getLogger("assur.compile")


def covers(plan) -> bool:
    """True when the plan has an op table (the compiled backend can solve it)."""
    return isinstance(plan, PlanarPlan) and plan.ops is not None


def available() -> bool:
    try:
        import numba  # noqa: F401
    except ImportError:
        return False
    return True


def cache_dir():
    """Where generated kernels live (:func:`assur.kernels.cache_root.cache_root`, kind 'kernels'); with the caches
    off (``ASSUR_CACHE_DIR=off``) a temporary directory of this process."""
    from ...kernels.cache_root import cache_root
    root = cache_root("kernels")
    if root is None:
        global _PROCESS_DIR
        if _PROCESS_DIR is None:
            import tempfile
            _PROCESS_DIR = tempfile.mkdtemp(prefix="assur-kernels-")
        return _PROCESS_DIR
    return root


_PROCESS_DIR = None


def _load(plan, key: str, make_source):
    """A generated kernel of the plan under ``key``: its source written once to the cache directory (a
    temporary one if that is not writable) and imported, so numba's disk cache applies."""
    kernels = _KERNELS.setdefault(plan, {})
    k = kernels.get(key)
    if k is None:
        src = make_source()
        try:
            k = codegen.load_kernel(src, cache_dir())
        except OSError:
            import tempfile
            from pathlib import Path
            k = codegen.load_kernel(src, Path(tempfile.gettempdir()) / "assur-kernels")
        if not _compiled(k):
            import os
            LOG.info("compiling a kernel for this mechanism (once, cached in %s)",
                     os.path.dirname(k.py_func.__code__.co_filename))
        kernels[key] = k
    return k


def _compiled(k) -> bool:
    """True when the numba dispatcher ``k`` is compiled in this process or has an index in numba's cache
    beside its module (``__pycache__/<module>.<function>-<line>.py<version>.nbi``)."""
    if k.signatures:
        return True
    from pathlib import Path
    module = Path(k.py_func.__code__.co_filename)
    return any((module.parent / "__pycache__").glob(f"{module.stem}.*.nbi"))


def kernel(plan, with_bodies: bool, order: int = 2):
    """The plan's generated straight-line kernel for a derivative order (compiled once, cached on
    disk by numba)."""
    key = f"{'bodies' if with_bodies else 'points'}_{order}"
    point_out = list(range(len(plan.point_names)))
    body_out = list(range(len(plan.body_names))) if with_bodies else []
    return _load(plan, key, lambda: codegen.generate_source(plan.ops, point_out, body_out, order))


def _constants(plan, designs: np.ndarray) -> np.ndarray:
    """The kernel's per-design constants G (n_designs, n_slots, 2); the last small set is memoised."""
    key = designs.tobytes() if designs.size <= MEMO_MAX_VALUES else None
    memo = _MEMO.get(plan)
    if key is not None and memo is not None and memo[0] == key:
        return memo[1]
    G = slot_constants(plan, designs)
    if key is not None:
        G.setflags(write=False)
        _MEMO[plan] = (key, G)
    return G


def path_objective(plan, params: np.ndarray, target_inputs: np.ndarray, target_xy: np.ndarray,
                   point: str, cycle_inputs: np.ndarray | None, tol: float):
    """Fused reduction of a path-synthesis objective; None if the plan is not covered.

    params (D, n_params); target_inputs (D or 1, N) input angles at the targets; target_xy (N, 2);
    cycle_inputs (M,) or None. Returns (D, 5): Σ squared distance, Σ distance (over the assembled
    targets), the number of targets and of cycle samples that cannot be assembled, and the sum over
    the cycle of the groups' shortfalls past their toggles (normalised radicands below −tol).
    """
    if not covers(plan):
        return None
    idx = plan.point_index(point)
    kern = _load(plan, f"objective_{idx}", lambda: codegen.generate_objective_source(plan.ops, idx))
    designs = np.ascontiguousarray(params, dtype=float)
    G = _constants(plan, designs)
    q = np.ascontiguousarray(target_inputs, dtype=float)
    cyc = np.zeros(0) if cycle_inputs is None else np.ascontiguousarray(cycle_inputs, dtype=float)
    out = np.empty((designs.shape[0], 5))
    kern(G, np.cos(q), np.sin(q), np.ascontiguousarray(target_xy, dtype=float), np.cos(cyc), np.sin(cyc), tol, out)
    return out


def cycle_covers(plan, transmission: bool = False) -> bool:
    """True when :func:`cycle_objective` covers the plan: an op table, and for the transmission angle only
    RRR dyads (the angle of RRP and RPR dyads needs a slide's direction: the numpy route computes it)."""
    return covers(plan) and not (transmission and any(st.kind in ("RRP", "RPR") for st in plan.steps))


def cycle_objective(plan, params: np.ndarray, cycle_inputs: np.ndarray, tol: float, *, foot: str | None = None,
                    ground=(1.0, 0.0), up=(0.0, 1.0), omega: float = 1.0, scale: float = 1.0,
                    path: str | None = None, target_xy=None, transmission: bool = False):
    """Fused reduction of the whole-cycle quantities of a population; None if the plan is not covered.

    params (D, n_params); cycle_inputs (M,) one uniform turn. Returns (D, 12 + N), the columns of
    :data:`assur.kernels.codegen.CYCLE_COLUMNS`: the unassembled samples and the groups' summed shortfall
    past their toggles; with ``transmission`` the smallest RRR transmission angle (rad, folded to [0, π/2]);
    with ``foot`` the sampled gait terms of :func:`assur.analysis.gait.population_gait` (``ground``, ``up``,
    ``omega``, ``scale`` as there); with ``path`` and ``target_xy (N, 2)`` the distance of each target to the
    closed polyline of that point's samples (SI), in the N last columns. NaN where a term does not apply.
    """
    if not cycle_covers(plan, transmission):
        return None
    fi = -1 if foot is None else plan.point_index(foot)
    pi = -1 if path is None else plan.point_index(path)
    dyads = tuple((plan.point_index(st.point_a), plan.point_index(st.joint), plan.point_index(st.point_b))
                  for st in plan.steps if st.kind == "RRR") if transmission else ()
    key = f"cycle_{fi}_{pi}_" + "_".join("-".join(map(str, t)) for t in dyads)
    kern = _load(plan, key, lambda: codegen.generate_cycle_source(plan.ops, fi, pi, dyads))
    designs = np.ascontiguousarray(params, dtype=float)
    G = _constants(plan, designs)
    q = np.ascontiguousarray(cycle_inputs, dtype=float)
    txy = np.zeros((0, 2)) if target_xy is None or path is None else np.ascontiguousarray(target_xy, dtype=float)
    out = np.empty((designs.shape[0], codegen.PATH_COLUMN + len(txy)))
    kern(G, np.cos(q), np.sin(q), float(tol), np.asarray(ground, dtype=float), np.asarray(up, dtype=float),
         float(omega), float(scale), txy, out)
    if not dyads:
        out[:, 2] = np.nan
    return out


def separable(pshape: tuple, ishape: tuple, shape: tuple):
    """Split the batch shape into (design axes, input axes): the params vary only over the leading
    axes and the inputs only over the trailing ones. Returns k (the split) or None."""
    n = len(shape)
    ps = (1,) * (n - len(pshape)) + tuple(pshape)
    qs = (1,) * (n - len(ishape)) + tuple(ishape)
    for k in range(n + 1):
        if all(x == 1 for x in ps[k:]) and all(x == 1 for x in qs[:k]):
            return k
    return None


def solve_compiled(plan, params: np.ndarray, inputs: np.ndarray, tol: float,
                   rates=(1.0, 1.0, 0.0), with_bodies: bool = False, order: int = 2, shape=None):
    """Run the plan's kernel; None if the plan or the batch layout is not covered.

    params (..., n_params), inputs (..., 1); shapes broadcast to ``shape``; the params must vary
    over leading axes only and the inputs over trailing axes only (designs × inputs). Returns
    ``(buffer (6·n_out, D, N), (pos, first, second), valid)`` where the three are float views
    (shape + (n_out, 2)) of the buffer: the position and, with ``rates = (w1, w2, w3)``,
    ``w1·d/dq`` and ``w2·d²/dq² + w3·d/dq`` (velocity and acceleration for (ω, ω², α)).
    """
    if not covers(plan):
        return None
    if shape is None:
        shape = np.broadcast_shapes(params.shape[:-1], inputs.shape[:-1])
    k = separable(params.shape[:-1], inputs.shape[:-1], shape)
    if k is None:
        return None
    n, n_params = len(shape), params.shape[-1]
    lead, trail = shape[:k], shape[k:]
    if params.ndim == 1:                       # one design (the common single-design call)
        designs = params.reshape(1, n_params)
    else:
        p_pad = params.reshape((1,) * (n - (params.ndim - 1)) + params.shape)
        designs = np.broadcast_to(p_pad[(slice(None),) * k + (0,) * (n - k)], lead + (n_params,))
        designs = np.ascontiguousarray(designs.reshape(-1, n_params))
    if inputs.shape[:-1] == trail:
        q = np.ascontiguousarray(inputs.reshape(-1), dtype=float)
    else:
        q_pad = inputs[..., 0].reshape((1,) * (n - (inputs.ndim - 1)) + inputs.shape[:-1])
        q = np.ascontiguousarray(np.broadcast_to(q_pad[(0,) * k], trail).reshape(-1), dtype=float)
    G = _constants(plan, designs)
    cq, sq = np.cos(q), np.sin(q)
    n_out = len(plan.point_names) + (len(plan.body_names) if with_bodies else 0)
    D, N = designs.shape[0], q.size
    out = np.empty((6 * n_out, D, N))         # rows of derivatives above ``order`` stay unwritten
    valid = np.empty((D, N), dtype=np.bool_)
    w1, w2, w3 = (float(r) for r in rates)
    kernel(plan, with_bodies, order)(G, cq, sq, tol, w1, w2, w3, out, valid)
    rows = out.reshape((n_out, 6) + shape)
    axes = tuple(range(2, 2 + n)) + (0, 1)     # (n_out, 2, *shape) → (*shape, n_out, 2), a view
    views = tuple(rows[:, 2 * j:2 * j + 2].transpose(axes) for j in range(3))
    return out, views, valid.reshape(shape)
