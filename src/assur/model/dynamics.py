"""Frozen descriptions of what the force analysis needs: mass properties, loads, friction, gravity.

All numbers are SI (kg, kg·m², m, N, N·m). Bodies are named as in the structure graph: a link by
its name, a pin-in-slot slider block ``"<pair>.block"``, an actuator's ``"<name>.cylinder"`` and
``"<name>.rod"``. Nothing here holds solved forces.
"""
from __future__ import annotations

from dataclasses import dataclass


@dataclass(frozen=True, slots=True)
class MassProperties:
    """The mass properties of one body.

    ``mass`` (kg). ``inertia`` (kg·m², about the centre of mass; None: the default — a slender bar
    m·L²/12 for a binary link, the point-mass polygon (m/k at each of its k points) for a link with
    more points, zero for a block, cylinder or rod). ``com``: None (the centroid of the body's
    points), ``"mid"`` (binary links: the midpoint), a point name, sketch coordinates ``(x, y)``
    (m, fixed to the body), or for a cylinder or rod a distance (m) from its hinge along the
    actuator's axis, towards the other hinge.
    """
    mass: float = 0.0
    inertia: float | None = None
    com: str | tuple[float, ...] | float | None = None


@dataclass(frozen=True, slots=True)
class LoadLaw:
    """A load that varies over the cycle: values at driver inputs (rad or m, strictly increasing),
    linearly interpolated; periodic over 2π for a crank. ``values`` is (n, 2) forces (N) or (n, 1)
    torques (N·m)."""
    inputs: tuple[float, ...]
    values: tuple[tuple[float, ...], ...]


@dataclass(frozen=True, slots=True)
class Load:
    """An external load: a force (N, frame coordinates) at a ``point`` of ``link`` (or of the bodies at
    the point when ``link`` is None), or a torque (N·m, counter-clockwise positive) on ``link``.

    ``opposes = "velocity"``: the force's magnitude |force| always acts against the point's velocity
    (zero where the point is at rest). ``law``: the force or torque as a table of the first driver's
    input instead of a constant."""
    point: str | None = None
    link: str | None = None
    force: tuple[float, float] | None = None
    torque: float | None = None
    opposes: str | None = None
    law: LoadLaw | None = None


def load_body(point: str, link: str | None, bodies, sliders) -> str:
    """The body a force at ``point`` acts on (docs/format.md, "Loads"): ``link`` when given; else the one body at
    the point; else, where a slider meets other bodies (a pin-in-slot's block, or a link that translates on a
    guide: a ram, a piston, a carriage), that slider; else ValueError naming the bodies that meet there.

    ``bodies``: the names of the bodies that carry the point; ``sliders``: those of them that translate on a guide
    (:func:`assur.model.mechanism.bodies_at` gives both). Where several bodies meet, the load's body matters for
    the reaction at that very joint (a pin's load on the rod or on the ram), never for the driving torque."""
    if link is not None:
        return link
    bodies = tuple(bodies)
    if len(bodies) == 1:
        return bodies[0]
    sliders = tuple(sliders)
    if len(sliders) == 1:
        return sliders[0]
    if not bodies:
        raise ValueError(f"no body carries the point {point!r}")
    raise ValueError(f"the point {point!r} joins {', '.join(repr(b) for b in bodies)}: give link = the body the "
                     "force acts on (it decides the reaction at that joint)")


@dataclass(frozen=True, slots=True)
class Friction:
    """Coulomb friction, used when the analysis asks for it.

    ``joint_radius`` (m): the friction-circle radius of every revolute (the journal radius times the
    friction coefficient); ``slide``: the friction coefficient μ of every prismatic pair.
    ``joints``: (point, radius) overrides; ``slides``: (pair name, μ) overrides.
    """
    joint_radius: float = 0.0
    slide: float = 0.0
    joints: tuple[tuple[str, float], ...] = ()
    slides: tuple[tuple[str, float], ...] = ()

    def radius_at(self, point: str) -> float:
        return dict(self.joints).get(point, self.joint_radius)

    def mu_of(self, pair: str) -> float:
        return dict(self.slides).get(pair, self.slide)

    @property
    def any(self) -> bool:
        return bool(self.joint_radius or self.slide or any(r for _, r in self.joints)
                    or any(m for _, m in self.slides))


@dataclass(frozen=True, slots=True)
class Dynamics:
    """Gravity (m/s², frame coordinates), the bodies' mass properties, the loads and the friction."""
    gravity: tuple[float, ...] = (0.0, 0.0)
    bodies: tuple[tuple[str, MassProperties], ...] = ()
    loads: tuple[Load, ...] = ()
    friction: Friction = Friction()

    def mass_of(self, body: str) -> MassProperties:
        return dict(self.bodies).get(body, MassProperties())

    @property
    def has_mass(self) -> bool:
        return any(mp.mass > 0 for _, mp in self.bodies)
