"""The fewest layers: an integer program over the conflict graph, solved by HiGHS (``scipy.optimize.milp``), with
the maximum clique of the conflict graph as its lower bound.

Unknowns (K layers at most, one per layered group: parts that share a layer by design form one group):

- x[g, k] = 1 when group g sits in layer k; y[k] = 1 when layer k is used (y[k] ≥ y[k + 1]);
- σ[f] = 1 when the frame end f (a frame pin's, or a block riding in a frame slot) is in the top plate instead of
  the base;
- a[j, k] ≥ 0: pin j crosses layer k (something it holds lies below k and something above);
- o[j, k] ≥ 0: pin j fills the gap above layer k (k = −1: the gap over the base) with a washer or a sleeve.

Constraints: each group in one layer; two conflicting groups never share a layer; a group that ever covers pin j
never sits in a layer j crosses; two pins that ever come close never fill the same gap. Phase 1 minimises the
layers used, Σ y; phase 2 keeps that count and minimises the layers the pins cross and the use of a top plate.

The result is *proven minimal* when HiGHS reports the first phase optimal (its dual bound meets its count) — and
the certificate also says whether the count equals the clique bound and, for up to :data:`EXHAUSTIVE_GROUPS`
groups, whether a search over every assignment with one layer fewer (:func:`feasible`, which checks a layout
without the integer program) found none.
"""
from __future__ import annotations

import itertools
from dataclasses import dataclass, field

import numpy as np

#: up to this many layered groups, minimality is also verified by exhaustive search
EXHAUSTIVE_GROUPS = 10
#: weight of a top plate in phase 2, in crossed layers
TOP_PLATE_WEIGHT = 2.0


@dataclass(eq=False)
class PinNeed:
    """A pin: ``groups`` it goes through, ``ends`` the frame ends it holds (indices into the side unknowns),
    ``blocked`` the groups that ever cover it."""
    name: str
    groups: list
    ends: list
    blocked: list


@dataclass(eq=False)
class Program:
    """The layer problem: ``groups`` (lists of part names), conflicting group pairs ``edges``, ``pins``,
    conflicting pin pairs ``pin_edges`` (indices), ``sides`` the frame ends' names."""
    groups: list
    edges: set
    pins: list
    pin_edges: list
    sides: list

    def group_of(self, part: str) -> int:
        for g, members in enumerate(self.groups):
            if part in members:
                return g
        raise KeyError(part)


@dataclass(eq=False)
class Layout:
    """A solution: ``layer`` (n_groups,) ints; ``side`` (n_sides,) 0 base, 1 top; ``layers`` the count."""
    layer: np.ndarray
    side: np.ndarray
    layers: int


@dataclass(eq=False)
class Certificate:
    """Why the layer count is minimal: ``layers`` the count, ``clique`` the maximum clique (part groups that
    conflict pairwise: no fewer layers can hold them) and its size ``bound``; ``status`` HiGHS's ('optimal',
    'time limit', …), ``dual_bound`` its proven lower bound and ``gap`` (layers − bound)/layers; ``exhaustive``:
    True when a search over all assignments with one layer fewer found none (None: not run); ``proven``."""
    layers: int
    bound: int
    clique: list
    status: str
    dual_bound: float
    gap: float
    exhaustive: bool | None
    proven: bool
    time: float = 0.0
    phase2_status: str = ""
    notes: list = field(default_factory=list)

    def as_dict(self) -> dict:
        return {k: getattr(self, k) for k in ("layers", "bound", "clique", "status", "dual_bound", "gap",
                                              "exhaustive", "proven", "time", "phase2_status", "notes")}


class Unstackable(Exception):
    """No layout within ``limit`` layers: ``parts`` (the part names of a set that cannot be stacked) and
    ``pairs`` (conflicting pairs among them)."""

    def __init__(self, limit, groups, clique: bool):
        self.limit, self.groups, self.clique = limit, groups, clique
        super().__init__(limit, groups, clique)


