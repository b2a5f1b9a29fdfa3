"""Which parts ever come closer than the clearance over the continuous run, certified between the samples.

For two parts A and B on bodies a and b, the distance of their regions (polygons that contain the parts) is
measured exactly at every sample of the solved run. Between two samples a point of A moves, as seen from B's
frame, by at most δ = (Δt/2)·V + (Δt²/8)·W from the nearer sample, with, from the exact velocities and
accelerations of the bodies at the samples (c: the centre of A's bounding circle of radius ρ, p: B's centre,
u = c − p, J the quarter turn):

    V = |v_c − v_p − ω_b·J·u| + |ω_a − ω_b|·ρ        (A's largest speed in B's frame at the sample)
    W = |a_c − a_p − α_b·J·u| + (|α_a − α_b| + ω_a²)·ρ + 2|ω_b|·(|v_c − v_p| + |ω_a|·ρ) + ω_b²·(|u| + ρ)

(W bounds A's acceleration in B's frame; on an interval the larger of its two end values is used, which leaves an
error of third order in the step). So the gap on the interval is at least min(d_i − δ_i, d_{i+1} − δ_{i+1}). Where
that certificate falls below the clearance c while the samples do not, the interval is refined: the run is solved
at interior inputs (``cycle.state``) and the bound applied again on the finer steps. A pair is in conflict when
a sampled distance is below c, or when a certificate stays below c after the refinements (the safe verdict).

Parts on one body never move against each other: their distance is measured once.
"""
from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

#: interior inputs per refined interval, and refinement rounds
REFINE_SPLIT = 8
REFINE_ROUNDS = 3


@dataclass(eq=False)
class Item:
    """A part that takes a layer or a pin, as the conflict check sees it: its region in body ``body``'s frame
    (exterior (k, 2)) and its bounding circle (centre (2,), radius)."""
    name: str
    body: int
    ring: np.ndarray
    centre: np.ndarray
    radius: float
    pin: bool = False


@dataclass(eq=False)
class PairVerdict:
    """The verdict on one pair: ``conflict``; ``gap``: the certified least gap over the run (m; the sampled
    least distance where that is below the clearance); ``sampled``: the least sampled distance and ``at`` its
    input (the run's value); ``refined``: intervals refined; ``curve``: (n,) the distance at every sample (a lower
    bound far from contact: the bounding circles' distance)."""
    a: str
    b: str
    conflict: bool
    gap: float
    sampled: float
    at: float
    refined: int = 0
    curve: np.ndarray | None = field(default=None, repr=False)


def items_of(parts) -> list[Item]:
    """The :class:`Item` of each part (:class:`~assur.parts.shapes.Part`)."""
    out = []
    for p in parts:
        region = p.region()
        ring = np.asarray(region.exterior.coords)[:-1]
        c = 0.5 * (ring.min(axis=0) + ring.max(axis=0))
        out.append(Item(p.name, p.body, ring, c, float(np.max(np.hypot(*(ring - c).T))), p.kind == "pin"))
    return out


def _world(frames_arrays, body, xy):
    """xy (k, 2) in body ``body``'s frame → (n, k, 2) world, at the poses ``frames_arrays``."""
    origin, angle = frames_arrays["origin"][:, body], frames_arrays["angle"][:, body]
    c, s = np.cos(angle)[:, None], np.sin(angle)[:, None]
    return np.stack([origin[:, None, 0] + c * xy[:, 0] - s * xy[:, 1],
                     origin[:, None, 1] + s * xy[:, 0] + c * xy[:, 1]], axis=-1)


def _point_motion(F, body, local):
    """World position, velocity, acceleration (n, 2) of the material point ``local`` (2,) of ``body``."""
    w = _world(F, body, local[None])[:, 0]
    r = w - F["origin"][:, body]
    jr = np.stack([-r[:, 1], r[:, 0]], axis=-1)
    om, al = F["omega"][:, body, None], F["alpha"][:, body, None]
    v = F["vel"][:, body] + om * jr
    a = F["acc"][:, body] + al * jr - om * om * r
    return w, v, a


