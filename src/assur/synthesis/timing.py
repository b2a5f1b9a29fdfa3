"""Free timing solved inside the evaluation: the best input of each target for a given design.

With ``[targets] timing = "free"`` the input values at the targets are unknowns. In the explicit formulation they are
design variables the optimiser searches (one per target); with ``free_timing = "inner"`` (the default for point
targets) each design's own best inputs are found here, so the optimiser searches the design variables alone. The
inner problem, per design,

    min over θ_1 … θ_N of Σ_i c(|P(θ_i) − T_i|)      (c(d) = d² for a squared deviation, d for a sum of distances)

subject to the order the problem asks for (``cyclic_order`` or ``defects``: in order within one counter-clockwise
turn; ``cyclic_order_any``: either sense; ``ascending``: ascending in [0, 2π) without wrap-around; none: each target
on its own), is solved in two steps:

1. **on the samples**: the target point over one turn of ``cycle_samples`` uniform inputs (the cycle the evaluator
   samples anyway), the cost of each target at each sample, and the least-cost ordered assignment
   (:mod:`assur.kernels.ordered`: exact on the samples) — or each target's nearest sample without an order;
2. **bracketed refinement**: each θ_i is refined inside [θ_k − h, θ_k + h] around its sample (h the sample spacing)
   by a safeguarded Newton iteration on g(θ) = |P(θ) − T_i|²/2 (g′ = (P − T)·P′, g″ = |P′|² + (P − T)·P″ from the
   engine's exact derivatives): a step past an end of the bracket tries that end, the bracket keeps the side g
   decreases towards, and a position that cannot be assembled (or g″ ≤ 0) bisects it; to round-off; then the order is restored where two neighbouring refinements crossed.

Pose targets (motion generation) take the same two steps on the pose deviation d = |P(θ) − T_i| + w·|ψ(θ) − ψ_i|
(ψ the link's angle, the difference the short way round; cost d² or d): the samples carry ψ beside the point, and
since d has a corner where a pose is met exactly (no Newton step there), step 2 is a golden-section search on d inside
the same bracket (:func:`refine_poses`; compiled: ``numba_backend.pose_timing_refine``), to round-off of d.

The minimum is global over each target's bracket and over the assignment of brackets; a nearer point of the curve
that falls between samples other than the bracketed ones (two branches of the curve at nearly equal distance, within
the sampling error) can be missed — raise ``cycle_samples`` for curves with sharp features.
"""
from __future__ import annotations

import numpy as np

from ..kernels.codegen import GOLDEN, GOLDEN_STEPS   # the pose refinement's golden section (the kernel's)

TWO_PI = 2.0 * np.pi
#: Newton iterations at most: a minimum inside the bracket converges in a few; one on a toggle (the edge of the
#: assembled stretch) is approached by bisection, to 2·(2π/M)·2^−30 (≈ 3e-11 rad at 360 samples)
MAX_ITERATIONS = 30

ORDERS = ("none", "ccw", "either", "ascending")
#: a target met a whole turn after the first (a closed curve's repeated point) is placed this much earlier (rad), so
#: that the wrapped angles' gaps still add up to less than one turn after rounding
FULL_TURN_MARGIN = 1e-12


def order_of(constraints) -> str:
    """The order the inner solve keeps, from a problem's constraint names."""
    c = set(constraints)
    if "ascending" in c:
        return "ascending"
    if "cyclic_order" in c or "defects" in c:
        return "ccw"
    if "cyclic_order_any" in c:
        return "either"
    return "none"


#: the order codes of :func:`assur.kernels.ordered.assign`
ORDER_CODES = {"none": 0, "ccw": 1, "either": 2, "ascending": 3}


def assign_samples(path, valid, xy, power: int, order: str, angle_weight: float = 0.0):
    """Unrolled sample indices (n, N) of the best assignment of the targets to the samples under ``order`` (module
    docstring), and for 'either' whether the clockwise sense won (n,) bool. path (n, M, 2) and xy (N, 2) for points;
    (n, M, 3) and (N, 3) for poses, the link's angle third, weighted by ``angle_weight`` (m per rad)."""
    from ..kernels.ordered import assign
    return assign(path, valid, xy, power, ORDER_CODES[order], angle_weight)