def max_clique(program: Program) -> list:
    """A maximum clique of the conflict graph (group indices), by networkx."""
    import networkx as nx
    G = nx.Graph()
    G.add_nodes_from(range(len(program.groups)))
    G.add_edges_from(program.edges)
    clique, _ = nx.max_weight_clique(G, weight=None)
    return sorted(clique)


class _Vars:
    """Column indices of the unknowns of a program with K layers."""

    def __init__(self, program: Program, K: int):
        n, J, F = len(program.groups), len(program.pins), len(program.sides)
        self.K, self.n, self.J, self.F = K, n, J, F
        self.x0 = 0
        self.y0 = n * K
        self.s0 = self.y0 + K
        self.a0 = self.s0 + F
        self.o0 = self.a0 + J * K
        self.u = self.o0 + J * (K + 1)         # 1 when a top plate is used (some σ = 1)
        self.size = self.u + 1

    def x(self, g, k):
        return self.x0 + g * self.K + k

    def y(self, k):
        return self.y0 + k

    def s(self, f):
        return self.s0 + f

    def a(self, j, k):
        return self.a0 + j * self.K + k

    def o(self, j, k):       # gap above layer k, k = -1 … K-1
        return self.o0 + j * (self.K + 1) + (k + 1)


class _Rows:
    def __init__(self, size):
        self.size, self.rows, self.lo, self.hi = size, [], [], []

    def add(self, terms, lo, hi):
        row = {}
        for col, v in terms:
            row[col] = row.get(col, 0.0) + v
        self.rows.append(row)
        self.lo.append(lo)
        self.hi.append(hi)

    def constraint(self):
        from scipy.optimize import LinearConstraint
        from scipy.sparse import lil_matrix
        A = lil_matrix((len(self.rows), self.size))
        for i, row in enumerate(self.rows):
            for col, v in row.items():
                A[i, col] = v
        return LinearConstraint(A.tocsr(), self.lo, self.hi)


def _below(V, item, k, strict=True):
    """Terms and constant of 'item lies below layer k' (strict) or 'at or below k'; item ('g', g) | ('s', f)."""
    kind, i = item
    if kind == "s":                        # the base is below every layer; the top (σ = 1) above
        return [(V.s(i), -1.0)], 1.0
    top = k if strict else k + 1
    return [(V.x(i, kk), 1.0) for kk in range(0, min(top, V.K))], 0.0


def _above(V, item, k, strict=True):
    kind, i = item
    if kind == "s":
        return [(V.s(i), 1.0)], 0.0
    bottom = k + 1 if strict else k
    return [(V.x(i, kk), 1.0) for kk in range(max(bottom, 0), V.K)], 0.0


def _build(program: Program, K: int):
    V = _Vars(program, K)
    R = _Rows(V.size)
    for g in range(V.n):
        R.add([(V.x(g, k), 1.0) for k in range(K)], 1, 1)
        for k in range(K):
            R.add([(V.x(g, k), 1.0), (V.y(k), -1.0)], -np.inf, 0)
    for k in range(K - 1):
        R.add([(V.y(k + 1), 1.0), (V.y(k), -1.0)], -np.inf, 0)
    for g, h in program.edges:
        for k in range(K):
            R.add([(V.x(g, k), 1.0), (V.x(h, k), 1.0), (V.y(k), -1.0)], -np.inf, 0)
    for j, pin in enumerate(program.pins):
        held = [("g", g) for g in pin.groups] + [("s", f) for f in pin.ends]
        for h1, h2 in itertools.permutations(held, 2):
            for k in range(K):              # crossing layer k: h1 below k, h2 above k
                t1, c1 = _below(V, h1, k)
                t2, c2 = _above(V, h2, k)
                R.add(t1 + t2 + [(V.a(j, k), -1.0)], -np.inf, 1.0 - c1 - c2)
            for k in range(-1, K):          # filling the gap above layer k: h1 at or below k, h2 above k
                t1, c1 = _below(V, h1, k, strict=False)
                t2, c2 = _above(V, h2, k)
                R.add(t1 + t2 + [(V.o(j, k), -1.0)], -np.inf, 1.0 - c1 - c2)
        for g in pin.blocked:
            for k in range(K):
                R.add([(V.x(g, k), 1.0), (V.a(j, k), 1.0)], -np.inf, 1)
    for j1, j2 in program.pin_edges:
        for k in range(-1, K):
            R.add([(V.o(j1, k), 1.0), (V.o(j2, k), 1.0)], -np.inf, 1)
    for f in range(V.F):
        R.add([(V.s(f), 1.0), (V.u, -1.0)], -np.inf, 0)
    integrality = np.zeros(V.size)
    integrality[V.x0:V.a0] = 1
    lo = np.zeros(V.size)
    hi = np.ones(V.size)
    return V, R, integrality, lo, hi