def _speed_bounds(F, A: Item, B: Item):
    """(V, W) (n,) at each pose of ``F``: A's largest speed and acceleration in B's frame (module docstring)."""
    c, vc, ac = _point_motion(F, A.body, A.centre)
    p, vp, ap = _point_motion(F, B.body, B.centre)
    u = c - p
    ju = np.stack([-u[:, 1], u[:, 0]], axis=-1)
    wa, wb = F["omega"][:, A.body], F["omega"][:, B.body]
    aa, ab = F["alpha"][:, A.body], F["alpha"][:, B.body]
    rho = A.radius
    V = np.hypot(*(vc - vp - wb[:, None] * ju).T) + np.abs(wa - wb) * rho
    W = (np.hypot(*(ac - ap - ab[:, None] * ju).T) + (np.abs(aa - ab) + wa * wa) * rho
         + 2.0 * np.abs(wb) * (np.hypot(*(vc - vp).T) + np.abs(wa) * rho) + wb * wb * (np.hypot(*u.T) + rho))
    return V, W


def _distances(F, A: Item, B: Item, need):
    """(n,) distances of the two regions at the poses of ``F``: exact where ``need`` (n,) bool, else the bounding
    circles' distance (a lower bound)."""
    import shapely
    ca = _world(F, A.body, A.centre[None])[:, 0]
    cb = _world(F, B.body, B.centre[None])[:, 0]
    d = np.hypot(*(ca - cb).T) - A.radius - B.radius
    idx = np.nonzero(need)[0]
    if idx.size:
        sub = {k: v[idx] for k, v in F.items()}
        pa = shapely.polygons(_world(sub, A.body, A.ring))
        pb = shapely.polygons(_world(sub, B.body, B.ring))
        d = d.copy()
        d[idx] = shapely.distance(pa, pb)
    return d


def _interval_gaps(d, V, W, dt, closed):
    """(n,) the certified least gap on each interval i → i+1 (the last wraps when ``closed``; else +inf)."""
    dn, Vn, Wn = np.roll(d, -1), np.roll(V, -1), np.roll(W, -1)
    Wm = np.maximum(W, Wn)
    left = d - 0.5 * dt * V - 0.125 * dt * dt * Wm
    right = dn - 0.5 * dt * Vn - 0.125 * dt * dt * Wm
    g = np.minimum(left, right)
    if not closed:
        g[-1] = np.inf
    return g


def frame_arrays(frames) -> dict:
    """The pose arrays of :class:`~assur.parts.motion.BodyFrames` as a dict of (n, …) arrays."""
    return {k: getattr(frames, k) for k in ("origin", "vel", "acc", "angle", "omega", "alpha")}


def _certify(frames, A, B, lo, hi, dt, clearance, rounds):
    """(certified least gap, (least sampled distance, its run value)) on the interval of the run between the
    full inputs ``lo`` and ``hi`` (``dt`` long in time), solved at REFINE_SPLIT steps inside it and refined again
    where needed."""
    from .motion import _poses
    f = np.linspace(0.0, 1.0, REFINE_SPLIT + 1)[:, None]
    inputs = lo + f * (hi - lo)
    origin, vel, acc, angle, omega, alpha = _poses(frames.plan, frames.solve(inputs), frames.ref)
    F = dict(origin=origin, vel=vel, acc=acc, angle=angle, omega=omega, alpha=alpha)
    d = _distances(F, A, B, np.ones(len(inputs), bool))
    V, W = _speed_bounds(F, A, B)
    h = dt / REFINE_SPLIT
    g = _interval_gaps(d, V, W, np.full(len(inputs), h), closed=False)[:-1]
    k = int(np.argmin(d))
    best = (float(d[k]), float(inputs[k, frames.moving]))
    if best[0] < clearance:
        return best[0], best
    worst = np.inf
    for j in range(REFINE_SPLIT):
        if g[j] >= clearance or rounds <= 1:
            worst = min(worst, float(g[j]))
            continue
        gj, bj = _certify(frames, A, B, inputs[j], inputs[j + 1], h, clearance, rounds - 1)
        worst = min(worst, gj)
        best = min(best, bj)
        if bj[0] < clearance:
            break
    return worst, best


