"""What the generated kernels (:mod:`assur.kernels.codegen`) call: the per-design reductions of sampled cycles (the
sampled gait terms of a walking leg's foot, the distances of targets to a sampled closed path) and :func:`select`, the
branch-free choice of the Newton kernels. Compiled by numba (imported with this module, which only generated kernels
and tests import)."""
from __future__ import annotations

import math

import numpy as np

from .numba_target import configure

configure()                     # before numba is imported (numba_target's docstring)
from numba import njit  # noqa: E402
from numba.core import types  # noqa: E402
from numba.extending import intrinsic  # noqa: E402

from .similarity import similarity  # noqa: E402
# the triad's constants, shared with its numpy functions: samples of its function per turn, a root's distance from the
# unit circle below which it is an assembly, the strip |Im φ| ≤ β that holds every such root, and the steps of
# triad_alone's walk each way (the numpy twin's, assur.kernels.triad.turn_alone)
from .triad import ON_CIRCLE as _ON_CIRCLE, SAMPLES as _TRIAD_SAMPLES, STRIP as _TRIAD_STRIP, WALK as _TRIAD_WALK


@intrinsic
def select(typingctx, cond, a, b):
    """``a if cond else b`` as one LLVM ``select`` instruction: no branch, so no basic blocks for numba's front end to
    analyse (a conditional expression makes three, and the cost of numba's analyses grows with blocks × variables:
    the traced Newton kernels, with a hundred selects in their iteration loops, compile in about half the time)."""
    if not isinstance(cond, types.Boolean):
        return None
    common = typingctx.unify_types(a, b)
    if common is None:
        return None

    def codegen(context, builder, signature, args):
        x = context.cast(builder, args[1], signature.args[1], common)
        y = context.cast(builder, args[2], signature.args[2], common)
        return builder.select(args[0], x, y)
    return common(cond, a, b), codegen


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


#: compiled without numba's disk cache: that cache follows this file's changes, not those of .similarity, where the
#: arithmetic is written (a kernel that calls it is cached under a name that follows both: codegen.GENERATOR_FILES)
_similarity = njit(error_model="numpy")(similarity)


@njit(error_model="numpy")
def similarity_fit(px, py, pv, txy, lim, rotate, out, d):
    """The best placement of design d (:mod:`assur.synthesis.placement`) from its points (px, py) (N,) at the
    reference placement, ``pv`` (N,) 1.0 where assembled, the targets ``txy (N, 2)``, its limits ``lim (6,)``:
    ``out[d, 0]`` and ``out[d, 1]`` the sums of the squared distances and of the distances of the placed points
    (over the assembled targets), ``out[d, 5:9]`` (s, φ, dx, dy). Centred sums (two passes), so the fit keeps its
    digits when the points lie far from the origin."""
    N = px.shape[0]
    n = 0.0
    qx = 0.0
    qy = 0.0
    tx = 0.0
    ty = 0.0
    for u in range(N):
        w = pv[u]
        n += w
        qx += w * px[u]
        qy += w * py[u]
        tx += w * txy[u, 0]
        ty += w * txy[u, 1]
    m = max(n, 1.0)
    qx /= m
    qy /= m
    tx /= m
    ty /= m
    A = 0.0
    C = 0.0
    D = 0.0
    for u in range(N):
        w = pv[u]
        ax = (px[u] - qx) * w
        ay = (py[u] - qy) * w
        bx = (txy[u, 0] - tx) * w
        by = (txy[u, 1] - ty) * w
        A += ax * ax + ay * ay
        C += ax * by - ay * bx
        D += ax * bx + ay * by
    s, phi, dx, dy = _similarity(qx, qy, tx, ty, A, C, D, lim, rotate)
    c = math.cos(phi)
    sn = math.sin(phi)
    e2sum = 0.0
    esum = 0.0
    for u in range(N):
        if pv[u] > 0.0:
            ex = txy[u, 0] - (s * (c * px[u] - sn * py[u]) + dx)
            ey = txy[u, 1] - (s * (sn * px[u] + c * py[u]) + dy)
            e2 = ex * ex + ey * ey
            e2sum += e2
            esum += math.sqrt(e2)
    out[d, 0] = e2sum
    out[d, 1] = esum
    out[d, 5] = s
    out[d, 6] = phi
    out[d, 7] = dx
    out[d, 8] = dy


