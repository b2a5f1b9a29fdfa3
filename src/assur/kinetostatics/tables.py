"""The force tables of a planar plan: bodies, pairs, unknowns and groups, built once per plan.

The reaction at a pair is the force (and, at a prismatic pair, the couple) that the pair's
*earlier* body exerts on its *later* body, where earlier means solved earlier by the plan (the
frame first). A revolute joining k bodies at one point is k − 1 pairs, each from the earliest
body at the point to one other. Unknowns per pair (the columns of the equations)::

    revolute at P        Rx, Ry          the force, acting at P
    prismatic (line u)   N, M            the force N·n (n = u turned 90° ccw) at the slider's
                                         reference point Q, and the couple M
    driven actuator      N, M, F         … and the actuator's force F·u (u from cylinder to rod)
    crank                T               the motor's torque on the crank (ccw positive)
    gear-driven link     T               the gear pair's torque on its driven link (ccw positive), later
                                         replaced by the tooth force (:mod:`.gearing`)
    cam-driven rocker    T               the cam's torque on an oscillating follower, later replaced by the
                                         contact force (:mod:`.camming`)
    cam-driven slider    N, M, F         a translating follower's slide, F the cam's drive along it (later
                                         replaced by the contact force)

Each pair belongs to the group (plan step) that solves its later body; the groups are solved
from the last back to the drivers, each from its own bodies' equilibrium.
"""
from __future__ import annotations

import weakref
from dataclasses import dataclass

import numpy as np

from ..engine.plan import PlanarPlan
from ..model.dynamics import Dynamics, MassProperties
from ..model.mechanism import FRAME


@dataclass(frozen=True, slots=True)
class ForcePair:
    """One pair of the force analysis.

    ``kind``: 'R' (revolute at ``point``), 'P' (prismatic; ``line`` indexes ``plan.lines``) or 'T'
    (a crank's motor torque, from the frame, ``point`` its pivot). ``earlier``, ``later``: body
    indices. ``columns``: the unknowns' indices. ``driven``: a driven actuator's slide (input index)
    or -1. ``name``: the joint point, the prismatic pair or actuator, or the driver.
    """
    kind: str
    earlier: int
    later: int
    columns: tuple[int, ...]
    point: int = -1
    line: int = -1
    driven: int = -1
    name: str = ""


@dataclass(frozen=True, slots=True)
class BodyMass:
    """Mass properties of a body as recipes on its points.

    com = Σ weights[k]·P[points[k]] + e^{iθ}·offset (offset complex, in the body frame). ``inertia``
    about the com (kg·m²), or None: the default ``default`` ('bar': m·|P1 − P0|²/12; 'polygon':
    Σ m/k·|P_k − com|²; 'zero').
    """
    mass: float
    points: tuple[int, ...]
    weights: tuple[float, ...]
    offset: complex
    inertia: float | None
    default: str


@dataclass(frozen=True, slots=True)
class BodyAngle:
    """How a body's orientation follows from the points: 'frame' (θ = 0), 'points' (arg(P[b] − P[a])
    + offset), 'line' (the guide body's θ + the line's angle parameter + offset) or 'still'."""
    how: str
    a: int = -1
    b: int = -1
    guide: int = -1
    angle_param: int = -1
    offset: float = 0.0


@dataclass(frozen=True)
class ForceTables:
    """Everything the force solver needs that does not change with the design or the input."""
    plan: PlanarPlan
    dynamics: Dynamics
    pairs: tuple[ForcePair, ...]
    n_unknowns: int
    #: per group (solve order): (step index, group bodies, pair indices whose later body is in the group)
    groups: tuple[tuple[int, tuple[int, ...], tuple[int, ...]], ...]
    masses: tuple[BodyMass | None, ...]
    angles: tuple[BodyAngle, ...]
    #: per body: the body of the solve order that places it (its index in the order)
    order: tuple[int, ...]
    #: per input: the driver's pair index (a crank's 'T' pair or a driven actuator's 'P' pair)
    driver_pairs: tuple[int, ...]
    #: per gear slot of the plan: the 'T' pair of the gear's torque on its driven link
    gear_pairs: tuple[int, ...] = ()
    #: per cam slot of the plan: the 'T' pair of an oscillating follower or the 'P' pair of a translating one
    cam_pairs: tuple[int, ...] = ()

    @property
    def n_bodies(self) -> int:
        return self.plan.n_bodies


