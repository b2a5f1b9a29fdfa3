"""The compiled backend: a planar plan's kinematics as fused numba loops over designs × inputs.

The kernels are generated per plan by the package's one code generator: the plan's step executors are traced on
symbols (:mod:`assur.engine.planar.traced`: the numpy backend's own closed forms and jets) and wrapped in loops by
:mod:`assur.kernels.codegen`, which also loads and caches them. A plan with Newton-solved groups has its own kernels
(:mod:`.newton_kernels`: the numpy backend's sweep through the inputs, Newton's iterations traced from the same loop
equations). A plan that is not traced (several inputs, gears, PRP/PPR, driven actuators) and a batch of a dyad plan
that is not laid out as designs × inputs return ``None`` here and the numpy backend solves them. numba is imported
only when a kernel runs. The loaded kernels are cached per plan outside the (frozen) plan, in a weak-keyed
dictionary, so they go with the plan.
"""
from __future__ import annotations

import weakref
from dataclasses import replace

import numpy as np

from ...kernels import codegen, newton_codegen
from ...kernels.codegen import LOG, available, cache_dir  # noqa: F401  (the backend's public names)
from ...kernels.trace import SAMPLE, minimum, where
from ...tolerances import DEFAULT
from ..plan import PlanarPlan
from . import newton_kernels, traced

#: plan → {kernel key: loaded kernel}
_KERNELS: "weakref.WeakKeyDictionary" = weakref.WeakKeyDictionary()
#: plan → whether the plan is traced (:func:`covers`)
_COVERS: "weakref.WeakKeyDictionary" = weakref.WeakKeyDictionary()
#: plan → whether the plan's Newton-solved groups are traced (:func:`newton_covers`)
_NEWTON: "weakref.WeakKeyDictionary" = weakref.WeakKeyDictionary()
#: generated source → its loaded kernel: a new plan of a known structure (the designer compiles one per move) takes
#: the kernel without hashing, reading or looking up its file again
_LOADED: dict = {}


def covers(plan) -> bool:
    """True when the compiled backend can solve the plan (:func:`assur.engine.planar.traced.covers`)."""
    if not isinstance(plan, PlanarPlan):
        return False
    c = _COVERS.get(plan)
    if c is None:
        c = _COVERS[plan] = traced.covers(plan)
    return c


def newton_covers(plan) -> bool:
    """True when the plan has Newton-solved groups and the compiled backend solves it
    (:func:`.newton_kernels.covers`)."""
    if not isinstance(plan, PlanarPlan):
        return False
    c = _NEWTON.get(plan)
    if c is None:
        c = _NEWTON[plan] = newton_kernels.covers(plan)
    return c


def _newton_key(each: bool) -> str:
    return f"newton_2_{'each' if each else 'sweep'}"


def newton_cached(plan, each: bool = True) -> bool:
    """True when the plan's Newton solve kernel (``each``: :func:`.newton_kernels.solve_source`) is compiled in this
    process or in numba's disk cache (a solve then costs no compile)."""
    k = _KERNELS.get(plan, {}).get(_newton_key(each))
    if k is not None:
        return codegen.ready(k)
    source = newton_kernels.solve_source(plan, 2, each)
    k = _LOADED.get(source)
    if k is not None:
        return codegen.ready(k)
    try:
        return codegen.cached(source)
    except OSError:
        return False


def solve_newton(plan, params: np.ndarray, inputs: np.ndarray, tol, shape, rates=(1.0, 1.0, 0.0), sweep=False):
    """Solve a plan with Newton-solved groups by its compiled continuation (:func:`.newton_kernels.solve`, order 2:
    one kernel per plan whatever the order asked); None if not covered. ``tol``: the Tolerances; ``sweep``: as
    ``solve(..., sweep=True)``, the designs swept through their inputs where the batch is one turn of inputs shared
    by every design (:func:`.newton_kernels.sweeps`), else every sample continued from the sketch on its own.
    Returns ``(buffer, (pos, first, second), valid, ambiguous)`` for the points and then the bodies (views shape +
    (n_points + n_bodies, 2): the value, w1·d/dq and w2·d²/dq² + w3·d/dq for ``rates = (w1, w2, w3)``; ambiguous
    (shape): ``State.ambiguous``)."""
    if not newton_covers(plan):
        return None
    each = not (sweep and newton_kernels.sweeps(plan, params, inputs, shape))
    k = _load(plan, _newton_key(each), lambda: newton_kernels.solve_source(plan, 2, each), "a Newton kernel")
    return newton_kernels.solve(plan, params, inputs, tol, 2, shape, k, rates, each)


