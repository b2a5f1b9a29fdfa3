"""Every assembly of a class-III triad of revolutes, from its univariate polynomial (no plan, no names).

The triad is a ternary link (the *platform*) whose three points P_k = p + e·w_k (k = 1, 2, 3; p its origin,
e = exp(iφ) its orientation, w_k its local points) are held at distances l_k from three known points Q_k by the
three binary links: the forward kinematics of a planar three-legged platform. In complex numbers, with
v_k = e·w_k − Q_k,

    |p + v_k|² = l_k²,   k = 1, 2, 3.

Subtracting the first equation from the other two leaves two equations linear in p:

    Re(p̄·u_k) = ρ_k,   u_k = v_k − v_1,   ρ_k = (l_k² − l_1² − |v_k|² + |v_1|²) / 2,   k = 2, 3,

so Δ·p = N with Δ = Im(ū_2·u_3) and N = i·(ρ_3·u_2 − ρ_2·u_3) (Cramer's rule), and the first equation becomes

    G(φ) = |N + Δ·v_1|² − l_1²·Δ² = 0.

Counting harmonics of e: u_k and v_k hold e⁰, e¹; Δ and ρ_k hold e⁻¹ … e¹ (|v_k|² = |w_k|² + |Q_k|² −
2·Re(e·w_k·Q̄_k)); N and Δ·v_1 hold e⁻¹ … e²; so |N + Δ·v_1|² and Δ² hold e⁻³ … e³. G is a real trigonometric
polynomial of degree 3: z³·G is a polynomial of degree 6 in z = e, and a triad has at most six assemblies (the
known bound for the three-legged platform; Gosselin, Sefrioui & Richard, J. Mech. Des. 116 (1994) 587–593).

:func:`triad_polynomial` samples G at eight orientations and takes its seven coefficients by the discrete Fourier
transform (exact for degree 3; the eighth bin, which would hold e^±4, is returned as a check and is round-off);
:func:`triad_roots` finds the roots on the unit circle (companion-matrix eigenvalues) and the platform position of
each. The roots are estimates: the caller polishes each by Newton on the loop equations
(:mod:`assur.engine.planar.assemblies`).
"""
from __future__ import annotations

import math

import numpy as np

#: samples of G per turn (≥ 7 for degree 3; the 8th bin checks the degree)
SAMPLES = 8
#: a root z of the degree-6 polynomial is a real assembly candidate when | |z| − 1 | is below this (the caller
#: polishes and verifies every candidate, so this only has to keep the real ones)
ON_CIRCLE = 1e-3
#: the strip |Im φ| ≤ β of complex orientations that holds every root z = exp(iφ) counted as an assembly
#: (| |z| − 1 | below ON_CIRCLE: |z| = exp(−Im φ))
STRIP = -math.log(1.0 - ON_CIRCLE)
#: steps of :func:`turn_alone`'s walk away from the solved orientation, each way
WALK = 4


def _legs(e, w, Q, ell):
    """u_2, u_3, ρ_2, ρ_3, v_1 at orientations e (..., m): w, Q (..., 3) complex, ell (..., 3) real."""
    e = np.asarray(e)
    v = e[..., None] * w[..., None, :] - Q[..., None, :]                      # (..., m, 3)
    vv = np.abs(v) ** 2
    u2, u3 = v[..., 1] - v[..., 0], v[..., 2] - v[..., 0]
    l2 = ell[..., None, :] ** 2
    rho2 = 0.5 * (l2[..., 1] - l2[..., 0] - vv[..., 1] + vv[..., 0])
    rho3 = 0.5 * (l2[..., 2] - l2[..., 0] - vv[..., 2] + vv[..., 0])
    return u2, u3, rho2, rho3, v[..., 0]


