"""Bodies and kinematic pairs of a mechanism description.

Bodies: the frame (index 0), every other link, one slider block per pin-in-slot prismatic pair,
and a cylinder and a rod per linear actuator. Pairs: a revolute joining k bodies at a point
counts as k − 1 pairs; each prismatic pair and each actuator's cylinder–rod slide is one pair; each gear
pair is one higher pair (kind 'G', class p4) between its two links, and so is each cam pair (kind 'C', the cam and
its follower).
"""
from __future__ import annotations

from dataclasses import dataclass

from ..model.mechanism import FRAME, Mechanism


@dataclass(frozen=True, slots=True)
class Body:
    name: str
    kind: str          # 'frame' | 'link' | 'block' | 'cylinder' | 'rod'
    points: tuple[str, ...]
    source: str        # the link, prismatic pair or actuator it comes from


@dataclass(frozen=True, slots=True)
class Pair:
    kind: str          # 'R' (revolute at `point`), 'P' (prismatic named `name`), 'G' (gear pair named `name`) or 'C'
                       # (cam pair named `name`: bodies (cam, follower))
    bodies: tuple[int, int]
    point: str | None = None
    name: str | None = None
    driven: bool = False
    joint: str = "revolute"   # for spatial descriptions: revolute, spherical, cylindrical, universal, prismatic


@dataclass(frozen=True, slots=True)
class StructureGraph:
    bodies: tuple[Body, ...]
    pairs: tuple[Pair, ...]
    #: point -> indices of the bodies that carry it
    joints: tuple[tuple[str, tuple[int, ...]], ...]

    def bodies_at(self, point: str) -> tuple[int, ...]:
        for p, b in self.joints:
            if p == point:
                return b
        return ()

    def index(self, name: str) -> int:
        for i, b in enumerate(self.bodies):
            if b.name == name:
                return i
        raise KeyError(name)


def build_graph(m: Mechanism) -> StructureGraph:
    bodies = [Body(FRAME, "frame", m.frame.points, FRAME)]
    for lk in m.links:
        if lk.name != FRAME:
            bodies.append(Body(lk.name, "link", lk.points, lk.name))
    for pr in m.prismatic:
        if pr.point is not None:
            bodies.append(Body(f"{pr.name}.block", "block", (pr.point,), pr.name))
    for ac in m.actuators:
        bodies.append(Body(f"{ac.name}.cylinder", "cylinder", (ac.between[0],), ac.name))
        bodies.append(Body(f"{ac.name}.rod", "rod", (ac.between[1],), ac.name))
    index = {b.name: i for i, b in enumerate(bodies)}
    joint_kind = {j.point: j.kind for j in m.joints}
    joints = []
    pairs: list[Pair] = []
    for name in m.point_names:
        at = tuple(i for i, b in enumerate(bodies) if name in b.points)
        joints.append((name, at))
        for other in at[1:]:
            pairs.append(Pair("R", (at[0], other), point=name, joint=joint_kind.get(name, "revolute")))
    driven = {d.actuator for d in m.drivers if d.kind == "linear"}
    for pr in m.prismatic:
        slider = index[f"{pr.name}.block"] if pr.point is not None else index[pr.link]
        pairs.append(Pair("P", (slider, index[pr.guide]), name=pr.name, joint="prismatic"))
    for ac in m.actuators:
        pairs.append(Pair("P", (index[f"{ac.name}.rod"], index[f"{ac.name}.cylinder"]), name=ac.name,
                          driven=ac.name in driven, joint="prismatic"))
    for gp in m.gears:
        pairs.append(Pair("G", (index[gp.a], index[gp.b]), name=gp.name, joint="gear"))
    for cp in m.cams:
        pairs.append(Pair("C", (index[cp.cam], index[cp.follower]), name=cp.name, joint="cam"))
    return StructureGraph(tuple(bodies), tuple(pairs), tuple(joints))
