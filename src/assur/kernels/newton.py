"""Batched Newton iterations on a residual callable (no mechanism, no names).

``newton(F_and_J, x, residual_tol, iterations)`` solves F(x) = 0 for every sample of a batch at
once: ``x (..., n)``, ``F_and_J(x) -> (F (..., n), J (..., n, n))``. Converged samples stop moving;
samples whose Jacobian is singular become NaN. One more Newton step then polishes the converged
samples to round-off, and a sample is accepted where every residual is below ``accept_tol``.

Newton's step is the same for any scaling of the equations and the unknowns; only the tests depend on units: the
residual tolerances are the caller's (in the residual's own unit), and a Jacobian counts as singular by the
determinant of its equilibrated form (:func:`scaled_det`), a pure number.
"""
from __future__ import annotations

import numpy as np

#: a Jacobian whose equilibrated determinant (:func:`scaled_det`, a pure number) is below this in absolute value is
#: singular
SINGULAR_DETERMINANT = 1e-300
#: the acceptance test allows this factor over the iteration's residual tolerance
ACCEPT_FACTOR = 1e3


def scaled_det(J):
    """(...) the determinant of J (..., n, n) after every column and then every row is divided by its largest
    magnitude: free of the units of the equations and of the unknowns (0 where J is singular)."""
    with np.errstate(all="ignore"):
        col = np.max(np.abs(J), axis=-2, keepdims=True)
        J = J / np.where(col > 0, col, 1.0)
        row = np.max(np.abs(J), axis=-1, keepdims=True)
        return np.linalg.det(J / np.where(row > 0, row, 1.0))


def newton(F_and_J, x: np.ndarray, residual_tol: float, iterations: int, accept_tol: float | None = None):
    """Solve F(x) = 0 per sample.

    Parameters
    ----------
    F_and_J : callable
        ``x (..., n) -> (F (..., n), J (..., n, n))``.
    x : ndarray (..., n)
        The start (a copy is iterated).
    residual_tol : float
        A sample has converged when every |F| is below this.
    iterations : int
        The iteration cap.
    accept_tol : float, optional
        A sample is accepted where every |F| is below this (default ``ACCEPT_FACTOR·residual_tol``).

    Returns
    -------
    x : ndarray (..., n)
        The solution, NaN where not accepted.
    ok : ndarray (...) bool
        Accepted samples.
    J : ndarray (..., n, n)
        The Jacobian at the returned x (before the NaN mask).
    """
    n = x.shape[-1]
    shape = x.shape[:-1]
    done = np.zeros(shape, dtype=bool)
    for _ in range(iterations):
        F, J = F_and_J(x)
        done = np.all(np.abs(F) < residual_tol, axis=-1) | ~np.all(np.isfinite(F), axis=-1)
        if np.all(done):
            break
        # only the samples still iterating are factorised (a converged or failed one does not move)
        active = ~done
        with np.errstate(all="ignore"):
            Jr = J[active]
            Jr = np.where(np.isfinite(Jr), Jr, 0.0) + 0.0
            singular = ~(np.abs(scaled_det(Jr)) >= SINGULAR_DETERMINANT)
            Jr = np.where(singular[..., None, None], np.eye(n), Jr)
            step = np.linalg.solve(Jr, -np.where(np.isfinite(F[active]), F[active], 0.0)[..., None])[..., 0]
        dx = np.zeros(x.shape)
        dx[active] = np.where(singular[..., None], np.nan, step)
        x = x + dx
    F, J = F_and_J(x)
    # one more Newton step polishes the converged samples to round-off
    with np.errstate(all="ignore"):
        good = np.all(np.isfinite(F), axis=-1) & (np.abs(scaled_det(np.where(np.isfinite(J), J, 0.0)))
                                                  > SINGULAR_DETERMINANT)
        if good.any():
            x[good] = x[good] - np.linalg.solve(J[good], F[good][..., None])[..., 0]
    F, J = F_and_J(x)
    if accept_tol is None:
        accept_tol = ACCEPT_FACTOR * residual_tol
    ok = np.all(np.abs(F) < accept_tol, axis=-1) & np.all(np.isfinite(x), axis=-1)
    x = np.where(ok[..., None], x, np.nan)
    return x, ok, J
