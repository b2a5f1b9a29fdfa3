"""Mass properties of the made parts, back into the mechanism: every moving body's mass, centre of mass and moment
of inertia from the parts it carries, in a copy of the mechanism that ``assur forces`` and the dynamics read.

A body carries its plates, gear, block, cylinder or rod, and the pins (with their washers and sleeves) whose
carrier it is (a pin is pressed into one of the bodies it joins: the first moving one). The body's centre of mass
is the parts' mass-weighted mean; its moment of inertia about that centre sums each part's own (about the part's
centre) and m·d² (parallel axes). The frame's parts are not bodies of the motion and are left out.
"""
from __future__ import annotations

import dataclasses

import numpy as np

from ..model.dynamics import Dynamics, MassProperties
from ..model.mechanism import FRAME


def body_masses(result) -> dict:
    """{body name: (mass (kg), centre of mass (2,) in the body's frame (m), inertia about it (kg·m²))} of every
    moving body that carries a part, from ``result`` (:class:`~assur.parts.api.Parts`)."""
    mass = result.mass()
    acc: dict[int, list] = {}
    for p in result.parts:
        if p.body == 0:
            continue
        acc.setdefault(p.body, []).append(mass[p.name])
    out = {}
    for b, props in acc.items():
        m = sum(mp.mass for mp in props)
        if m <= 0:
            continue
        com = sum(mp.mass * np.asarray(mp.com[:2]) for mp in props) / m
        inertia = sum(mp.inertia + mp.mass * float(np.sum((np.asarray(mp.com[:2]) - com) ** 2)) for mp in props)
        out[result.plan.body_names[b]] = (m, com, inertia)
    return out


def with_masses(result):
    """A copy of the mechanism whose ``dynamics`` holds the made parts' mass properties (SI) for every body that
    carries parts (other bodies keep what the file gave)."""
    m = result.mechanism
    plan = result.plan
    index = {n: b for b, n in enumerate(plan.body_names)}
    made = body_masses(result)
    given = dict(m.dynamics.bodies) if m.dynamics is not None else {}
    bodies = []
    for name in plan.body_names:
        if name == FRAME:
            continue
        if name not in made:
            if name in given:
                bodies.append((name, given[name]))
            continue
        mass, com, inertia = made[name]
        b = index[name]
        if name.endswith(".block"):
            com_value = None                         # a block's centre of mass is its pin (the part is symmetric)
        elif name.endswith(".cylinder") or name.endswith(".rod"):
            com_value = float(com[0]) if name.endswith(".cylinder") else float(-com[0])
        else:
            world = result.frames.at_sketch(b, com[None])[0]
            com_value = (float(world[0]), float(world[1]))
        bodies.append((name, MassProperties(float(mass), float(inertia), com_value)))
    dyn = m.dynamics if m.dynamics is not None else Dynamics()     # no gravity unless the file gives it
    return dataclasses.replace(m, dynamics=dataclasses.replace(dyn, bodies=tuple(bodies)))


def write_mass_back(result, path) -> str:
    """Write the mechanism with the parts' masses to ``path`` (TOML, atomically); returns the text."""
    from ..io.mechanism_writer import dump
    return dump(with_masses(result), path)


__all__ = ["body_masses", "with_masses", "write_mass_back"]
