"""Mobility (Chebyshev, Somov–Malyshev) and the decomposition into Assur groups.

The decomposition is found from connectivity alone: starting from the frame and the driven links
(class I), it repeatedly takes the smallest set of undetermined bodies whose pairs to each other
and to already-determined bodies make it statically determinate (3·n = 2·p5): a dyad (class II,
n = 2), then a triad (class III, n = 4), and so on. A driven linear actuator is one body of given
length for this purpose (its driven slide is the input).

A gear pair is a higher pair (p4). For the structure it is replaced by its substitute link: a binary link
hinged at the centres of curvature of the two pitch curves at the contact point (two p5 for one p4, one more
link). A gear pair whose driving link is determined therefore determines its driven link, hinged on the frame:
the driven link and the substitute link form a class II group (an RRR dyad), written ``II(crank, drive′)``
with the substitute link named after the pair.

A cam pair is a higher pair (p4) too. Its follower either oscillates about a frame pivot or translates on a frame
slide; with the cam determined, the follower and the pair's substitute link (hinged at the cam profile's centre of
curvature at the contact and at the follower's: the roller's centre) form a class II group, an RRR dyad (oscillating)
or an RRP dyad (translating), written ``II(follower, cam′)``.
"""
from __future__ import annotations

import itertools
from dataclasses import dataclass
from enum import Enum

from ..errors import StructureError
from ..model.mechanism import Mechanism
from .graph import StructureGraph, build_graph
from .spatial import spatial_dyads


class GroupKind(str, Enum):
    RRR = "RRR"   # 1st kind
    RRP = "RRP"   # 2nd kind
    RPR = "RPR"   # 3rd kind
    PRP = "PRP"   # 4th kind
    PPR = "PPR"   # 5th kind (R outer, P inner, P outer)
    TRIAD = "triad"
    GENERAL = "general"
    RSS = "RSS"   # spatial: rocker hinged on the frame (R), coupler with spherical ends (S, S)
    GEAR = "gear"  # a link hinged on the frame and driven through a gear pair (with its substitute link, an RRR dyad)
    CAM = "cam"    # a follower hinged on, or sliding on, the frame and driven by a cam (with its substitute link)

    @property
    def dyad_kind_number(self) -> int | None:
        return {"RRR": 1, "RRP": 2, "RPR": 3, "PRP": 4, "PPR": 5}.get(self.value)


class PairCounts(dict):
    """Kinematic pairs by class (``'p5'``, ``'p4'`` …): a read-only dict."""
    __slots__ = ()

    def _read_only(self, *args, **kwargs):
        raise TypeError("pair counts are read-only")

    __setitem__ = __delitem__ = clear = pop = popitem = setdefault = update = __ior__ = _read_only

    def __reduce__(self):
        return PairCounts, (dict(self),)


@dataclass(frozen=True, slots=True)
class AssurGroup:
    """One Assur group: its bodies (indices into the graph), class, order and kind.

    ``outer``: the pairs to already-determined bodies, as (group body, pair index);
    ``inner``: the pairs between the group's bodies (pair indices).
    ``attaches_to``: the determined bodies it is hinged or slides on.
    """
    bodies: tuple[int, ...]
    group_class: int
    order: int
    kind: GroupKind
    outer: tuple[tuple[int, int], ...]
    inner: tuple[int, ...]
    attaches_to: tuple[int, ...]


@dataclass(frozen=True, slots=True)
class Driven:
    """A class-I mechanism: the frame and one driven link (or driven actuator)."""
    driver: str
    bodies: tuple[int, ...]
    kind: str  # 'rotary' | 'linear'


