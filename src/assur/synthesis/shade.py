"""L-SHADE: success-history adaptive differential evolution with a linear population size reduction.

R. Tanabe and A. Fukunaga, "Improving the search performance of SHADE using linear population size reduction",
IEEE Congress on Evolutionary Computation (CEC) 2014, pp. 1658–1665 (the winner of that year's single-objective
competition); SHADE itself: R. Tanabe and A. Fukunaga, "Success-history based parameter adaptation for differential
evolution", CEC 2013, pp. 71–78. The settings are the paper's: an initial population of 18 designs per variable
shrinking linearly to 4 by the end of the run's evaluations, current-to-pbest/1/bin with p = 0.11, an archive of
2.6 × the population, a history of H = 6 means of F and CR (both 0.5 at the start), F ~ Cauchy(M_F, 0.1) and
CR ~ N(M_CR, 0.1), the weighted Lehmer mean for F and the weighted mean for CR (weights: the improvements), a
component leaving the box set halfway between the parent and the bound.

Written here (no maintained PyPI package ships L-SHADE as a small dependency); vectorised over the population: one
evaluation call per generation. Designs compare by the optimiser's scalar F (Deb's feasibility rules,
:mod:`assur.synthesis.evaluate`).
"""
from __future__ import annotations

import numpy as np

#: the paper's settings (see the module docstring)
INITIAL_PER_VARIABLE, FINAL_SIZE, P_BEST, ARCHIVE_RATE, MEMORY = 18, 4, 0.11, 2.6, 6


def lshade(F, bounds, rng, max_evaluations: int, *, initial=None, per_variable: int = INITIAL_PER_VARIABLE):
    """Minimise ``F`` (population (n, D) → (n,)) over the box ``bounds`` (D, 2) with at most ``max_evaluations``
    evaluations; ``initial``: a starting population (n0, D) (default: uniform in the box). Returns (best x (D,),
    best value)."""
    lo, hi = np.asarray(bounds, dtype=float).T
    D = len(lo)
    n_init = max(FINAL_SIZE, int(round(per_variable * D)))
    X = lo + rng.random((n_init, D)) * (hi - lo) if initial is None else np.array(initial, dtype=float)
    n_init = len(X)
    f = np.asarray(F(X), dtype=float)
    used = len(X)
    m_cr, m_f = np.full(MEMORY, 0.5), np.full(MEMORY, 0.5)
    k = 0
    archive = np.empty((0, D))
    while used < max_evaluations:
        n = len(X)
        r = rng.integers(0, MEMORY, n)
        cr = np.where(np.isnan(m_cr[r]), 0.0, np.clip(rng.normal(np.nan_to_num(m_cr[r]), 0.1), 0.0, 1.0))
        fs = m_f[r] + 0.1 * np.tan(np.pi * (rng.random(n) - 0.5))
        while np.any(fs <= 0):                                   # regenerate non-positive F
            bad = fs <= 0
            fs[bad] = m_f[r[bad]] + 0.1 * np.tan(np.pi * (rng.random(bad.sum()) - 0.5))
        fs = np.minimum(fs, 1.0)
        order = np.argsort(f, kind="stable")
        top = max(2, int(round(P_BEST * n)))
        pbest = X[order[rng.integers(0, top, n)]]
        r1 = _distinct(rng, n, n, [np.arange(n)])
        pool = np.vstack([X, archive]) if len(archive) else X
        r2 = _distinct(rng, n, len(pool), [np.arange(n), r1])
        V = X + fs[:, None] * (pbest - X) + fs[:, None] * (X[r1] - pool[r2])
        V = np.where(V < lo, 0.5 * (lo + X), V)                 # halfway between the parent and the bound
        V = np.where(V > hi, 0.5 * (hi + X), V)
        cross = rng.random((n, D)) < cr[:, None]
        cross[np.arange(n), rng.integers(0, D, n)] = True
        U = np.where(cross, V, X)
        fu = np.asarray(F(U), dtype=float)
        used += n
        better = fu < f
        keep = fu <= f
        if better.any():                                         # success history: weights = the improvements
            w = f[better] - fu[better]
            w = w / w.sum() if np.isfinite(w.sum()) and w.sum() > 0 else np.full(better.sum(), 1.0 / better.sum())
            s_cr, s_f = cr[better], fs[better]
            m_cr[k] = np.nan if np.isnan(m_cr[k]) or s_cr.max() == 0 else float(np.sum(w * s_cr))
            m_f[k] = float(np.sum(w * s_f * s_f) / np.sum(w * s_f))
            k = (k + 1) % MEMORY
            archive = np.vstack([archive, X[better]])
        X = np.where(keep[:, None], U, X)
        f = np.where(keep, fu, f)
        # linear population size reduction: drop the worst
        target = int(round(n_init + (FINAL_SIZE - n_init) * min(used, max_evaluations) / max_evaluations))
        target = max(FINAL_SIZE, target)
        if target < len(X):
            idx = np.argsort(f, kind="stable")[:target]
            X, f = X[idx], f[idx]
        limit = int(round(ARCHIVE_RATE * len(X)))
        if len(archive) > limit:
            archive = archive[rng.choice(len(archive), limit, replace=False)]
    i = int(np.argmin(f))
    return X[i].copy(), float(f[i])


def _distinct(rng, n, size, avoid):
    """(n,) indices in [0, size), each different from ``avoid[j][i]`` for every j (redrawn where equal)."""
    idx = rng.integers(0, size, n)
    for _ in range(100):
        clash = np.zeros(n, dtype=bool)
        for a in avoid:
            clash |= idx == a
        if not clash.any():
            break
        idx[clash] = rng.integers(0, size, clash.sum())
    return idx


__all__ = ["lshade"]
