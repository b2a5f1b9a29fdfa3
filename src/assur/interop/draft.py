"""A mechanism as another tool describes it, on its way to an ``assur/1`` description.

Every importer fills a :class:`Draft` with what its format says — points in the source's own initial (assembled)
positions and ids, rigid links, the ground, pins in slots, cranks — and :meth:`Draft.build` turns it into a
:class:`~assur.model.mechanism.Mechanism` through :class:`~assur.io.builder.Builder` (so it is checked exactly like
a file). The sketch *is* the source's initial position, so the imported mechanism starts on the same assembly;
:meth:`Draft.build` also writes a ``[branches]`` hint for every dyad from that position, which keeps the assembly
explicit when the file is edited later.

Names: assur names hold letters, digits, ``_`` and ``'`` and start with a letter or ``_``. A source id that is not
such a name is renamed (spaces and dots become ``_``) and the rename is reported as an :class:`InteropWarning`;
nothing is dropped silently.
"""
from __future__ import annotations

import math
import re
import warnings
from dataclasses import dataclass, field

from ..errors import SpecError
from ..io import units as U
from ..io.builder import Builder
from ..model.mechanism import FRAME, Mechanism

#: an assur name (points, links, drivers)
NAME_RE = re.compile(r"^[A-Za-z_][A-Za-z0-9_']*$")
#: the most points, links or joints an imported document may hold (a larger one is not a mechanism drawing)
MAX_ELEMENTS = 2000
#: a coordinate, length or speed of an imported document must be finite and below this in magnitude (file units)
MAX_MAGNITUDE = 1e9


class InteropWarning(UserWarning):
    """Something of the source that the imported (or exported) description does not carry: the message names it."""


def finite(value, where: str, what: str = "a number") -> float:
    """``value`` as a finite float below :data:`MAX_MAGNITUDE`; SpecError at ``where`` otherwise."""
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        raise SpecError([(where, f"must be {what}: {value!r}")])
    v = float(value)
    if not math.isfinite(v) or abs(v) >= MAX_MAGNITUDE:
        raise SpecError([(where, f"must be a finite number below {MAX_MAGNITUDE:g} in magnitude: {value!r}")])
    return v


def count_limit(items, where: str, what: str) -> None:
    """SpecError at ``where`` when a document lists more than :data:`MAX_ELEMENTS` ``what``."""
    if len(items) > MAX_ELEMENTS:
        raise SpecError([(where, f"lists {len(items)} {what}; at most {MAX_ELEMENTS} are read")])


def safe_name(text, taken: set, what: str, warn) -> str:
    """An assur name for the source id ``text``, not in ``taken`` (which it joins); ``warn`` reports a rename."""
    raw = str(text)
    name = re.sub(r"[^A-Za-z0-9_']", "_", raw.strip()) or "_"
    if not re.match(r"[A-Za-z_]", name):
        name = "_" + name
    if what == "link" and name == FRAME:
        name = "frame_"
    base, k = name, 2
    while name in taken:
        name = f"{base}_{k}"
        k += 1
    taken.add(name)
    if name != raw:
        warn(f"{what} {raw!r} is named {name!r} (assur names hold letters, digits, _ and ')")
    return name


@dataclass
class Slot:
    """A prismatic pair of the source: the pin ``point`` in a slot of ``guide`` (a link id or None for the frame),
    or the whole ``link`` translating along it. The slot's line passes through ``at`` (sketch, file length unit)
    with the absolute direction ``angle`` (rad) in the sketch; for ``link`` the line must pass through the
    link's first point."""
    angle: float
    at: tuple[float, float]
    point: str | None = None
    link: str | None = None
    guide: str | None = None
    name: str | None = None


