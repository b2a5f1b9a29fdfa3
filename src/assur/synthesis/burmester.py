"""Burmester theory of a rigid body in 3, 4 or 5 finitely separated poses: the RR dyads whose moving pivot
(circle point) stays on a circle about a fixed pivot (centre point) through every pose.

A pose j is (x_j, y_j, θ_j): the body's point at d_j = x_j + i·y_j and its angle θ_j. The body's displacement
from pose 1 to pose j maps a point Z (given in pose 1) to R_j·(Z − d_1) + d_j with R_j = exp(i(θ_j − θ_1)).
A dyad (centre G, circle point Z) fits when |Z_j − G| = |Z − G| for every j; with u = Z − d_1 this is, for
each j ≥ 2, linear in u for a given G and linear in G for a given Z (Sandor & Erdman, *Advanced Mechanism
Design* vol. 2, ch. 2; McCarthy & Soh, *Geometric Design of Linkages*, ch. 4–5):

    u · m_j(G) = h_j(G),   m_j = 2·[conj(R_j)(d_j − G) − (d_1 − G)],   h_j = |d_1 − G|² − |d_j − G|²

(complex numbers read as 2-vectors). Three poses leave G free (two equations, two unknowns in u); four
poses make the 3×3 matrix [m_j | h_j] singular, a cubic in G: the centre-point curve, which passes through
every pole P_1k. On a line G = P_1k + r·e through such a pole the row k vanishes linearly in r, so the
curve's other points on that line are the roots of a quadratic in r — one pencil parameter (the line's
angle τ) samples the whole curve. Five poses: the centres common to the curves of poses {1, k, a, b} and
{1, k, a, c}; on each line of the pencil through P_1k both quadratics are known and they share a root
exactly where their resultant vanishes, a 1-D root search in τ followed by a Newton polish (at most four
real Burmester points; the spurious common poles P_1a, P_ka are rejected by the full residual).

All work is done on coordinates centred at the mean pose point and scaled by the poses' spread.
"""
from __future__ import annotations

import numpy as np

from ..errors import SpecError, SynthesisError


def check_poses(poses) -> np.ndarray:
    """poses (n, 3) with n = 3, 4 or 5, finite → float array; else a SpecError saying what is wrong."""
    try:
        P = np.asarray(poses, dtype=float)
    except (TypeError, ValueError):
        raise SpecError([("poses", "must be an (n, 3) array of numbers (x, y, angle)")]) from None
    if P.ndim != 2 or P.shape[1] != 3 or P.shape[0] not in (3, 4, 5):
        raise SpecError([("poses", f"must have shape (n, 3) with n = 3, 4 or 5 (x, y, angle rows): {P.shape}")])
    if not np.all(np.isfinite(P)):
        raise SpecError([("poses", "must be finite numbers")])
    for j in range(1, len(P)):
        for k in range(j):
            if np.hypot(*(P[j, :2] - P[k, :2])) < 1e-12 and abs(np.sin((P[j, 2] - P[k, 2]) / 2)) < 1e-12:
                raise SpecError([(f"poses[{j}]", f"is the same pose as poses[{k}]")])
    return P


