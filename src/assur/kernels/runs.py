"""Runs of a boolean mask: the stretches of consecutive True samples, as index pairs.

``runs`` reads the mask as a line (a sweep), ``cyclic_runs`` as a ring (samples over one input turn, where
a run may wrap from the last sample to the first). Pure numpy.
"""
from __future__ import annotations

import numpy as np


def runs(mask) -> np.ndarray:
    """(first, last) indices of each run of True in a 1-D mask (n,), in order: (k, 2) int array.

    ``[F, T, T, F, T]`` → ``[[1, 2], [4, 4]]``; no True → shape (0, 2)."""
    m = np.asarray(mask, dtype=bool).reshape(-1)
    edges = np.diff(np.concatenate([[False], m, [False]]).astype(np.int8))
    return np.stack([np.flatnonzero(edges == 1), np.flatnonzero(edges == -1) - 1], axis=1)


def cyclic_runs(mask) -> list[tuple[int, int]]:
    """Runs of True in a 1-D mask (n,) read as a ring: a list of (first, last) index pairs.

    A run through the end continues at the start, so ``last < first`` for it. An all-True mask is the one run
    ``(0, n − 1)``; the runs are listed from the first one that starts after the first False sample."""
    m = np.asarray(mask, dtype=bool).reshape(-1)
    n = len(m)
    if m.all():
        return [(0, n - 1)]
    if not m.any():
        return []
    shift = int(np.argmin(m)) + 1            # start just after a False sample: no run crosses the seam
    r = runs(np.roll(m, -shift))
    return [(int((a + shift) % n), int((b + shift) % n)) for a, b in r]


__all__ = ["cyclic_runs", "runs"]