@dataclass(frozen=True, slots=True)
class Structure:
    graph: StructureGraph
    n_moving: int
    #: pairs by class ('p5', 'p4', …), read-only
    pair_counts: "PairCounts"
    mobility: int
    formula_name: str      # 'Chebyshev' | 'Somov–Malyshev'
    drivers: tuple[Driven, ...]
    groups: tuple[AssurGroup, ...]
    #: bodies (their source names) that no Assur group determines with the given drivers
    undetermined: tuple[str, ...] = ()
    #: idle (local) freedoms of a spatial description: a binary link between two spherical joints
    #: spins about its own axis without moving anything else
    idle: int = 0

    @property
    def mobility_without_idle(self) -> int:
        return self.mobility - self.idle

    def body_label(self, i: int) -> str:
        return self.graph.bodies[i].name

    @property
    def structural_formula(self) -> str:
        """The papers' notation with body names, e.g. ``I(frame, crank) → II(coupler, rocker)``."""
        return self._formula(self.body_label, numbered=False)

    @property
    def structural_formula_numbered(self) -> str:
        """The papers' notation with body numbers (frame 0, links in file order), e.g. ``I(0,1) → II(2,3)``."""
        return self._formula(str, numbered=True).replace(", ", ",")

    def _formula(self, label, numbered: bool) -> str:
        """A driven actuator (cylinder + rod of given length) is one member, named once."""
        driven = {b: d.bodies[0] for d in self.drivers if d.kind == "linear" for b in d.bodies}
        bodies = self.graph.bodies

        def names(members):
            out = []
            for b in members:
                if b in driven:
                    text = label(driven[b]) if numbered else bodies[b].source
                else:
                    text = label(b)
                if text not in out:
                    out.append(text)
            return out

        parts = []
        for d in self.drivers:
            parts.append(f"I({', '.join([label(0)] + names(d.bodies))})")
        for g in self.groups:
            members = names(g.bodies)
            if g.kind in (GroupKind.GEAR, GroupKind.CAM):
                members.append(self.substitute_link(g))
            parts.append(f"{roman(g.group_class)}({', '.join(members)})")
        return " → ".join(parts)

    def substitute_link(self, group: "AssurGroup") -> str:
        """The name of a gear or cam group's substitute link: the higher pair's name primed."""
        return f"{self.graph.pairs[group.outer[1][1]].name}′"

    def describe(self) -> list[dict]:
        out = []
        for g in self.groups:
            out.append({
                "class": g.group_class, "order": g.order, "kind": g.kind.value,
                "bodies": [self.body_label(b) for b in g.bodies],
                "attaches_to": [self.body_label(b) for b in g.attaches_to],
            })
            if g.kind is GroupKind.GEAR:
                out[-1]["gear_pair"] = self.graph.pairs[g.outer[1][1]].name
                out[-1]["substitute_link"] = self.substitute_link(g)
            elif g.kind is GroupKind.CAM:
                out[-1]["cam_pair"] = self.graph.pairs[g.outer[1][1]].name
                out[-1]["substitute_link"] = self.substitute_link(g)
        return out


def roman(n: int) -> str:
    """The papers' class numeral of a group (I … VI; larger classes as digits)."""
    return {1: "I", 2: "II", 3: "III", 4: "IV", 5: "V", 6: "VI"}.get(n, str(n))


def mobility_chebyshev(n: int, p5: int, p4: int = 0) -> int:
    """W = 3n − 2p5 − p4 (planar)."""
    return 3 * n - 2 * p5 - p4


def mobility_somov_malyshev(n: int, p5: int = 0, p4: int = 0, p3: int = 0, p2: int = 0, p1: int = 0) -> int:
    """W = 6n − 5p5 − 4p4 − 3p3 − 2p2 − p1 (spatial; p_k = pairs of class k, i.e. with 6 − k freedoms)."""
    return 6 * n - 5 * p5 - 4 * p4 - 3 * p3 - 2 * p2 - p1


_SPATIAL_CLASS = {"revolute": 5, "prismatic": 5, "cylindrical": 4, "universal": 4, "spherical": 3}


def analyse(m: Mechanism) -> Structure:
    """Mobility and Assur decomposition of a mechanism description. Raises StructureError."""
    from ..model.mechanism import require_mechanism
    g = build_graph(require_mechanism(m))
    n = len(g.bodies) - 1
    if m.dimension == 3:
        counts = {f"p{k}": 0 for k in (5, 4, 3, 2, 1)}
        for p in g.pairs:
            counts[f"p{_SPATIAL_CLASS[p.joint]}"] += 1
        W = mobility_somov_malyshev(n, counts["p5"], counts["p4"], counts["p3"], counts["p2"], counts["p1"])
        kinds = {j.point: j.kind for j in m.joints}
        idle = sum(1 for b in g.bodies[1:] if b.kind == "link" and len(b.points) == 2
                   and all(kinds.get(p) == "spherical" for p in b.points))
        drivers = tuple(Driven(d.name, (g.index(d.link),), "rotary") for d in m.drivers if d.kind == "rotary")
        dyads, left = spatial_dyads(m, g)
        groups = tuple(_spatial_group(g, dy) for dy in dyads)
        return Structure(g, n, PairCounts(counts), W, "Somov–Malyshev", drivers, groups,
                         tuple(g.bodies[i].source for i in left), idle=idle)
    p4 = sum(1 for p in g.pairs if p.kind in ("G", "C"))
    counts = {"p5": len(g.pairs) - p4, "p4": p4}
    W = mobility_chebyshev(n, counts["p5"], p4)
    drivers, groups, undetermined = _decompose(m, g)
    return Structure(g, n, PairCounts(counts), W, "Chebyshev", drivers, groups, undetermined)


