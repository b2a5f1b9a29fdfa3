"""Describe a mechanism in Python: :class:`Builder`, the mechanism file's tables as chained calls.

The builder writes the same document a mechanism file holds (``format = "assur/1"``, docs/format.md) and
reads it with the file reader, so a built mechanism is validated exactly like a file and its problems come
as one :class:`~assur.errors.SpecError` with the same locations (``links.coupler[2]: unknown point 'Q'``)::

    m = (assur.Builder(units="mm", name="four-bar")
         .point("O", 0, 0).point("C", 100, 0).point("A", 30, 0).point("B", 80, 90)
         .link("frame", "O", "C").link("crank", "O", "A", length=30).link("coupler", "A", "B")
         .link("rocker", "C", "B")
         .crank("crank", pivot="O", arm="A", speed="60 rpm")
         .build())

Numbers are in the builder's units (``units`` for lengths, ``angle`` for angles), as in a file.
"""
from __future__ import annotations

import copy

from ..errors import SpecError
from ..model.mechanism import FRAME, Mechanism
from .dynamics_file import MASS_KEYS
from .mechanism_file import FORMAT, from_dict

_SOURCE = "builder"


def _plain(v):
    """numpy scalars and tuples as the plain values a TOML document holds (other values pass unchanged and are
    checked by the reader)."""
    if hasattr(v, "item") and callable(v.item) and getattr(v, "shape", None) == ():
        return v.item()
    if isinstance(v, (tuple, list)):
        return [_plain(x) for x in v]
    if isinstance(v, dict):
        return {k: _plain(x) for k, x in v.items()}
    return v


def _given(**kw) -> dict:
    """The keyword arguments that are not None, as plain values (an omitted key takes the file's default)."""
    return {k: _plain(v) for k, v in kw.items() if v is not None}


