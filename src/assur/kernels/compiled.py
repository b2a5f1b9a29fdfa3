"""Compiled (numba) kernel: one fused loop over samples that interprets a solve plan's op table.

The numpy backend evaluates each group on whole arrays of jets; this backend runs the same
closed forms sample by sample in native code, with every jet held in registers as a tuple:
a complex jet is ``(x, y, dx, dy, ddx, ddy)``, a real jet ``(v, d, dd)`` (derivatives by the
single input q). It is numerically the same computation (tests compare the two backends).

Op table rows (int64, width ``OP_WIDTH``); slots index the per-design complex constants
``G (n_designs, n_slots, 2)``:

====  =========  =============================================================================
code  name       operands
====  =========  =============================================================================
0     FRAMEPT    point, slot                      P[point] = G[slot]
1     CRANK      body, pivot, slot_w_pivot, slot_uconj, slot_zero, sense, slot_k (= exp(i·zero)·uconj)
2     PLACE      body, point, slot_w              P[point] = O[body] + E[body]·w
3     FROM_TWO   body, p1, p2, slot_w1, slot_inv  E = (P2 − P1)·inv, O = P1 − E·w1
4     RRR        A, slot_rA, B, slot_rB, J, branch
5     RRP        A, slot_rA, guide, slot_q, slot_u, slot_k, slot_off, J, branch, slider, slot_wJ
6     RPR        guide, gp, slider, sp, slot_wg, slot_c, slot_invu, slot_invus, slot_ws, branch
====  =========  =============================================================================
"""
from __future__ import annotations

import math

import numpy as np
from numba import njit, prange

OP_WIDTH = 14
FRAMEPT, CRANK, PLACE, FROM_TWO, RRR, RRP, RPR = range(7)


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
def _cmulk(a, kr, ki):
    """complex jet × complex constant"""
    ar, ai, adr, adi, aer, aei = a
    return (ar * kr - ai * ki, ar * ki + ai * kr, adr * kr - adi * ki, adr * ki + adi * kr,
            aer * kr - aei * ki, aer * ki + aei * kr)


@njit(inline="always", cache=True, error_model="numpy")
def _cadd(a, b):
    return (a[0] + b[0], a[1] + b[1], a[2] + b[2], a[3] + b[3], a[4] + b[4], a[5] + b[5])


@njit(inline="always", cache=True, error_model="numpy")
def _csub(a, b):
    return (a[0] - b[0], a[1] - b[1], a[2] - b[2], a[3] - b[3], a[4] - b[4], a[5] - b[5])


@njit(inline="always", cache=True, error_model="numpy")
def _ckonst(kr, ki):
    return (kr, ki, 0.0, 0.0, 0.0, 0.0)


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
def _load(P, i):
    return (P[i, 0], P[i, 1], P[i, 2], P[i, 3], P[i, 4], P[i, 5])


@njit(inline="always", cache=True, error_model="numpy")
def _store(P, i, a):
    for k in range(6):
        P[i, k] = a[k]


@njit(inline="always", cache=True, error_model="numpy")
def _dot(a, b):
    """Re(conj(a)·b) as a real jet"""
    v = a[0] * b[0] + a[1] * b[1]
    d = a[2] * b[0] + a[3] * b[1] + a[0] * b[2] + a[1] * b[3]
    dd = a[4] * b[0] + a[5] * b[1] + 2.0 * (a[2] * b[2] + a[3] * b[3]) + a[0] * b[4] + a[1] * b[5]
    return (v, d, dd)