def prepare_newton(plan) -> bool:
    """Load the plan's Newton solve kernel of the default continuation now, compiling it if it is not cached (a long
    session, such as the designer's, calls it in a background thread: numba is then imported and the kernel ready, so
    its previews take the kernel by the automatic backend's rule). True when it had to compile; False when it only
    loaded it, or had nothing to do (numba missing, no Newton-solved group)."""
    if not (available() and newton_covers(plan)):
        return False
    compiles = not newton_cached(plan)
    solve_newton(plan, plan.defaults, np.array([plan.sketch_inputs]), DEFAULT, (1,))
    return compiles


def _load(plan, key: str, make_source, what: str = "a kernel"):
    """A generated kernel of the plan under ``key``, generated, written and compiled once (:func:`codegen.load`)."""
    kernels = _KERNELS.setdefault(plan, {})
    k = kernels.get(key)
    if k is None:
        source = make_source()
        k = _LOADED.get(source)
        if k is None:
            if len(_LOADED) > 64:
                _LOADED.clear()
            k = _LOADED[source] = codegen.load(source, what)
        kernels[key] = k
    return k


def _designs(params) -> np.ndarray:
    """``P (D, n_params)``: C-contiguous, writeable float64 (one numba signature per kernel)."""
    return np.require(params, dtype=float, requirements=["C", "W"])


def solve_source(plan, with_bodies: bool, order: int) -> str:
    """The source of the plan's solve kernel (:func:`assur.kernels.codegen.solve_source`): per point (then per body
    with ``with_bodies``) six rows — x, y of the value, of w1·d/dq and of w2·d²/dq² + w3·d/dq — of which the first
    2·(order + 1) are written; ``valid`` is the groups' flag and every written value finite."""
    t = traced.trace_plan(plan, order)
    w1, w2, w3 = (t.tracer.free(n) for n in ("w1", "w2", "w3"))
    jets = [t.pos[p] for p in plan.point_names] + (t.orient if with_bodies else [])
    rows, values = [], []
    for m, z in enumerate(jets):
        for xy, part in enumerate((np.real, np.imag)):
            v = part(z.v)
            written = [(6 * m + xy, v)]
            if order >= 1:
                written.append((6 * m + 2 + xy, part(z.d) * w1))
            if order >= 2:
                written.append((6 * m + 4 + xy, part(z.dd) * w2 + part(z.d) * w3))
            rows += written
            values.append(v)
    ok = t.finite(*[v for v in values if getattr(v, "level", 0) & SAMPLE])
    return codegen.solve_source(t.tracer, rows, ok)


def kernel_ready(plan, with_bodies: bool = False, order: int = 2, sweep: bool = False) -> bool:
    """True when the plan's kernel (:func:`kernel`, or for a plan with Newton-solved groups its Newton kernel:
    :func:`newton_cached`, ``sweep`` as in :func:`solve_newton`) runs without a compile: compiled in this process or
    found in the disk cache. False without numba or for a plan the backend does not cover."""
    if newton_covers(plan):
        return available() and newton_cached(plan, not sweep)
    if not (covers(plan) and available()):
        return False
    try:
        k = kernel(plan, with_bodies, order)
    except OSError:
        return False
    return codegen.ready(k)


def kernel(plan, with_bodies: bool, order: int = 2):
    """The plan's generated straight-line kernel for a derivative order (compiled once, cached on
    disk by numba)."""
    key = f"{'bodies' if with_bodies else 'points'}_{order}"
    return _load(plan, key, lambda: solve_source(plan, with_bodies, order))