# -- a triad's assemblies near a solved pose ----------------------------------------------------------------------
#: exp(iφ_j) at the triad's sample orientations φ_j = 2πj/8, and the discrete Fourier transform's factors
#: exp(−2πi·jk/8) (numpy's fft) — constants of the compiled code
_TRIAD_E = np.exp(1j * 2.0 * np.pi * np.arange(_TRIAD_SAMPLES) / _TRIAD_SAMPLES)
_TRIAD_DFT = np.exp(-2j * np.pi * np.outer(np.arange(_TRIAD_SAMPLES), np.arange(_TRIAD_SAMPLES)) / _TRIAD_SAMPLES)


@njit(cache=True, error_model="numpy")
def _triad_coefficients(TA, TS):
    """The coefficients of z³·G(z) (assur.kernels.triad.triad_polynomial), highest power first, into ``TS[8:15]``
    (complex scratch; ``TS[0:8]`` the samples of G) from ``TA``'s w (0:6, re/im × 3), Q (6:12) and ell (12:15): the
    discrete Fourier transform of G's eight samples, whose bins −k are the conjugates of the bins k (G is real)."""
    for j in range(_TRIAD_SAMPLES):
        TS[j] = _triad_at(TA, _TRIAD_E[j])[0]
    for k in range(4):
        acc = 0j
        for j in range(_TRIAD_SAMPLES):
            acc += TS[j].real * _TRIAD_DFT[j, k]
        c = acc / _TRIAD_SAMPLES
        TS[11 - k] = c                   # e^{+ikφ}: the coefficient of z^{3+k}
        if k:
            TS[11 + k] = c.conjugate()   # e^{−ikφ}: of z^{3−k}


@njit(cache=True, error_model="numpy")
def _triad_function(TA, phi):
    """(G(φ), p(φ)) of assur.kernels.triad.triad_function for one orientation φ."""
    return _triad_at(TA, complex(math.cos(phi), math.sin(phi)))


@njit(cache=True, error_model="numpy")
def _triad_at(TA, e):
    """(G, p) of assur.kernels.triad.triad_function at the orientation e = exp(iφ) (real arithmetic)."""
    er, ei = e.real, e.imag
    v0r = er * TA[0] - ei * TA[1] - TA[6]
    v0i = er * TA[1] + ei * TA[0] - TA[7]
    v1r = er * TA[2] - ei * TA[3] - TA[8]
    v1i = er * TA[3] + ei * TA[2] - TA[9]
    v2r = er * TA[4] - ei * TA[5] - TA[10]
    v2i = er * TA[5] + ei * TA[4] - TA[11]
    vv0 = v0r * v0r + v0i * v0i
    vv1 = v1r * v1r + v1i * v1i
    vv2 = v2r * v2r + v2i * v2i
    u2r, u2i = v1r - v0r, v1i - v0i
    u3r, u3i = v2r - v0r, v2i - v0i
    l0 = TA[12] * TA[12]
    rho2 = 0.5 * (TA[13] * TA[13] - l0 - vv1 + vv0)
    rho3 = 0.5 * (TA[14] * TA[14] - l0 - vv2 + vv0)
    delta = u2r * u3i - u2i * u3r
    # N = i·(ρ3·u2 − ρ2·u3)
    ar, ai = rho3 * u2r - rho2 * u3r, rho3 * u2i - rho2 * u3i
    Nr, Ni = -ai, ar
    gr, gi = Nr + delta * v0r, Ni + delta * v0i
    ld = TA[12] * delta
    return gr * gr + gi * gi - ld * ld, complex(Nr / delta, Ni / delta)


#: Weierstrass iterations at most when the roots are tracked from the last call's
_TRACK_ITERATIONS = 30


