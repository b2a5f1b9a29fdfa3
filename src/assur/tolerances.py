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
    #: Continuation steps from the sketch configuration to the requested input (Newton fallback).
    newton_continuation: int = 8
    #: Branch choice at compile time is ambiguous when the two candidate assemblies are closer than
    #: this, relative to the length scale.
    branch_separation: float = 1e-6


DEFAULT = Tolerances()
