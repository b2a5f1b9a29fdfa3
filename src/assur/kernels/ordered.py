"""Ordered assignment of targets to the samples of a closed curve: the discrete inner problem of free timing.

Given the cost ``C[i, u] ≥ 0`` of meeting target i at sample u of one uniform turn (M samples; an unassembled sample
costs :data:`BIG`), choose one sample per target so that the targets are met in their order within one turn of the
input and the summed cost is least.

- :func:`cyclic_assignment`: in order counter-clockwise within one turn, from any start — unrolled indices
  ``s = x_0 ≤ x_1 ≤ … ≤ x_{N−1} ≤ s + M`` (``s`` in [0, M); several targets may share a sample). Exact: the
  unconstrained nearest samples when they are already in order, else a divide and conquer over the start
  sample. For starts s < s'' < s' optimal paths can be taken between those of s and s' (if a is optimal for s
  and x for s'', the element-wise max(x, a) is feasible and optimal for s'' and min(x, a) for s, as their costs
  add up to the same sum), so each start is solved in the band its neighbours leave: O(N·M·log M) in all; an
  interval of starts none of which can beat the best path so far (its first cost plus every later target's least
  cost, a lower bound) is skipped, the best path so far starting from the first target's nearest sample.
- :func:`ascending_assignment`: ascending within [0, M) without wrap-around (one linear pass with a running
  minimum).

Written in plain Python over numpy arrays so that the same code runs compiled (numba, :func:`compiled`: these
functions written into a cached kernel module) or, without numba, interpreted. Arrays: ``C (N, M)`` float64; the result is ``(N,)`` int64 unrolled sample indices and the cost.
"""
from __future__ import annotations

import numpy as np

TWO_PI = 2.0 * np.pi
#: the cost of an unassembled sample (finite, so that sums and comparisons stay ordered)
BIG = 1e30


def _band_path(C, start, lo, hi, best, bad, arg, path):
    """The least-cost ordered path with x_0 = start, lo[i] ≤ x_i ≤ hi[i] and x_{N−1} ≤ start + M (unrolled
    indices); written into ``path`` (N,); returns (its cost over the assembled samples, its unassembled samples). Paths compare lexicographically by (unassembled samples,
    cost), so that every comparison is exact in the order the exchange argument needs (a cost of BIG would absorb the
    small ones). ``best``, ``bad``, ``arg`` (N, 2M + 1): scratch."""
    N, M = C.shape
    best[0, start] = _cost(C[0, start % M])
    bad[0, start] = _bad(C[0, start % M])
    prev_lo, prev_hi = start, start
    for i in range(1, N):
        a = max(lo[i], prev_lo)
        b = min(hi[i], start + M)
        if b < a:                              # an empty band cannot happen for consistent bands; stay put
            b = a
        run, run_bad, run_at = np.inf, N + 1, prev_lo
        j = prev_lo
        for u in range(a, b + 1):
            while j <= min(u, prev_hi):        # bring in the previous row's entries up to u
                if bad[i - 1, j] < run_bad or (bad[i - 1, j] == run_bad and best[i - 1, j] < run):
                    run, run_bad, run_at = best[i - 1, j], bad[i - 1, j], j
                j += 1
            best[i, u] = _cost(C[i, u % M]) + run
            bad[i, u] = _bad(C[i, u % M]) + run_bad
            arg[i, u] = run_at
        prev_lo, prev_hi = a, b
    k, cost, nbad = prev_lo, np.inf, N + 1
    for u in range(prev_lo, prev_hi + 1):
        if bad[N - 1, u] < nbad or (bad[N - 1, u] == nbad and best[N - 1, u] < cost):
            cost, nbad, k = best[N - 1, u], bad[N - 1, u], u
    for i in range(N - 1, 0, -1):
        path[i] = k
        k = arg[i, k]
    path[0] = start
    return cost, nbad


def _bad(c):
    return 1 if c >= BIG else 0


def _cost(c):
    return 0.0 if c >= BIG else c


def _better(c1, b1, c2, b2):
    """Whether (unassembled samples b1, cost c1) comes before (b2, c2): fewer unassembled samples first."""
    return b1 < b2 or (b1 == b2 and c1 < c2)