_CACHE: "weakref.WeakKeyDictionary" = weakref.WeakKeyDictionary()


def force_tables(plan: PlanarPlan) -> ForceTables:
    """The force tables of ``plan``, built on first use and kept for the plan's lifetime."""
    t = _CACHE.get(plan)
    if t is None:
        t = _build(plan)
        _CACHE[plan] = t
    return t


def _build(plan: PlanarPlan) -> ForceTables:
    m = plan.mechanism
    g = plan.structure.graph
    dyn = m.dynamics or Dynamics()
    nb = plan.n_bodies
    # the solve order of bodies: the frame, then every step's bodies
    order_list = [0]
    step_of_body = {0: 0}
    for i, st in enumerate(plan.steps):
        for b in st.bodies:
            if b not in step_of_body:
                step_of_body[b] = i
                order_list.append(b)
    for b in range(nb):          # bodies a step solves implicitly (an actuator's rod with its cylinder)
        if b not in step_of_body:
            for p in g.pairs:
                if p.kind == "P" and b in p.bodies:
                    other = p.bodies[0] if p.bodies[1] == b else p.bodies[1]
                    if other in step_of_body:
                        step_of_body[b] = step_of_body[other]
                        order_list.append(b)
                        break
    rank = {b: k for k, b in enumerate(order_list)}
    pidx = {n: i for i, n in enumerate(plan.point_names)}
    pairs: list[ForcePair] = []
    col = 0

    def add(kind, i, j, n_cols, **kw):
        nonlocal col
        pairs.append(ForcePair(kind, i, j, tuple(range(col, col + n_cols)), **kw))
        col += n_cols

    for point, at in g.joints:
        if len(at) < 2:
            continue
        ranked = sorted(at, key=lambda b: rank[b])
        for other in ranked[1:]:
            add("R", ranked[0], other, 2, point=pidx[point], name=point)
    driven = {d.actuator: k for k, d in enumerate(m.drivers) if d.kind == "linear"}
    line_of = {rec[1]: i for i, rec in enumerate(plan.lines)}
    # a translating cam follower's slide carries the cam's drive as a third unknown, like a driven actuator's (its
    # 'driven' index past the inputs: no input of its own)
    cam_slides = {plan.lines[st.line][1]: plan.n_inputs + j
                  for j, st in enumerate(s for s in plan.steps if s.kind in ("cam", "cam_slide")) if st.kind == "cam_slide"}
    cam_pair_of: dict[str, int] = {}
    for p in g.pairs:
        if p.kind != "P":
            continue
        i, j = sorted(p.bodies, key=lambda b: rank[b])
        k = driven.get(p.name, -1) if p.driven else cam_slides.get(p.name, -1)
        add("P", i, j, 3 if k >= 0 else 2, line=line_of[p.name], driven=k, name=p.name)
        if p.name in cam_slides:
            cam_pair_of[p.name] = len(pairs) - 1
    driver_pairs = []
    for k, d in enumerate(m.drivers):
        if d.kind == "rotary":
            add("T", 0, g.index(d.link), 1, point=pidx[d.pivot], name=d.name)
            driver_pairs.append(len(pairs) - 1)
        else:
            driver_pairs.append(next(i for i, fp in enumerate(pairs) if fp.kind == "P" and fp.driven == k))
    gear_pairs = []
    for st in plan.steps_of("gear"):
        add("T", 0, st.bodies[0], 1, point=pidx[st.pivot], name=m.gears[st.gear].name)
        gear_pairs.append(len(pairs) - 1)
    cam_pairs = []
    for st in plan.steps_of("cam", "cam_slide"):
        if st.kind == "cam":
            add("T", 0, st.bodies[0], 1, point=pidx[st.pivot], name=m.cams[st.cam].name)
            cam_pairs.append(len(pairs) - 1)
        else:
            cam_pairs.append(cam_pair_of[plan.lines[st.line][1]])
    groups = []
    for i, st in enumerate(plan.steps):
        if st.kind == "frame":
            continue
        bodies = tuple(b for b in order_list if step_of_body[b] == i)
        mine = tuple(k for k, fp in enumerate(pairs) if fp.later in bodies)
        groups.append((i, bodies, mine))
    masses = tuple(_mass(plan, b, dyn.mass_of(g.bodies[b].name), pidx) if b else None for b in range(nb))
    angles = tuple(_angle(plan, b, pidx) for b in range(nb))
    return ForceTables(plan, dyn, tuple(pairs), col, tuple(groups), masses, angles,
                       tuple(rank[b] for b in range(nb)), tuple(driver_pairs), tuple(gear_pairs), tuple(cam_pairs))


