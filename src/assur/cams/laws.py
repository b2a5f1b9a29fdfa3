"""Cam motion laws: lift programs over one cam turn, their SVAJ diagrams and their continuity.

A law is a :class:`~assur.model.camming.CamLaw` (the object a mechanism file's ``[[cams]]`` holds): a program of
segments — dwells and rises or returns by a normalised law (:mod:`assur.kernels.cam_motion`: harmonic,
cycloidal, modified trapezoid, modified sine, 3-4-5 and 4-5-6-7 polynomials) — or a periodic C² cubic spline
through given points. Its displacement s, velocity v = ds/dφ, acceleration a = d²s/dφ² and jerk j = d³s/dφ³ per
unit of cam angle are exact (closed forms, or the spline's own derivatives); at a cam speed ω (rad/s) they become
s, v·ω, a·ω², j·ω³ in time (:func:`svaj`).

:func:`continuity` checks the *fundamental law of cam design* (Norton, *Cam Design and Manufacturing Handbook*,
§2.1): s, v and a must be continuous over the whole turn (the jerk finite). A simple-harmonic rise after a dwell
breaks it (its acceleration jumps by π²/2·h/β²: infinite jerk), a cycloidal one does not.

Example (Norton's double-dwell cam, *Design of Machinery*, Examples 8-1 and 8-2)::

    law = program(("dwell", 90), ("cycloidal", 90, 0.0254), ("dwell", 90), ("cycloidal", 90, -0.0254),
                  unit="deg")
    continuity(law).ok                 # True: s, v, a continuous
    peaks(law, speed=2 * math.pi)      # v 8 in/s, a 100.5 in/s², j 2527 in/s³ (in m/s …)
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..errors import SpecError
from ..kernels.cam_motion import LAWS
from ..model.camming import TWO_PI, CamLaw, CamSegment

#: the four quantities of an SVAJ diagram, in the order of their arrays
QUANTITIES = ("s", "v", "a", "j")
#: a boundary's jump counts as a discontinuity above this times the quantity's peak over the turn
JUMP_TOLERANCE = 1e-9
MOTIONS = ("dwell",) + LAWS


def program(*segments, unit: str = "rad") -> CamLaw:
    """A lift program from segments ``(motion, angle)`` (a dwell) or ``(motion, angle, lift)`` (a rise, lift > 0,
    or a return, lift < 0), in order from law angle 0; the angles (``unit`` 'rad' or 'deg') must add up to a turn
    and the lifts to 0. SpecError (located ``segments[k]``) otherwise."""
    factor = math.pi / 180.0 if unit == "deg" else 1.0
    out, start, base, problems = [], 0.0, 0.0, []
    for k, sg in enumerate(segments):
        motion, span = sg[0], float(sg[1]) * factor
        lift = float(sg[2]) if len(sg) > 2 else 0.0
        if motion not in MOTIONS:
            problems.append((f"segments[{k}]", f"unknown motion {motion!r} (known: {', '.join(MOTIONS)})"))
            continue
        if not span > 0:
            problems.append((f"segments[{k}]", f"the angle must be positive: {sg[1]!r}"))
            continue
        if (motion == "dwell") != (lift == 0.0):
            problems.append((f"segments[{k}]", "a dwell has no lift and a rise or return has one"))
            continue
        out.append(CamSegment(None if motion == "dwell" else motion, start, span, base, lift))
        start, base = start + span, base + lift
    if not problems and abs(start - TWO_PI) > 1e-9:
        problems.append(("segments", f"the angles add up to {math.degrees(start):.9g}°, not 360°"))
    if not problems and abs(base) > 1e-9 * max(1e-300, max(abs(s.base) + abs(s.lift) for s in out)):
        problems.append(("segments", f"the lifts add up to {base:.9g}, not 0: the law does not close"))
    if problems:
        raise SpecError(problems)
    return CamLaw("segments", tuple(out), source="program")


def spline(angles, lifts, unit: str = "rad") -> CamLaw:
    """A periodic C² cubic spline law through ``(angles, lifts)`` over one turn (angles from 0, increasing,
    below a turn)."""
    factor = math.pi / 180.0 if unit == "deg" else 1.0
    a = np.asarray(angles, dtype=float) * factor
    s = np.asarray(lifts, dtype=float)
    if a.shape != s.shape or a.ndim != 1 or len(a) < 4:
        raise SpecError([("angles", "a spline needs at least 4 points, as many angles as lifts")])
    if abs(a[0]) > 1e-12 or not np.all(np.diff(a) > 0) or a[-1] >= TWO_PI:
        raise SpecError([("angles", "must start at 0 and increase strictly within one turn")])
    return CamLaw("spline", angles=tuple(a.tolist()), lifts=tuple(s.tolist()), source="spline")


@dataclass(frozen=True)
class SVAJ:
    """A law's diagrams over law angles ``phi (n,)`` (rad): ``s``, ``v``, ``a``, ``j`` (n,) per unit of cam angle
    (m or rad, per rad, per rad², per rad³), or in time at ``speed`` (rad/s): v·ω, a·ω², j·ω³."""
    phi: np.ndarray
    s: np.ndarray
    v: np.ndarray
    a: np.ndarray
    j: np.ndarray
    speed: float | None = None


def svaj(law: CamLaw, phi=None, *, samples: int = 720, speed: float | None = None) -> SVAJ:
    """The SVAJ of ``law`` at ``phi`` (default ``samples`` angles over the turn), per rad of cam angle, or in time
    at the cam ``speed`` (rad/s)."""
    phi = np.linspace(0.0, TWO_PI, samples, endpoint=False) if phi is None else np.asarray(phi, dtype=float)
    s, v, a, j = law.evaluate(phi)
    if speed is not None:
        w = float(speed)
        v, a, j = v * w, a * w * w, j * w ** 3
    return SVAJ(phi, s, v, a, j, speed)


def peaks(law: CamLaw, *, speed: float | None = None, samples: int = 4096) -> dict:
    """The largest |v|, |a| and |j| over the turn (per rad, or in time at ``speed``), the stroke, and where each
    peak is (law angle, rad). Segment laws are searched on a fine grid of each segment and refined (bounded
    scalar search); a spline's on a fine grid."""
    d = svaj(law, samples=samples, speed=speed)
    out = {"stroke": law.stroke}
    w = 1.0 if speed is None else float(speed)
    for k, name in enumerate(("v", "a", "j")):
        y = np.abs(getattr(d, name))
        i = int(np.argmax(y))
        at, value = float(d.phi[i]), float(y[i])
        if law.kind == "segments":
            from scipy.optimize import minimize_scalar
            h = TWO_PI / samples
            best = minimize_scalar(lambda x: -abs(law.evaluate(np.array([x]))[k + 1][0]) * w ** (k + 1),
                                   bounds=(at - h, at + h), method="bounded", options={"xatol": 1e-13})
            if -best.fun > value:
                at, value = float(best.x) % TWO_PI, float(-best.fun)
        out[name] = value
        out[f"{name}_at"] = at
    return out