@njit(cache=True, error_model="numpy")
def _track_roots(TS, RT):
    """The six roots of the polynomial in ``TS[8:15]`` by Weierstrass (Durand–Kerner) iterations started from
    ``RT[0:6]`` (the roots found at the last call: the walk moves them little), written back to ``RT``; False where
    they do not converge to distinct finite roots within :data:`_TRACK_ITERATIONS` iterations (then the caller finds
    them afresh: an eigenvalue solve costs as much as some thirty of these iterations)."""
    a0 = TS[8]
    if not RT[6].real > 0.0 or a0 == 0:
        return False
    for it in range(_TRACK_ITERATIONS):
        worst = 0.0
        for i in range(6):
            z = RT[i]
            f = TS[8]
            for k in range(1, 7):
                f = f * z + TS[8 + k]
            den = a0
            for j in range(6):
                if j != i:
                    den *= z - RT[j]
            dz = f / den
            RT[i] = z - dz
            # |dz|² / (1 + |z|²): the relative step, squared (no square roots)
            worst = max(worst, (dz.real * dz.real + dz.imag * dz.imag) / (1.0 + z.real * z.real + z.imag * z.imag))
        if not worst == worst:
            return False
        if worst < 1e-18:
            # a relative step below 1e-9 between distinct roots (none closer than 1e-6, relative): Newton's quadratic
            # convergence leaves an error of about (1e-9)²/1e-6 = 1e-12 of a root's size, far below what the
            # certificates resolve (a root within 1e-6 of the scale, the factor 2 between distances)
            for i in range(6):
                zi = RT[i]
                for j in range(i + 1, 6):
                    d = zi - RT[j]
                    if not d.real * d.real + d.imag * d.imag > 1e-12 * (1.0 + zi.real * zi.real + zi.imag * zi.imag):
                        return False
            return True
    return False


#: |e^{ikφ}| ≤ e^{kβ} on that strip, k = 1, 2, 3
_TRIAD_GROWTH = (math.exp(_TRIAD_STRIP), math.exp(2.0 * _TRIAD_STRIP), math.exp(3.0 * _TRIAD_STRIP))


@njit(cache=True, error_model="numpy")
def _triad_slopes(TS, e1):
    """(G'(φ), G''(φ)) at e1 = exp(iφ) from the coefficients c_k in ``TS[8:15]`` (c_k = TS[11 − k], c_−k = c̄_k):
    G' = −2·Σ k·Im(c_k·e^{ikφ}), G'' = −2·Σ k²·Re(c_k·e^{ikφ}), k = 1, 2, 3."""
    ek = e1
    g1 = 0.0
    g2 = 0.0
    for k in range(1, 4):
        t = TS[11 - k] * ek
        g1 -= 2.0 * k * t.imag
        g2 -= 2.0 * k * k * t.real
        ek = ek * e1
    return g1, g2


@njit(cache=True, error_model="numpy")
def triad_alone(TA, TS, reach):
    """A lower bound (m) on the distance from the triad's pose x to every other assembly its polynomial has, from the
    coefficients in ``TS[8:15]`` (:func:`_triad_coefficients`) alone: no root is found. 0 where nothing is proven.
    ``reach`` (rad): the turn of the ternary beyond which the bound need not look (π: as far as it can).

    G(φ) = Σ c_k·e^{ikφ} (|k| ≤ 3) has |G‴| ≤ M = 2·Σ k³·|c_k|·e^{kβ} on the strip |Im φ| ≤ β
    (:data:`assur.kernels.triad.STRIP`) that holds every root counted as an assembly. From x's orientation θ the bound
    walks each way: at φ_j, with g = |G'(φ_j)| and h = |G''(φ_j)|, |G'| stays above m = M·β²/6 for a further δ with
    g − h·δ − M·δ²/2 = m (Taylor). Where |G'| > m on a real interval I around θ, G is monotone on I (at most one real
    root there), and a complex root φ + iy (0 < |y| ≤ β, φ in I) cannot be: Im G(φ + iy) = y·G'(φ) + R with
    |R| ≤ M·|y|³/6. So every assembly but the one I may hold is turned at least r from θ (r: I's shorter side, at most
    π), and two poses of the ternary turned by Δ apart move one of the ends of its longest side D by at least
    |sin(Δ/2)|·D: the bound is sin(r/2)·D. Each step and the bound are shrunk by 1 % for round-off (a step needs g
    above m = 10⁻⁶·M/6, far above G's round-off)."""
    return 0.99 * math.sin(0.5 * _turn_alone(TS, complex(math.cos(TA[17]), math.sin(TA[17])), reach)) \
        * _longest_side(TA)