def objective_source(plan, point: str) -> str:
    """The source of the plan's path-objective kernel for one point (:func:`assur.kernels.codegen.objective_source`):
    the squared distance of the point to the target ``txy[u]``, valid where the groups assemble and it is finite."""
    t = traced.trace_plan(plan, 0)
    z = t.pos[point].v
    dx = np.real(z) - t.tracer.load("txy[u, 0]", SAMPLE)
    dy = np.imag(z) - t.tracer.load("txy[u, 1]", SAMPLE)
    e2 = dx * dx + dy * dy
    return codegen.objective_source(t.tracer, e2, t.finite(e2), t.valid, t.deficit())


def placed_objective_source(plan, point: str) -> str:
    """The source of the plan's placed path-objective kernel for one point
    (:func:`assur.kernels.codegen.placed_objective_source`): the point's x and y, valid where the groups assemble and
    they are finite."""
    t = traced.trace_plan(plan, 0)
    z = t.pos[point].v
    x, y = np.real(z), np.imag(z)
    return codegen.placed_objective_source(t.tracer, x, y, t.finite(x + y), t.valid, t.deficit())


def path_objective(plan, params: np.ndarray, target_inputs: np.ndarray, target_xy: np.ndarray,
                   point: str, cycle_inputs: np.ndarray | None, tol: float, limits: np.ndarray | None = None,
                   rotate: bool = False):
    """Fused reduction of a path-synthesis objective; None if the plan is not covered.

    params (D, n_params); target_inputs (D or 1, N) input angles at the targets; target_xy (N, 2);
    cycle_inputs (M,) or None. Returns (D, 5): Σ squared distance, Σ distance (over the assembled
    targets), the number of targets and of cycle samples that cannot be assembled, and the sum over
    the cycle of the groups' shortfalls past their toggles (normalised radicands below −tol).

    With ``limits`` (D, 6) (:func:`assur.synthesis.placement.limits`), each design's placement is solved
    (:mod:`assur.synthesis.placement`; turned too when ``rotate``): params are the designs at their reference
    placement, and the result (D, 9) has the five columns for the placed designs, then s, φ, dx, dy.
    """
    if not covers(plan):
        return None
    placed = limits is not None
    index = plan.point_index(point)
    kern = (_load(plan, f"placed_{index}", lambda: placed_objective_source(plan, point)) if placed else
            _load(plan, f"objective_{index}", lambda: objective_source(plan, point)))
    designs = _designs(params)
    q = np.asarray(target_inputs, dtype=float)
    cyc = np.zeros(0) if cycle_inputs is None else np.asarray(cycle_inputs, dtype=float)
    out = np.empty((designs.shape[0], 9 if placed else 5))
    extra = (_designs(limits), 1.0 if rotate else 0.0) if placed else ()
    kern(designs, np.cos(q), np.sin(q), _designs(target_xy), np.cos(cyc), np.sin(cyc), float(tol), *extra, out)
    return out


def cycle_covers(plan, transmission: bool = False) -> bool:
    """True when :func:`cycle_objective` covers the plan: a traced plan (:func:`covers`, or one with Newton-solved
    groups: :func:`newton_covers`), and for the transmission angle only RRR dyads (the angle of RRP and RPR dyads
    needs a slide's direction: the numpy route computes it)."""
    return (covers(plan) or newton_covers(plan)) and not (
        transmission and any(st.kind in ("RRP", "RPR") for st in plan.steps))


