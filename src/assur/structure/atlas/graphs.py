"""Chain graphs and their canonical form.

A planar kinematic chain of revolute pairs is a simple graph: one vertex per link, one edge per joint (two
links joined by two joints would be rigid, so a chain graph is simple). :func:`canonical` relabels a graph by
nauty's canonical labelling (``pynauty``), so two isomorphic chains get the same canonical edge list and the
same :func:`chain_id`: deduplication is a hash look-up, never a pairwise isomorphism test.

Shapes: ``edges`` is a tuple of (u, v) pairs with 0 ≤ u < v < n, sorted.
"""
from __future__ import annotations

import hashlib
from dataclasses import dataclass
from functools import cached_property

#: the version of the canonical form: bumped if the labelling rule ever changes (IDs carry it)
CANON_VERSION = 1


def _sorted_edges(edges) -> tuple[tuple[int, int], ...]:
    return tuple(sorted((min(u, v), max(u, v)) for u, v in edges))


def _nauty_graph(n: int, edges, colours=None):
    import pynauty
    adj: dict[int, list[int]] = {i: [] for i in range(n)}
    for u, v in edges:
        adj[u].append(v)
    parts = [set(c) for c in colours] if colours else []
    return pynauty.Graph(n, directed=False, adjacency_dict=adj, vertex_coloring=parts)


def canonical(n: int, edges, colours=None) -> tuple[tuple[tuple[int, int], ...], tuple[int, ...]]:
    """(canonical edges, labelling): ``labelling[k]`` is the original vertex put at canonical position k.
    ``colours``: an ordered partition of the vertices (e.g. ``[[frame], others]``) that the relabelling keeps
    (vertices of colour class 0 first, …)."""
    import pynauty
    lab = pynauty.canon_label(_nauty_graph(n, edges, colours))
    pos = {v: k for k, v in enumerate(lab)}
    return _sorted_edges((pos[u], pos[v]) for u, v in edges), tuple(lab)


def automorphism_orbits(n: int, edges, colours=None) -> tuple[int, ...]:
    """The orbit of each vertex under the graph's automorphisms (respecting ``colours``): orbit[v] is the
    smallest vertex of v's orbit."""
    import pynauty
    _, _, _, orbits, _ = pynauty.autgrp(_nauty_graph(n, edges, colours))
    return tuple(int(o) for o in orbits)


def connected(n: int, edges) -> bool:
    """True when the graph of ``n`` vertices and ``edges`` is connected."""
    adj: list[list[int]] = [[] for _ in range(n)]
    for u, v in edges:
        adj[u].append(v)
        adj[v].append(u)
    seen, stack = {0}, [0]
    while stack:
        for w in adj[stack.pop()]:
            if w not in seen:
                seen.add(w)
                stack.append(w)
    return len(seen) == n


def edge_text(n: int, edges) -> str:
    """``"n:u-v,u-v,…"``: a graph as text (the atlas's edge lists)."""
    return f"{n}:" + ",".join(f"{u}-{v}" for u, v in edges)


def chain_id(n: int, edges, prefix: str = "K") -> str:
    """A stable ID of the isomorphism class: ``K<n>-<12 hex digits>`` from the canonical edge list."""
    ce, _ = canonical(n, edges)
    digest = hashlib.sha256(f"v{CANON_VERSION};{edge_text(n, ce)}".encode()).hexdigest()[:12]
    return f"{prefix}{n}-{digest}"


@dataclass(frozen=True)
class ChainGraph:
    """A chain graph in canonical form: ``n`` links, ``edges`` (the canonical edge list)."""
    n: int
    edges: tuple[tuple[int, int], ...]

    @classmethod
    def of(cls, n: int, edges) -> "ChainGraph":
        ce, _ = canonical(n, _sorted_edges(edges))
        return cls(n, ce)

    @cached_property
    def id(self) -> str:
        return chain_id(self.n, self.edges)

    @property
    def joints(self) -> int:
        return len(self.edges)

    @property
    def mobility(self) -> int:
        """Chebyshev's W = 3(n − 1) − 2j of the chain (one link taken as the frame)."""
        return 3 * (self.n - 1) - 2 * len(self.edges)

    @cached_property
    def degrees(self) -> tuple[int, ...]:
        d = [0] * self.n
        for u, v in self.edges:
            d[u] += 1
            d[v] += 1
        return tuple(d)

    @property
    def link_assortment(self) -> tuple[int, ...]:
        """(binary, ternary, quaternary, …) link counts."""
        top = max(self.degrees, default=2)
        return tuple(sum(1 for d in self.degrees if d == k) for k in range(2, top + 1))
