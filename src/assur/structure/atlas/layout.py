"""A planar sketch of an atlas mechanism: joint coordinates and rigid links, so that the entry opens as a
mechanism file (docs/atlas.md, "Each entry as a mechanism").

A 1-DOF inversion (a chain with a frame link) driven by a crank (a link hinged to the frame) is drawn as

* one point per joint of the chain (``J0 … J(j−1)``, the canonical edge order);
* one rigid link per chain link: a link of degree k is the k-gon through its k joints (``frame`` for the frame
  link, ``L1 … L(n−1)`` for the others in canonical order);
* a rotary driver on the crank about its joint with the frame.

The geometry: the chain graph's links are placed by a Kamada–Kawai layout (``networkx``, deterministic: no random
start), each joint near the middle of its two links' positions, moved by a small seeded perturbation (so that no
two links are parallel by construction), then the crank's other joints are pulled towards its pivot (a short
crank turns more often through a full turn). The picture is turned so that the frame lies along x below the rest.
Coordinates are rounded to 0.01 mm, the mechanism's size is about :data:`SIZE` mm.

:func:`sketch` gives the sketch of one *attempt* (attempt 0, 1, … differ by the perturbation's seed and the crank's
length); whether a sketch assembles and turns is the engine's to say (:mod:`assur.io.atlas` tries the attempts in
order). Everything is deterministic: the same attempt gives the same numbers on every run.
"""
from __future__ import annotations

import hashlib
import math
from dataclasses import dataclass

import numpy as np

from .mechanisms import Inversion

__all__ = ["CRANK_SHRINK", "SIZE", "Sketch", "crank_joints", "document", "joint_names", "link_names", "sketch"]

#: the size of a sketch (mm): the extent of the link layout before the joints are placed
SIZE = 1000.0
#: the crank's length factor of successive attempts (the crank's moving joints at this fraction of their
#: distance to the pivot); the list repeats with new perturbation seeds
CRANK_SHRINK = (0.3, 0.18, 0.45, 0.1)
#: the perturbation of the joints (fraction of SIZE) of attempt 0; later attempts perturb more
JITTER = 0.04


@dataclass(frozen=True)
class Sketch:
    """The drawing of an inversion with a crank.

    ``joints``: (x, y) in mm of each joint (canonical edge order, ``inversion.chain.edges[k]`` joins the two links
    of joint k); ``links``: for each link (canonical position) its joints in polygon order (counter-clockwise
    around their centroid); ``crank``: the crank link; ``pivot``: its joint with the frame; ``arm``: the
    crank's joint that sets the input angle; ``attempt``: the attempt number."""
    inversion: Inversion
    crank: int
    joints: tuple[tuple[float, float], ...]
    links: tuple[tuple[int, ...], ...]
    pivot: int
    arm: int
    attempt: int

    @property
    def link_names(self) -> tuple[str, ...]:
        return link_names(self.inversion)

    @property
    def joint_names(self) -> tuple[str, ...]:
        return joint_names(self.inversion)


def link_names(inversion: Inversion) -> tuple[str, ...]:
    """The name of each link (canonical position): ``frame`` for the frame, ``L1``, ``L2``, … for the others."""
    names, k = [], 1
    for v in range(inversion.chain.n):
        if v == inversion.frame:
            names.append("frame")
        else:
            names.append(f"L{k}")
            k += 1
    return tuple(names)


def joint_names(inversion: Inversion) -> tuple[str, ...]:
    """``J0 … J(j−1)``: one point per joint, in canonical edge order."""
    return tuple(f"J{k}" for k in range(len(inversion.chain.edges)))


def crank_joints(inversion: Inversion, crank: int) -> tuple[int, tuple[int, ...]]:
    """(pivot, others): the crank's joint with the frame and its other joints (joint indices). ValueError when
    ``crank`` is not hinged to the frame."""
    edges = inversion.chain.edges
    f = inversion.frame
    pivot = [k for k, e in enumerate(edges) if set(e) == {f, crank}]
    if crank == f or not pivot:
        raise ValueError(f"link {crank} is not hinged to the frame link {f} of {inversion.id}")
    return pivot[0], tuple(k for k, e in enumerate(edges) if crank in e and k != pivot[0])


def _seed(inversion: Inversion, crank: int, attempt: int) -> list[int]:
    """A stable seed of (inversion, crank, attempt): from the SHA-256 of the inversion ID, not Python's hash."""
    digest = hashlib.sha256(f"{inversion.id}/c{crank}".encode()).digest()
    return [int.from_bytes(digest[:8], "little"), attempt]