def pair_verdict(cycle, frames, F, A: Item, B: Item, clearance: float, keep_curve: bool = True) -> PairVerdict:
    """The certified verdict on the pair (A, B) over the run of ``frames`` (the pose arrays ``F``)."""
    n = frames.n
    if A.body == B.body:                      # fixed to each other: one distance
        import shapely
        d = float(shapely.distance(shapely.Polygon(A.ring), shapely.Polygon(B.ring)))
        return PairVerdict(A.name, B.name, d < clearance, d, d, float(frames.q[0]), 0,
                           np.full(n, d) if keep_curve else None)
    V, W = _speed_bounds(F, A, B)
    dt = frames.dt
    reach = 0.5 * dt * np.maximum(V, np.roll(V, 1)) + 0.125 * dt * dt * np.maximum(W, np.roll(W, -1))
    reach = np.maximum(reach, np.roll(reach, 1))
    circle = _distances(F, A, B, np.zeros(n, bool))
    need = circle < clearance + 2.0 * reach + 1e-12
    d = _distances(F, A, B, need)
    k = int(np.argmin(d))
    sampled, at = float(d[k]), float(frames.q[k])
    if sampled < clearance:
        return PairVerdict(A.name, B.name, True, sampled, sampled, at, 0, d if keep_curve else None)
    g = _interval_gaps(d, V, W, dt, frames.closed)
    bad = np.nonzero(g < clearance)[0]
    worst = float(g.min())
    refined = 0
    if bad.size:
        gaps = []
        for i in bad:
            lo, hi = frames.inputs_between(int(i), [0.0, 1.0])
            gi, (di, qi) = _certify(frames, A, B, lo, hi, float(dt[i]), clearance, REFINE_ROUNDS)
            gaps.append(gi)
            refined += 1
            if di < sampled:
                sampled, at = di, qi
        good = g[g >= clearance]
        worst = min(min(gaps), float(good.min()) if good.size else np.inf)
    conflict = worst < clearance or sampled < clearance
    return PairVerdict(A.name, B.name, conflict, min(worst, sampled), sampled, at, refined,
                       d if keep_curve else None)


@dataclass(eq=False)
class Conflicts:
    """The verdicts on every pair that could meet in a layer: two layered parts (``parts``), a pin and a layered
    part it does not go through (``pins``: the part may not sit in a layer the pin crosses) and two pins
    (``pin_pairs``: what they carry may not share a gap). ``clearance`` (m)."""
    clearance: float
    parts: list = field(default_factory=list)
    pins: list = field(default_factory=list)
    pin_pairs: list = field(default_factory=list)

    def all(self):
        return self.parts + self.pins + self.pin_pairs

    def edges(self, which: str = "parts") -> list[tuple[str, str]]:
        """The conflicting pairs (a, b) of ``which`` ("parts", "pins" or "pin_pairs")."""
        return [(v.a, v.b) for v in getattr(self, which) if v.conflict]

    def verdict(self, a: str, b: str) -> PairVerdict | None:
        for v in self.all():
            if {v.a, v.b} == {a, b}:
                return v
        return None


def find_conflicts(cycle, frames, design, clearance: float) -> Conflicts:
    """The certified verdicts over the run (``frames`` of ``cycle``) on the pairs of ``design``'s layered parts
    and pins (:class:`~assur.parts.footprints.Design`) at ``clearance`` (m). Pairs that touch by design (a gear
    and its mate, a block and its guide; a pin and the parts it goes through) are not checked."""
    F = frame_arrays(frames)
    stack = items_of(design.stack)
    pins = items_of([p.part for p in design.pins])
    designed = {frozenset(pair) for pair in design.same_layer}
    out = Conflicts(clearance)
    for i, A in enumerate(stack):
        for B in stack[i + 1:]:
            if frozenset((A.name, B.name)) in designed:
                continue
            out.parts.append(pair_verdict(cycle, frames, F, A, B, clearance))
    for spec, P in zip(design.pins, pins):
        for B in stack:
            if B.name in spec.through:
                continue
            out.pins.append(pair_verdict(cycle, frames, F, P, B, clearance))
    for i, P in enumerate(pins):
        for Q in pins[i + 1:]:
            out.pin_pairs.append(pair_verdict(cycle, frames, F, P, Q, clearance))
    return out


__all__ = ["Conflicts", "Item", "PairVerdict", "find_conflicts", "frame_arrays", "items_of", "pair_verdict"]