@njit(inline="always", cache=True, error_model="numpy")
def rrr(c1, c2, r1, r2, branch, tol):
    """circle–circle on jets: (z, ok); branch +1 puts z left of c1 → c2."""
    D = _csub(c2, c1)
    d2 = _abs2(D)
    ok = d2[0] > 0.0
    inv2 = _rinv(d2)
    a = _rmul((d2[0] + r1 * r1 - r2 * r2, d2[1], d2[2]), inv2)
    a = (0.5 * a[0], 0.5 * a[1], 0.5 * a[2])
    h2 = (r1 * r1 * inv2[0] - a[0] * a[0], r1 * r1 * inv2[1] - 2.0 * a[0] * a[1],
          r1 * r1 * inv2[2] - 2.0 * (a[1] * a[1] + a[0] * a[2]))
    if h2[0] < 0.0:
        ok = ok and h2[0] >= -tol
        h2 = (0.0, h2[1], h2[2])
    h = _rsqrt(h2)
    f = (a[0], branch * h[0], a[1], branch * h[1], a[2], branch * h[2])
    return _cadd(c1, _cmul(D, f)), ok


@njit(inline="always", cache=True, error_model="numpy")
def rrp(pa, r, og, eg, gq, gu, gk, goff, branch, tol):
    """circle–line on jets for an RRP dyad: (z, e_slider, ok)."""
    es = _cmulk(eg, gk[0], gk[1])
    qj = _cadd(_cadd(og, _cmulk(eg, gq[0], gq[1])), _cmulk(es, goff[0], goff[1]))
    U = _cmulk(eg, gu[0], gu[1])
    w = _csub(qj, pa)
    proj = _dot(U, w)
    ww = _abs2(w)
    rad = (proj[0] * proj[0] - ww[0] + r * r, 2.0 * proj[0] * proj[1] - ww[1],
           2.0 * (proj[1] * proj[1] + proj[0] * proj[2]) - ww[2])
    ok = True
    if rad[0] < 0.0:
        ok = rad[0] >= -tol * (r * r + 1e-300)
        rad = (0.0, rad[1], rad[2])
    sq = _rsqrt(rad)
    t = (branch * sq[0] - proj[0], branch * sq[1] - proj[1], branch * sq[2] - proj[2])
    return _cadd(qj, _cscale(U, t)), es, ok


@njit(inline="always", cache=True, error_model="numpy")
def rpr(pg, ps, cpar, cperp, branch, tol):
    """orientation e·u of an RPR group's guide line on jets: (e_u, ok)."""
    D = _csub(ps, pg)
    DD = _abs2(D)
    rad = (DD[0] - cperp * cperp, DD[1], DD[2])
    ok = True
    if rad[0] < 0.0:
        ok = rad[0] >= -tol * (DD[0] + 1e-300)
        rad = (0.0, rad[1], rad[2])
    s = _rsqrt(rad)
    # e_u = D / (s·branch + i·c_perp) = D·(s·branch − i·c_perp) / (s² + c_perp²)
    den = _rinv((rad[0] + cperp * cperp, rad[1], rad[2]))
    num = _cmul(D, (branch * s[0], -cperp, branch * s[1], 0.0, branch * s[2], 0.0))
    return _cscale(num, den), ok


@njit(inline="always", cache=True, error_model="numpy")
def crank(c, s, sense, k):
    """e = exp(i·(zero + sense·q))·conj(u_arm) on jets from cos q, sin q and k = exp(i·zero)·conj(u_arm)."""
    ss = sense * s
    vr = c * k[0] - ss * k[1]
    vi = c * k[1] + ss * k[0]
    return (vr, vi, -sense * vi, sense * vr, -vr, -vi)


