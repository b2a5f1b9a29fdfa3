"""Compiled (numba) primitives of the generated kernels: complex and real second-order jets held
in registers as tuples — a complex jet is ``(x, y, dx, dy, ddx, ddy)``, a real jet ``(v, d, dd)``
(derivatives by the single input q) — and the closed forms of the crank and of the RRR, RRP and RPR
dyads on them. The kernels that call them are generated per plan by :mod:`assur.kernels.codegen`.
"""
from __future__ import annotations

import math

from numba import njit



@njit(inline="always", cache=True, error_model="numpy")
def _cmul(a, b):
    ar, ai, adr, adi, aer, aei = a
    br, bi, bdr, bdi, ber, bei = b
    vr = ar * br - ai * bi
    vi = ar * bi + ai * br
    dr = adr * br - adi * bi + ar * bdr - ai * bdi
    di = adr * bi + adi * br + ar * bdi + ai * bdr
    er = aer * br - aei * bi + 2.0 * (adr * bdr - adi * bdi) + ar * ber - ai * bei
    ei = aer * bi + aei * br + 2.0 * (adr * bdi + adi * bdr) + ar * bei + ai * ber
    return (vr, vi, dr, di, er, ei)


@njit(inline="always", cache=True, error_model="numpy")
def cmulk(a, kr, ki):
    """complex jet × complex constant"""
    ar, ai, adr, adi, aer, aei = a
    return (ar * kr - ai * ki, ar * ki + ai * kr, adr * kr - adi * ki, adr * ki + adi * kr,
            aer * kr - aei * ki, aer * ki + aei * kr)


@njit(inline="always", cache=True, error_model="numpy")
def cadd(a, b):
    return (a[0] + b[0], a[1] + b[1], a[2] + b[2], a[3] + b[3], a[4] + b[4], a[5] + b[5])


@njit(inline="always", cache=True, error_model="numpy")
def csub(a, b):
    return (a[0] - b[0], a[1] - b[1], a[2] - b[2], a[3] - b[3], a[4] - b[4], a[5] - b[5])


@njit(inline="always", cache=True, error_model="numpy")
def _abs2(a):
    """|z|² as a real jet"""
    ar, ai, adr, adi, aer, aei = a
    v = ar * ar + ai * ai
    d = 2.0 * (ar * adr + ai * adi)
    dd = 2.0 * (ar * aer + ai * aei) + 2.0 * (adr * adr + adi * adi)
    return (v, d, dd)


@njit(inline="always", cache=True, error_model="numpy")
def _rmul(a, b):
    return (a[0] * b[0], a[1] * b[0] + a[0] * b[1], a[2] * b[0] + 2.0 * a[1] * b[1] + a[0] * b[2])


@njit(inline="always", cache=True, error_model="numpy")
def _rinv(a):
    r = 1.0 / a[0]
    r2 = r * r
    return (r, -a[1] * r2, -a[2] * r2 + 2.0 * a[1] * a[1] * r2 * r)


@njit(inline="always", cache=True, error_model="numpy")
def _rsqrt(a):
    s = math.sqrt(a[0])
    inv = 0.5 / s
    return (s, a[1] * inv, a[2] * inv - a[1] * a[1] * inv * inv * inv * 2.0)


@njit(inline="always", cache=True, error_model="numpy")
def _cscale(a, r):
    """complex jet × real jet"""
    return _cmul(a, (r[0], 0.0, r[1], 0.0, r[2], 0.0))


@njit(inline="always", cache=True, error_model="numpy")
def _dot(a, b):
    """Re(conj(a)·b) as a real jet"""
    v = a[0] * b[0] + a[1] * b[1]
    d = a[2] * b[0] + a[3] * b[1] + a[0] * b[2] + a[1] * b[3]
    dd = a[4] * b[0] + a[5] * b[1] + 2.0 * (a[2] * b[2] + a[3] * b[3]) + a[0] * b[4] + a[1] * b[5]
    return (v, d, dd)


