"""Kinetostatics group by group: the reactions of each Assur group from its own equilibrium (numpy rows).

The groups are solved from the last one attached back to the drivers (Artobolevsky's order): when
a group is solved, the loads of every later group on its bodies are already known. A dyad has two
closed forms (:mod:`.kernel`), written once for every dyad kind:

* **inner revolute at J** (RRR, RRP, PRP): each side's moment about J fixes the part of an outer
  revolute's force across X − J (p = −M_J/|X − J|); the rest is one unknown along X − J (a revolute)
  or along the normal n of an outer slide; the dyad's force balance μ_a·e_a + μ_b·e_b = G gives both
  (Cramer). The condition measure is |e_a × e_b| (0 at a toggle: A, J, B in line).
* **inner slide** (RPR, PPR): the sides' force balances along the slide, the dyad's balance across it
  and its moment balance. The condition measure is |cos| of the angle between the outer revolutes'
  line and the slide (RPR), or |sin| of the angle between the two slides (PPR).

A driven actuator's own slide (its force) follows from its rod's equilibrium; a crank's torque from the
crank's. Any other group (triads and higher) is a small linear solve per sample
(:func:`solve_group_linear`), which over every moving body at once is the global Newton–Euler matrix:
the test oracle and the fallback (``method="matrix"``).
"""
from __future__ import annotations

import numpy as np

from . import kernel as K
from .program import Program


def solve_rows(prog: Program, z, v, a, p, F, M, *, method: str = "groups", length_scale: float = 1.0):
    """Solve N samples at once. ``z``, ``v``, ``a`` (n_points, N) complex; ``p`` (n_params, N or 1); ``F``, ``M``
    (n_bodies, N) the loads applied so far (extra loads; gravity, inertia and the constant loads are added
    here). Returns (lam (n_unknowns, N), orient (e^{iθ}), omega, alpha (n_bodies, N), condition (N,))."""
    nb, N = F.shape
    orient, omega, alpha = body_rows(prog, z, v, a, p)
    lam = np.full((prog.n_unknowns, N), np.nan)
    with np.errstate(all="ignore"):
        K.mass_loads(prog.massive, prog.mass, prog.inertia, prog.idef, prog.ipts, prog.cpts, prog.cw, prog.coff,
                     prog.gravity, z, v, a, orient, omega, alpha, F, M)
        K.point_loads(prog.lpts, prog.lforce, prog.torque, z, F, M)
        cond = np.ones(N)
        if method == "matrix":
            bodies = tuple(range(1, nb))
            c = solve_group_linear(prog, bodies, tuple(range(prog.pr.shape[0])), z, p, orient, F, M, lam,
                                   length_scale)
            return lam, orient, omega, alpha, c
        generic = iter(prog.generic)
        for g in range(prog.gr.shape[0]):
            code = prog.gr[g, K.GR_CODE]
            args = (prog.gr, g, prog.gb, prog.gd, prog.pr, prog.ln, z, p, orient, F, M, lam)
            if code == K.G_CRANK:
                c = K.crank(prog.gr, g, prog.gb, prog.pr, prog.ln, z, p, orient, F, M, lam)
            elif code == K.G_INNER_R:
                c = K.inner_revolute(*args)
            elif code == K.G_INNER_P:
                c = K.inner_slide(*args)
            else:
                bodies, pairs = next(generic)
                c = solve_group_linear(prog, bodies, pairs, z, p, orient, F, M, lam, length_scale)
            cond = np.fmin(cond, c)
    return lam, orient, omega, alpha, cond


def body_rows(prog: Program, z, v, a, p):
    """Every body's orientation e^{iθ}, ω, α as rows (n_bodies, N), from the points' rows ``z``, ``v``, ``a`` (n_points, N)."""
    nb, N = prog.ang.shape[0], z.shape[1]
    orient, omega, alpha = np.ones((nb, N), complex), np.zeros((nb, N)), np.zeros((nb, N))
    with np.errstate(all="ignore"):
        K.body_motion(prog.ang_order, prog.ang, prog.ang_param, prog.ang_off, z, v, a, p, orient, omega, alpha)
    return orient, omega, alpha