@njit(cache=True, error_model="numpy")
def _turn_alone(TS, e0, reach):
    """The turn r (rad, at most π; 0 where nothing is proven) within which :func:`triad_alone`'s walk from the
    orientation e0 = exp(iθ) proves no other assembly, looking no further than ``reach``."""
    big = 0.0
    for k in range(1, 4):
        big += k * k * k * abs(TS[11 - k]) * _TRIAD_GROWTH[k - 1]
    big *= 2.0
    floor = 1.01 * big * _TRIAD_STRIP * _TRIAD_STRIP / 6.0
    if not (big > 0.0 and math.isfinite(big)):
        return 0.0
    reach = min(reach, math.pi)
    r = math.pi
    for way in (1.0, -1.0):
        e = e0
        gone = 0.0
        for _ in range(_TRIAD_WALK):
            g, h = _triad_slopes(TS, e)
            g, h = abs(g), abs(h)
            if not g > floor:
                break
            # the largest δ with g − h·δ − M·δ²/2 ≥ m
            step = 0.99 * 2.0 * (g - floor) / (h + math.sqrt(h * h + 2.0 * big * (g - floor)))
            gone += step
            if gone >= reach:
                break
            e = e * complex(math.cos(way * step), math.sin(way * step))
        r = min(r, gone)
    return r


@njit(cache=True, error_model="numpy")
def _longest_side(TA):
    """The longest side D (m) of the ternary's triangle of joints w (``TA[0:6]``, re/im)."""
    side2 = 0.0
    for i in range(3):
        for j in range(i + 1, 3):
            dr, di = TA[2 * i] - TA[2 * j], TA[2 * i + 1] - TA[2 * j + 1]
            side2 = max(side2, dr * dr + di * di)
    return math.sqrt(side2)


@njit(cache=True, error_model="numpy")
def triad_check(TA, TS, RT, sep):
    """A triad's certificates at a solved pose, as the numpy backend's continuation checks them
    (assur.engine.planar.continuation._nearest_triad_assembly and separate): (the step's: the pose x is the assembly
    of the triad's polynomial nearest the prediction and every other at least twice as far from it; the sample's: no
    other assembly within ``sep`` (m) of x). Distances are the largest of the ternary's three joints.

    ``TA``: w (0:6, the ternary's three points in its frame, re/im), Q (6:12, the three known points), ell (12:15, the
    binary links' lengths), the ternary's pose at x (15:18: x, y, θ) and at the prediction (18:21), the length scale
    (21); ``TS``: complex scratch (22,); ``RT``: the roots of the last call (0:6) and whether they are known (6: > 0).

    Where :func:`triad_alone` proves every other assembly at least L from x, both hold without a root: the sample's
    when L > sep; the step's when L ≥ 3·d + 2·10⁻⁶·scale (d: the distance of x from the prediction; the assembly
    within 10⁻⁶·scale of x, if any, is then x's own, at most d + 10⁻⁶·scale from the prediction, and every other is
    at least L − d from it). The bound looks only as far as that needs. Otherwise :func:`triad_check_roots`
    decides."""
    _triad_coefficients(TA, TS)
    d2 = 0.0
    c, s = math.cos(TA[17]), math.sin(TA[17])
    cp, sp = math.cos(TA[20]), math.sin(TA[20])
    for k in range(3):
        wr, wi = TA[2 * k], TA[2 * k + 1]
        dr = TA[15] + c * wr - s * wi - (TA[18] + cp * wr - sp * wi)
        di = TA[16] + c * wi + s * wr - (TA[19] + cp * wi + sp * wr)
        d2 = max(d2, dr * dr + di * di)
    step = 3.0 * math.sqrt(d2) + 2e-6 * TA[21]
    side = _longest_side(TA)
    # the ternary's turn that moves an end of its longest side by what is needed (the bound's 1 % included)
    ratio = max(step, sep) / (0.99 * side)
    if ratio < 0.999:
        alone = 0.99 * math.sin(0.5 * _turn_alone(TS, complex(c, s), 1.001 * 2.0 * math.asin(ratio))) * side
        if alone > sep and alone >= step:
            return True, True
    return triad_check_roots(TA, TS, RT, sep)


