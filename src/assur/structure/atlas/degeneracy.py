"""Rigid sub-chains: the degeneracy test of a chain graph over all its link subsets.

A sub-chain is a set S of links with every joint between two of them. Its own mobility (one of its links taken
as the frame) is ``3(|S| − 1) − 2 e(S)``, ``e(S)`` the number of joints inside S. A chain is *degenerate* when some
sub-chain of at least two links has a mobility ≤ 0: it holds a rigid (or over-constrained) part, a triangle, a
rigid five-link sub-chain (the Baranov truss of two ternary and three binary links), … Every subset is tested,
never triangles only. A disconnected S needs no separate treatment: its mobility condition follows from its
components' (``3(|S| − 1) − 2e(S)`` is the sum of the components' mobilities plus 3 per extra component, and a
single link adds 3), so testing all subsets is the same as testing the connected ones.

The test runs over all ``2**n`` subsets at once with numpy: ``e(S)`` by a dynamic programme over the highest link
of S (``e(S) = e(S − {b}) + |S ∩ N(b)|``), a few microseconds per subset block; :func:`rigid_mask` does it for a
batch of graphs of the same size.
"""
from __future__ import annotations

import numpy as np

#: above this many links the all-subsets table would be too large (2**n entries per graph)
MAX_LINKS = 20

_POPCOUNT16 = np.array([bin(i).count("1") for i in range(1 << 16)], dtype=np.int8)


def _popcount(x: np.ndarray) -> np.ndarray:
    return _POPCOUNT16[x & 0xFFFF] + _POPCOUNT16[(x >> 16) & 0xFFFF]


def _adjacency_masks(n: int, edges) -> np.ndarray:
    adj = np.zeros(n, dtype=np.int64)
    for u, v in edges:
        adj[u] |= 1 << v
        adj[v] |= 1 << u
    return adj


def _joints_inside(n: int, adj: np.ndarray) -> np.ndarray:
    """e(S) for every subset S of the links of each graph: (B, 2**n) from adjacency masks ``adj`` (B, n), by the
    recurrence over the highest link of S."""
    size = 1 << n
    subsets = np.arange(size, dtype=np.int64)
    e = np.zeros((adj.shape[0], size), dtype=np.int16)
    for b in range(1, n):
        low = subsets[: 1 << b]
        lower_neighbours = adj[:, b] & ((1 << b) - 1)                # neighbours of b below b
        e[:, 1 << b: 1 << (b + 1)] = e[:, : 1 << b] + _popcount(low[None, :] & lower_neighbours[:, None])
    return e


def _too_dense(n: int) -> tuple[np.ndarray, np.ndarray]:
    """(subset sizes (2**n,), the largest 2 e(S) of a sub-chain of mobility ≥ 1: 3|S| − 4)."""
    pop = _popcount(np.arange(1 << n, dtype=np.int64)).astype(np.int16)
    return pop, 3 * pop - 4


def rigid_mask(n: int, edge_lists) -> np.ndarray:
    """For each graph of ``edge_lists`` (all with ``n`` vertices): True when some subset of ≥ 2 of its links is a
    sub-chain of mobility ≤ 0 (degenerate). Shape (len(edge_lists),) bool."""
    if not 1 <= n <= MAX_LINKS:
        raise ValueError(f"the degeneracy test takes 1 to {MAX_LINKS} links: {n}")
    edge_lists = list(edge_lists)
    out = np.zeros(len(edge_lists), dtype=bool)
    if not edge_lists:
        return out
    pop, limit = _too_dense(n)
    relevant = pop >= 2
    chunk = max(1, (1 << 22) // (1 << n))     # about 4 M table entries per block
    for start in range(0, len(edge_lists), chunk):
        block = edge_lists[start:start + chunk]
        e = _joints_inside(n, np.stack([_adjacency_masks(n, e) for e in block]))     # (B, 2**n)
        bad = (2 * e > limit[None, :]) & relevant[None, :]
        out[start:start + len(block)] = bad.any(axis=1)
    return out


def rigid_subchain(n: int, edges, proper: bool = False) -> tuple[int, ...] | None:
    """The links of a smallest rigid sub-chain (mobility ≤ 0, at least two links) of the graph, or None;
    ``proper``: only sub-chains with fewer than all ``n`` links."""
    pop, limit = _too_dense(n)
    e = _joints_inside(n, _adjacency_masks(n, edges)[None, :])[0]
    bad = (2 * e > limit) & (pop >= 2)
    if proper:
        bad[-1] = False
    bad = np.flatnonzero(bad)
    if bad.size == 0:
        return None
    s = int(bad[np.argmin(pop[bad])])
    return tuple(k for k in range(n) if s >> k & 1)
