"""Cam pairs of a mechanism: a higher pair (p4) between a cam turning about a frame pivot and its follower.

A cam pair makes the follower's lift a function of the cam's rotation. The law gives the lift s(φ) over one cam
turn (φ the law's angle, rad; s in m for a translating follower, rad for an oscillating one), s(φ + 2π) = s(φ).
With x the cam's counter-clockwise rotation from the sketch, the law's angle is φ = phase + rotation·x
(``rotation`` +1 when the law advances as the cam turns counter-clockwise, −1 clockwise) and the follower moves
from its sketch position by

    Δ = lift_sign · (s(phase + rotation·x) − s(phase))

along its slide (translating) or about its pivot (oscillating); ``lift_sign`` (fixed at compile time from the
sketch) makes a positive lift carry the trace point away from the cam's pivot.

:class:`CamLaw` is a program of segments with closed forms (:mod:`assur.kernels.cam_motion`), a periodic C²
cubic spline through given points, or a periodic quintic spline of a sampled table (the lift a given profile
imposes): s, s′, s″ and s‴ are exact derivatives of the law the engine holds.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from ..kernels.cam_motion import segment

TWO_PI = 2.0 * math.pi
#: follower contact kinds
FOLLOWER_KINDS = ("knife", "roller", "flat")
#: follower motions
FOLLOWER_MOTIONS = ("translating", "oscillating")


@dataclass(frozen=True, slots=True)
class CamSegment:
    """One piece of a lift program: from law angle ``start`` over ``span`` (rad) the lift goes from ``base`` to
    ``base + lift`` by the normalised law ``motion`` (a name of :data:`assur.kernels.cam_motion.LAWS`), or stays
    at ``base`` (a dwell: ``motion`` None, ``lift`` 0)."""
    motion: str | None
    start: float
    span: float
    base: float
    lift: float


@dataclass(frozen=True)
class CamLaw:
    """The lift s(φ) of a follower over one cam turn (φ in [0, 2π), rad; periodic).

    kind 'segments': ``segments`` covering [0, 2π) in order (closed forms); 'spline': a periodic C² cubic spline
    through (``angles``, ``lifts``); 'table': a periodic quintic spline through (``angles``, ``lifts``) (a sampled
    lift, e.g. the one a given profile imposes: then ``profile`` holds that profile's polar table ((angle, radius)
    pairs, rad and m, the cam's frame), which a written file repeats). ``source`` says where it came from."""
    kind: str
    segments: tuple[CamSegment, ...] = ()
    angles: tuple[float, ...] = field(default=(), repr=False)
    lifts: tuple[float, ...] = field(default=(), repr=False)
    source: str = ""
    profile: tuple = field(default=(), repr=False)
    _spline: object = field(default=None, init=False, repr=False, compare=False)

    def _splines(self):
        s = self._spline
        if s is None:
            x = np.append(np.asarray(self.angles, float), self.angles[0] + TWO_PI)
            y = np.append(np.asarray(self.lifts, float), self.lifts[0])
            if self.kind == "spline":
                from scipy.interpolate import CubicSpline
                s0 = CubicSpline(x, y, bc_type="periodic")
                s = (s0, s0.derivative(1), s0.derivative(2), s0.derivative(3))
            else:
                from scipy.interpolate import make_interp_spline
                s0 = make_interp_spline(x, y, k=5, bc_type="periodic")
                s = (s0, s0.derivative(1), s0.derivative(2), s0.derivative(3))
            object.__setattr__(self, "_spline", s)
        return s

    def evaluate(self, phi):
        """(s, s′, s″, s‴) at law angles ``phi (...)`` (any real angles: the law is periodic), each (...)."""
        phi = np.asarray(phi, dtype=float)
        if self.kind in ("spline", "table"):
            s = self._splines()
            u = self.angles[0] + np.mod(phi - self.angles[0], TWO_PI)
            return tuple(np.asarray(f(u), dtype=float) for f in s)
        u = np.mod(phi, TWO_PI)
        out = [np.zeros(phi.shape) for _ in range(4)]
        for k, sg in enumerate(self.segments):
            last = k == len(self.segments) - 1
            inside = (u >= sg.start) & ((u < sg.start + sg.span) | last)
            if not inside.any():
                continue
            parts = segment(sg.motion, u, sg.start, sg.span, sg.lift, sg.base)
            for i in range(4):
                out[i] = np.where(inside, parts[i], out[i])
        return tuple(out)

    @property
    def stroke(self) -> float:
        """The largest lift minus the smallest over the turn (m or rad)."""
        if self.kind == "segments":
            ends = [sg.base for sg in self.segments] + [sg.base + sg.lift for sg in self.segments]
            return float(max(ends) - min(ends))
        s = self.evaluate(np.linspace(0.0, TWO_PI, 4096, endpoint=False))[0]
        return float(np.max(s) - np.min(s))

    def __reduce__(self):   # the spline cache is rebuilt on the other side of a pickle
        return CamLaw, (self.kind, self.segments, self.angles, self.lifts, self.source, self.profile)


@dataclass(frozen=True, slots=True)
class CamPair:
    """A cam pair: the cam link ``cam`` (turning about a frame pivot) drives the follower link ``follower``
    (translating on a frame slide, or oscillating about a frame pivot) through the contact at the follower's trace
    point ``point`` (a knife's edge, a roller's centre, a point of a flat face).

    ``law`` the lift program (:class:`CamLaw`; m for a translating follower, rad for an oscillating one);
    ``contact`` 'knife', 'roller' or 'flat'; ``motion`` 'translating' or 'oscillating' (what the follower's own
    pair makes it); ``roller_radius`` (m); ``face_angle`` (rad) a flat face's direction from the default (across the
    slide for a translating follower, along the arm pivot → trace point for an oscillating one); ``phase`` the law's
    angle at the sketch; ``rotation`` +1 when the law advances with the cam turning counter-clockwise, −1
    clockwise; ``pressure_limit`` (rad) the largest pressure angle a check accepts (reports flag more)."""
    name: str
    cam: str
    follower: str
    point: str
    law: CamLaw
    contact: str = "roller"
    motion: str = "translating"
    roller_radius: float = 0.0
    face_angle: float = 0.0
    phase: float = 0.0
    rotation: int = 1
    pressure_limit: float = math.radians(30.0)

    def relative(self, x):
        """(y, y′, y″) of the follower's law lift from the sketch, s(phase + rotation·x) − s(phase), and its first
        two derivatives by the cam's ccw rotation ``x (...)`` from the sketch (before ``lift_sign``)."""
        s, s1, s2, _ = self.law.evaluate(self.phase + self.rotation * np.asarray(x, dtype=float))
        s0 = self.law.evaluate(np.asarray(self.phase, dtype=float))[0]
        r = float(self.rotation)
        return s - s0, r * s1, s2


def cam_ends(mechanism, cam: CamPair) -> tuple[str, str]:
    """(pivot, arm) of the cam link: its frame pivot and another of its points (its turn is the pivot → arm
    direction's)."""
    frame = set(mechanism.frame.points)
    pts = mechanism.link(cam.cam).points
    pivot = next(p for p in pts if p in frame)
    return pivot, next(p for p in pts if p != pivot)