def triad_function(phi, w, Q, ell):
    """G(φ) (..., m) and the platform origin p = N/Δ (..., m) complex at orientations ``phi (..., m)`` (rad).

    w : (..., 3) complex, the platform's three points in its own frame (B, C, D);
    Q : (..., 3) complex, the known points the three binary links are hinged to;
    ell : (..., 3) the binary links' lengths."""
    w, Q, ell = np.asarray(w, dtype=complex), np.asarray(Q, dtype=complex), np.asarray(ell, dtype=float)
    e = np.exp(1j * np.asarray(phi, dtype=float))
    u2, u3, rho2, rho3, v1 = _legs(e, w, Q, ell)
    delta = (np.conj(u2) * u3).imag
    N = 1j * (rho3 * u2 - rho2 * u3)
    G = np.abs(N + delta * v1) ** 2 - (ell[..., None, 0] * delta) ** 2
    with np.errstate(all="ignore"):
        p = N / delta
    return G, p


def triad_polynomial(w, Q, ell):
    """The coefficients of z³·G(z), a polynomial of degree 6 in z = exp(iφ), highest power first: (..., 7) complex,
    and the size of the e^±4 bin relative to the largest coefficient (..., a round-off check of the degree bound)."""
    phi = 2.0 * np.pi * np.arange(SAMPLES) / SAMPLES
    G, _ = triad_function(np.broadcast_to(phi, np.shape(ell)[:-1] + (SAMPLES,)), w, Q, ell)
    # numpy's c[k] = Σ_j G(2πj/n)·e^{−2πi·jk/n}, divided by n, is the coefficient of e^{+ikφ} (−k at n − k)
    c = np.fft.fft(G, axis=-1) / SAMPLES
    coeff = np.stack([c[..., 3], c[..., 2], c[..., 1], c[..., 0], c[..., -1], c[..., -2], c[..., -3]], axis=-1)
    big = np.max(np.abs(coeff), axis=-1)
    with np.errstate(all="ignore"):
        alias = np.abs(c[..., 4]) / np.where(big > 0, big, 1.0)
    return coeff, alias


def turn_alone(coeff, theta, reach=np.pi):
    """(...) a turn r (rad, at most π; 0 where nothing is proven) of the platform from the orientation ``theta`` (...)
    within which the polynomial ``coeff`` (..., 7) of :func:`triad_polynomial` has no root but, at most, the one at
    ``theta``'s assembly, looking no further than ``reach`` (rad): no root is found.

    G(φ) = Σ c_k·e^{ikφ} (|k| ≤ 3) has |G‴| ≤ M = 2·Σ k³·|c_k|·e^{kβ} on the strip |Im φ| ≤ β (:data:`STRIP`) that
    holds every root counted as an assembly. From θ the bound walks :data:`WALK` steps each way: at φ_j, with
    g = |G'(φ_j)| and h = |G''(φ_j)|, |G'| stays above m = M·β²/6 for a further δ with g − h·δ − M·δ²/2 = m (Taylor).
    Where |G'| > m on a real interval I around θ, G is monotone on I (at most one real root there), and a complex root
    φ + iy (0 < |y| ≤ β, φ in I) cannot be: Im G(φ + iy) = y·G'(φ) + R with |R| ≤ M·|y|³/6. So every assembly but the
    one I may hold is turned at least r from θ (r: I's shorter side). Each step and m are widened by 1 % for
    round-off. Two poses of the platform turned Δ apart move one end of its longest side D by at least |sin(Δ/2)|·D.

    The compiled kernels' twin is :func:`assur.kernels.reductions.triad_alone`, one sample at a time."""
    coeff = np.asarray(coeff, dtype=complex)
    theta = np.asarray(theta, dtype=float)
    ck = [coeff[..., 3 - k] for k in (1, 2, 3)]                     # c_k, the coefficient of e^{+ikφ}
    with np.errstate(all="ignore"):
        big = 2.0 * sum(k ** 3 * np.abs(c) * np.exp(k * STRIP) for k, c in zip((1, 2, 3), ck))
        floor = 1.01 * big * STRIP * STRIP / 6.0
        usable = (big > 0.0) & np.isfinite(big)
        reach = np.minimum(reach, np.pi)
        r = np.full(np.shape(big), np.pi)
        for way in (1.0, -1.0):
            phi = theta.copy() if theta.shape == big.shape else np.broadcast_to(theta, big.shape).copy()
            gone = np.zeros(big.shape)
            walking = usable.copy()
            for _ in range(WALK):
                e = [np.exp(1j * k * phi) for k in (1, 2, 3)]
                g = np.abs(-2.0 * sum(k * (c * ek).imag for k, c, ek in zip((1, 2, 3), ck, e)))
                h = np.abs(-2.0 * sum(k * k * (c * ek).real for k, c, ek in zip((1, 2, 3), ck, e)))
                walking &= g > floor
                # the largest δ with g − h·δ − M·δ²/2 ≥ m
                step = 0.99 * 2.0 * (g - floor) / (h + np.sqrt(h * h + 2.0 * big * (g - floor)))
                gone = np.where(walking, gone + step, gone)
                walking &= gone < reach
                phi = phi + way * np.where(walking, step, 0.0)
            r = np.minimum(r, np.where(usable, gone, 0.0))
    return r