class Poses:
    """The normalised displacement data of n poses: d (n,) complex, R (n,) complex, and the scale."""

    def __init__(self, poses):
        P = check_poses(poses)
        z = P[:, 0] + 1j * P[:, 1]
        self.origin = z.mean()
        spread = float(np.max(np.abs(z - self.origin)))
        self.scale = spread if spread > 1e-12 else 1.0
        self.d = (z - self.origin) / self.scale
        self.R = np.exp(1j * (P[:, 2] - P[0, 2]))
        self.n = len(P)

    def to_world(self, w):
        return np.asarray(w) * self.scale + self.origin

    def to_local(self, w):
        return (np.asarray(w) - self.origin) / self.scale

    def pole(self, k: int) -> complex:
        """The pole P_1k of the displacement from pose 1 to pose k (its fixed point)."""
        return complex((self.d[k] - self.R[k] * self.d[0]) / (1.0 - self.R[k]))

    def rows(self, G, js):
        """[m_j | h_j] rows for centres G (...,) complex → (..., len(js), 3)."""
        G = np.asarray(G, dtype=complex)[..., None]
        d1, dj, Rj = self.d[0], self.d[list(js)], self.R[list(js)]
        m = 2.0 * (np.conj(Rj) * (dj - G) - (d1 - G))
        h = np.abs(d1 - G) ** 2 - np.abs(dj - G) ** 2
        return np.stack([m.real, m.imag, h], axis=-1)

    def circle_points(self, G):
        """Circle points Z (local, complex) of centres G (m,) by least squares over all poses, and the
        relative residual (m,)."""
        G = np.atleast_1d(np.asarray(G, dtype=complex))
        M = self.rows(G, range(1, self.n))
        A, h = M[..., :2], M[..., 2]
        u = np.full(len(G), np.nan + 0j)
        res = np.full(len(G), np.inf)
        for i in range(len(G)):
            if not np.all(np.isfinite(A[i])):
                continue
            sol, *_ = np.linalg.lstsq(A[i], h[i], rcond=None)
            u[i] = sol[0] + 1j * sol[1]
            res[i] = self.residual(G[i], u[i] + self.d[0])
        return u + self.d[0], res

    def residual(self, G, Z) -> float:
        """max_j | |Z_j − G| − |Z − G| | relative to |Z − G| (0 for an exact dyad)."""
        Zj = self.R * (Z - self.d[0]) + self.d
        r = np.abs(Zj - G)
        return float(np.max(np.abs(r - r[0])) / max(r[0], 1e-300))

    def pencil_pole(self) -> int:
        """The pose k ≥ 2 whose rotation from pose 1 is largest (its pole is the best-conditioned pencil
        centre); a SynthesisError if no pose turns."""
        s = np.abs(np.sin(np.angle(self.R[1:]) / 2))
        k = int(np.argmax(s)) + 1
        if s[k - 1] < 1e-9:
            raise SynthesisError("the poses do not rotate: four or five poses need a turn of the body between "
                                 "them for a finite set of centre points")
        return k

    def quadratic(self, k: int, js, tau):
        """Coefficients (…, 3) of the quadratic q0 + q1 r + q2 r² whose roots are the centre-point curve of
        poses {1, k} ∪ js on the line G = P_1k + r·exp(iτ) (besides r = 0)."""
        C = self.pole(k)
        e = np.exp(1j * np.asarray(tau, dtype=float))[..., None]
        a = self.rows(np.full(np.shape(tau), C), js)                       # (…, 2, 3) constants
        dj = self.d[list(js)]
        s = np.stack([(2.0 * e * (1 - np.conj(self.R[list(js)]))).real,
                      (2.0 * e * (1 - np.conj(self.R[list(js)]))).imag,
                      2.0 * np.real(np.conj(e) * (dj - self.d[0]))], axis=-1)  # (…, 2, 3) slopes
        ek = e[..., 0]
        sk = np.stack([(2.0 * ek * (1 - np.conj(self.R[k]))).real, (2.0 * ek * (1 - np.conj(self.R[k]))).imag,
                       2.0 * np.real(np.conj(ek) * (self.d[k] - self.d[0]))], axis=-1)   # (…, 3)

        def det(r1, r2):
            return np.linalg.det(np.stack([r1, r2, sk], axis=-2))

        q0 = det(a[..., 0, :], a[..., 1, :])
        q1 = det(s[..., 0, :], a[..., 1, :]) + det(a[..., 0, :], s[..., 1, :])
        q2 = det(s[..., 0, :], s[..., 1, :])
        return np.stack([q0, q1, q2], axis=-1)


def _real_roots(q, eps=1e-12):
    q0, q1, q2 = q
    scale = max(abs(q0), abs(q1), abs(q2), 1e-300)
    q0, q1, q2 = q0 / scale, q1 / scale, q2 / scale
    if abs(q2) < eps:
        return [] if abs(q1) < eps else [-q0 / q1]
    disc = q1 * q1 - 4 * q2 * q0
    if disc < 0:
        return []
    sq = np.sqrt(disc)
    return [(-q1 - sq) / (2 * q2), (-q1 + sq) / (2 * q2)]


def three_pose_dyads(P: Poses, centres):
    """n = 3: the circle point of each given centre (local complex) → (G, Z, residual)."""
    G = np.asarray(centres, dtype=complex)
    Z, res = P.circle_points(G)
    return G, Z, res