def _link_positions(inversion: Inversion) -> np.ndarray:
    """(n, 2) link positions of the chain graph: a Kamada–Kawai layout scaled to SIZE (deterministic)."""
    import networkx as nx
    g = inversion.chain
    G = nx.Graph()
    G.add_nodes_from(range(g.n))
    G.add_edges_from(g.edges)
    pos = nx.kamada_kawai_layout(G, pos=nx.circular_layout(G), scale=1.0)
    P = np.array([pos[v] for v in range(g.n)], dtype=float)
    P -= P.mean(axis=0)
    extent = float(np.max(np.ptp(P, axis=0))) or 1.0
    return P * (SIZE / extent)


def _orient(J: np.ndarray, frame_joints: list[int]) -> np.ndarray:
    """Turn (and mirror) the joints so that the frame's joints lie along +x, below the centroid of the others."""
    F = J[frame_joints]
    c = F.mean(axis=0)
    if len(frame_joints) == 2:
        d = F[1] - F[0]
    else:   # the principal direction of the frame's joints
        _, _, vt = np.linalg.svd(F - c)
        d = vt[0]
    a = math.atan2(d[1], d[0])
    R = np.array([[math.cos(a), math.sin(a)], [-math.sin(a), math.cos(a)]])
    out = (J - c) @ R.T
    others = [k for k in range(len(J)) if k not in frame_joints]
    if others and out[others, 1].mean() < 0:
        out[:, 1] = -out[:, 1]
    return out - out.min(axis=0) + 0.05 * SIZE      # a margin: every coordinate positive


def sketch(inversion: Inversion, crank: int, attempt: int = 0) -> Sketch:
    """The sketch of ``inversion`` driven by the crank link ``crank`` (canonical position of a link hinged to the
    frame), attempt number ``attempt`` (0, 1, …: other perturbations and crank lengths)."""
    g = inversion.chain
    pivot, moving = crank_joints(inversion, crank)
    P = _link_positions(inversion)
    rng = np.random.default_rng(_seed(inversion, crank, attempt))
    jitter = JITTER * SIZE * (1.0 + 0.5 * (attempt // len(CRANK_SHRINK)))
    J = np.empty((len(g.edges), 2))
    for k, (u, v) in enumerate(g.edges):
        t = 0.5 + rng.uniform(-0.15, 0.15)
        J[k] = P[u] + t * (P[v] - P[u]) + rng.normal(0.0, jitter, 2)
    s = CRANK_SHRINK[attempt % len(CRANK_SHRINK)]
    for k in moving:
        J[k] = J[pivot] + s * (J[k] - J[pivot])
    frame_joints = [k for k, e in enumerate(g.edges) if inversion.frame in e]
    J = np.round(_orient(J, frame_joints), 2) + 0.0       # + 0.0: no negative zero in the text
    links = []
    for v in range(g.n):
        ks = [k for k, e in enumerate(g.edges) if v in e]
        c = J[ks].mean(axis=0)
        links.append(tuple(sorted(ks, key=lambda k: (math.atan2(J[k, 1] - c[1], J[k, 0] - c[0]), k))))
    arm = moving[0]
    return Sketch(inversion, crank, tuple((float(x), float(y)) for x, y in J), tuple(links), pivot, arm, attempt)


def document(sk: Sketch, speed: str = "60 rpm") -> dict:
    """The mechanism file's document (``format = "assur/1"``, docs/format.md) of a sketch: points in mm, the links
    by their joints (lengths from the sketch), a rotary driver on the crank about its pivot."""
    inv = sk.inversion
    jn, ln = sk.joint_names, sk.link_names
    crank_points = [jn[k] for k in sk.links[sk.crank]]
    # the crank's point list starts at its pivot, then its arm: the link's own frame is pivot → arm
    crank_points.remove(jn[sk.pivot])
    crank_points.remove(jn[sk.arm])
    links = {}
    for v in range(inv.chain.n):
        pts = [jn[sk.pivot], jn[sk.arm], *crank_points] if v == sk.crank else [jn[k] for k in sk.links[v]]
        links[ln[v]] = pts
    name = f"{inv.name} ({inv.id})" if inv.name else inv.id
    return {
        "format": "assur/1",
        "name": name,
        "description": (f"atlas mechanism {inv.id}: chain {inv.chain.id} with frame link {inv.frame}, crank link "
                        f"{sk.crank} ({ln[sk.crank]}); sketch attempt {sk.attempt}"),
        "units": {"length": "mm", "angle": "deg"},
        "points": {jn[k]: [x, y] for k, (x, y) in enumerate(sk.joints)},
        "links": {k: links[k] for k in sorted(ln, key=lambda name: name != "frame")},
        "drivers": [{"name": "crank", "kind": "rotary", "link": ln[sk.crank], "pivot": jn[sk.pivot],
                     "arm": jn[sk.arm], "speed": speed}],
    }