@dataclass
class Crank:
    """A crank of the source: ``link`` turns about the ground point ``pivot``; ``arm`` another point of the link;
    ``speed`` rad/s, negative clockwise (None: assur's default)."""
    link: str
    pivot: str
    arm: str
    speed: float | None = None
    name: str | None = None
    #: the crank's absolute direction (rad) at input 0; the input is measured from it
    zero: float = 0.0


@dataclass
class Draft:
    """The source's mechanism in its own ids and units (see the module docstring); ``source`` names the format in
    messages ("pylinkage JSON", "PMKS+ link", …)."""
    source: str
    length_unit: str = "m"
    angle_unit: str = "deg"
    name: str = ""
    description: str = ""
    points: dict = field(default_factory=dict)       # id -> (x, y), file length unit
    links: dict = field(default_factory=dict)        # id -> [point ids]; the frame is ``ground``
    ground: list = field(default_factory=list)       # point ids fixed to the frame
    slots: list = field(default_factory=list)
    cranks: list = field(default_factory=list)
    labels: dict = field(default_factory=dict)       # id -> preferred name (a point's or link's display name)
    messages: list = field(default_factory=list)

    # -- filling -------------------------------------------------------------------------------------------
    def warn(self, message: str) -> None:
        """Report something the description will not carry (issued as an InteropWarning by :meth:`build`)."""
        if message not in self.messages:
            self.messages.append(message)

    def point(self, pid: str, x, y, where: str, label: str | None = None) -> None:
        """A point at (x, y) in the file's length unit; ``where`` locates it in the source for messages."""
        if pid in self.points:
            raise SpecError([(where, f"the id {pid!r} is defined twice")])
        self.points[pid] = (finite(x, f"{where}.x"), finite(y, f"{where}.y"))
        if label:
            self.labels[("p", pid)] = label
        count_limit(self.points, where, "points")

    def link(self, lid: str, points, where: str, label: str | None = None) -> None:
        """A rigid link through ``points`` (ids); the first two fix its frame."""
        pts = []
        for i, p in enumerate(points):
            if p not in self.points:
                raise SpecError([(f"{where}[{i}]", f"unknown point {p!r}")])
            if p not in pts:
                pts.append(p)
        if lid in self.links:
            raise SpecError([(where, f"the link id {lid!r} is defined twice")])
        self.links[lid] = pts
        if label:
            self.labels[("l", lid)] = label
        count_limit(self.links, where, "links")

    def fix(self, pid: str) -> None:
        """Put the point ``pid`` on the frame."""
        if pid not in self.ground:
            self.ground.append(pid)

    # -- building -------------------------------------------------------------------------------------------
    def names(self):
        taken_p, taken_l = set(), set()
        pname = {pid: safe_name(self.labels.get(("p", pid), pid), taken_p, "point", self.warn) for pid in self.points}
        lname = {lid: safe_name(self.labels.get(("l", lid), lid), taken_l, "link", self.warn) for lid in self.links}
        return pname, lname

    def builder(self, hints=()) -> tuple[Builder, dict, dict]:
        """The Builder of the description (with the branch ``hints`` (point, side, of)), and the point and link
        name maps (source id → assur name)."""
        if not self.points:
            raise SpecError([("", f"the {self.source} holds no points")])
        if not self.ground:
            raise SpecError([("", f"the {self.source} has no point fixed to the ground (no frame to build on)")])
        pname, lname = self.names()
        used = set(self.ground) | {s.point for s in self.slots if s.point is not None}
        for lid, pts in self.links.items():
            if len(pts) < 2:
                self.warn(f"link {lid!r} holds one point only ({pts[0] if pts else 'none'}): not a link, left out")
            else:
                used.update(pts)
        b = Builder(units=self.length_unit, angle=self.angle_unit, name=self.name, description=self.description)
        for pid, (x, y) in self.points.items():
            if pid in used:
                b.point(pname[pid], x, y)
            else:
                self.warn(f"point {pid!r} is on no link of the {self.source}: left out")
        b.frame(*[pname[p] for p in self.ground])
        for lid, pts in self.links.items():
            if len(pts) >= 2:
                b.link(lname[lid], *[pname[p] for p in pts])
        A = U.ANGLE[self.angle_unit]
        for k, s in enumerate(self.slots):
            self._slot(b, s, k, pname, lname, A)
        taken_d: set = set()
        for c in self.cranks:
            speed = None if c.speed is None else U.format_speed(abs(c.speed), "rotary")
            sense = "cw" if (c.speed or 0.0) < 0 else "ccw"
            name = safe_name(c.name, taken_d, "driver", self.warn) if c.name else None
            zero = c.zero / A
            b.crank(lname[c.link], pivot=pname[c.pivot], arm=pname[c.arm], speed=speed, zero=zero, sense=sense,
                    name=name)
        for point, side, of in hints:
            b.branch(point, side, of=of)
        return b, pname, lname

    def _slot(self, b: Builder, s: Slot, k: int, pname, lname, A) -> None:
        """A ``[[prismatic]]`` entry: the line through ``s.at`` at ``s.angle``, referred to a point of its guide."""
        where = f"slot {s.name or k}"
        if s.guide is None:
            guide, gpts = FRAME, [pname[p] for p in self.ground]
            base_angle = 0.0
            through = gpts[0]
            tx, ty = self.points[self.ground[0]]
        else:
            guide, pts = lname[s.guide], self.links[s.guide]
            if len(pts) < 2:
                raise SpecError([(where, f"the guide link {s.guide!r} needs two points to carry a slot")])
            (x0, y0), (x1, y1) = self.points[pts[0]], self.points[pts[1]]
            base_angle = math.atan2(y1 - y0, x1 - x0)
            through, (tx, ty) = pname[pts[0]], (x0, y0)
        dx, dy = math.cos(s.angle), math.sin(s.angle)
        offset = dx * (s.at[1] - ty) - dy * (s.at[0] - tx)
        rel = math.remainder(s.angle - base_angle, 2 * math.pi)
        name = None if s.name is None else safe_name(s.name, set(), "slot", lambda m: None)
        kw = {"point": pname[s.point]} if s.point is not None else {"link": lname[s.link]}
        b.slider(**kw, through=through, guide=guide, angle=rel / A, offset=offset, name=name)

    def build(self) -> Mechanism:
        """The Mechanism: built, compiled once to find each dyad's assembly in the sketch, and built again with a
        ``[branches]`` hint for each. Issues the collected messages as InteropWarnings. Raises SpecError (located
        in the description that would be written) or StructureError."""
        from ..engine import compile as compile_
        b, pname, _ = self.builder()
        m = _built(b, self.source)
        plan = compile_(m)
        hints = []
        if m.dimension == 2:
            sketch = dict(m.points)
            scale = m.length_scale
            for st in plan.steps:
                if st.kind != "RRR":
                    continue
                (ax, ay), (bx, by), (zx, zy) = sketch[st.point_a], sketch[st.point_b], sketch[st.joint]
                cross = (bx - ax) * (zy - ay) - (by - ay) * (zx - ax)
                if abs(cross) > 1e-9 * scale * scale:
                    hints.append((st.joint, "left" if cross > 0 else "right", (st.point_a, st.point_b)))
        if hints:
            b, _, _ = self.builder(hints)
            m = _built(b, self.source)
            compile_(m)
        for message in self.messages:
            warnings.warn(f"{self.source}: {message}", InteropWarning, stacklevel=3)
        return m


def _built(b: Builder, source: str) -> Mechanism:
    """``b.build()`` with the problems named as problems of the imported description."""
    try:
        return b.build()
    except SpecError as exc:
        raise SpecError(exc.problems, f"imported {source}") from None


__all__ = ["Crank", "Draft", "InteropWarning", "MAX_ELEMENTS", "NAME_RE", "Slot", "count_limit", "finite", "safe_name"]
