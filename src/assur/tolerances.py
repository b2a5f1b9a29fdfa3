"""Numeric tolerances, in one documented place.

All lengths are SI (metres) inside the toolkit; tolerances that compare lengths are relative to
a length scale of the mechanism (its sketch bounding box), so a millimetre-scale and a
metre-scale mechanism behave alike.
"""
from __future__ import annotations

from dataclasses import dataclass


@dataclass(frozen=True, slots=True)
class Tolerances:
    #: A radicand (e.g. of a circle-circle intersection) in ``[-radicand, 0)`` relative to the
    #: squared length scale is treated as a tangent contact (0); below that the sample is unbuildable.
    radicand: float = 1e-12
    #: Two lines whose direction cross product is below this are parallel (unbuildable intersection).
    parallel: float = 1e-12
    #: Newton iterations stop when the residual, relative to the length scale, is below this.
    newton_residual: float = 1e-12
    #: Newton iteration cap per continuation step.
    newton_iterations: int = 30
    #: Newton fallback: each sample is continued from the sketch to its input in stages of at most this
    #: crank angle (rad) ...
    stage_angle: float = 0.17453292519943295   # 10°
    #: ... or this actuator stroke, relative to the length scale ...
    stage_length: float = 0.05
    #: ... and in at least this many stages when the design differs from the file's.
    stages_for_new_design: int = 12
    #: Branch choice at compile time is ambiguous when the two candidate assemblies are closer than
    #: this, relative to the length scale.
    branch_separation: float = 1e-6


DEFAULT = Tolerances()
