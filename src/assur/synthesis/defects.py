"""Circuit, branch and order defects of a design against its targets (the ``defects`` constraint).

A design counts only if it meets its targets in their order on one assembly branch with the whole stretch
between them buildable. The engine solves every design on the one assembly branch its sketch fixes, so a
design that would have to change branch (pass a toggle) or circuit between two targets shows up as
unassemblable samples of the input cycle inside the stretch. The check runs on the cycle samples:

* order: going from the first target's input in the direction of increasing input (the driver's sense), the
  targets are met in their order within one turn: the gaps (θ_{i+1} − θ_i) mod 2π sum to less than 2π;
  the excess of that sum over 2π (rad) measures an order defect;
* stretch: the share of the cycle samples between the first and the last target (the whole turn when the
  order fails) that cannot be assembled.

A sample spacing of 2π/M cannot see a stretch of unassembly narrower than that spacing.
"""
from __future__ import annotations

import numpy as np

TWO_PI = 2.0 * np.pi


def defect_measures(theta, valid, cycle_q):
    """theta (n, N) target inputs (rad); valid (n, M) whether each cycle sample ``cycle_q`` (M,) assembles
    → (order (n,) rad ≥ 0, stretch (n,) share in [0, 1]); both 0 exactly when the design has no defect."""
    theta = np.asarray(theta, dtype=float)
    span = np.mod(np.diff(theta, axis=1), TWO_PI).sum(axis=1)                      # (n,)
    order = np.maximum(0.0, span - TWO_PI)
    rel = np.mod(np.asarray(cycle_q)[None, :] - theta[:, :1], TWO_PI)              # (n, M)
    inside = rel <= np.minimum(span, TWO_PI)[:, None]
    stretch = np.count_nonzero(inside & ~valid, axis=1) / np.maximum(np.count_nonzero(inside, axis=1), 1)
    return np.where(np.isfinite(order), order, TWO_PI), stretch


def nearest_inputs(path, targets, cycle_q):
    """The cycle input (M,) at which each target (N, 2) comes nearest the sampled path (n, M, 2) → (n, N);
    the timing of targets without one (``path``) for the order check."""
    d = np.linalg.norm(path[:, :, None, :] - targets[None, None, :, :], axis=-1)   # (n, M, N)
    d = np.where(np.isfinite(d), d, np.inf)
    return np.asarray(cycle_q)[np.argmin(d, axis=1)]


__all__ = ["defect_measures", "nearest_inputs"]
