"""The planar kinematic chains of revolute pairs with ``n`` links and mobility F, each once (docs/atlas.md).

A chain here is a simple graph (links as vertices, revolute joints as edges) that is

* connected, every link with at least two joints;
* of mobility F: ``3(n − 1) − 2j = F`` (Chebyshev–Grübler–Kutzbach; j joints, one link taken as the frame);
* without a cut link (a link whose removal disconnects the chain: a *fractionated* chain), so the graph is
  2-connected;
* non-degenerate: every sub-chain of at least two links keeps a mobility ≥ 1 (:mod:`.degeneracy`, all link
  subsets, not triangles only).

The enumeration goes through the contracted graphs (:mod:`.contracted`): for each multigraph of the multi-joint
links with the chain's loop count ``L = j − n + 1``, every distribution of the ``n − m`` binary links over its edges
(at most F + 1 binary links in series — more would make the rest of the chain rigid —, no two parallel edges both
without binary links, at least three on a loop: both would close a triangle), then one canonical certificate per
chain graph (pynauty) so that isomorphs are dropped by a hash look-up. Degenerate graphs are removed by the
all-subsets test; the chains with a cut link are counted apart (:func:`count`'s ``chains_with_cut_links``).

Each :class:`ChainEntry` carries the canonical :class:`~.graphs.ChainGraph` (stable ID), the link assortment,
the planarity flag (``networkx.check_planarity``; non-planar chains are kept and flagged) and its number of
inversions (the frame choices up to the chain's symmetry: the orbits of its automorphism group).
"""
from __future__ import annotations

import itertools
from dataclasses import dataclass
from functools import cached_property, lru_cache

from .contracted import contracted_graphs, cubic_multigraphs, is_block
from .degeneracy import rigid_mask
from .graphs import ChainGraph, automorphism_orbits, edge_text

#: the largest chain enumerated per mobility (the counts grow about thirty-fold per two links)
MAX_LINKS = {1: 14, 2: 13, 3: 12}
MAX_LINKS_OTHER = 12


def joints_of(links: int, dof: int) -> int:
    """The joint count j of a chain with ``links`` links and mobility ``dof``: 3(n − 1) − 2j = F. ValueError when
    it is not a whole number ≥ n (every link has at least two joints)."""
    twice = 3 * (links - 1) - dof
    if twice % 2:
        raise ValueError(f"no chain of {links} links has mobility {dof}: 3(n − 1) − F = {twice} is odd, "
                         f"so the joint count would not be a whole number")
    j = twice // 2
    if j < links:
        raise ValueError(f"no closed chain of {links} links has mobility {dof}: it would need {j} joints, "
                         f"fewer than its {links} links")
    return j


def check_size(links: int, dof: int) -> int:
    """The joint count, or ValueError for a request that has no chains or would not finish in minutes."""
    if links < 4:
        raise ValueError(f"a closed chain of revolute pairs needs at least 4 links: {links}")
    if dof < 1:
        raise ValueError(f"the mobility must be at least 1: {dof}")
    j = joints_of(links, dof)
    top = MAX_LINKS.get(dof, MAX_LINKS_OTHER)
    if links > top:
        raise ValueError(f"{links} links with mobility {dof} is too large to enumerate here (at most {top})")
    return j


@dataclass(frozen=True)
class ChainEntry:
    """One chain of the atlas."""
    graph: ChainGraph
    planar: bool
    cut_link: bool = False           # True: a fractionated chain (only with ``chains(..., cut_links=True)``)

    @property
    def id(self) -> str:
        return self.graph.id

    @property
    def n(self) -> int:
        return self.graph.n

    @property
    def edges(self) -> tuple[tuple[int, int], ...]:
        return self.graph.edges

    @property
    def assortment(self) -> tuple[int, ...]:
        """(binary, ternary, quaternary, …) link counts."""
        return self.graph.link_assortment

    @property
    def edge_text(self) -> str:
        return edge_text(self.graph.n, self.graph.edges)

    @cached_property
    def orbits(self) -> tuple[int, ...]:
        """The automorphism orbit of each link (orbit[v]: the smallest link of v's orbit)."""
        return automorphism_orbits(self.graph.n, self.graph.edges)

    @property
    def inversions(self) -> int:
        """The distinct mechanisms of the chain: frame choices up to its symmetry."""
        return len(set(self.orbits))

    def sort_key(self):
        return (self.assortment, self.graph.edges)

    def as_dict(self) -> dict:
        return {"id": self.id, "edges": self.edge_text, "assortment": list(self.assortment), "planar": self.planar}


def is_degenerate(n: int, edges, dof: int | None = None) -> bool:
    """True when the chain graph holds a rigid sub-chain: some set of at least two of its links whose own
    mobility 3(|S| − 1) − 2e(S) is ≤ 0 (every subset is tested: a triangle, a rigid five-link truss, …). ``dof``
    (optional) is the chain's mobility; a graph whose mobility is not ``dof`` raises ValueError."""
    edges = [tuple(e) for e in edges]
    if dof is not None and 3 * (n - 1) - 2 * len(edges) != dof:
        raise ValueError(f"the graph has mobility {3 * (n - 1) - 2 * len(edges)}, not {dof}")
    return bool(rigid_mask(n, [edges])[0])


