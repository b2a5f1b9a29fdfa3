"""Per-design reductions of sampled cycles, called by the generated cycle kernels (:mod:`assur.kernels.codegen`):
the sampled gait terms of a walking leg's foot and the distances of targets to a sampled closed path. Compiled by
numba (imported with this module, which only generated kernels and tests import)."""
from __future__ import annotations

import math

from numba import njit


@njit(cache=True, error_model="numpy")
def gait_reduce(x, v, sp, vx, out, d, col):
    """The sampled gait terms of one design (the definitions of ``analysis.gait.population_gait``) into
    ``out[d, col:col + 9]``: step, lift, sag, duty, speed mean, speed spread, the spreads of |vx| over the central
    fractions 0.8 and 0.9 of the stride (``analysis.gait.central_vx_spread``) and the path's top height.

    x, v, sp, vx (M,): stride coordinate, height, foot speed and horizontal velocity at M uniform inputs over one
    turn, every sample assembled. The contact arc runs between the first samples of smallest and largest x, the one
    of the two arcs (both ends included) whose sample-mean height is lower (the first arc, smallest x → largest x,
    on a tie)."""
    M = x.shape[0]
    ia = 0
    ib = 0
    vmin = v[0]
    vmax = v[0]
    for k in range(1, M):
        if x[k] < x[ia]:
            ia = k
        if x[k] > x[ib]:
            ib = k
        vmin = min(vmin, v[k])
        vmax = max(vmax, v[k])
    w1 = (ib - ia + M) % M
    w2 = (ia - ib + M) % M
    m1 = 0.0
    for j in range(w1 + 1):
        m1 += v[(ia + j) % M]
    m2 = 0.0
    for j in range(w2 + 1):
        m2 += v[(ib + j) % M]
    if m1 / (w1 + 1) <= m2 / (w2 + 1):
        start, width = ia, w1
    else:
        start, width = ib, w2
    cmin = math.inf
    cmax = -math.inf
    smin = math.inf
    smax = -math.inf
    ssum = 0.0
    for j in range(width + 1):
        k = (start + j) % M
        cmin = min(cmin, v[k])
        cmax = max(cmax, v[k])
        smin = min(smin, sp[k])
        smax = max(smax, sp[k])
        ssum += sp[k]
    smean = ssum / (width + 1)
    out[d, col] = x[ib] - x[ia]
    out[d, col + 1] = vmax - vmin
    out[d, col + 2] = cmax - cmin
    out[d, col + 3] = (width + 1) / M
    out[d, col + 4] = smean
    out[d, col + 5] = (smax - smin) / smean
    centre = 0.5 * (x[ia] + x[ib])
    for c, fraction in ((col + 6, 0.8), (col + 7, 0.9)):
        half = 0.5 * fraction * (x[ib] - x[ia])
        wmin = math.inf
        wmax = -math.inf
        wsum = 0.0
        count = 0
        for j in range(width + 1):
            k = (start + j) % M
            if abs(x[k] - centre) <= half:
                a = abs(vx[k])
                wmin = min(wmin, a)
                wmax = max(wmax, a)
                wsum += a
                count += 1
        out[d, c] = (wmax - wmin) / (wsum / count) if count > 0 else math.nan
    out[d, col + 8] = vmax


@njit(cache=True, error_model="numpy")
def polyline_distance(px, py, txy, out, d, col):
    """Distance of each target ``txy (N, 2)`` to the closed polyline through (px, py) (M,) into
    ``out[d, col:col + N]``: the nearest point of each segment (its parameter clipped to [0, 1]), the
    smallest over the segments (the square root taken once, of the smallest square)."""
    M = px.shape[0]
    for j in range(txy.shape[0]):
        tx = txy[j, 0]
        ty = txy[j, 1]
        best = math.inf
        for k in range(M):
            k1 = k + 1 if k + 1 < M else 0
            ax = px[k]
            ay = py[k]
            abx = px[k1] - ax
            aby = py[k1] - ay
            t = ((tx - ax) * abx + (ty - ay) * aby) / max(abx * abx + aby * aby, 1e-300)
            t = min(max(t, 0.0), 1.0)
            ex = ax + t * abx - tx
            ey = ay + t * aby - ty
            best = min(best, ex * ex + ey * ey)
        out[d, col + j] = math.sqrt(best)
