"""The atlas entry of a mechanism description: its chain, its inversion (frame) and their names.

The chain graph is the mechanism's structure graph (:func:`assur.structure.graph.build_graph`): one vertex per
body (the frame, every link, a slider block per pin-in-slot, a cylinder and a rod per linear actuator) and one
edge per kinematic pair, revolute or prismatic (a revolute joining k bodies counts as k − 1 pairs, from the first
body that carries the point: the frame first, then the links in file order). Revolute and prismatic pairs are
both edges, so a slider-crank has the four-bar chain; the number of prismatic pairs and the names
"slider-crank" / "inverted slider-crank" tell them apart. Spatial descriptions are not in the planar atlas.
"""
from __future__ import annotations

from dataclasses import dataclass

from ...model.mechanism import Mechanism
from ..graph import build_graph
from .graphs import connected
from .mechanisms import chain_name, inversion_at

__all__ = ["Identification", "identify"]


@dataclass(frozen=True)
class Identification:
    """A mechanism's atlas entry. ``name``: the inversion's name (Watt I … Stephenson III, four-bar,
    slider-crank …) or None; ``chain_name``: 'four-bar', 'Watt', 'Stephenson' or None; ``frame``: the canonical
    position of the frame link; ``prismatic``: the number of prismatic pairs."""
    chain_id: str
    chain_name: str | None
    inversion_id: str
    name: str | None
    links: int
    joints: int
    dof: int
    prismatic: int
    frame: int

    @property
    def label(self) -> str:
        """The name, or a description by counts when the atlas has no name for it."""
        if self.name:
            return self.name
        return f"{self.links}-link chain, F = {self.dof}"

    def line(self) -> str:
        """``atlas: <chain id> <name> (frame: <inversion id>)``."""
        return f"atlas: {self.chain_id} {self.label} (frame: {self.inversion_id})"

    def as_dict(self) -> dict:
        return {"chain": self.chain_id, "chain_name": self.chain_name, "inversion": self.inversion_id,
                "name": self.name, "links": self.links, "joints": self.joints, "dof": self.dof,
                "prismatic": self.prismatic}


def identify(mechanism: Mechanism) -> Identification | None:
    """The atlas entry of a planar mechanism, None for a spatial one or a structure that is not a simple
    connected chain graph (two pairs joining the same two bodies, or a body joined to nothing)."""
    if mechanism.dimension != 2:
        return None
    g = build_graph(mechanism)
    n = len(g.bodies)
    edges = []
    seen = set()
    prismatic = 0
    frame_prismatic = False
    for p in g.pairs:
        u, v = sorted(p.bodies)
        if u == v or (u, v) in seen:
            return None
        seen.add((u, v))
        edges.append((u, v))
        if p.kind == "P":
            prismatic += 1
            frame_prismatic = frame_prismatic or 0 in (u, v)
    if n < 2 or not connected(n, edges):
        return None
    inv = inversion_at(n, edges, 0)
    cname = chain_name(inv.chain)
    name = inv.name
    if prismatic:
        if cname == "four-bar" and prismatic == 1:
            name = "slider-crank" if frame_prismatic else "inverted slider-crank"
        elif name:
            name = f"{name} with {prismatic} prismatic pair{'s' if prismatic > 1 else ''}"
    return Identification(inv.chain.id, cname, inv.id, name, n, len(edges), inv.chain.mobility, prismatic,
                          inv.frame)