class Builder:
    """A mechanism described by chained calls; :meth:`build` returns the frozen :class:`Mechanism`.

    ``units``: the length unit of every length and coordinate (m, mm, cm, dm, km, in, ft); ``angle``: of every
    angle (deg, rad); ``dimension``: 2 or 3 (default: 3 when a point has three coordinates, else 2).
    Each call adds one entry of the file's tables and returns the builder.
    """

    def __init__(self, units: str = "m", angle: str = "deg", *, name: str = "", description: str = "",
                 dimension: int | None = None):
        self._doc: dict = {"format": FORMAT, "units": {"length": units, "angle": angle}, "points": {},
                           "links": {}}
        if name:
            self._doc["name"] = name
        if description:
            self._doc["description"] = description
        self._dimension = dimension
        self._problems: list[tuple[str, str]] = []

    # -- the tables --------------------------------------------------------------------------------------
    def _put(self, table: str, key: str, value) -> "Builder":
        section = self._doc.setdefault(table, {})
        if not isinstance(key, str):            # a name that is not text: refused where it is given
            self._problems.append((f"{table}.{key!r:.40}", f"a name must be text: {key!r:.40}"))
            return self
        if key in section:
            self._problems.append((f"{table}.{key}", "is defined twice"))
        else:
            section[key] = value
        return self

    def _append(self, table: str, value: dict) -> "Builder":
        self._doc.setdefault(table, []).append(value)
        return self

    def point(self, name: str, x, y, z=None) -> "Builder":
        """A point with sketch coordinates (x, y) or (x, y, z); ``[points] name = [x, y]``."""
        return self._put("points", name, _plain([x, y] if z is None else [x, y, z]))

    def link(self, name: str, *points: str, length=None) -> "Builder":
        """A rigid link through ``points``; ``length`` overrides the sketch distance of its first two points."""
        spec = list(points) if length is None else {"points": list(points), "length": _plain(length)}
        return self._put("links", name, spec)

    def frame(self, *points: str) -> "Builder":
        """The ground link through ``points`` (fixed at their coordinates)."""
        return self.link(FRAME, *points)

    def place(self, link: str, point: str, *, distance, angle=0.0, origin: str | None = None,
              toward: str | None = None) -> "Builder":
        """Place a further point of ``link`` in polar form: ``origin + distance·rot(angle)·unit(toward − origin)``
        (``[links.LINK.place.POINT]``; ``origin``/``toward`` default to the link's first/second point)."""
        spec = self._doc["links"].get(link)
        where = f"links.{link}.place.{point}"
        if spec is None:
            self._problems.append((where, f"place a point after defining the link '{link}'"))
            return self
        if isinstance(spec, list):
            spec = self._doc["links"][link] = {"points": spec}
        table = spec.setdefault("place", {})
        if point in table:
            self._problems.append((where, "is defined twice"))
            return self
        table[point] = _given(**{"from": origin, "toward": toward, "distance": distance, "angle": angle})
        return self

    def crank(self, link: str, *, pivot: str, arm: str | None = None, speed=None, zero=None, sense: str | None = None,
              name: str | None = None) -> "Builder":
        """A rotary driver: ``link`` turns about the frame point ``pivot``; the input is the direction
        pivot → ``arm`` (``zero + q``, or ``zero − q`` with ``sense="cw"``); ``speed`` e.g. ``"60 rpm"``."""
        return self._append("drivers", {"kind": "rotary", **_given(name=name, link=link, pivot=pivot, arm=arm,
                                                                   zero=zero, sense=sense, speed=speed)})

    def slider(self, *, point: str | None = None, link: str | None = None, through: str, guide: str = FRAME,
               angle=None, offset=None, name: str | None = None) -> "Builder":
        """A prismatic pair (``[[prismatic]]``): the pin ``point`` in a slot of ``guide``, or the ``link``
        translating on it, along the line through ``through`` at ``angle``, shifted by ``offset``."""
        return self._append("prismatic", _given(name=name, point=point, link=link, guide=guide, through=through,
                                                angle=angle, offset=offset))

    def actuator(self, name: str, cylinder: str, rod: str) -> "Builder":
        """A linear actuator hinged at ``cylinder`` and ``rod`` (``[actuators.NAME] between = [A, B]``)."""
        return self._put("actuators", name, {"between": [cylinder, rod]})

    def linear(self, actuator: str, *, speed=None, range=None, law: dict | None = None,  # noqa: A002
               name: str | None = None) -> "Builder":
        """A linear driver: the input is the length of ``actuator``; ``range`` its working stroke; ``law`` a
        table ``{"time": [...], "length": [...], "interpolation": "cubic"}``."""
        return self._append("drivers", {"kind": "linear", **_given(name=name, actuator=actuator, speed=speed,
                                                                   range=range, law=law)})

    def cam(self, cam: str, follower: str, *, point: str, law, contact: str | None = None, roller_radius=None,
            face_angle=None, phase=None, rotation: str | None = None, pressure_limit=None,
            name: str | None = None) -> "Builder":
        """A cam pair (``[[cams]]``): ``cam`` (turning about a frame pivot) drives ``follower`` (translating on a frame
        slide, or oscillating about a frame pivot) through its trace ``point``; ``law`` a list of segments
        ``{"motion": "cycloidal", "angle": 120, "lift": 20}`` or a spline ``{"angle": [...], "lift": [...]}``."""
        return self._append("cams", _given(name=name, cam=cam, follower=follower, point=point, contact=contact,
                                           roller_radius=roller_radius, face_angle=face_angle, phase=phase,
                                           rotation=rotation, pressure_limit=pressure_limit, law=law))

    def branch(self, point: str, side: str | None = None, of: tuple[str, str] | None = None, *,
               slide: str | None = None, on: str | None = None) -> "Builder":
        """Assemble ``point`` on ``side`` ('left' | 'right') of the directed line of[0] → of[1], and/or, for the RPR
        group whose slider is hinged at ``point``, ``slide`` ('ahead' | 'behind') of its guide's hinge along the slide
        ``on`` (``[branches]``)."""
        spec = {} if side is None and of is None else {"side": side, "of": _plain(of)}
        if slide is not None or on is not None:
            spec |= {"slide": slide, "on": on}
        return self._put("branches", point, spec)

    def joint(self, point: str, kind: str, axis=None) -> "Builder":
        """The joint at ``point`` of a spatial mechanism (``[joints]``); ``axis`` a vector or
        ``{"gamma1": …, "gamma2": …}``."""
        return self._put("joints", point, kind if axis is None else {"kind": kind, "axis": _plain(axis)})

    def gait(self, foot: str, *, ground=None, up=None, phases=None, weight=None, friction=None) -> "Builder":
        """The foot of a walking leg (``[gait]``); ``weight`` the body weight the feet carry (N or "200 N"),
        ``friction`` the ground's friction coefficient."""
        if "gait" in self._doc:
            self._problems.append(("gait", "is defined twice"))
        else:
            self._doc["gait"] = _given(foot=foot, ground=ground, up=up, phases=phases, weight=weight,
                                       friction=friction)
        return self

    # -- forces --------------------------------------------------------------------------------------------
    def mass(self, body: str, mass, inertia=None, com=None) -> "Builder":
        """The mass properties of ``body``: a link (``[links.NAME]``), a slider block ``"<pair>.block"``
        (``[[prismatic]]``) or an actuator's ``"<name>.cylinder"`` / ``"<name>.rod"`` (``[actuators.NAME]``).
        ``mass`` kg or "500 g"; ``inertia`` kg·m² or "0.02 kg*m^2" about the centre of mass; ``com`` as in the
        file (a link: "mid", a point or (x, y); a cylinder or rod: a distance from its hinge)."""
        props = _given(mass=mass, inertia=inertia, com=com)
        head, _, part = body.rpartition(".")
        if part in ("cylinder", "rod") and head:
            where, spec = f"actuators.{head}.{part}", self._doc.get("actuators", {}).get(head)
            if spec is not None:
                if part in spec:
                    self._problems.append((where, "is defined twice"))
                else:
                    spec[part] = props
                return self
        elif part == "block" and head:
            where = f"prismatic ({body})"
            for i, spec in enumerate(self._doc.get("prismatic", [])):
                if spec.get("name", f"slide{i + 1}") == head:
                    return self._add_mass(spec, props, f"prismatic[{i}]")
        else:
            where, spec = f"links.{body}", self._doc["links"].get(body)
            if spec is not None:
                if isinstance(spec, list):
                    spec = self._doc["links"][body] = {"points": spec}
                return self._add_mass(spec, props, where)
        self._problems.append((where, f"give the mass of '{body}' after defining it (a link, '<pair>.block', "
                                      "'<actuator>.cylinder' or '<actuator>.rod')"))
        return self

    def _add_mass(self, spec: dict, props: dict, where: str) -> "Builder":
        if any(k in spec for k in MASS_KEYS):
            self._problems.append((f"{where}.mass", "is defined twice"))
        else:
            spec.update(props)
        return self

    def load(self, *, point: str | None = None, link: str | None = None, force=None, torque=None,
             opposes: str | None = None, law: dict | None = None) -> "Builder":
        """An external load (``[[loads]]``): a ``force`` (N, frame coordinates) at ``point`` (of ``link``), or a
        ``torque`` (N·m, counter-clockwise positive) on ``link``; ``opposes="velocity"``: against the point's
        velocity; ``law``: ``{"input": [...], "force": [[x, y], ...]}`` or ``{"input": [...], "torque": [...]}``."""
        return self._append("loads", _given(point=point, link=link, force=force, torque=torque, opposes=opposes,
                                            law=law))

    def dynamics(self, *, gravity=None, joint_friction_radius=None, slide_friction=None, joints: dict | None = None,
                 slides: dict | None = None) -> "Builder":
        """``[dynamics]``: ``gravity`` (m/s², frame coordinates), the friction-circle radius of every revolute
        (length unit or "1 mm"), the friction coefficient of every prismatic pair, and the overrides ``joints``
        (point → radius) and ``slides`` (pair or actuator → μ)."""
        table = self._doc.setdefault("dynamics", {})
        for k, v in _given(gravity=gravity, joint_friction_radius=joint_friction_radius,
                           slide_friction=slide_friction, joints=joints, slides=slides).items():
            if k in table:
                self._problems.append((f"dynamics.{k}", "is defined twice"))
            else:
                table[k] = v
        return self

    def motor(self, kind: str, **keys) -> "Builder":
        """``[motor]``: the motor of a driver for forward dynamics, ``kind`` and its keys as in the file
        (``stall_torque="2 N*m"``, ``no_load_speed="3000 rpm"``, ``gear_ratio=10``, ``driver="crank"`` …;
        docs/dynamics.md)."""
        if "motor" in self._doc:
            self._problems.append(("motor", "is defined twice"))
        else:
            self._doc["motor"] = {"kind": kind, **_given(**keys)}
        return self

    # -- results -------------------------------------------------------------------------------------------
    def to_dict(self) -> dict:
        """The mechanism file's document (what the TOML reader would produce from the equivalent file)."""
        doc = copy.deepcopy(self._doc)
        dim = self._dimension
        if dim is None and any(isinstance(xy, list) and len(xy) == 3 for xy in doc["points"].values()):
            dim = 3
        if dim is not None:
            doc["dimension"] = dim
        return doc

    def build(self) -> Mechanism:
        """The frozen Mechanism. Raises SpecError listing every problem with its location."""
        try:
            mech = from_dict(self.to_dict(), _SOURCE)
        except SpecError as exc:
            raise SpecError(self._problems + exc.problems, _SOURCE) from None
        if self._problems:
            raise SpecError(self._problems, _SOURCE)
        return mech