def _is_couple(prog: Program, k: int, j: int) -> bool:
    kind = prog.pr[k, 0]
    return kind == K.PAIR_T or (kind == K.PAIR_P and j == 1)


def solve_group_linear(prog: Program, bodies, pairs, z, p, orient, F, M, lam, length_scale: float):
    """The group's equilibrium as one linear system per sample: 3 equations per body (its force, and its
    moment about the group's first body's first point over the length scale), one column per unknown
    (couples over the length scale too). Returns the condition measure σ_min/σ_max of the scaled matrix."""
    L = length_scale
    N = F.shape[1]
    nb = F.shape[0]
    rows = {b: 3 * i for i, b in enumerate(bodies)}
    cols = [(k, j) for k in pairs for j in range(_n_cols(prog, k))]
    n = 3 * len(bodies)
    if len(cols) != n:
        raise ValueError(f"a group of {len(bodies)} bodies has {len(cols)} unknowns")
    X = z[_first_point(prog, bodies[0])]
    A = np.zeros((N, n, n))
    rhs = np.zeros((N, n))
    for b in bodies:
        r = rows[b]
        MX = M[b] - K.cross(X, F[b])
        rhs[:, r], rhs[:, r + 1], rhs[:, r + 2] = -F[b].real, -F[b].imag, -MX / L
    scratch_lam = np.zeros((prog.n_unknowns, N))
    for c, (k, j) in enumerate(cols):
        Fs, Ms = np.zeros((nb, N), complex), np.zeros((nb, N))
        x = [0.0, 0.0, 0.0]
        x[j] = L if _is_couple(prog, k, j) else 1.0
        K.set_pair(prog.pr, prog.ln, k, x[0], x[1], x[2], z, p, orient, Fs, Ms, scratch_lam)
        for b in bodies:
            r = rows[b]
            A[:, r, c] = Fs[b].real
            A[:, r + 1, c] = Fs[b].imag
            A[:, r + 2, c] = (Ms[b] - K.cross(X, Fs[b])) / L
    x, cond = linear_solve(A, rhs)
    values: dict[int, list] = {}
    for c, (k, j) in enumerate(cols):
        values.setdefault(k, [0.0, 0.0, 0.0])[j] = x[:, c] * (L if _is_couple(prog, k, j) else 1.0)
    for k, vals in values.items():
        K.set_pair(prog.pr, prog.ln, k, vals[0], vals[1], vals[2], z, p, orient, F, M, lam)
    return cond


def _n_cols(prog: Program, k: int) -> int:
    kind = prog.pr[k, 0]
    if kind == K.PAIR_R:
        return 2
    if kind == K.PAIR_T:
        return 1
    return 3 if prog.pr[k, 5] >= 0 else 2


def _first_point(prog: Program, b: int) -> int:
    if prog.ang[b, 0] == K.ANG_POINTS:
        return int(prog.ang[b, 1])
    for k in range(prog.pr.shape[0]):
        if prog.pr[k, 0] == K.PAIR_R and b in (prog.pr[k, 1], prog.pr[k, 2]):
            return int(prog.pr[k, 3])
    return 0


def linear_solve(A, rhs):
    """Batched ``A x = rhs`` with A (N, n, n): x (N, n) and the condition measure σ_min/σ_max (N,) (the reciprocal
    of the 2-norm condition number: 1 for orthogonal columns, 0 when singular); NaN where a sample's matrix is
    not finite or exactly singular (never an exception for one bad sample)."""
    with np.errstate(all="ignore"):
        finite = np.all(np.isfinite(A), axis=(-1, -2)) & np.all(np.isfinite(rhs), axis=-1)
        safe = np.where(finite[..., None, None], A, np.eye(A.shape[-1]))
        sv = np.linalg.svd(safe, compute_uv=False)
        ratio = np.where(finite, sv[..., -1] / np.where(sv[..., 0] > 0, sv[..., 0], 1.0), np.nan)
        ok = finite & (ratio > 0)
        safe = np.where(ok[..., None, None], safe, np.eye(A.shape[-1]))
        x = np.linalg.solve(safe, np.where(ok[..., None], rhs, 0.0)[..., None])[..., 0]
    x = np.where(ok[..., None], x, np.nan)
    return x, np.where(ok, ratio, np.where(finite, 0.0, np.nan))
