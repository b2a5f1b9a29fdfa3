"""Assur groups as Baranov trusses with a frame link, their class and order, and their R/P types.

A **Baranov truss** is a planar chain of revolute pairs (links as vertices, joints as edges, a simple graph)
with n links and j joints such that

* its mobility is zero: 3(n − 1) − 2j = 0, and
* no proper sub-chain is rigid: every set S of 2 ≤ |S| < n links with j(S) joints among them has
  3(|S| − 1) − 2j(S) ≥ 1.

(A truss is then connected, has no link of degree < 2, and no cut-link.) Taking one link of a truss as the
frame and removing it leaves an **Assur group** (structural group) of n − 1 links whose outer pairs are the
joints of the frame link: W = 3(n − 1) − 2j = 0 once attached, and no smaller group can be split off. Two
frame choices give the same group when an automorphism of the truss maps one onto the other, so the groups of
n − 1 links are the orbits of the trusses' automorphism groups on their links.

* **order** = the number of outer pairs (the degree of the frame link in the truss);
* **class** (Artobolevsky's rule): the number of kinematic pairs of the most complex closed contour formed by
  the inner pairs: a cycle of k links joined by inner pairs is a contour of k pairs, and a link carrying k
  inner pairs is a rigid contour of k pairs; a dyad (no contour) is class II by definition. So the dyad is
  II, the triad (a ternary base link with three binary links) III, the four-link closed loop with two outer
  pairs IV.

Generation (exact, not tuned to a count): in a truss of n ≥ 5 links every binary link joins two non-binary
links (a path of k ≥ 2 binary links, with its k + 1 joints, would leave a rest of mobility 2 − k ≤ 0: a
rigid sub-chain). So a truss is a graph H0 on its non-binary links (triangle-free and with no rigid part)
plus binary links, each joining two distinct non-binary links that H0 does not join directly; with h non-binary
links, 2|E(H0)| = 4h − n − 3. Every such candidate is put in nauty's canonical form (a hash look-up, never a
pairwise test) and kept when it passes the definition above, checked on all subsets.

IDs: a truss's ID is ``B<n>-<12 hex digits>`` (the chain ID scheme of :mod:`.graphs` with the prefix B), a
group's ``<truss id>/f<k>`` with k the smallest canonical position of its frame's orbit.
"""
from __future__ import annotations

import itertools
from dataclasses import dataclass
from functools import cached_property

from .degeneracy import rigid_subchain
from .graphs import ChainGraph, automorphism_orbits, canonical, chain_id, connected

__all__ = ["AssurGroupType", "DYAD_KINDS", "assur_group_counts", "assur_groups", "baranov_trusses",
           "dyad_kinds", "group_class", "is_baranov_truss", "type_assignments"]


# -- the definition, checked on all subsets ------------------------------------------------------------------
def is_baranov_truss(n: int, edges) -> bool:
    """The definition of the module's docstring (simple graph assumed)."""
    return (n >= 3 and 3 * (n - 1) == 2 * len(edges) and connected(n, edges)
            and rigid_subchain(n, edges, proper=True) is None)


# -- generation ------------------------------------------------------------------------------------------------
def _sparse_graphs(k: int, e0: int) -> list[tuple[tuple[int, int], ...]]:
    """Unlabelled graphs on k vertices (isolated ones allowed) with e0 edges and no rigid part (so no triangle):
    every set S of ≥ 2 vertices has 2 e(S) ≤ 3|S| − 4. The property survives deleting an edge, so the graphs are
    grown one edge at a time, deduplicated by canonical form."""
    pairs = list(itertools.combinations(range(k), 2))
    level = {()}
    for _ in range(e0):
        nxt = set()
        for es in level:
            have = set(es)
            for p in pairs:
                if p in have:
                    continue
                cand = tuple(sorted(have | {p}))
                ce, _ = canonical(k, cand)
                if ce not in nxt and rigid_subchain(k, ce) is None:
                    nxt.add(ce)
        level = nxt
    return sorted(level)


def _binary_placements(k: int, h0, nb: int):
    """Multisets of nb vertex pairs (the binary links' ends) on H0 = (k, h0) leaving every vertex of degree ≥ 3;
    a pair joined in H0 is excluded (it would close a triangle)."""
    deg = [0] * k
    for u, v in h0:
        deg[u] += 1
        deg[v] += 1
    have = set(h0)
    pairs = [p for p in itertools.combinations(range(k), 2) if p not in have]
    chosen: list[tuple[int, int]] = []

    def rec(start: int, left: int):
        deficit = sum(max(0, 3 - d) for d in deg)
        if deficit > 2 * left:
            return
        if left == 0:
            yield tuple(chosen)
            return
        for i in range(start, len(pairs)):
            u, v = p = pairs[i]
            deg[u] += 1
            deg[v] += 1
            chosen.append(p)
            yield from rec(i, left - 1)
            chosen.pop()
            deg[u] -= 1
            deg[v] -= 1

    yield from rec(0, nb)