def refine(plan, params, point: str, xy, theta0, h: float, backend: str):
    """Safeguarded Newton refinement of each θ (n, N) within [θ0 − h, θ0 + h] on |P(θ) − T|²/2 (module docstring);
    returns the refined angles (n, N), never worse than θ0."""
    from ..engine import solve
    idx = plan.point_index(point)
    a, b = theta0 - h, theta0 + h
    x = theta0.copy()
    best_x, best_g = theta0.copy(), np.full(theta0.shape, np.inf)
    active = np.ones(theta0.shape, dtype=bool)
    P = params[:, None, :]
    for it in range(MAX_ITERATIONS):
        st = solve(plan, P, x[..., None], order=2, backend=backend)
        pos = st.pos[:, :, idx, :]
        d1 = st.dpos_dq[:, :, idx, :, 0]
        d2 = st.d2pos_dq2[:, :, idx, :, 0, 0]
        ok = st.valid & np.all(np.isfinite(pos), axis=-1)
        e = pos - xy
        g = 0.5 * np.sum(e * e, axis=-1)
        g1 = np.sum(e * d1, axis=-1)
        g2 = np.sum(d1 * d1, axis=-1) + np.sum(e * d2, axis=-1)
        better = ok & (g < best_g)
        best_x = np.where(better, x, best_x)
        best_g = np.where(better, g, best_g)
        # the bracket: a local minimum lies on the side g decreases towards; an unassembled x shrinks towards θ0
        right = np.where(ok, g1 > 0, x > theta0)
        b = np.where(active & right, x, b)
        a = np.where(active & ~right, x, a)
        with np.errstate(all="ignore"):
            step = np.where(ok & (g2 > 0), -g1 / g2, np.nan)
        xn = np.clip(x + step, a, b)           # a Newton step past an end tries that end (a minimum on it ends there)
        xn = np.where(np.isfinite(xn) & (xn != x), xn, 0.5 * (a + b))
        scale = np.maximum(1.0, np.abs(x))
        done = ~active | (np.abs(xn - x) <= 4e-16 * scale) | (b - a <= 4e-16 * scale)
        if it == 0:
            done |= ~ok                            # an unassembled start (no sample assembles): nothing to refine
        x = np.where(active, xn, x)
        active = active & ~done
        if not active.any():
            break
    return best_x


def pose_cost(st, idx: int, body: int, pose, angle_weight: float):
    """|P − T| + w·|ψ − ψ_T| (the angle difference wrapped, as the objective's pose deviation
    :func:`.targets.target_offsets` takes it) of solved states ``st`` (…) against target poses ``pose`` (…, 3)
    (m, m, rad); inf where a state is not assembled."""
    from .targets import wrap_angle
    pos = st.pos[..., idx, :]
    d = (np.linalg.norm(pos - pose[..., :2], axis=-1)
         + angle_weight * np.abs(wrap_angle(st.body_angle[..., body] - pose[..., 2])))
    return np.where(st.valid & np.isfinite(d), d, np.inf)


def refine_poses(plan, params, point: str, link: str, poses, angle_weight: float, theta0, h: float, backend: str):
    """Golden-section refinement of each θ (n, N) within [θ0 − h, θ0 + h] on the pose deviation
    |P(θ) − T| + w·|ψ(θ) − ψ_T| of its target ``poses`` (N, 3), which has a corner where it vanishes (so no Newton
    step); returns the refined angles (n, N), never worse than θ0. A bracket with one local minimum converges to it
    (:data:`GOLDEN_STEPS`: to round-off); an unassembled θ counts as infinitely far."""
    from ..engine import solve
    idx, body = plan.point_index(point), plan.body_names.index(link)
    P = params[:, None, :]

    def cost(theta, targets=poses):
        with np.errstate(all="ignore"):
            st = solve(plan, P, theta[..., None], order=0, backend=backend)
            return pose_cost(st, idx, body, targets, angle_weight)
    a, b = theta0 - h, theta0 + h
    c, d = b - GOLDEN * (b - a), a + GOLDEN * (b - a)
    both = cost(np.concatenate([theta0, c, d], axis=1), np.tile(poses, (3, 1)))
    N = theta0.shape[1]
    start, fc, fd = both[:, :N], both[:, N:2 * N], both[:, 2 * N:]
    best_x, best_g = theta0.copy(), start.copy()
    active = np.isfinite(start)                 # an unassembled θ0 is left as it is (the compiled kernel's rule)
    for x, g in ((c, fc), (d, fd)):
        better = active & (g < best_g)
        best_x, best_g = np.where(better, x, best_x), np.where(better, g, best_g)
    for _ in range(GOLDEN_STEPS):
        active &= b - a > 4e-16 * np.maximum(1.0, np.abs(a))
        if not active.any():
            break
        left = fc < fd                          # the minimum lies in [a, d]: drop (d, b]
        b = np.where(active & left, d, b)
        a = np.where(active & ~left, c, a)
        c, d, fc, fd = (np.where(left, b - GOLDEN * (b - a), d), np.where(left, c, a + GOLDEN * (b - a)),
                        np.where(left, np.nan, fd), np.where(left, fc, np.nan))
        x = np.where(left, c, d)
        g = cost(x)
        fc, fd = np.where(left, g, fc), np.where(left, fd, g)
        better = active & (g < best_g)
        best_x, best_g = np.where(better, x, best_x), np.where(better, g, best_g)
    return best_x


