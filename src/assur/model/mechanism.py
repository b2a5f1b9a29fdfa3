"""Frozen dataclasses describing a mechanism. All numbers are SI (m, rad, rad/s, m/s).

A mechanism is a set of named points with sketch (reference) coordinates, rigid links listing
their points, prismatic pairs, linear actuators, drivers, optional branch hints and an optional
gait block (the foot point of a walking leg). The sketch fixes each group's assembly branch;
explicit dimensions (``Link.length``, ``Link.place``) override the sketch's distances.
Changes make new objects (``dataclasses.replace``); nothing here holds solved positions.
"""
from __future__ import annotations

from dataclasses import dataclass, field

from .dynamics import Dynamics
from .camming import CamPair
from .gearing import GearPair
from .motor import Motor
from .making import MakeSpec

FRAME = "frame"


@dataclass(frozen=True, slots=True)
class Units:
    """Units the file was written in; numbers are converted to SI at load and back at dump."""
    length: str = "m"
    angle: str = "deg"


@dataclass(frozen=True, slots=True)
class Placement:
    """A point of a link placed in polar form: ``from + distance·rot(angle)·unit(toward − from)``.

    ``angle`` (rad) is counter-clockwise from the direction from → toward.
    """
    origin: str
    toward: str
    distance: float
    angle: float


@dataclass(frozen=True, slots=True)
class Link:
    """A rigid link through ``points`` (binary, ternary, …).

    Its own frame has the first point at the origin and the second on the +x axis.
    ``length`` overrides the sketch distance of the first two points; ``place`` overrides the
    sketch position of further points (``(point, Placement)`` pairs).
    """
    name: str
    points: tuple[str, ...]
    length: float | None = None
    place: tuple[tuple[str, Placement], ...] = ()

    def placement(self, point: str) -> Placement | None:
        for name, p in self.place:
            if name == point:
                return p
        return None


@dataclass(frozen=True, slots=True)
class Prismatic:
    """A prismatic pair.

    With ``point`` set: a pin-in-slot: the point (a revolute of its links) rides on a slider block
    that slides along a line of ``guide`` (one implicit block body, one R and one P pair).
    With ``link`` set: that link translates along the line of ``guide`` (one P pair); the
    link's first point stays on the line.
    The line passes through ``through`` (a point of ``guide``) shifted by ``offset`` to its left,
    with direction ``angle``: absolute on the frame, relative to the guide link's first → second
    point direction on a moving link.
    """
    name: str
    guide: str
    through: str
    angle: float
    offset: float = 0.0
    point: str | None = None
    link: str | None = None


@dataclass(frozen=True, slots=True)
class Actuator:
    """A linear actuator (cylinder + rod with a prismatic pair) between two points.

    The cylinder is hinged at ``between[0]``, the rod at ``between[1]``; its length is the
    distance between them. Driven by a :class:`LinearDriver`, the length is an input; otherwise
    it follows the mechanism (an RPR group).
    """
    name: str
    between: tuple[str, str]


@dataclass(frozen=True, slots=True)
class RotaryDriver:
    """A crank: ``link`` turns about ``pivot`` (a frame point); the input angle q gives the
    direction pivot → arm as ``zero + sense·q`` (absolute, counter-clockwise positive)."""
    name: str
    link: str
    pivot: str
    arm: str
    zero: float = 0.0
    sense: int = 1
    speed: float = 1.0  # rad/s
    kind: str = field(default="rotary", init=False)


@dataclass(frozen=True, slots=True)
class LinearDriver:
    """A driven actuator: the input q is its length (m); ``speed`` is dq/dt (m/s).

    ``range`` (m, optional): the actuator length from start to stop of a working stroke, the run
    that analyses, plots and reports use by default. ``law`` (optional): a programmed motion.
    """
    name: str
    actuator: str
    speed: float = 0.0
    range: tuple[float, float] | None = None
    law: "TimeTable | None" = None
    kind: str = field(default="linear", init=False)


@dataclass(frozen=True, slots=True)
class TimeTable:
    """A driver's input as a table of times (s, strictly increasing) and values (m), interpolated
    by ``interpolation``: 'cubic' (a C² cubic spline: continuous acceleration) or 'pchip' (monotone
    between the table values, C¹)."""
    times: tuple[float, ...]
    values: tuple[float, ...]
    interpolation: str = "cubic"