def cycle_objective(plan, params: np.ndarray, cycle_inputs: np.ndarray, tol: float, *, foot: str | None = None,
                    ground=(1.0, 0.0), up=(0.0, 1.0), omega: float = 1.0, scale: float = 1.0,
                    path: str | None = None, target_xy=None, transmission: bool = False, tolerances=DEFAULT):
    """Fused reduction of the whole-cycle quantities of a population; None if the plan is not covered.

    params (D, n_params); cycle_inputs (M,) one uniform turn. Returns (D, 12 + N), the columns of
    :data:`assur.kernels.codegen.CYCLE_COLUMNS`: the unassembled samples and the groups' summed shortfall
    past their toggles; with ``transmission`` the smallest RRR transmission angle (rad, folded to [0, π/2]);
    with ``foot`` the sampled gait terms of :func:`assur.analysis.gait.population_gait` (``ground``, ``up``,
    ``omega``, ``scale`` as there); with ``path`` and ``target_xy (N, 2)`` the distance of each target to the
    closed polyline of that point's samples (SI), in the N last columns. NaN where a term does not apply. A plan with
    Newton-solved groups is swept through the turn from each design's assembly at the sketch
    (:mod:`.newton_kernels`; ``tolerances``: its Newton tolerances), as ``solve(..., sweep=True)`` solves it; its
    shortfall is 0 (a Newton-solved group has no margin).
    """
    if not cycle_covers(plan, transmission):
        return None
    newton = newton_covers(plan)
    key = f"cycle_{foot}_{path}_{transmission}"
    kern = _load(plan, key, lambda: cycle_source(plan, foot, path, transmission))
    designs = _designs(params)
    q = np.asarray(cycle_inputs, dtype=float)
    txy = np.zeros((0, 2)) if target_xy is None or path is None else _designs(target_xy)
    out = np.empty((designs.shape[0], codegen.PATH_COLUMN + len(txy)))
    extra = (_designs(ground), _designs(up), float(omega), float(scale), txy, out)
    if newton:
        kern(*newton_kernels.arguments(plan, designs, q[None, :], replace(tolerances, radicand=float(tol))), *extra)
    else:
        kern(designs, np.cos(q), np.sin(q), float(tol), *extra)
    if not (transmission and plan.steps_of("RRR")):
        out[:, 2] = np.nan
    return out


def cycle_source(plan, foot: str | None, path: str | None, transmission: bool) -> str:
    """The source of the plan's cycle kernel (:func:`assur.kernels.codegen.cycle_source`, or
    :func:`~assur.kernels.codegen.newton_cycle_source` for a plan with Newton-solved groups): its per-sample values
    traced from the plan's state — the tangent of the smallest folded transmission angle of the RRR dyads
    (|cross|/|dot| of J→A and J→B, 0 where they are parallel, +inf where the sample does not assemble), the foot's
    stride coordinate x = P·g·scale, height P·up·scale, speed |dP/dq|·omega·scale and horizontal velocity
    dP/dq·g·omega·scale, the path point's x and y."""
    newton = newton_covers(plan)
    order = 1 if foot is not None else 0
    t = traced.trace_plan(plan, order, row="p[{}]", select="select") if newton else traced.trace_plan(plan, order)
    tr = t.tracer
    worst = None
    if transmission:
        for st in plan.steps_of("RRR"):
            j = t.pos[st.joint].v
            a, b = t.pos[st.point_a].v - j, t.pos[st.point_b].v - j
            ax, ay, bx, by = np.real(a), np.imag(a), np.real(b), np.imag(b)
            tc, td = abs(ax * by - ay * bx), abs(ax * bx + ay * by)
            tan = where(t.valid, where(tc > 0.0, tc / td, 0.0), np.inf)
            worst = tan if worst is None else minimum(worst, tan)
    foot_values = None
    if foot is not None:
        g0, g1, u0, u1 = (tr.load(f"{a}[{i}]") for a in ("g", "up") for i in (0, 1))
        omega, scale = tr.free("omega"), tr.free("scale")
        z = t.pos[foot]
        x, y, dx, dy = np.real(z.v), np.imag(z.v), np.real(z.d), np.imag(z.d)
        foot_values = ((x * g0 + y * g1) * scale, (x * u0 + y * u1) * scale,
                       np.sqrt(dx * dx + dy * dy) * omega * scale, (dx * g0 + dy * g1) * omega * scale)
    path_values = None if path is None else (np.real(t.pos[path].v), np.imag(t.pos[path].v))
    if newton:
        return newton_codegen.newton_cycle_source(tr, t.groups, t.valid, t.valid, transmission=worst,
                                                  foot=foot_values, path=path_values)
    return codegen.cycle_source(tr, t.valid, t.deficit(), transmission=worst, foot=foot_values, path=path_values)


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
    designs = _designs(designs)
    cq, sq = np.cos(q), np.sin(q)
    n_out = len(plan.point_names) + (len(plan.body_names) if with_bodies else 0)
    D, N = designs.shape[0], q.size
    out = np.empty((6 * n_out, D, N))         # rows of derivatives above ``order`` stay unwritten
    valid = np.empty((D, N), dtype=np.bool_)
    w1, w2, w3 = (float(r) for r in rates)
    kernel(plan, with_bodies, order)(designs, cq, sq, float(tol), w1, w2, w3, out, valid)
    rows = out.reshape((n_out, 6) + shape)
    axes = tuple(range(2, 2 + n)) + (0, 1)     # (n_out, 2, *shape) → (*shape, n_out, 2), a view
    views = tuple(rows[:, 2 * j:2 * j + 2].transpose(axes) for j in range(3))
    return out, views, valid.reshape(shape)


