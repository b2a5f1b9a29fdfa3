"""The Assur groups of a spatial description: a crank hinged on the frame, then R–S–S dyads.

A spatial R–S–S dyad is a rocker hinged on the frame at one point D and a coupler joined to the
rocker at B and to an already determined body at A. It is found from connectivity alone: starting
from the frame and the driven links, each step takes the first undetermined rocker (exactly one
frame hinge) and coupler (exactly one point shared with the rocker besides D, exactly one point on
a determined body) in file order. Joint kinds and axes are checked where the plan is compiled.
"""
from __future__ import annotations

from dataclasses import dataclass

from ..model.mechanism import Mechanism
from .graph import StructureGraph


@dataclass(frozen=True, slots=True)
class SpatialDyad:
    """An R–S–S dyad: ``rocker`` hinged on the frame at ``pivot`` (D), ``coupler`` from the known
    point ``start`` (A) to the rocker at ``joint`` (B); bodies are graph indices."""
    rocker: int
    coupler: int
    pivot: str
    start: str
    joint: str


def spatial_dyads(m: Mechanism, g: StructureGraph) -> tuple[tuple[SpatialDyad, ...], tuple[int, ...]]:
    """The R–S–S dyads in solve order, and the graph indices of the bodies no group determines."""
    frame_points = set(g.bodies[0].points)
    known: set[str] = set(frame_points)
    placed: set[int] = {0}
    for d in m.drivers:
        if d.kind == "rotary":
            b = g.index(d.link)
            placed.add(b)
            known |= set(g.bodies[b].points)
    dyads: list[SpatialDyad] = []
    n = len(g.bodies)
    progress = True
    while progress:
        progress = False
        for ri in range(n):
            rocker = g.bodies[ri]
            if ri in placed or rocker.kind != "link":
                continue
            hinges = [p for p in rocker.points if p in frame_points]
            if len(hinges) != 1:
                continue
            D = hinges[0]
            for ci in range(n):
                coupler = g.bodies[ci]
                if ci in placed or ci == ri or coupler.kind != "link":
                    continue
                common = [p for p in rocker.points if p in coupler.points and p != D]
                starts = [p for p in coupler.points if p in known and p not in rocker.points]
                if len(common) != 1 or len(starts) != 1:
                    continue
                dyads.append(SpatialDyad(ri, ci, D, starts[0], common[0]))
                placed |= {ri, ci}
                known |= set(rocker.points) | set(coupler.points)
                progress = True
                break
            if progress:
                break
    left = tuple(i for i in range(n) if i not in placed)
    return tuple(dyads), left