@dataclass(frozen=True, slots=True)
class BranchHint:
    """The solved ``point`` lies on ``side`` ('left' | 'right') of the directed line of[0] → of[1]
    in the sketch position; it overrides the branch the sketch would give.

    ``slide`` ('ahead' | 'behind') with ``on`` (a prismatic pair's or an actuator's name): the branch of the RPR
    group whose slider is hinged at ``point`` and slides on ``on``: ``point`` lies ahead of (or behind) the guide's
    hinge along the slide's direction (an actuator's: from its cylinder's hinge towards its rod's, as drawn). It is
    the one hint of an RPR group whose bodies carry no point but their hinges, where the sketch cannot show the
    branch. A hint gives ``side`` and ``of``, ``slide`` and ``on``, or both pairs (one point may be solved by a dyad
    and be the slider hinge of an RPR group)."""
    point: str
    side: str | None = None
    of: tuple[str, str] | None = None
    slide: str | None = None
    on: str | None = None


@dataclass(frozen=True, slots=True)
class Joint:
    """A joint at a point of a spatial description (kind: spherical, cylindrical, universal,
    revolute). ``axis`` (a unit vector, sketch position) is the axis of a revolute, or the
    crank-side (pin) axis of a universal joint."""
    point: str
    kind: str
    axis: tuple[float, float, float] | None = None


@dataclass(frozen=True, slots=True)
class Gait:
    """The foot of a walking leg. ``ground`` is the stride direction, ``up`` points away from the
    ground side (default: ``ground`` turned 90° counter-clockwise). ``phases`` (rad) are the
    crank phase offsets of the legs of a walking module (one leg: ``(0,)``)."""
    foot: str
    ground: tuple[float, float] = (1.0, 0.0)
    up: tuple[float, float] | None = None
    phases: tuple[float, ...] = (0.0,)
    #: the body weight (N) carried by the feet on the ground, shared equally; None: no foot load
    weight: float | None = None
    #: the ground's friction coefficient: a horizontal reaction up to μ·N against the foot's slip
    friction: float | None = None

    @property
    def up_vector(self) -> tuple[float, float]:
        if self.up is not None:
            return self.up
        return (-self.ground[1], self.ground[0])