def _spatial_group(g: StructureGraph, dy) -> AssurGroup:
    """The Assur group record of a spatial R–S–S dyad (class II, order 2)."""
    at_a = next(b for b in g.bodies_at(dy.start) if b != dy.coupler)
    outer = ((dy.rocker, _pair_at(g, dy.pivot, dy.rocker, 0)), (dy.coupler, _pair_at(g, dy.start, dy.coupler, at_a)))
    inner = (_pair_at(g, dy.joint, dy.rocker, dy.coupler),)
    return AssurGroup((dy.rocker, dy.coupler), 2, 2, GroupKind.RSS, outer, inner, tuple(sorted({0, at_a})))


def _decompose(m: Mechanism, g: StructureGraph):
    nb = len(g.bodies)
    # units: driven actuators' cylinder and rod act as one body of given length
    unit = list(range(nb))
    for p in g.pairs:
        if p.kind == "P" and p.driven:
            a, b = p.bodies
            unit[b] = unit[a] = min(unit[a], unit[b])
    def u(i):
        return unit[i]
    known = {u(0)}
    drivers = []
    for d in m.drivers:
        if d.kind == "rotary":
            b = g.index(d.link)
            if u(b) in known:
                raise StructureError(f"driver '{d.name}': link '{d.link}' is driven twice or is the frame")
            known.add(u(b))
            drivers.append(Driven(d.name, (b,), "rotary"))
        else:
            cyl, rod = g.index(f"{d.actuator}.cylinder"), g.index(f"{d.actuator}.rod")
            drivers.append(Driven(d.name, (cyl, rod), "linear"))
    # unit-level pairs (drop the driven slides, which are inputs)
    upairs = [(i, p) for i, p in enumerate(g.pairs) if not (p.kind == "P" and p.driven) and p.kind not in ("G", "C")]
    units_all = sorted({u(i) for i in range(nb)})
    members = {x: tuple(i for i in range(nb) if u(i) == x) for x in units_all}

    def pairs_of(G: set, K: set):
        used = []
        for i, p in upairs:
            a, b = u(p.bodies[0]), u(p.bodies[1])
            if (a in G or b in G) and a in G | K and b in G | K and a != b:
                used.append(i)
        return used

    def is_group(G: set, K: set):
        used = pairs_of(G, K)
        # revolute pairs were generated as a star from one body per point; re-count per joint
        count = 0
        for point, at in g.joints:
            us = {u(b) for b in at}
            gi = len(us & G)
            if gi == 0:
                continue
            if us & K:
                count += gi
            else:
                count += gi - 1
        count += sum(1 for i in used if g.pairs[i].kind == "P")
        if 2 * count != 3 * len(G):
            return None
        # every unit needs two pairs to be held
        deg = {x: 0 for x in G}
        for point, at in g.joints:
            us = {u(b) for b in at}
            inside = us & G
            if inside and (len(inside) > 1 or us & K):
                for x in inside:
                    deg[x] += 1
        for i in used:
            p = g.pairs[i]
            if p.kind == "P":
                for b in p.bodies:
                    if u(b) in G:
                        deg[u(b)] += 1
        if min(deg.values()) < 2:
            return None
        return used

    groups = []
    unknown = [x for x in units_all if x not in known]
    while unknown:
        geared = _gear_driven(g, known, u) or _cam_driven(g, known, u)
        if geared is not None:
            groups.append(geared)
            known.add(u(geared.bodies[0]))
            unknown = [x for x in unknown if x not in known]
            continue
        found = None
        for size in (2, 4, 6):
            if size > len(unknown):
                break
            for combo in itertools.combinations(unknown, size):
                G = set(combo)
                used = is_group(G, known)
                if used is not None and _connected(G, used, g, u):
                    found = (combo, used)
                    break
            if found:
                break
        if not found:
            undetermined = tuple(dict.fromkeys(g.bodies[b].source for x in unknown for b in members[x]))
            return tuple(drivers), tuple(groups), undetermined
        combo, used = found
        groups.append(_classify(combo, used, known, g, u, members))
        known |= set(combo)
        unknown = [x for x in unknown if x not in known]
    return tuple(drivers), tuple(groups), ()


def _gear_driven(g: StructureGraph, known: set, u):
    """The group of the first gear pair whose driving link is determined and whose driven link, hinged on the
    frame, is not (None if there is none)."""
    frame_points = set(g.bodies[0].points)
    for i, p in enumerate(g.pairs):
        if p.kind != "G":
            continue
        a, b = p.bodies
        if u(a) not in known or u(b) in known:
            continue
        pivot = next((q for q in g.bodies[b].points if q in frame_points), None)
        if pivot is None:
            continue
        return AssurGroup((b,), 2, 2, GroupKind.GEAR, ((b, _pair_at(g, pivot, b, 0)), (b, i)), (), tuple(sorted({0, a})))
    return None