@njit(inline="always", cache=True, error_model="numpy")
def rrr(c1, c2, r1, r2, branch, tol):
    """circle–circle on jets: (z, ok, margin); branch +1 puts z left of c1 → c2. Branchless
    (vectorisable): a radicand in [−tol, 0) counts as 0; below that ``ok`` is False (the caller NaNs
    the sample). ``margin`` = normalised radicand + tol: how far from (< 0: how far past) the toggle."""
    D = csub(c2, c1)
    d2 = _abs2(D)
    inv2 = _rinv(d2)
    a = _rmul((d2[0] + r1 * r1 - r2 * r2, d2[1], d2[2]), inv2)
    a = (0.5 * a[0], 0.5 * a[1], 0.5 * a[2])
    h2 = (r1 * r1 * inv2[0] - a[0] * a[0], r1 * r1 * inv2[1] - 2.0 * a[0] * a[1],
          r1 * r1 * inv2[2] - 2.0 * (a[1] * a[1] + a[0] * a[2]))
    ok = (d2[0] > 0.0) & (h2[0] >= -tol)
    h = _rsqrt((max(h2[0], 0.0), h2[1], h2[2]))
    f = (a[0], branch * h[0], a[1], branch * h[1], a[2], branch * h[2])
    return cadd(c1, _cmul(D, f)), ok, h2[0] + tol


@njit(inline="always", cache=True, error_model="numpy")
def rrp(pa, r, og, eg, gq, gu, gk, goff, branch, tol):
    """circle–line on jets for an RRP dyad: (z, e_slider, ok, margin). Branchless."""
    es = cmulk(eg, gk[0], gk[1])
    qj = cadd(cadd(og, cmulk(eg, gq[0], gq[1])), cmulk(es, goff[0], goff[1]))
    U = cmulk(eg, gu[0], gu[1])
    w = csub(qj, pa)
    proj = _dot(U, w)
    ww = _abs2(w)
    rad = (proj[0] * proj[0] - ww[0] + r * r, 2.0 * proj[0] * proj[1] - ww[1],
           2.0 * (proj[1] * proj[1] + proj[0] * proj[2]) - ww[2])
    ok = rad[0] >= -tol * (r * r + 1e-300)
    sq = _rsqrt((max(rad[0], 0.0), rad[1], rad[2]))
    t = (branch * sq[0] - proj[0], branch * sq[1] - proj[1], branch * sq[2] - proj[2])
    return cadd(qj, _cscale(U, t)), es, ok, rad[0] / (r * r + 1e-300) + tol


@njit(inline="always", cache=True, error_model="numpy")
def rpr(pg, ps, cpar, cperp, branch, tol):
    """orientation e·u of an RPR group's guide line on jets: (e_u, ok, margin). Branchless."""
    D = csub(ps, pg)
    DD = _abs2(D)
    rad0 = DD[0] - cperp * cperp
    ok = rad0 >= -tol * (DD[0] + 1e-300)
    rad = (max(rad0, 0.0), DD[1], DD[2])
    s = _rsqrt(rad)
    # e_u = D / (s·branch + i·c_perp) = D·(s·branch − i·c_perp) / (s² + c_perp²)
    den = _rinv((rad[0] + cperp * cperp, rad[1], rad[2]))
    num = _cmul(D, (branch * s[0], -cperp, branch * s[1], 0.0, branch * s[2], 0.0))
    return _cscale(num, den), ok, rad0 / (DD[0] + 1e-300) + tol


@njit(inline="always", cache=True, error_model="numpy")
def crank(c, s, sense, k):
    """e = exp(i·(zero + sense·q))·conj(u_arm) on jets from cos q, sin q and k = exp(i·zero)·conj(u_arm)."""
    ss = sense * s
    vr = c * k[0] - ss * k[1]
    vi = c * k[1] + ss * k[0]
    return (vr, vi, -sense * vi, sense * vr, -vr, -vi)


# -- per-design reductions of sampled cycles (called by the generated cycle kernels) -----------------

@njit(cache=True, error_model="numpy")
def gait_reduce(x, v, sp, vx, out, d, col):
    """The sampled gait terms of one design (the definitions of ``analysis.gait.population_gait``) into
    ``out[d, col:col + 9]``: step, lift, sag, duty, speed mean, speed spread, the spreads of |vx| over the
    central fractions 0.8 and 0.9 of the stride (``analysis.gait.central_vx_spread``) and the path's top height. x, v, sp, vx (M,): stride
    coordinate, height, foot speed and horizontal velocity at M uniform inputs over one turn, every sample
    assembled. The contact
    arc runs between the first samples of smallest and largest x, the one of the two arcs (both ends
    included) whose sample-mean height is lower (the first arc, smallest x → largest x, on a tie)."""
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