def restore_order(theta, order: str, cw):
    """Unrolled angles (n, N) after refinement, put back in order where two neighbours crossed: counter-clockwise
    (and clockwise where ``cw``) within one turn of the first, or ascending in [0, 2π)."""
    t = theta.copy()
    if order == "none" or t.shape[1] < 2:
        return t
    if order == "ascending":
        t = np.clip(t, 0.0, np.nextafter(TWO_PI, 0.0))
        t = np.maximum.accumulate(t, axis=1)
        return t
    s = np.where(cw[:, None], -t, t)           # clockwise: the same rule on the negated angles
    s = np.maximum.accumulate(s, axis=1)
    s = np.minimum(s, s[:, :1] + TWO_PI - FULL_TURN_MARGIN)   # a last target back at the first stays within the turn
    return np.where(cw[:, None], -s, s)


#: designs whose turn is sampled at once (the samples of every point are held: chunk × M × points × 2 numbers)
SAMPLE_CHUNK = 512


def solve_timing(plan, params, point: str, xy, cycle_inputs, order: str, power: int, backend: str, cycle=None,
                 link: str | None = None, angles=None, angle_weight: float = 0.0):
    """The best input of each target (n, N), wrapped into [0, 2π), for every design of ``params`` (n, n_params).

    ``cycle_inputs`` (M,): one uniform turn; ``cycle``: its already solved (path (n, M, 2), valid (n, M)) of the
    target point (path (n, M, 3) for poses, the link's angle third), or None to solve it here (:data:`SAMPLE_CHUNK` designs at a time); ``power`` 2 for a squared
    deviation, 1 for a sum of distances. Poses: ``link``, its target ``angles`` (N,) rad and ``angle_weight`` (m per
    rad): each target's cost is the pose deviation |Δp| + w·|Δψ| (then the cycle carries the link's angle as a third
    column and the refinement is :func:`refine_poses`)."""
    if cycle is None and len(params) > SAMPLE_CHUNK:
        return np.concatenate([solve_timing(plan, params[i:i + SAMPLE_CHUNK], point, xy, cycle_inputs, order, power,
                                            backend, None, link, angles, angle_weight)
                               for i in range(0, len(params), SAMPLE_CHUNK)])
    from ..engine import solve
    poses = None if angles is None else np.column_stack([xy, angles])
    if cycle is None and backend == "numba":      # the compiled kernel's positions without building a State
        from ..engine.planar.numba_backend import solve_compiled
        from ..tolerances import DEFAULT
        r = solve_compiled(plan, params[:, None, :], cycle_inputs[:, None], DEFAULT.radicand, order=0,
                           shape=(len(params), len(cycle_inputs)), with_bodies=poses is not None)
        if r is not None:
            pos = r[1][0]
            path = pos[:, :, plan.point_index(point), :]
            if poses is not None:                 # the link's orientation e = exp(iψ), after the points
                e = pos[:, :, len(plan.point_names) + plan.body_names.index(link), :]
                path = np.concatenate([path, np.arctan2(e[..., 1], e[..., 0])[..., None]], axis=-1)
            cycle = (path, r[2])
    if cycle is None:
        st = solve(plan, params[:, None, :], cycle_inputs[:, None], order=0, backend=backend, sweep=True)
        path = st.pos[:, :, plan.point_index(point), :]
        if poses is not None:
            path = np.concatenate([path, st.body_angle[:, :, plan.body_names.index(link), None]], axis=-1)
        cycle = (path, st.valid)
    path, valid = cycle
    valid = valid & np.all(np.isfinite(path), axis=-1)
    M = len(cycle_inputs)
    h = TWO_PI / M
    k, cw = assign_samples(path, valid, xy if poses is None else poses, power, order, angle_weight)
    theta0 = cycle_inputs[0] + k * h
    theta = None
    if backend == "numba":
        from ..engine.planar.numba_backend import pose_timing_refine, timing_refine
        from ..tolerances import DEFAULT
        theta = (timing_refine(plan, params, point, theta0, h, xy, DEFAULT.radicand) if poses is None else
                 pose_timing_refine(plan, params, point, plan.body_names.index(link), theta0, h, poses, angle_weight,
                                    DEFAULT.radicand))
    if theta is None:
        theta = (refine(plan, params, point, xy, theta0, h, backend) if poses is None else
                 refine_poses(plan, params, point, link, poses, angle_weight, theta0, h, backend))
    theta = restore_order(theta, order, cw)
    return np.mod(theta, TWO_PI)


__all__ = ["ORDERS", "SAMPLE_CHUNK", "assign_samples", "order_of", "pose_cost", "refine", "refine_poses", "restore_order",
           "solve_timing"]