def _cam_driven(g: StructureGraph, known: set, u):
    """The group of the first cam pair whose cam is determined and whose follower, hinged on the frame or sliding on
    a frame slide, is not (None if there is none)."""
    frame_points = set(g.bodies[0].points)
    for i, p in enumerate(g.pairs):
        if p.kind != "C":
            continue
        a, b = p.bodies
        if u(a) not in known or u(b) in known:
            continue
        pivot = next((q for q in g.bodies[b].points if q in frame_points), None)
        if pivot is not None:
            own = _pair_at(g, pivot, b, 0)
        else:
            own = next((k for k, pk in enumerate(g.pairs) if pk.kind == "P" and set(pk.bodies) == {b, 0}), None)
            if own is None:
                continue
        return AssurGroup((b,), 2, 2, GroupKind.CAM, ((b, own), (b, i)), (), tuple(sorted({0, a})))
    return None


def _connected(G, used, g, u):
    G = set(G)
    adj = {x: set() for x in G}
    for point, at in g.joints:
        us = [u(b) for b in at if u(b) in G]
        for a, b in itertools.combinations(set(us), 2):
            adj[a].add(b)
            adj[b].add(a)
    for i in used:
        p = g.pairs[i]
        a, b = u(p.bodies[0]), u(p.bodies[1])
        if a in G and b in G:
            adj[a].add(b)
            adj[b].add(a)
    start = next(iter(G))
    seen, stack = {start}, [start]
    while stack:
        x = stack.pop()
        for y in adj[x] - seen:
            seen.add(y)
            stack.append(y)
    return seen == G


def _classify(combo, used, known, g, u, members):
    G = set(combo)
    bodies = tuple(sorted(b for x in combo for b in members[x]))
    outer, inner, attaches = [], [], set()
    # revolute joints
    for point, at in g.joints:
        us_in = [b for b in at if u(b) in G]
        if not us_in:
            continue
        ks = [b for b in at if u(b) in known]
        if ks:
            for b in us_in:
                pi = _pair_at(g, point, b, ks[0])
                outer.append((b, pi))
            attaches.add(ks[0])
        else:
            for b in us_in[1:]:
                inner.append(_pair_at(g, point, us_in[0], b))
    for i in used:
        p = g.pairs[i]
        if p.kind != "P":
            continue
        a, b = p.bodies
        if u(a) in G and u(b) in G:
            inner.append(i)
        else:
            gb, kb = (a, b) if u(a) in G else (b, a)
            outer.append((gb, i))
            attaches.add(kb)
    size = len(combo)
    if size == 2:
        ka = g.pairs[outer[0][1]].kind
        kb = g.pairs[outer[1][1]].kind
        ki = g.pairs[inner[0]].kind if inner else "R"
        if ka == "P" and kb == "R":
            ka, kb = kb, ka
            outer = outer[::-1]
        key = ka + ki + kb
        kind = {"RRR": GroupKind.RRR, "RRP": GroupKind.RRP, "RPR": GroupKind.RPR, "PRP": GroupKind.PRP,
                "RPP": GroupKind.PPR}.get(key, GroupKind.GENERAL)
        return AssurGroup(bodies, 2, 2, kind, tuple(outer), tuple(inner), tuple(sorted(attaches)))
    # class III (a ternary base body) or IV (a closed four-sided contour) for four bodies
    group_class = 3
    if size == 4 and _has_four_cycle(G, inner, g, u):
        group_class = 4
    elif size > 4:
        group_class = size // 2 + 1
    return AssurGroup(bodies, group_class, len(outer), GroupKind.TRIAD if size == 4 and group_class == 3
                      else GroupKind.GENERAL, tuple(outer), tuple(inner), tuple(sorted(attaches)))


def _pair_at(g, point, a, b) -> int:
    """Index of a revolute pair at `point` joining bodies a and b (or any pair at the point touching a)."""
    best = None
    for i, p in enumerate(g.pairs):
        if p.kind == "R" and p.point == point:
            if set(p.bodies) == {a, b}:
                return i
            if a in p.bodies and best is None:
                best = i
    return best if best is not None else -1


def _has_four_cycle(G, inner, g, u):
    edges = set()
    for i in inner:
        a, b = (u(x) for x in g.pairs[i].bodies)
        edges.add(frozenset((a, b)))
    nodes = list(G)
    for perm in itertools.permutations(nodes):
        if all(frozenset((perm[k], perm[(k + 1) % 4])) in edges for k in range(4)):
            return True
    return False