def cyclic_assignment(C):
    """(path (N,) int64 unrolled sample indices, cost): the least-cost assignment of the N targets to the M samples
    in counter-clockwise order within one turn (see the module docstring)."""
    N, M = C.shape
    path = np.empty(N, dtype=np.int64)
    near = np.empty(N, dtype=np.int64)
    for i in range(N):
        near[i] = np.argmin(C[i])
    span = 0
    for i in range(1, N):
        span += (near[i] - near[i - 1]) % M
    if span <= M:                              # the nearest samples are in order: optimal as they stand
        path[0] = near[0]
        cost = C[0, near[0]]
        for i in range(1, N):
            path[i] = path[i - 1] + (near[i] - near[i - 1]) % M
            cost += C[i, near[i]]
        return path, cost
    best = np.empty((N, 2 * M + 1))
    bad = np.zeros((N, 2 * M + 1), dtype=np.int64)
    arg = np.zeros((N, 2 * M + 1), dtype=np.int64)
    pool = np.empty((M + 1, N), dtype=np.int64)      # the path of start s in row s (start M: start 0 shifted)
    lo0 = np.zeros(N, dtype=np.int64)
    hi0 = np.full(N, M, dtype=np.int64)
    row = np.empty(N, dtype=np.int64)
    # a lower bound of every start s: its own first cost plus each later target's least cost (lexicographic)
    rest_cost, rest_bad = 0.0, 0
    for i in range(1, N):
        rest_cost += _cost(C[i, near[i]])
        rest_bad += _bad(C[i, near[i]])
    # an upper bound first: the start at the first target's nearest sample, over the whole turn
    s0 = near[0]
    cost, nbad = _band_path(C, s0, np.full(N, s0, dtype=np.int64), np.full(N, s0 + M, dtype=np.int64), best, bad,
                            arg, row)
    best_cost, best_bad, best_start = cost, nbad, -1
    first = row.copy()
    cost, nbad = _band_path(C, 0, lo0, hi0, best, bad, arg, row)
    pool[0] = row
    pool[M] = row + M
    if _better(cost, nbad, best_cost, best_bad):
        best_cost, best_bad, best_start = cost, nbad, 0
    stack = np.empty((2 * M + 4, 2), dtype=np.int64)  # (s_lo, s_hi) intervals still to split
    stack[0, 0], stack[0, 1] = 0, M
    top = 1
    while top > 0:
        top -= 1
        s_lo, s_hi = stack[top, 0], stack[top, 1]
        if s_hi - s_lo <= 1:
            continue
        promising = False                      # prune an interval none of whose starts can beat the best
        for u in range(s_lo + 1, s_hi):
            if _better(_cost(C[0, u]) + rest_cost, _bad(C[0, u]) + rest_bad, best_cost, best_bad):
                promising = True
                break
        if not promising:
            continue
        mid = (s_lo + s_hi) // 2
        cost, nbad = _band_path(C, mid, pool[s_lo], pool[s_hi], best, bad, arg, row)
        pool[mid] = row
        if _better(cost, nbad, best_cost, best_bad):
            best_cost, best_bad, best_start = cost, nbad, mid
        stack[top, 0], stack[top, 1] = s_lo, mid
        stack[top + 1, 0], stack[top + 1, 1] = mid, s_hi
        top += 2
    if best_start < 0:
        path[:] = first
        return path, best_cost + best_bad * BIG
    path[:] = pool[best_start]
    return path, best_cost + best_bad * BIG


def ascending_assignment(C):
    """(path (N,) int64 sample indices in [0, M), cost): the least-cost assignment with x_0 ≤ x_1 ≤ … ≤ x_{N−1}
    (no wrap-around)."""
    N, M = C.shape
    best = np.empty((N, M))
    arg = np.zeros((N, M), dtype=np.int64)
    for u in range(M):
        best[0, u] = C[0, u]
    for i in range(1, N):
        run, run_at = np.inf, 0
        for u in range(M):
            if best[i - 1, u] < run:
                run, run_at = best[i - 1, u], u
            best[i, u] = C[i, u] + run
            arg[i, u] = run_at
    k, cost = 0, np.inf
    for u in range(M):
        if best[N - 1, u] < cost:
            cost, k = best[N - 1, u], u
    path = np.empty(N, dtype=np.int64)
    for i in range(N - 1, 0, -1):
        path[i] = k
        k = arg[i, k]
    path[0] = k
    return path, cost


def _costs(path, valid, xy, power, weight, C):
    """C (N, M) ← d^power of one design's samples path (M, K), BIG where not ``valid`` (M,): K = 2, d = |P_u − T_i|
    (points); K = 3, the third column an angle, d = |P_u − T_i| + weight·|ψ_u − ψ_i| (poses, the angle difference
    taken the short way round, in [0, π])."""
    N, M = C.shape
    K = path.shape[1]
    for i in range(N):
        for u in range(M):
            if valid[u]:
                dx = path[u, 0] - xy[i, 0]
                dy = path[u, 1] - xy[i, 1]
                d2 = dx * dx + dy * dy
                if K > 2:
                    e = abs(path[u, 2] - xy[i, 2]) % TWO_PI
                    d = np.sqrt(d2) + weight * min(e, TWO_PI - e)
                    c = d * d if power == 2 else d
                else:
                    c = d2 if power == 2 else np.sqrt(d2)
                C[i, u] = c if c == c else BIG
            else:
                C[i, u] = BIG