@njit(cache=True, error_model="numpy")
def _sample(ops, g, q, P, O, E, tol):
    """Solve one sample by interpreting the op table; returns False if a group cannot be assembled."""
    ok = True
    for r in range(ops.shape[0]):
        op = ops[r]
        code = op[0]
        if code == FRAMEPT:
            s = op[2]
            _store(P, op[1], _ckonst(g[s, 0], g[s, 1]))
        elif code == CRANK:
            b, pivot, sw, sense, sk = op[1], op[2], op[3], op[6], op[7]
            e = crank(math.cos(q), math.sin(q), float(sense), (g[sk, 0], g[sk, 1]))
            _store(E, b, e)
            _store(O, b, _csub(_load(P, pivot), _cmulk(e, g[sw, 0], g[sw, 1])))
        elif code == PLACE:
            b, p, sw = op[1], op[2], op[3]
            _store(P, p, _cadd(_load(O, b), _cmulk(_load(E, b), g[sw, 0], g[sw, 1])))
        elif code == FROM_TWO:
            b, p1, p2, sw1, sinv = op[1], op[2], op[3], op[4], op[5]
            a1 = _load(P, p1)
            e = _cmulk(_csub(_load(P, p2), a1), g[sinv, 0], g[sinv, 1])
            _store(E, b, e)
            _store(O, b, _csub(a1, _cmulk(e, g[sw1, 0], g[sw1, 1])))
        elif code == RRR:
            z, good = rrr(_load(P, op[1]), _load(P, op[3]), g[op[2], 0], g[op[4], 0], float(op[6]), tol)
            ok = ok and good
            _store(P, op[5], z)
        elif code == RRP:
            A, sra, gb, sq, su, sk, soff, J, branch, sb, swj = (op[1], op[2], op[3], op[4], op[5], op[6], op[7],
                                                               op[8], op[9], op[10], op[11])
            z, es, good = rrp(_load(P, A), g[sra, 0], _load(O, gb), _load(E, gb), (g[sq, 0], g[sq, 1]),
                              (g[su, 0], g[su, 1]), (g[sk, 0], g[sk, 1]), (g[soff, 0], g[soff, 1]),
                              float(branch), tol)
            ok = ok and good
            _store(P, J, z)
            _store(E, sb, es)
            _store(O, sb, _csub(z, _cmulk(es, g[swj, 0], g[swj, 1])))
        elif code == RPR:
            gb, gp, sb, sp, swg, sc, sinvu, sinvus, sws, branch = (op[1], op[2], op[3], op[4], op[5], op[6],
                                                                   op[7], op[8], op[9], op[10])
            pg = _load(P, gp)
            eu, good = rpr(pg, _load(P, sp), g[sc, 0], g[sc, 1], float(branch), tol)
            ok = ok and good
            eg = _cmulk(eu, g[sinvu, 0], g[sinvu, 1])
            _store(E, gb, eg)
            _store(O, gb, _csub(pg, _cmulk(eg, g[swg, 0], g[swg, 1])))
            es = _cmulk(eu, g[sinvus, 0], g[sinvus, 1])
            _store(E, sb, es)
            _store(O, sb, _csub(_load(P, sp), _cmulk(es, g[sws, 0], g[sws, 1])))
    return ok


@njit(parallel=True, cache=True, error_model="numpy")
def run(ops, G, design_of, q, point_out, body_out, tol, n_points, n_bodies, out):
    """Solve every sample: design_of (S,) design index, q (S,) input; out (3, S, m, 2) float:
    [value, d/dq, d²/dq²] × (x, y) of the m = n_points + n_bodies outputs (points, then body
    orientations exp(iθ)); returns valid (S,) bool. point_out/body_out map output slots."""
    S = q.shape[0]
    valid = np.empty(S, dtype=np.bool_)
    n_chunks = 64 if S >= 64 * 256 else 1
    per = (S + n_chunks - 1) // n_chunks
    for c in prange(n_chunks):
        P = np.zeros((n_points, 6))
        O = np.zeros((n_bodies, 6))
        E = np.zeros((n_bodies, 6))
        E[0, 0] = 1.0
        for i in range(c * per, min(S, (c + 1) * per)):
            ok = _sample(ops, G[design_of[i]], q[i], P, O, E, tol)
            valid[i] = ok
            if ok:
                for k in range(point_out.shape[0]):
                    p = point_out[k]
                    for j in range(3):
                        out[j, i, k, 0] = P[p, 2 * j]
                        out[j, i, k, 1] = P[p, 2 * j + 1]
                for k in range(body_out.shape[0]):
                    b = body_out[k]
                    m = point_out.shape[0] + k
                    for j in range(3):
                        out[j, i, m, 0] = E[b, 2 * j]
                        out[j, i, m, 1] = E[b, 2 * j + 1]
            else:
                for k in range(out.shape[2]):
                    for j in range(3):
                        out[j, i, k, 0] = np.nan
                        out[j, i, k, 1] = np.nan
    return valid