def _class_options(size: int, loop: bool, cap: int) -> list[tuple[int, ...]]:
    """The binary-link counts of ``size`` interchangeable contracted edges (parallel edges, or loops at one
    link), each multiset once as a non-decreasing tuple: at most ``cap`` in series; a loop needs ≥ 3 (a shorter
    one closes a triangle or a double joint); two parallel edges need ≥ 2 between them (else a triangle or a
    double joint)."""
    low = 3 if loop else 0
    out = []
    for ks in itertools.combinations_with_replacement(range(low, cap + 1), size):
        if not loop and size >= 2 and ks[0] + ks[1] < 2:
            continue
        out.append(ks)
    return out


def _distributions(total: int, classes) -> list[tuple[int, ...]]:
    """Every choice of one option per class (lists of tuples) whose numbers sum to ``total``, concatenated."""
    if not classes:
        return [()] if total == 0 else []
    head, rest = classes[0], classes[1:]
    rest_max = sum(max(map(sum, c)) for c in rest)
    rest_min = sum(min(map(sum, c)) for c in rest)
    out = []
    for ks in head:
        left = total - sum(ks)
        if rest_min <= left <= rest_max:
            out.extend(ks + tail for tail in _distributions(left, rest))
    return out


def _planar(graph) -> bool:
    """Planarity of every chain made from a contracted graph (subdividing edges, parallel edges and loops do not
    change it)."""
    import networkx as nx
    m, cedges = graph
    g = nx.Graph()
    g.add_nodes_from(range(m))
    g.add_edges_from((a, b) for a, b in cedges if a != b)
    return bool(nx.check_planarity(g)[0])


def _candidates(links: int, dof: int, loops: int):
    """(contracted graph is a block, planar, chain edges) for every chain graph made from a contracted graph,
    one per isomorphism class (pynauty certificates)."""
    import pynauty
    seen: set[bytes] = set()
    cap = dof + 1
    for graph in contracted_graphs(loops):
        m, cedges = graph
        binaries = links - m
        if binaries < 0:
            continue
        runs = [list(g) for _, g in itertools.groupby(cedges)]       # edges are sorted: equal edges adjacent
        classes = [_class_options(len(r), r[0][0] == r[0][1], cap) for r in runs]
        if any(not c for c in classes):
            continue
        order = [e for r in runs for e in r]
        dists = _distributions(binaries, classes)
        if not dists:
            continue
        block, planar = is_block(graph), _planar(graph)
        for ks in dists:
            adj: dict[int, list[int]] = {v: [] for v in range(links)}
            edges = []
            nxt = m
            for (a, b), k in zip(order, ks):
                prev = a
                for _ in range(k):
                    edges.append((prev, nxt))
                    prev = nxt
                    nxt += 1
                edges.append((prev, b))
            for u, v in edges:
                adj[u].append(v)
                adj[v].append(u)
            cert = pynauty.certificate(pynauty.Graph(links, directed=False, adjacency_dict=adj))
            if cert not in seen:
                seen.add(cert)
                yield block, planar, tuple(edges)


@lru_cache(maxsize=8)
def _enumerate(links: int, dof: int, cut_links: bool) -> tuple[ChainEntry, ...]:
    j = check_size(links, dof)
    loops = j - links + 1
    if loops == 1:   # a single loop of binary links: 3(n − 1) − 2n = n − 3 = F
        ring = tuple((k, (k + 1) % links) for k in range(links))
        return (ChainEntry(ChainGraph.of(links, ring), planar=True),)
    flags, graphs = [], []
    for block, planar, edges in _candidates(links, dof, loops):
        if block or cut_links:
            flags.append((block, planar))
            graphs.append(edges)
    rigid = rigid_mask(links, graphs)
    out = []
    for (block, planar), edges, bad in zip(flags, graphs, rigid):
        if not bad:
            out.append(ChainEntry(ChainGraph.of(links, edges), planar=planar, cut_link=not block))
    return tuple(sorted(out, key=ChainEntry.sort_key))


def chains(links: int, dof: int, cut_links: bool = False) -> list[ChainEntry]:
    """The chains with ``links`` links and mobility ``dof`` (module docstring), sorted by link assortment then
    canonical edge list. ``cut_links=True`` adds the non-degenerate chains with a cut link (flagged
    ``cut_link``). ValueError for a size with no chain or too large to enumerate."""
    return list(_enumerate(links, dof, cut_links))


def count(links: int, dof: int, cut_links: bool = True) -> dict:
    """The atlas numbers: ``chains`` (no cut link), ``planar_chains``, ``mechanisms`` (inversions of those
    chains), ``joints``, ``by_assortment`` ({"n2,n3,…": chains}) and, with ``cut_links``, ``chains_with_cut_links``
    (the non-degenerate fractionated chains, not in ``chains``)."""
    entries = chains(links, dof, cut_links=cut_links)
    whole = [e for e in entries if not e.cut_link]
    by: dict[str, int] = {}
    for e in whole:
        key = ",".join(map(str, e.assortment))
        by[key] = by.get(key, 0) + 1
    out = {"links": links, "dof": dof, "joints": joints_of(links, dof), "chains": len(whole),
           "planar_chains": sum(e.planar for e in whole), "mechanisms": sum(e.inversions for e in whole),
           "by_assortment": by}
    if cut_links:
        out["chains_with_cut_links"] = len(entries) - len(whole)
    return out


def clear_cache() -> None:
    """Forget the enumerations kept in memory (the next call enumerates again; e.g. for timing)."""
    _enumerate.cache_clear()
    contracted_graphs.cache_clear()
    cubic_multigraphs.cache_clear()
