"""``make_parts(cycle)``: a solved cycle → the parts, their certified conflicts, the proven-minimal layer stack and
(on demand) their solids and mass properties. :class:`Parts` is the result the command, the files and the page
read.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from ..errors import SpecError
from ..model.mechanism import FRAME
from .motion import _input_text, body_frames


@dataclass(eq=False)
class Parts:
    """The parts of a mechanism over its solved run.

    ``settings`` (:class:`~assur.parts.settings.Settings`), ``frames`` (the body poses), ``design`` (the flat
    parts), ``conflicts`` (the certified verdicts), ``program`` and ``layout`` (the layer program and its
    solution), ``certificate`` (why the layer count is minimal), ``parts`` (every part with its ``layer`` and
    ``z``). ``solids()`` and ``mass()`` build the B-reps (build123d) on first use."""
    mechanism: object
    plan: object
    settings: object
    frames: object
    design: object
    conflicts: object
    program: object
    layout: object
    certificate: object
    parts: list
    cycle: object = None
    _solids: dict = field(default_factory=dict, repr=False)
    _mass: dict = field(default_factory=dict, repr=False)
    _meshes: dict = field(default_factory=dict, repr=False)
    _flat: dict = field(default_factory=dict, repr=False)

    @property
    def layers(self) -> int:
        return self.layout.layers

    def part(self, name: str):
        for p in self.parts:
            if p.name == name:
                return p
        raise KeyError(f"no part {name!r} (parts: {', '.join(p.name for p in self.parts)})")

    def layer_of(self) -> dict:
        """{part name: layer} of the parts that take a layer."""
        return {p.name: p.layer for p in self.parts if isinstance(p.layer, int) and p.kind in LAYERED}

    def solids(self) -> dict:
        """{part name: its flat build123d solid (mm)}, built on first use."""
        from .solids import flat_solid, require_make
        if not self._solids:
            require_make()
            for p in self.parts:
                self._solids[p.name] = flat_solid(p)
        return self._solids

    def flat_meshes(self) -> dict:
        """{part name: its flat solid as a closed trimesh (mm)}: what the STL and 3MF files hold (centred)."""
        from .solids import tessellation
        if not self._flat:
            for name, solid in self.solids().items():
                self._flat[name] = tessellation(solid)
        return self._flat

    def meshes(self) -> dict:
        """{part name: (vertices (v, 3), triangles (t, 3))} of every part at its sketch pose and height (mm): the
        flat meshes moved into the assembly."""
        from .solids import pose_matrix
        if not self._meshes:
            for p in self.parts:
                mesh = self.flat_meshes()[p.name]
                T = pose_matrix(p, self.frames)
                v = np.asarray(mesh.vertices) @ T[:3, :3].T + T[:3, 3]
                self._meshes[p.name] = (v, np.asarray(mesh.faces))
        return self._meshes

    def mass(self) -> dict:
        """{part name: :class:`~assur.parts.solids.MassProperties`}."""
        from .solids import mass_properties
        if not self._mass:
            for name, solid in self.solids().items():
                self._mass[name] = mass_properties(self.part(name), solid)
        return self._mass

    def outline(self, part) -> np.ndarray:
        """(k, 2) the part's footprint at the sketch pose (m, sketch frame): its conflict region's exterior."""
        ring = np.asarray(part.region().exterior.coords)[:-1]
        return self.frames.at_sketch(part.body, ring)

    def input_text(self, q) -> str:
        """A run value as the driver's input in the file's units ("37.5 deg")."""
        return _input_text(self.plan, q, self.frames.moving)


#: the part kinds that take a layer of the stack
LAYERED = ("plate", "gear", "block", "cylinder", "rod")


def _shortest(mechanism) -> float:
    """The least distance between two points of one moving link (m; the sketch's size when there is none)."""
    pos = dict(mechanism.points)
    out = [math.dist(pos[a], pos[b]) for lk in mechanism.links if lk.name != FRAME
           for i, a in enumerate(lk.points) for b in lk.points[i + 1:]]
    out = [d for d in out if d > 0]
    return min(out) if out else mechanism.length_scale


def make_parts(cycle, *, clearance: float | None = None, process: str | None = None,
               max_layers: int | None = None, time_limit: float = 60.0) -> Parts:
    """The parts of ``cycle``'s mechanism (a solved :class:`~assur.analysis.study.Study` or Cycle), laid
    out on the fewest layers with every conflict certified over the continuous run.

    ``clearance`` (m) and ``process`` override the file's ``[make]``; ``max_layers`` caps the stack;
    ``time_limit`` (s) bounds each phase of the layer program (a stopped solve reports its gap). SpecError for a
    ``[make]`` value that does not fit, for what cannot be made, and when the parts cannot be stacked within
    ``max_layers`` (naming the parts that conflict and the inputs where they meet); nothing is written."""
    from .conflicts import find_conflicts
    from .footprints import build
    from .layers import Unstackable, solve_layers
    from .settings import resolve
    from .stack import assemble, program_of
    plan = cycle.plan
    m = plan.mechanism
    if plan.dimension != 2:
        raise SpecError([("dimension", "assur make builds planar mechanisms (dimension = 2)")])
    if max_layers is not None and int(max_layers) < 1:
        raise SpecError([("max_layers", f"must be at least 1: {max_layers!r}")])
    settings = resolve(m.make, size=m.length_scale, shortest=_shortest(m), clearance=clearance, process=process)
    frames = body_frames(cycle)
    design = build(m, plan, frames, settings)
    conflicts = find_conflicts(cycle, frames, design, settings.clearance)
    program = program_of(design, conflicts)
    try:
        layout, cert = solve_layers(program, max_layers=max_layers, time_limit=time_limit)
    except Unstackable as exc:
        raise _unstackable_error(exc, program, conflicts, plan, max_layers, frames.moving) from None
    parts = assemble(design, program, layout, frames, settings)
    return Parts(m, plan, settings, frames, design, conflicts, program, layout, cert, parts, cycle)


def _unstackable_error(exc, program, conflicts, plan, max_layers, moving) -> SpecError:
    """The SpecError of a stack that does not fit: the parts of a set that cannot be stacked, and where each
    conflicting pair among them meets (the input of their least distance)."""
    names = [n for g in exc.groups for n in program.groups[g]]
    lines = []
    for v in conflicts.all():
        if v.conflict and v.a in names and v.b in names:
            lines.append(f"{v.a} and {v.b} meet at {_input_text(plan, v.at, moving)} (gap {1e3 * max(v.sampled, 0.0):.3g} mm)")
    for v in conflicts.pins:           # a pin of the set's parts that another of them covers
        if v.conflict and v.b in names and v.a not in names:
            lines.append(f"{v.b} covers {v.a} at {_input_text(plan, v.at, moving)}")
    within = f"in {exc.limit} layer{'s' if exc.limit != 1 else ''}" if max_layers is not None else "at all"
    why = "conflict pairwise" if exc.clique else "cannot share fewer layers"
    head = f"the parts cannot be stacked {within}: {', '.join(names)} {why}"
    return SpecError([("max_layers" if max_layers is not None else "make", head + ("; " if lines else "")
                       + "; ".join(lines[:12]) + (" …" if len(lines) > 12 else ""))])


__all__ = ["LAYERED", "Parts", "make_parts"]