def _sketch(m, p) -> complex:
    xy = m.sketch(p)
    return complex(xy[0], xy[1])


def _mass(plan, b: int, mp: MassProperties, pidx) -> BodyMass | None:
    """The mass recipe of body ``b`` (None for a massless body)."""
    if mp.mass <= 0 and not mp.inertia:
        return None
    m = plan.mechanism
    body = plan.structure.graph.bodies[b]
    pts = body.points
    if body.kind in ("block", "cylinder", "rod"):
        ac = None if body.kind == "block" else next(a for a in m.actuators if a.name == body.source)
        if ac is None:
            return BodyMass(mp.mass, (pidx[pts[0]],), (1.0,), 0j, mp.inertia, "zero")
        dist = float(mp.com or 0.0)
        offset = dist if body.kind == "cylinder" else -dist
        return BodyMass(mp.mass, (pidx[pts[0]],), (1.0,), complex(offset), mp.inertia, "zero")
    default = "bar" if len(pts) == 2 else "polygon"
    com = mp.com
    if com is None:
        return BodyMass(mp.mass, tuple(pidx[p] for p in pts), (1.0 / len(pts),) * len(pts), 0j, mp.inertia, default)
    if com == "mid":
        return BodyMass(mp.mass, (pidx[pts[0]], pidx[pts[1]]), (0.5, 0.5), 0j, mp.inertia, default)
    if isinstance(com, str):
        return BodyMass(mp.mass, (pidx[com],), (1.0,), 0j, mp.inertia, default)
    # sketch coordinates fixed to the body: an offset from its first point in its own frame
    z0 = _sketch(m, pts[0])
    theta = _sketch_angle(plan, b)
    offset = (complex(com[0], com[1]) - z0) * complex(np.cos(-theta), np.sin(-theta))
    return BodyMass(mp.mass, (pidx[pts[0]],), (1.0,), offset, mp.inertia, default)


def _sketch_angle(plan, b: int) -> float:
    return float(plan.sketch_poses[b][2])


def _angle(plan, b: int, pidx) -> BodyAngle:
    """How body ``b``'s orientation follows from the solved points."""
    m, g = plan.mechanism, plan.structure.graph
    body = g.bodies[b]
    if body.kind == "frame":
        return BodyAngle("frame")
    if body.kind in ("cylinder", "rod"):
        ac = next(a for a in m.actuators if a.name == body.source)
        return BodyAngle("points", pidx[ac.between[0]], pidx[ac.between[1]])
    for rec in plan.lines:
        kind, name, gb, slider, through, ia, io, ref, u_slider = rec
        if kind == "prismatic" and slider == b and (body.kind == "block" or len(body.points) < 2):
            return BodyAngle("line", guide=gb, angle_param=ia, offset=-float(np.angle(u_slider)))
    if len(body.points) >= 2:
        return BodyAngle("points", pidx[body.points[0]], pidx[body.points[1]])
    return BodyAngle("still")


def body_index(plan, name: str) -> int:
    """The body named ``name`` (a link, ``pair.block``, ``actuator.cylinder`` …), or the frame."""
    if name == FRAME:
        return 0
    return plan.structure.graph.index(name)