def costs(path, valid, xy, power, weight):
    """What :func:`_costs` writes, for every design at once (n, N, M): the interpreted route's costs (numpy
    elementwise, the same operations in the same order)."""
    d2 = np.sum((path[:, None, :, :2] - xy[None, :, None, :2]) ** 2, axis=-1)
    if path.shape[-1] > 2:
        e = np.mod(np.abs(path[:, None, :, 2] - xy[None, :, None, 2]), TWO_PI)
        d = np.sqrt(d2) + weight * np.minimum(e, TWO_PI - e)
        c = d * d if power == 2 else d
    else:
        c = d2 if power == 2 else np.sqrt(d2)
    return np.where(valid[:, None, :] & (c == c), c, BIG)


def _assign_one(C, mode, R, out, cw, d):
    """Design d's assignment from its costs C (N, M) into ``out[d]`` (and ``cw[d]``), by ``mode`` (:func:`_batch`);
    R (N, M) scratch."""
    N = C.shape[0]
    if mode == 0 or N == 1:
        for i in range(N):
            out[d, i] = np.argmin(C[i])
    elif mode == 3:
        p, c = ascending_assignment(C)
        out[d] = p
    else:
        p, c = cyclic_assignment(C)
        out[d] = p
        if mode == 2:
            for i in range(N):
                R[i] = C[N - 1 - i]
            q, cq = cyclic_assignment(R)
            if cq < c:
                cw[d] = True
                for i in range(N):
                    out[d, i] = q[N - 1 - i]


def _batch(path, valid, xy, power, mode, weight):
    """Every design: path (n, M, K), valid (n, M), targets xy (N, K) (K = 2: points; K = 3: poses, the angle third,
    weighted by ``weight``: :func:`_costs`) → (indices (n, N) int64 unrolled, cw (n,) bool).
    mode 0: each target's nearest sample; 1: counter-clockwise order within a turn; 2: either sense; 3: ascending."""
    n, M = valid.shape
    N = xy.shape[0]
    out = np.empty((n, N), dtype=np.int64)
    cw = np.zeros(n, dtype=np.bool_)
    C = np.empty((N, M))
    R = np.empty((N, M))
    for d in range(n):
        _costs(path[d], valid[d], xy, power, weight, C)
        _assign_one(C, mode, R, out, cw, d)
    return out, cw


_COMPILED = None


def compiled():
    """The batch assignment :func:`_batch` compiled by numba, or None without numba: this module's functions written
    into a kernel module (each ``@njit(cache=True)``, :func:`_batch` as its ``kernel``) and loaded through the kernel
    cache (:func:`assur.kernels.codegen.load`), so it is compiled once and reused across processes."""
    global _COMPILED
    if _COMPILED is None:
        from . import codegen
        if not codegen.available():
            _COMPILED = False
            return None
        import inspect
        parts = ['"""Generated by assur.kernels.ordered.compiled from its functions; do not edit."""',
                 "import numpy as np", "from numba import njit", "", f"BIG = {BIG!r}",
                 f"TWO_PI = {TWO_PI!r}"]
        for f in (_bad, _cost, _better, _band_path, cyclic_assignment, ascending_assignment, _costs,
                  _assign_one):
            parts += ["", "", '@njit(cache=True, error_model="numpy")', inspect.getsource(f).rstrip()]
        parts += ["", "", '@njit(cache=True, error_model="numpy")',
                  inspect.getsource(_batch).replace("def _batch(", "def kernel(", 1).rstrip(), ""]
        _COMPILED = codegen.load("\n".join(parts), "the ordered assignment")
    return _COMPILED or None


def assign(path, valid, xy, power: int, mode: int, angle_weight: float = 0.0):
    """Assignment of the targets to the samples of every design (see :func:`_batch`), compiled when numba is
    installed, the same code interpreted otherwise."""
    args = (np.ascontiguousarray(path, dtype=float), np.ascontiguousarray(valid, dtype=np.bool_),
            np.ascontiguousarray(xy, dtype=float), int(power), int(mode), float(angle_weight))
    fn = compiled()
    if fn is not None:
        return fn(*args)
    path, valid, xy, power, mode, weight = args           # interpreted: the costs of all designs at once
    C = costs(path, valid, xy, power, weight)
    n, N, M = C.shape
    out, cw, R = np.empty((n, N), dtype=np.int64), np.zeros(n, dtype=np.bool_), np.empty((N, M))
    for d in range(n):
        _assign_one(C[d], mode, R, out, cw, d)
    return out, cw