def _status(res) -> str:
    return {0: "optimal", 1: "time limit", 2: "infeasible", 3: "unbounded"}.get(res.status, "failed")


def _decode(V, program, x) -> Layout:
    layer = np.array([int(np.argmax([x[V.x(g, k)] for k in range(V.K)])) for g in range(V.n)], dtype=int)
    used = sorted(set(layer.tolist()))
    remap = {k: i for i, k in enumerate(used)}      # drop empty layers (never needed; kept for safety)
    layer = np.array([remap[k] for k in layer], dtype=int)
    side = np.array([int(round(x[V.s(f)])) for f in range(V.F)], dtype=int)
    return Layout(layer, side, len(used))


def solve_layers(program: Program, *, max_layers: int | None = None, time_limit: float = 60.0):
    """(Layout, Certificate) of the fewest layers (at most ``max_layers``). Raises :class:`Unstackable` when no
    layout exists within the limit (or at all)."""
    import time

    from scipy.optimize import Bounds, milp
    start = time.perf_counter()
    n = len(program.groups)
    clique = max_clique(program)
    K = n if max_layers is None else min(n, int(max_layers))
    if n == 0:
        return Layout(np.zeros(0, int), np.zeros(len(program.sides), int), 0), \
            Certificate(0, 0, [], "optimal", 0.0, 0.0, True, True)
    if len(clique) > K:
        raise Unstackable(K, clique, True)
    V, R, integrality, lo, hi = _build(program, K)
    c = np.zeros(V.size)
    c[V.y0:V.y0 + K] = 1.0
    cons = R.constraint()
    res = milp(c, integrality=integrality, bounds=Bounds(lo, hi), constraints=cons,
               options={"time_limit": time_limit, "presolve": True})
    status = _status(res)
    if res.x is None:
        if status == "infeasible":
            raise Unstackable(K, _minimal_infeasible(program, K), False)
        raise Unstackable(K, list(range(n)), False)
    layout = _decode(V, program, res.x)
    L = layout.layers
    dual = float(res.mip_dual_bound) if res.mip_dual_bound is not None else float(len(clique))
    dual = max(dual, float(len(clique)))
    # phase 2: the same count, the fewest crossed layers and no top plate unless it helps
    c2 = np.zeros(V.size)
    for j in range(V.J):
        for k in range(K):
            c2[V.a(j, k)] = 1.0
        for k in range(-1, K):
            c2[V.o(j, k)] = 0.01
    c2[V.u] = TOP_PLATE_WEIGHT
    from scipy.optimize import LinearConstraint
    count = np.zeros(V.size)
    count[V.y0:V.y0 + K] = 1.0
    extra = [LinearConstraint(count[None, :], L, L)]
    res2 = milp(c2, integrality=integrality, bounds=Bounds(lo, hi), constraints=[cons] + extra,
                options={"time_limit": max(5.0, 0.5 * time_limit), "presolve": True})
    phase2 = _status(res2)
    if res2.x is not None:
        layout2 = _decode(V, program, res2.x)
        if layout2.layers == L:
            layout = layout2
    proven = status == "optimal"
    exhaustive = None
    if n <= EXHAUSTIVE_GROUPS and L > len(clique):
        exhaustive = not _exists(program, L - 1)
        proven = proven or exhaustive
    elif L == len(clique):
        proven = True
    gap = 0.0 if proven else max(0.0, (L - np.ceil(dual - 1e-6)) / L)
    cert = Certificate(L, len(clique), [sorted(program.groups[g]) for g in clique], status, dual, gap, exhaustive,
                       proven, time.perf_counter() - start, phase2)
    if not feasible(program, layout):          # the integer program's answer, checked without it
        raise RuntimeError("the layer program returned a layout that violates its constraints")
    return layout, cert


