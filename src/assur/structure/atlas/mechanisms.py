"""Mechanisms of a chain (its inversions: the choice of the frame link) and the placements of a driver.

An *inversion* is a chain with one link taken as the frame. Two frame choices give the same mechanism when an
automorphism of the chain graph maps one frame link onto the other, so the inversions of a chain are the
orbits of its automorphism group acting on the links (nauty's orbits, :func:`automorphism_orbits`).

IDs: the links of a :class:`ChainGraph` are numbered by their canonical position (its edges are canonical), and
an inversion's ID is ``<chain id>/f<k>`` with ``k`` the smallest canonical position in the frame's orbit; it
is as stable as the chain ID (both follow ``CANON_VERSION``).

Textbook names (by graph properties; docs/atlas.md, "Mechanisms and drivers"):

* four links, four joints: the **four-bar** (five links, five joints: the two-DOF **five-bar**);
* six links, seven joints (the two 1-DOF six-bar chains, each with two ternary links): the **Watt** chain when
  the ternary links share a joint, else the **Stephenson** chain. Watt I: the frame is a binary link; Watt II:
  the frame is a ternary link. Stephenson I: the frame is the binary link joined to both ternary links (the
  one binary link of the four-link loop: the ternary crank and rocker are both hinged to the frame);
  Stephenson II: the frame is a binary link joined to only one ternary link; Stephenson III: the frame is a
  ternary link (a four-bar whose coupler is joined to the frame by a second dyad). The convention of
  Tsai, *Mechanism Design: Enumeration of Kinematic Structures According to Function* (CRC 2001), and
  McCarthy & Soh, *Geometric Design of Linkages* (2nd ed., Springer 2011); Norton, *Design of Machinery*,
  draws the same five (Watt I, II; Stephenson I, II, III).
"""
from __future__ import annotations

from dataclasses import dataclass

from .graphs import ChainGraph, automorphism_orbits, canonical

__all__ = ["DriverPlacement", "Inversion", "chain_name", "driver_placements", "inversion_at", "inversion_name",
           "inversions"]


@dataclass(frozen=True)
class Inversion:
    """A chain with a frame link: ``frame`` is the canonical position of the frame (the smallest of its orbit),
    ``orbit`` the links equivalent to it, ``name`` the textbook name where one exists."""
    chain: ChainGraph
    frame: int
    orbit: tuple[int, ...]
    name: str | None

    @property
    def id(self) -> str:
        return f"{self.chain.id}/f{self.frame}"


@dataclass(frozen=True)
class DriverPlacement:
    """A driver of an inversion: ``kind`` 'crank' (a link hinged to the frame), ``link`` the canonical position of
    the driven link (the smallest of its orbit under the automorphisms that fix the frame), ``orbit`` the links
    equivalent to it."""
    kind: str
    link: int
    orbit: tuple[int, ...]


def _adjacency(g: ChainGraph) -> list[set[int]]:
    adj: list[set[int]] = [set() for _ in range(g.n)]
    for u, v in g.edges:
        adj[u].add(v)
        adj[v].add(u)
    return adj


def chain_name(g: ChainGraph) -> str | None:
    """The textbook name of a chain: 'four-bar', 'five-bar' (2 DOF), 'Watt' or 'Stephenson' (None for the
    others)."""
    if g.n == 4 and g.joints == 4 and all(d == 2 for d in g.degrees):
        return "four-bar"
    if g.n == 5 and g.joints == 5 and all(d == 2 for d in g.degrees):
        return "five-bar"
    if g.n == 6 and g.joints == 7 and sorted(g.degrees) == [2, 2, 2, 2, 3, 3]:
        t1, t2 = (i for i, d in enumerate(g.degrees) if d == 3)
        return "Watt" if t2 in _adjacency(g)[t1] else "Stephenson"
    return None


def inversion_name(g: ChainGraph, frame: int) -> str | None:
    """The textbook name of the chain ``g`` inverted on link ``frame`` (see the module's docstring)."""
    name = chain_name(g)
    if name in ("four-bar", "five-bar"):
        return name
    if name not in ("Watt", "Stephenson"):
        return None
    if g.degrees[frame] == 3:
        return f"{name} II" if name == "Watt" else "Stephenson III"
    if name == "Watt":
        return "Watt I"
    ternary_neighbours = sum(1 for v in _adjacency(g)[frame] if g.degrees[v] == 3)
    return "Stephenson I" if ternary_neighbours == 2 else "Stephenson II"


def inversions(graph: ChainGraph) -> list[Inversion]:
    """One inversion per orbit of the chain's automorphism group on its links, by canonical position."""
    orbits = automorphism_orbits(graph.n, graph.edges)
    reps = sorted(set(orbits))
    return [Inversion(graph, r, tuple(v for v in range(graph.n) if orbits[v] == r), inversion_name(graph, r))
            for r in reps]


def inversion_at(n: int, edges, frame: int) -> Inversion:
    """The inversion of the chain ``(n, edges)`` (any labelling) whose frame is its link ``frame``."""
    es = tuple(sorted((min(u, v), max(u, v)) for u, v in edges))
    ce, lab = canonical(n, es)
    g = ChainGraph(n, ce)
    pos = lab.index(frame)
    orbits = automorphism_orbits(g.n, g.edges)
    r = orbits[pos]
    return Inversion(g, r, tuple(v for v in range(g.n) if orbits[v] == r), inversion_name(g, r))


def driver_placements(inversion: Inversion) -> list[DriverPlacement]:
    """The cranks of an inversion: the links hinged to the frame, one per orbit of the automorphisms that fix the
    frame link (a linear actuator between the frame and a link is placed the same way: one per such orbit)."""
    g, f = inversion.chain, inversion.frame
    others = [v for v in range(g.n) if v != f]
    orbits = automorphism_orbits(g.n, g.edges, colours=[[f], others])
    hinged = sorted(_adjacency(g)[f])
    reps = sorted({orbits[v] for v in hinged})
    return [DriverPlacement("crank", r, tuple(v for v in hinged if orbits[v] == r)) for r in reps]