@dataclass(frozen=True)
class Boundary:
    """One joint of a law (a segment boundary or a spline knot) at law angle ``angle``: the jump of each of s, v, a,
    j across it (right minus left), and ``order``, the lowest derivative that jumps (0 s, 1 v, 2 a, 3 j; None)."""
    angle: float
    jumps: tuple[float, float, float, float]
    order: int | None


@dataclass(frozen=True)
class Continuity:
    """The continuity of a law over its turn: every ``boundaries`` entry, and the law's class ``smooth``: the
    number of continuous derivatives (3: s, v, a and j continuous; 2: jerk jumps, finite; 1: acceleration jumps
    (infinite jerk); 0: velocity jumps; −1: the lift jumps)."""
    boundaries: tuple[Boundary, ...]
    smooth: int

    @property
    def ok(self) -> bool:
        """The fundamental law of cam design: s, v and a continuous (finite jerk)."""
        return self.smooth >= 2

    def findings(self, *, unit: str = "deg") -> list[str]:
        """One line per boundary that breaks the fundamental law (an acceleration, velocity or lift jump)."""
        out = []
        for b in self.boundaries:
            if b.order is not None and b.order <= 2:
                what = ("lift", "velocity", "acceleration")[b.order]
                at = math.degrees(b.angle) if unit == "deg" else b.angle
                out.append(f"the {what} jumps by {b.jumps[b.order]:.4g} at {at:.6g}{'°' if unit == 'deg' else ' rad'}"
                           + (": infinite jerk" if b.order == 2 else ""))
        return out


def continuity(law: CamLaw) -> Continuity:
    """The jumps of s, v, a, j at every boundary of ``law`` (each relative to the quantity's peak over the turn:
    below :data:`JUMP_TOLERANCE` counts as continuous)."""
    if law.kind == "segments":
        angles = [sg.start for sg in law.segments]
        left = [_segment_end(sg) for sg in law.segments[-1:] + law.segments[:-1]]
        right = [_segment_start(sg) for sg in law.segments]
    else:
        angles = list(law.angles)
        right = [np.array([float(c[0]) for c in law.evaluate(np.array([a]))]) for a in angles]
        left = [np.array(_left_spline(law, a), dtype=float) for a in angles]
    scale = np.array([max(np.max(np.abs(x)), 1e-300) for x in
                      law.evaluate(np.linspace(0.0, TWO_PI, 4096, endpoint=False))])
    out, smooth = [], 3
    for a, lo, hi in zip(angles, left, right):
        jump = tuple(float(x) for x in (hi - lo))
        order = next((k for k in range(4) if abs(jump[k]) > JUMP_TOLERANCE * scale[k]), None)
        out.append(Boundary(float(a), jump, order))
        if order is not None:
            smooth = min(smooth, order - 1)
    return Continuity(tuple(out), smooth)


def _segment_start(sg: CamSegment) -> np.ndarray:
    from ..kernels.cam_motion import segment
    return np.array([float(x) for x in segment(sg.motion, sg.start, sg.start, sg.span, sg.lift, sg.base)])


def _segment_end(sg: CamSegment) -> np.ndarray:
    from ..kernels.cam_motion import segment
    end = sg.start + sg.span
    return np.array([float(x) for x in segment(sg.motion, end, sg.start, sg.span, sg.lift, sg.base)])


def _left_spline(law: CamLaw, a: float):
    """(s, v, a, j) of a spline law just before knot ``a``: its polynomial piece on the left evaluated at the knot."""
    spl = law._splines()[0]
    x = np.asarray(spl.x)
    k = int(np.searchsorted(x, a, side="left"))
    k = len(x) - 1 if k == 0 else k          # the first knot's left piece is the last one, at the turn's end
    at = x[k] if k < len(x) else a
    piece = k - 1
    c = spl.c[:, piece]
    t = at - x[piece]
    s = c[0] * t ** 3 + c[1] * t ** 2 + c[2] * t + c[3]
    v = 3 * c[0] * t ** 2 + 2 * c[1] * t + c[2]
    acc = 6 * c[0] * t + 2 * c[1]
    return s, v, acc, 6 * c[0]