def _feasible_milp(program: Program, K: int, time_limit: float = 30.0) -> bool | None:
    from scipy.optimize import Bounds, milp
    if K <= 0:
        return len(program.groups) == 0
    V, R, integrality, lo, hi = _build(program, K)
    res = milp(np.zeros(V.size), integrality=integrality, bounds=Bounds(lo, hi), constraints=R.constraint(),
               options={"time_limit": time_limit})
    if res.status == 0:
        return True
    if res.status == 2:
        return False
    return None


def _minimal_infeasible(program: Program, K: int) -> list:
    """A set of groups that cannot be stacked in K layers, none of which can be left out (deletion filter)."""
    keep = list(range(len(program.groups)))
    for g in list(keep):
        trial = [h for h in keep if h != g]
        if _feasible_milp(_restrict(program, trial), K) is False:
            keep = trial
    return keep


def _restrict(program: Program, groups: list) -> Program:
    """The program on the groups ``groups`` only (pins keep the ends and the groups that remain)."""
    new = {g: i for i, g in enumerate(groups)}
    edges = {(new[g], new[h]) for g, h in program.edges if g in new and h in new}
    pins = [PinNeed(p.name, [new[g] for g in p.groups if g in new], p.ends, [new[g] for g in p.blocked if g in new])
            for p in program.pins]
    return Program([program.groups[g] for g in groups], edges, pins, program.pin_edges, program.sides)


def feasible(program: Program, layout: Layout) -> bool:
    """Whether ``layout`` meets every constraint of ``program`` (checked directly, without the integer program)."""
    lay, side = layout.layer, layout.side
    L = layout.layers
    if any(lay[g] == lay[h] for g, h in program.edges):
        return False

    def level(item):
        kind, i = item
        return lay[i] if kind == "g" else (L if side[i] else -1)
    gaps = []
    for pin in program.pins:
        levels = [level(("g", g)) for g in pin.groups] + [level(("s", f)) for f in pin.ends]
        lo, hi = min(levels), max(levels)
        if any(lo < lay[g] < hi for g in pin.blocked):
            return False
        gaps.append(set(range(lo, hi)))
    return all(not (gaps[j1] & gaps[j2]) for j1, j2 in program.pin_edges)


def _exists(program: Program, K: int) -> bool:
    """Whether any layout with K layers exists: backtracking over the groups' layers (conflicts pruned), every
    choice of frame ends at the leaves."""
    n = len(program.groups)
    if K <= 0:
        return n == 0
    nbrs = [set() for _ in range(n)]
    for g, h in program.edges:
        nbrs[g].add(h)
        nbrs[h].add(g)
    order = sorted(range(n), key=lambda g: -len(nbrs[g]))
    lay = np.full(n, -1, dtype=int)
    sides = list(itertools.product((0, 1), repeat=len(program.sides)))

    def leaf():          # a partition into layers: try every order of its layers and every choice of ends
        used = sorted(set(lay.tolist()))
        for perm in itertools.permutations(range(len(used))):
            remap = np.full(K, -1)
            remap[used] = perm
            compact = remap[lay]
            if any(feasible(program, Layout(compact, np.array(s, dtype=int), len(used))) for s in sides):
                return True
        return False

    def place(i, top):
        if i == n:
            return leaf()
        g = order[i]
        for k in range(min(top + 1, K)):       # partitions only (open at most one new label); leaf() orders them
            if all(lay[h] != k for h in nbrs[g]):
                lay[g] = k
                if place(i + 1, max(top, k + 1)):
                    return True
                lay[g] = -1
        return False
    return place(0, 0)


__all__ = ["Certificate", "EXHAUSTIVE_GROUPS", "Layout", "PinNeed", "Program", "Unstackable", "feasible",
           "max_clique", "solve_layers"]