def longest_side(w):
    """(...) the longest side (m) of the triangle of the platform's points ``w`` (..., 3) complex."""
    return np.max(np.abs(w[..., [0, 1, 2]] - w[..., [1, 2, 0]]), axis=-1)


def triad_alone(coeff, theta, w, reach=np.pi):
    """(...) a lower bound (m) on the distance (the largest of the platform's three points) from the assembly at
    orientation ``theta`` to every other assembly of the polynomial ``coeff`` (:func:`triad_polynomial`):
    0.99·sin(r/2)·D with r of :func:`turn_alone` and D the platform's longest side (:func:`longest_side`)."""
    return 0.99 * np.sin(0.5 * turn_alone(coeff, theta, reach)) * longest_side(np.asarray(w, dtype=complex))


def triad_roots(w, Q, ell):
    """Candidate assemblies of a batch of triads: orientations φ (..., 6) (rad, in [0, 2π), ascending, NaN where
    fewer) of the roots of z³·G on the unit circle, and the platform origins p (..., 6) complex there. ``w``,
    ``Q``, ``ell`` as :func:`triad_function`. The roots are the eigenvalues of the companion matrices, all at once
    (a polynomial whose leading coefficient vanishes to round-off, a lower degree, by numpy's ``roots``)."""
    coeff, _ = triad_polynomial(w, Q, ell)
    shape = coeff.shape[:-1]
    flat = coeff.reshape(-1, 7)
    m = len(flat)
    z = np.full((m, 6), np.nan + 0j)
    big = np.max(np.abs(flat), axis=-1)
    with np.errstate(all="ignore"):
        regular = np.all(np.isfinite(flat), axis=-1) & (np.abs(flat[:, 0]) > 1e-13 * big)
    if regular.any():
        a = flat[regular]
        comp = np.zeros((len(a), 6, 6), dtype=complex)
        comp[:, 0, :] = -a[:, 1:] / a[:, :1]
        comp[:, np.arange(1, 6), np.arange(5)] = 1.0
        z[regular] = np.linalg.eigvals(comp)
    for i in np.flatnonzero(~regular & np.all(np.isfinite(flat), axis=-1) & (big > 0)):
        r = np.roots(flat[i])
        z[i, :len(r)] = r
    on = np.abs(np.abs(z) - 1.0) < ON_CIRCLE
    phi = np.where(on, np.mod(np.angle(z), 2.0 * np.pi), np.nan)
    phi = np.sort(phi, axis=-1)                       # NaN last
    phi = phi.reshape(shape + (6,))
    _, p = triad_function(np.where(np.isfinite(phi), phi, 0.0), w, Q, ell)
    return phi, np.where(np.isfinite(phi), p, np.nan)