def baranov_trusses(links: int) -> list[ChainGraph]:
    """All Baranov trusses of ``links`` links (odd, ≥ 3), in canonical form, sorted by ID."""
    n = links
    if n < 3 or n % 2 == 0:
        return []
    if n == 3:
        return [ChainGraph.of(3, [(0, 1), (1, 2), (0, 2)])]
    found: dict[tuple, ChainGraph] = {}
    for k in range(2, n - 2):                      # k non-binary links, n − k binary ones
        two_e0 = 4 * k - n - 3
        if two_e0 < 0 or two_e0 % 2:
            continue
        nb = n - k
        for h0 in _sparse_graphs(k, two_e0 // 2):
            for placement in _binary_placements(k, h0, nb):
                edges = list(h0)
                for i, (u, v) in enumerate(placement):
                    edges += [(u, k + i), (v, k + i)]
                ce, _ = canonical(n, sorted(edges))
                if ce in found:
                    continue
                if is_baranov_truss(n, ce):
                    found[ce] = ChainGraph(n, ce)
    return sorted(found.values(), key=lambda g: chain_id(g.n, g.edges, prefix="B"))


# -- Assur groups ---------------------------------------------------------------------------------------------
def _longest_cycle(n: int, edges, keep) -> int:
    """Length of the longest cycle among the vertices ``keep`` (0 if none)."""
    adj = [set() for _ in range(n)]
    for u, v in edges:
        if u in keep and v in keep:
            adj[u].add(v)
            adj[v].add(u)
    best = 0

    def dfs(start, v, seen, length):
        nonlocal best
        for w in adj[v]:
            if w == start and length >= 3:
                best = max(best, length)
            elif w > start and w not in seen:
                seen.add(w)
                dfs(start, w, seen, length + 1)
                seen.remove(w)

    for s in sorted(keep):
        dfs(s, s, {s}, 1)
    return best


def group_class(truss: ChainGraph, frame: int) -> int:
    """Artobolevsky's class of the group left by removing ``frame`` from ``truss`` (the module's docstring)."""
    keep = set(range(truss.n)) - {frame}
    inner_deg = [0] * truss.n
    for u, v in truss.edges:
        if u in keep and v in keep:
            inner_deg[u] += 1
            inner_deg[v] += 1
    return max(2, max(inner_deg), _longest_cycle(truss.n, truss.edges, keep))


@dataclass(frozen=True)
class AssurGroupType:
    """An Assur group: a Baranov truss with a frame link (``frame``: the smallest canonical position of its
    orbit). ``links`` = truss links − 1, ``order`` = outer pairs, ``group_class`` = the papers' class."""
    truss: ChainGraph
    frame: int
    orbit: tuple[int, ...]

    @cached_property
    def truss_id(self) -> str:
        return chain_id(self.truss.n, self.truss.edges, prefix="B")

    @property
    def id(self) -> str:
        return f"{self.truss_id}/f{self.frame}"

    @property
    def links(self) -> int:
        return self.truss.n - 1

    @property
    def joints(self) -> int:
        return self.truss.joints

    @property
    def order(self) -> int:
        return self.truss.degrees[self.frame]

    @cached_property
    def group_class(self) -> int:
        return group_class(self.truss, self.frame)


def assur_groups(links: int) -> list[AssurGroupType]:
    """All Assur groups of ``links`` links (even, ≥ 2; the frame not counted)."""
    out = []
    for t in baranov_trusses(links + 1):
        orbits = automorphism_orbits(t.n, t.edges)
        for r in sorted(set(orbits)):
            out.append(AssurGroupType(t, r, tuple(v for v in range(t.n) if orbits[v] == r)))
    return out


def assur_group_counts(links: int) -> dict:
    """The Assur groups of ``links`` links counted: ``groups``, ``by_order`` {order: count}, ``by_class``
    {class: count}, and ``baranov_trusses`` (the trusses of ``links + 1`` links they come from)."""
    groups = assur_groups(links)
    by_order: dict[int, int] = {}
    by_class: dict[int, int] = {}
    for g in groups:
        by_order[g.order] = by_order.get(g.order, 0) + 1
        by_class[g.group_class] = by_class.get(g.group_class, 0) + 1
    return {"links": links, "truss_links": links + 1, "baranov_trusses": len({g.truss for g in groups}),
            "groups": len(groups), "by_order": dict(sorted(by_order.items())),
            "by_class": dict(sorted(by_class.items()))}


# -- type synthesis: R/P assignments ----------------------------------------------------------------------------
def _automorphisms(g: ChainGraph, fixed: int | None = None) -> list[tuple[int, ...]]:
    """Every automorphism of ``g`` (fixing the link ``fixed``) as a vertex permutation: the closure of nauty's
    generators."""
    import pynauty
    adj: dict[int, list[int]] = {i: [] for i in range(g.n)}
    for u, v in g.edges:
        adj[u].append(v)
    colours = [{fixed}, set(range(g.n)) - {fixed}] if fixed is not None else []
    gens, *_ = pynauty.autgrp(pynauty.Graph(g.n, directed=False, adjacency_dict=adj, vertex_coloring=colours))
    ident = tuple(range(g.n))
    group = {ident}
    todo = [ident]
    while todo:
        p = todo.pop()
        for s in gens:
            q = tuple(s[p[i]] for i in range(g.n))
            if q not in group:
                group.add(q)
                todo.append(q)
    return sorted(group)


def _p_loop(edges, kinds) -> bool:
    """Whether the prismatic pairs close a loop (union–find over the P edges)."""
    parent: dict[int, int] = {}

    def find(x):
        while parent.get(x, x) != x:
            x = parent[x]
        return x

    for (u, v), k in zip(edges, kinds):
        if k != "P":
            continue
        a, b = find(u), find(v)
        if a == b:
            return True
        parent[a] = b
    return False


def type_assignments(truss: ChainGraph, frame: int) -> list[tuple[str, ...]]:
    """The R/P types of the Assur group (``truss``, ``frame``): one assignment of 'R' or 'P' to each joint of
    ``truss.edges`` per orbit of the automorphisms fixing the frame, excluding those in which prismatic pairs
    close a loop. A loop of prismatic pairs only has its angular closure satisfied identically: its links
    cannot turn relative to each other, the loop loses one of its three constraints and the group is no longer
    statically determinate (for the dyad: the PPP group, whose links keep a free translation, which is why
    Artobolevsky's classification of the dyads by kind, *Theory of Mechanisms and Machines*, lists five kinds
    and no PPP)."""
    edges = truss.edges
    index = {e: i for i, e in enumerate(edges)}
    perms = _automorphisms(truss, frame)
    edge_perms = [tuple(index[tuple(sorted((p[u], p[v])))] for u, v in edges) for p in perms]
    out = set()
    for kinds in itertools.product("RP", repeat=len(edges)):
        if _p_loop(edges, kinds):
            continue
        images = []
        for ep in edge_perms:
            img = [""] * len(edges)
            for i, j in enumerate(ep):
                img[j] = kinds[i]
            images.append(tuple(img))
        out.add(min(images, key=lambda t: tuple("0" if c == "R" else "1" for c in t)))
    return sorted(out, key=lambda t: (t.count("P"), tuple("0" if c == "R" else "1" for c in t)))


#: the five kinds of the dyad in the papers' order (kind 1 … 5), outer–inner–outer with an R outer pair first
#: where the outer pairs differ (the 5th kind R–P–P is written PPR)
DYAD_KINDS = ("RRR", "RRP", "RPR", "PRP", "PPR")


def dyad_kinds() -> list[str]:
    """The kinds of the dyad from :func:`type_assignments` on the three-link truss (frame + two links), named
    outer–inner–outer (an R outer pair first where the outer pairs differ; R–P–P is the papers' PPR)."""
    t = ChainGraph.of(3, [(0, 1), (1, 2), (0, 2)])
    frame = 0
    out = []
    for kinds in type_assignments(t, frame):
        kind = dict(zip(t.edges, kinds))
        a, b = (e for e in t.edges if frame in e)             # the outer pairs
        inner = next(e for e in t.edges if frame not in e)
        ka, kb = kind[a], kind[b]
        if ka == "P" and kb == "R":
            ka, kb = kb, ka
        name = ka + kind[inner] + kb
        out.append("PPR" if name == "RPP" else name)
    return sorted(out, key=lambda s: DYAD_KINDS.index(s) if s in DYAD_KINDS else len(DYAD_KINDS))