def timing_source(plan, point: str) -> str:
    """The source of the plan's free-timing refinement kernel (:func:`assur.kernels.codegen.timing_source`):
    g = |P − T|²/2 of the point to the target ``txy[i]``, its first and second derivatives by the input (from the
    traced jets), valid where the groups assemble and g is finite."""
    t = traced.trace_plan(plan, 2)
    z = t.pos[point]
    ex = np.real(z.v) - t.tracer.load("txy[i, 0]", SAMPLE)
    ey = np.imag(z.v) - t.tracer.load("txy[i, 1]", SAMPLE)
    dx, dy, ddx, ddy = np.real(z.d), np.imag(z.d), np.real(z.dd), np.imag(z.dd)
    g = 0.5 * (ex * ex + ey * ey)
    g1 = ex * dx + ey * dy
    g2 = dx * dx + dy * dy + ex * ddx + ey * ddy
    return codegen.timing_source(t.tracer, g, g1, g2, t.finite(g, g1, g2))


def pose_timing_source(plan, point: str, body: int) -> str:
    """The source of the plan's free-timing refinement kernel for pose targets
    (:func:`assur.kernels.codegen.pose_timing_source`): c = |P − T| + w·|ψ − ψ_T| of the point and the body's angle
    to the target row ``txy[i] = (x, y, cos ψ_T, sin ψ_T, w)`` (the angle difference the short way round, from the
    traced orientation e = exp(iψ) times exp(−iψ_T)), valid where the groups assemble and c is finite."""
    t = traced.trace_plan(plan, 0)
    z, e = t.pos[point].v, t.orient[body].v
    row = [t.tracer.load(f"txy[i, {k}]", SAMPLE) for k in range(5)]
    ex, ey = np.real(z) - row[0], np.imag(z) - row[1]
    re = np.real(e) * row[2] + np.imag(e) * row[3]          # e·exp(−iψ_T) = cos Δψ + i sin Δψ
    im = np.imag(e) * row[2] - np.real(e) * row[3]
    c = np.sqrt(ex * ex + ey * ey) + row[4] * np.arctan2(abs(im), re)
    return codegen.pose_timing_source(t.tracer, c, t.finite(c))


def pose_timing_refine(plan, params: np.ndarray, point: str, body: int, theta0: np.ndarray, h: float,
                       poses: np.ndarray, angle_weight: float, tol: float):
    """The compiled refinement of free timing for pose targets (:func:`pose_timing_source`); None if the plan is not
    covered. params (D, n_params), theta0 (D, N), poses (N, 3) (x, y m; ψ rad), angle_weight m per rad → refined
    inputs (D, N)."""
    if not covers(plan):
        return None
    kern = _load(plan, f"pose_timing_{plan.point_index(point)}_{body}", lambda: pose_timing_source(plan, point, body))
    rows = np.column_stack([poses[:, :2], np.cos(poses[:, 2]), np.sin(poses[:, 2]),
                            np.full(len(poses), float(angle_weight))])
    th0 = _designs(theta0)
    out = np.empty_like(th0)
    kern(_designs(params), th0, float(h), _designs(rows), float(tol), out)
    return out


def timing_refine(plan, params: np.ndarray, point: str, theta0: np.ndarray, h: float, target_xy: np.ndarray,
                  tol: float):
    """The compiled refinement of free timing (:func:`assur.kernels.codegen.timing_source`); None if the plan is not
    covered. params (D, n_params), theta0 (D, N) starting inputs, target_xy (N, 2) → refined inputs (D, N)."""
    if not covers(plan):
        return None
    kern = _load(plan, f"timing_{plan.point_index(point)}", lambda: timing_source(plan, point))
    th0 = _designs(theta0)
    out = np.empty_like(th0)
    kern(_designs(params), th0, float(h), _designs(target_xy), float(tol), out)
    return out