@dataclass(frozen=True, slots=True)
class Mechanism:
    name: str
    points: tuple[tuple[str, tuple[float, ...]], ...]
    links: tuple[Link, ...]
    prismatic: tuple[Prismatic, ...] = ()
    actuators: tuple[Actuator, ...] = ()
    drivers: tuple[RotaryDriver | LinearDriver, ...] = ()
    branches: tuple[BranchHint, ...] = ()
    joints: tuple[Joint, ...] = ()
    gait: Gait | None = None
    #: mass properties, loads, friction and gravity for the force analysis (None: none given)
    dynamics: "Dynamics | None" = None
    #: gear pairs (higher pairs, p4) between links turning about frame pivots
    gears: tuple[GearPair, ...] = ()
    #: cam pairs (higher pairs, p4): a cam turning about a frame pivot driving a translating or oscillating follower
    cams: tuple[CamPair, ...] = ()
    description: str = ""
    units: Units = Units()
    dimension: int = 2
    format: str = "assur/1"
    #: the motor of a driver for forward dynamics (``[motor]``; None: none given)
    motor: Motor | None = None
    #: the ``[make]`` table: how ``assur make`` builds the parts (None: the file has none)
    make: "MakeSpec | None" = None

    # -- look-ups -------------------------------------------------------------------------------
    @property
    def point_names(self) -> tuple[str, ...]:
        return tuple(n for n, _ in self.points)

    def sketch(self, point: str) -> tuple[float, ...]:
        for n, xy in self.points:
            if n == point:
                return xy
        raise KeyError(point)

    def bodies_at(self, point: str) -> tuple[tuple[str, ...], tuple[str, ...]]:
        """(bodies, sliders) at ``point``: see :func:`bodies_at`."""
        return bodies_at(point, self.links, self.prismatic, self.actuators)

    def load_body(self, point: str, link: str | None = None) -> str:
        """The body a force at ``point`` (of ``link``, if given) acts on: :func:`assur.model.dynamics.load_body`."""
        from .dynamics import load_body
        return load_body(point, link, *self.bodies_at(point))

    def link(self, name: str) -> Link:
        for lk in self.links:
            if lk.name == name:
                return lk
        raise KeyError(name)

    @property
    def frame(self) -> Link:
        return self.link(FRAME)

    def _repr_html_(self) -> str:
        """A small table for notebooks (SI numbers: m, rad/s)."""
        from .display import fmt, html_table
        rows = [("name", self.name or "(unnamed)"), ("dimension", self.dimension),
                ("file units", f"{self.units.length}, {self.units.angle}"),
                ("points (m)", "; ".join(f"{n} ({fmt(tuple(xy))})" for n, xy in self.points)),
                ("links", "; ".join(f"{lk.name}: {', '.join(lk.points)}" for lk in self.links))]
        if self.prismatic:
            rows.append(("prismatic", "; ".join(f"{p.name}: {p.point or p.link} on {p.guide}" for p in self.prismatic)))
        if self.actuators:
            rows.append(("actuators", "; ".join(f"{a.name}: {a.between[0]}–{a.between[1]}" for a in self.actuators)))
        for d in self.drivers:
            what = (f"crank {d.link} about {d.pivot}, {fmt(d.speed)} rad/s" if d.kind == "rotary"
                    else f"actuator {d.actuator}, {fmt(d.speed)} m/s")
            rows.append((f"driver {d.name}", what))
        for gp in self.gears:
            rows.append((f"gear pair {gp.name}", f"{gp.a} → {gp.b} ({gp.mesh}, mean ratio {fmt(gp.law.mean_ratio)})"))
        for cp in self.cams:
            rows.append((f"cam pair {cp.name}", f"{cp.cam} → {cp.follower} ({cp.motion} {cp.contact} follower)"))
        if self.gait is not None:
            rows.append(("gait foot", self.gait.foot))
        return html_table(f"Mechanism {self.name}".rstrip(), rows)

    @property
    def length_scale(self) -> float:
        """Size of the sketch's bounding box (m), the scale of relative tolerances."""
        import numpy as np
        xy = np.array([c for _, c in self.points], dtype=float)
        span = float(np.max(np.ptp(xy, axis=0))) if len(xy) else 0.0
        return span if span > 0 else 1.0


def bodies_at(point: str, links, prismatic, actuators) -> tuple[tuple[str, ...], tuple[str, ...]]:
    """The bodies that carry ``point`` and, among them, the sliders, named as the force analysis names bodies:
    links (the frame too), a pin-in-slot's block ``"<pair>.block"``, an actuator's ``"<name>.cylinder"`` (at its
    first point) and ``"<name>.rod"`` (at its second). Sliders: the blocks at the point and the links that
    translate on a guide (``[[prismatic]] link``). ``links``, ``prismatic``, ``actuators``: the description's
    elements (or those read so far)."""
    bodies = [lk.name for lk in links if point in lk.points]
    sliders = [pr.link for pr in prismatic if pr.link is not None and pr.link in bodies]
    for pr in prismatic:
        if pr.point == point:
            bodies.append(f"{pr.name}.block")
            sliders.append(f"{pr.name}.block")
    for ac in actuators:
        if ac.between[0] == point:
            bodies.append(f"{ac.name}.cylinder")
        if ac.between[1] == point:
            bodies.append(f"{ac.name}.rod")
    return tuple(bodies), tuple(dict.fromkeys(sliders))


def require_mechanism(m, what: str = "mechanism"):
    """``m`` when it is a :class:`Mechanism`, else ArgumentTypeError naming the argument ``what``."""
    if isinstance(m, Mechanism):
        return m
    from ..errors import ArgumentTypeError
    hint = ": read it first, assur.load(path)" if isinstance(m, str) or hasattr(m, "__fspath__") else ""
    raise ArgumentTypeError([(what, f"must be a Mechanism (assur.load, assur.loads or assur.Builder), not "
                                    f"{type(m).__name__}{hint}")])
