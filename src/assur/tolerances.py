"""Numeric tolerances, in one documented place.

All lengths are SI (metres) inside the toolkit. Every tolerance is a pure number: one that compares a length, a
determinant or a residual says what it is relative to (the mechanism's length scale, the size of its sketch's
bounding box; a group's or a body's own size; a squared length for a radicand), so a mechanism drawn at any size
(tests/test_scale.py: every example scaled by 10⁻³ … 10³) has the same buildability, branches, dead centres and
gait ratios, and positions that scale exactly.
"""
from __future__ import annotations

from dataclasses import dataclass


@dataclass(frozen=True, slots=True)
class Tolerances:
    #: A radicand of a dyad's closed form, divided by a squared length of its own (circle ∩ circle: the squared
    #: distance of the centres; circle ∩ line: the squared radius; a slide: the squared distance of its revolutes),
    #: in ``[-radicand, 0)`` is a tangent contact (0); below that the sample is unbuildable. A pure number.
    radicand: float = 1e-12
    #: Two lines whose unit directions' cross product (a sine, a pure number) is below this are parallel
    #: (unbuildable intersection).
    parallel: float = 1e-12
    #: Newton iterations stop when every residual (m: each loop equation is written as a distance) is below this
    #: times the mechanism's length scale.
    newton_residual: float = 1e-12
    #: Newton iteration cap per continuation step.
    newton_iterations: int = 30
    #: Newton-solved groups are continued from the sketch to each sample in certified steps
    #: (:mod:`assur.engine.planar.continuation`) of at most this crank angle (rad) ...
    stage_angle: float = 0.17453292519943295   # 10°
    #: ... or this actuator stroke, relative to the length scale ...
    stage_length: float = 0.05
    #: ... and of at most this many-th of a design change.
    stages_for_new_design: int = 12
    #: A continuation step is certified only where Newton's correction of its prediction moves no point of a group
    #: by more than this fraction of the length scale (else it is retried shorter) ...
    continuation_correction: float = 0.05
    #: ... and a sample whose steps would have to be shorter than this crank angle (rad; this fraction of the
    #: length scale of stroke) to be certified is unbuildable (a toggle, a singular position).
    continuation_min_step: float = 1e-9
    #: Branch choice at compile time is ambiguous when the two candidate assemblies are closer than
    #: this, relative to the length scale.
    branch_separation: float = 1e-6
    #: A ``[branches]`` hint on a point that lies on its reference line in the sketch is decided this
    #: far off the sketch input (rad of crank; relative to the length scale for a stroke).
    branch_nudge: float = 1e-3
    #: A point is on a line (neither side) when the cross product, relative to the squared length
    #: scale, is below this.
    collinear: float = 1e-12
    #: A spatial arm (or a universal joint's pin) within this fraction of its length of its axis (of
    #: the coupler) is parallel to it.
    axis_offset: float = 1e-9
    #: A Newton-solved sample is certified on the seed's branch only where the determinant of its dimensionless
    #: Jacobian (each body's angle column divided by the body's own size, then every row scaled to unit length:
    #: a pure number, |det| ≤ 1, :func:`assur.engine.planar.newton_group.certificate_det`) has the seed's sign and at
    #: least this magnitude; closer to a singular position (a toggle, a change point) it is reported unbuildable,
    #: never possibly mirrored.
    newton_certify: float = 1e-9
    #: Two assemblies of a group closer than this fraction of the length scale (the largest distance of one point
    #: of the group between them) are one; a solved sample this close to another assembly of its group is at a
    #: singular position (where two assemblies meet) and is reported unbuildable, never possibly the other one.
    assembly_separation: float = 1e-6
    #: At compile time the drawn sketch must close the loop equations of every Newton-solved group to
    #: within this fraction of the length scale (the sketch seeds the solver and so fixes its branch).
    sketch_fit: float = 1e-3
    #: A link ``length`` that differs from its sketch by more than this fraction is reported (SketchWarning).
    sketch_length_mismatch: float = 0.01
    #: A direction vector in a file whose norm is 1 within this is taken as written (not divided by its norm).
    unit_norm: float = 1e-14
    #: Two directions in a file (gait.ground, gait.up) are perpendicular when their unit vectors' dot product
    #: is below this.
    perpendicular: float = 1e-9
    #: A length given twice in a design file (a shoe's c and r_min; the shoe and its gear law's a, b, c)
    #: must agree within this, relative to the length (or to 1 m, 1 mm as the file's check says).
    design_agreement: float = 1e-9
    #: A file length unit is an exact fraction 1/k of a metre (mm, cm: divided by k, not multiplied) when
    #: 1/factor is within this of an integer.
    unit_reciprocal: float = 1e-9
    #: A transmission law closes when θ after its whole cycle is the wanted angle within this (rad).
    law_closure: float = 1e-6
    #: A speed ratio k(φ) is 2π-periodic when k(2π) equals k(0) within this, relative to max(1, |k(0)|).
    ratio_periodic: float = 1e-9
    #: A pitch perimeter carries z teeth of module m when it equals z·π·m within this fraction.
    tooth_perimeter: float = 1e-3
    #: The sector partition of a gear pair is symmetric, and its sectors tile a turn, within this (rad;
    #: relative to the centre distance for radii).
    sector_symmetry: float = 1e-9
    #: Consecutive points of a tooth outline closer than this fraction of the outline's largest radius are one
    #: point.
    outline_point: float = 1e-12
    #: A ray within this fraction of the ray spacing beyond a polyline segment's end still crosses the
    #: segment (a ray through a shared end belongs to both neighbours).
    ray_end: float = 1e-7
    #: Targets with uniform timing cover a whole input turn when they span 2π less at most this (rad).
    full_turn: float = 1e-12
    #: Four-bar constraints: Grashof's s + l ≤ p + q holds with a slack of this fraction of the longest link,
    #: and a link is degenerate when shorter than this fraction of the mean length.
    fourbar_slack: float = 1e-9
    #: The ends of a crank's buildable ranges over a turn are refined by bisection to this input angle (rad).
    toggle_angle: float = 1e-12
    #: Roots over a turn (a crank's dead centres, the stops of a spatial rocker) are located to this input angle
    #: (rad).
    root_angle: float = 1e-13
    #: The ends of a stroke's buildable ranges are refined by bisection to this fraction of the stroke.
    stroke_edge: float = 1e-12
    #: Extrema along a stroke are located by a root of the time derivative to this fraction of the run's
    #: duration ...
    stroke_root: float = 1e-12
    #: ... the derivative taken by central differences over this fraction of the run's duration.
    stroke_step: float = 1e-5
    #: Sampled values of a quantity that differ by less than this fraction of its largest magnitude are equal
    #: (rounding noise): no extremum lies between them, a quantity within it is constant, and a value within
    #: it of zero is shown as 0.
    rounding_noise: float = 1e-9
    #: A value (SI; display only, no result depends on it) of magnitude below this, and within the rounding noise of
    #: its own quantity, is shown as 0.
    shown_zero: float = 1e-12
    #: The triangle a rod sweeps from the start is empty (the ratio of two rods' triangles is undefined) below
    #: this area, relative to the squared length scale.
    swept_area: float = 1e-14
    #: A sine or cosine below this is zero: paper 002's start triangle or guide is degenerate (B0 on the line
    #: O–A: relative to |O A|), its eq. (14) singular.
    degenerate_sine: float = 1e-12
    #: Paper 002's printed formulas are reported singular where a square-root (or arcsine) argument is within
    #: this of zero or below it, relative to the squared rod length.
    literal_singular: float = 1e-9
    #: A gear design's installation centre distance is a second one (its mesh checked too) when it differs from
    #: the design's by more than this fraction of the design's centre distance.
    distinct_distance: float = 1e-12
    #: A force analysis flags a sample singular (a toggle: its reactions grow without bound) where a group's
    #: dimensionless condition measure (|sin| of the angle between the two unknown directions of a dyad, the
    #: σ_min/σ_max of a larger group's scaled matrix) is below this; its forces are NaN, never numbers.
    force_condition: float = 1e-6
    #: Friction iterations stop when no unknown changes by more than this fraction of the largest one ...
    friction_change: float = 1e-12
    #: ... or after this many iterations (then reported not converged).
    friction_iterations: int = 100


DEFAULT = Tolerances()