def centre_curve(P: Poses, samples: int = 36, reach: float = 20.0):
    """n = 4: the centre-point curve sampled on ``samples`` lines of the pencil through the pole P_1k
    (τ = π·i/samples) → (G, Z, residual), centres within ``reach`` (local units) of the poses."""
    k = P.pencil_pole()
    js = [j for j in range(1, P.n) if j != k]
    C = P.pole(k)
    taus = np.pi * np.arange(samples) / samples
    Q = P.quadratic(k, js, taus)
    G = []
    for tau, q in zip(taus, Q):
        for r in _real_roots(q):
            g = C + r * np.exp(1j * tau)
            if 1e-9 < abs(r) and abs(g) < reach:
                G.append(g)
    G = np.array(G, dtype=complex)
    Z, res = P.circle_points(G)
    return G, Z, res


def snap_to_curve(P: Poses, points):
    """n = 4: each given point Q moved onto the centre-point curve along its line through the pole P_1k
    (the root nearest Q on that line) → (G, Z, residual); a point whose line misses the curve is dropped."""
    k = P.pencil_pole()
    js = [j for j in range(1, P.n) if j != k]
    C = P.pole(k)
    G = []
    for Q in np.atleast_1d(np.asarray(points, dtype=complex)):
        tau, rq = float(np.angle(Q - C)), float(abs(Q - C))
        roots = [r for r in _real_roots(P.quadratic(k, js, np.array(tau))) if abs(r) > 1e-9]
        if roots:
            r = min(roots, key=lambda r: abs(r - rq))
            G.append(C + r * np.exp(1j * tau))
    G = np.array(G, dtype=complex)
    Z, res = P.circle_points(G)
    return G, Z, res


def burmester_points(P: Poses, samples: int = 2880, tol: float = 1e-8):
    """n = 5: the Burmester points (centre, circle point), at most four real ones → (G, Z, residual)."""
    from scipy.optimize import brentq, least_squares
    k = P.pencil_pole()
    a, b, c = [j for j in range(1, P.n) if j != k]
    C = P.pole(k)

    def quads(tau):
        q = P.quadratic(k, [a, b], tau)
        p = P.quadratic(k, [a, c], tau)
        q = q / np.maximum(np.abs(q).max(axis=-1, keepdims=True), 1e-300)
        p = p / np.maximum(np.abs(p).max(axis=-1, keepdims=True), 1e-300)
        return q, p

    def resultant(tau):
        q, p = quads(np.asarray(tau, dtype=float))
        q0, q1, q2 = q[..., 0], q[..., 1], q[..., 2]
        p0, p1, p2 = p[..., 0], p[..., 1], p[..., 2]
        return (q2 * p0 - q0 * p2) ** 2 - (q2 * p1 - q1 * p2) * (q1 * p0 - q0 * p1)

    taus = np.linspace(0.0, np.pi, samples + 1)
    f = resultant(taus)
    roots = [float(taus[i]) for i in np.flatnonzero(f == 0)]
    for i in np.flatnonzero(np.sign(f[:-1]) * np.sign(f[1:]) < 0):
        roots.append(brentq(resultant, taus[i], taus[i + 1], xtol=1e-15))

    def equations(v):
        G, Z = v[0] + 1j * v[1], v[2] + 1j * v[3]
        Zj = P.R * (Z - P.d[0]) + P.d
        r2 = np.abs(Zj - G) ** 2
        return r2[1:] - r2[0]

    found = []
    for tau in roots:
        q, p = quads(np.array(tau))
        den = q[2] * p[1] - q[1] * p[2]
        if abs(den) < 1e-14:
            continue
        r = -(q[2] * p[0] - q[0] * p[2]) / den
        if abs(r) < 1e-9:
            continue
        G0 = C + r * np.exp(1j * tau)
        Z0, _ = P.circle_points(G0)
        if not np.isfinite(Z0[0]):
            continue
        sol = least_squares(equations, [G0.real, G0.imag, Z0[0].real, Z0[0].imag], xtol=1e-15, ftol=1e-15,
                            gtol=1e-15)
        G, Z = sol.x[0] + 1j * sol.x[1], sol.x[2] + 1j * sol.x[3]
        if abs(Z - G) < 1e-6 or P.residual(G, Z) > tol:
            continue
        if any(abs(G - g) < 1e-6 and abs(Z - z) < 1e-6 for g, z in found):
            continue
        found.append((G, Z))
    G = np.array([g for g, _ in found], dtype=complex)
    Z = np.array([z for _, z in found], dtype=complex)
    return G, Z, np.array([P.residual(g, z) for g, z in found])


__all__ = ["Poses", "burmester_points", "centre_curve", "check_poses", "snap_to_curve", "three_pose_dyads"]