@njit(cache=True, error_model="numpy")
def triad_check_roots(TA, TS, RT, sep):
    """:func:`triad_check` from every root of the polynomial whose coefficients :func:`_triad_coefficients` left in
    ``TS[8:15]``: the last call's roots, refined (:func:`_track_roots`); where that fails, the companion matrix's
    eigenvalues, as numpy finds them."""
    ox, oth = (TA[15], TA[16]), TA[17]
    po, pth = (TA[18], TA[19]), TA[20]
    scale = TA[21]
    cx, sx, cp, sp = math.cos(oth), math.sin(oth), math.cos(pth), math.sin(pth)
    a = TS[8:15]
    big2 = 0.0
    finite = True
    for i in range(7):
        big2 = max(big2, a[i].real * a[i].real + a[i].imag * a[i].imag)
        finite = finite and math.isfinite(a[i].real) and math.isfinite(a[i].imag)
    big = math.sqrt(big2)
    n = 0
    regular = finite and abs(a[0]) > 1e-13 * big
    if regular and _track_roots(TS, RT):
        n = 6
    else:
        RT[6] = 0.0
        if regular:
            comp = np.zeros((6, 6), dtype=np.complex128)
            for j in range(6):
                comp[0, j] = -a[j + 1] / a[0]
            for i in range(1, 6):
                comp[i, i - 1] = 1.0
            z = np.linalg.eigvals(comp)
            for i in range(6):
                RT[i] = z[i]
            RT[6] = 1.0
            n = 6
        elif finite and big > 0.0:
            z = np.roots(a.copy())
            n = len(z)
            for i in range(n):
                RT[i] = z[i]
    # the roots on the unit circle (numpy's order, by angle, does not change what follows): for each, the largest
    # squared distance of the ternary's joints in that assembly from those at the prediction and at x
    lo, hi = (1.0 - _ON_CIRCLE) ** 2, (1.0 + _ON_CIRCLE) ** 2
    mine = -1
    dxm = np.inf
    dpm = np.inf
    for i in range(n):
        z = RT[i]
        r2 = z.real * z.real + z.imag * z.imag
        if not lo < r2 < hi:
            continue
        rr = math.sqrt(r2)
        e = complex(z.real / rr, z.imag / rr)
        p = _triad_at(TA, e)[1]
        mp = 0.0
        mx = 0.0
        for k in range(3):
            wr, wi = TA[2 * k], TA[2 * k + 1]
            ar, ai = p.real + e.real * wr - e.imag * wi, p.imag + e.real * wi + e.imag * wr
            dr, di = ar - (po[0] + cp * wr - sp * wi), ai - (po[1] + cp * wi + sp * wr)
            mp = max(mp, dr * dr + di * di)
            dr, di = ar - (ox[0] + cx * wr - sx * wi), ai - (ox[1] + cx * wi + sx * wr)
            mx = max(mx, dr * dr + di * di)
        TA[22 + i] = mp if math.isfinite(mp) else np.inf
        TA[28 + i] = mx if math.isfinite(mx) else np.inf
        if TA[28 + i] < dxm:
            mine, dxm, dpm = i, TA[28 + i], TA[22 + i]
    # squared distances throughout: the numpy code's comparisons of distances, on their squares
    others = np.inf
    second = np.inf
    for i in range(n):
        z = RT[i]
        r2 = z.real * z.real + z.imag * z.imag
        if i == mine or not lo < r2 < hi:
            continue
        others = min(others, TA[22 + i])
        second = min(second, TA[28 + i])
    is_root = dxm <= (1e-6 * scale) ** 2
    return (not is_root) or (4.0 * dpm <= others), not (second <= sep * sep)
