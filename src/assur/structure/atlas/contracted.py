"""Contracted graphs: the multigraphs of the multi-joint links of a chain.

A chain graph whose binary links are suppressed leaves its *contracted graph*: one vertex per link of degree ≥ 3,
one edge per string of binary links (0, 1, 2, … binary links in series) between two such links; a string that
returns to its link is a loop. The contracted graph is connected, has minimum degree 3 and the chain's number of
independent loops ``L = j − n + 1`` as its cyclomatic number. Conversely every such multigraph with a number of
binary links on each edge is a chain graph.

All contracted graphs with cyclomatic number L are made here, each once up to isomorphism:

1. the connected cubic multigraphs (loops allowed) on ``2L − 2`` vertices, grown from the two on two vertices
   (the theta graph and the dumbbell) by inserting an edge between two edge subdivisions (or between two
   subdivisions of one edge), or a pendant loop on one subdivision; every connected cubic multigraph on four or
   more vertices comes from a smaller one so (remove a loop with its stem, or a non-bridge edge, and suppress the
   two vertices left with degree 2);
2. then every contraction of their non-loop edges, one edge at a time (a vertex of degree d > 3 is a tree of
   cubic vertices contracted), deduplicated by canonical form at each step.

A multigraph is hashed through nauty on its incidence graph (vertices and edges as two colour classes).
Shapes: a multigraph is ``(m, edges)``, ``edges`` a sorted tuple of (u, v) with u ≤ v (u == v: a loop),
repeated for parallel edges.
"""
from __future__ import annotations

from functools import lru_cache

Multigraph = tuple[int, tuple[tuple[int, int], ...]]


def _norm(m: int, edges) -> Multigraph:
    return m, tuple(sorted((min(u, v), max(u, v)) for u, v in edges))


def certificate(m: int, edges) -> bytes:
    """A hashable canonical certificate of a multigraph (isomorphic multigraphs get equal certificates)."""
    import pynauty
    adj: dict[int, list[int]] = {i: [] for i in range(m + len(edges))}
    for k, (u, v) in enumerate(edges):
        adj[m + k].append(u)
        if v != u:
            adj[m + k].append(v)
    parts = [set(range(m)), set(range(m, m + len(edges)))] if edges else [set(range(m))]
    g = pynauty.Graph(m + len(edges), directed=False, adjacency_dict=adj, vertex_coloring=parts)
    return m.to_bytes(2, "little") + pynauty.certificate(g)


def _dedupe(graphs) -> list[Multigraph]:
    seen: dict[bytes, Multigraph] = {}
    for m, edges in graphs:
        seen.setdefault(certificate(m, edges), (m, edges))
    return [seen[k] for k in sorted(seen)]


def _grow(graph: Multigraph):
    """Every cubic multigraph with two more vertices made from ``graph`` by one edge insertion."""
    m, edges = graph
    x, y = m, m + 1
    for i, (a, b) in enumerate(edges):
        rest_i = edges[:i] + edges[i + 1:]
        # a pendant loop: subdivide edge i by x, x—y, a loop at y
        yield _norm(m + 2, rest_i + ((a, x), (x, b), (x, y), (y, y)))
        # two subdivisions of edge i joined: a—x, x=y (two edges), y—b
        yield _norm(m + 2, rest_i + ((a, x), (x, y), (x, y), (y, b)))
        for j in range(i + 1, len(edges)):
            c, d = edges[j]
            rest = tuple(e for k, e in enumerate(edges) if k not in (i, j))
            yield _norm(m + 2, rest + ((a, x), (x, b), (c, y), (y, d), (x, y)))


@lru_cache(maxsize=None)
def cubic_multigraphs(loops: int) -> tuple[Multigraph, ...]:
    """The connected cubic multigraphs (loops allowed) with cyclomatic number ``loops`` ≥ 2 (2·loops − 2
    vertices), one per isomorphism class."""
    if loops < 2:
        raise ValueError(f"cubic multigraphs need a cyclomatic number of at least 2: {loops}")
    if loops == 2:
        return tuple(_dedupe([(2, ((0, 1), (0, 1), (0, 1))), (2, ((0, 0), (0, 1), (1, 1)))]))
    return tuple(_dedupe(g for h in cubic_multigraphs(loops - 1) for g in _grow(h)))


def _contract(graph: Multigraph, i: int) -> Multigraph:
    m, edges = graph
    u, v = edges[i]

    def ren(w: int) -> int:
        w = u if w == v else w
        return w - 1 if w > v else w
    return _norm(m - 1, [(ren(a), ren(b)) for k, (a, b) in enumerate(edges) if k != i])


@lru_cache(maxsize=None)
def contracted_graphs(loops: int) -> tuple[Multigraph, ...]:
    """Every connected multigraph of minimum degree 3 (loops allowed) with cyclomatic number ``loops`` ≥ 2, one
    per isomorphism class, sorted by vertex count, then certificate."""
    level = list(cubic_multigraphs(loops))
    out = list(level)
    while level:
        nxt = _dedupe(_contract(g, i) for g in level for i, (a, b) in enumerate(g[1]) if a != b)
        out.extend(nxt)
        level = nxt
    return tuple(sorted(out, key=lambda g: (g[0], certificate(*g))))


def is_block(graph: Multigraph) -> bool:
    """True when the multigraph has no loop and no cut vertex (its chains then have no cut link)."""
    m, edges = graph
    if any(a == b for a, b in edges):
        return False
    if m <= 2:
        return True
    for cut in range(m):
        nbr: dict[int, set[int]] = {w: set() for w in range(m) if w != cut}
        for a, b in edges:
            if cut not in (a, b):
                nbr[a].add(b)
                nbr[b].add(a)
        start = next(iter(nbr))
        seen, stack = {start}, [start]
        while stack:
            for w in nbr[stack.pop()] - seen:
                seen.add(w)
                stack.append(w)
        if len(seen) != m - 1:
            return False
    return True
