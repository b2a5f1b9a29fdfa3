"""A cam and its follower: the contact by conjugate geometry, the pitch curve, the profile, pressure angles and radii
of curvature.

Everything follows from the follower's motion and Aronhold–Kennedy's theorem. With the cam turning by x (ccw, rad)
and the follower moving by its law (a translation along ``direction`` or a turn about ``follower_pivot``), the
relative instant centre of cam and follower is

    translating:  I = O − i·Δ′·d              (d the direction of increasing lift, Δ′ = dΔ/dx)
    oscillating:  I = (O − ω·O_f)/(1 − ω)     (ω = the follower's turn per unit of cam turn)

and the common normal at the contact passes through it: through the trace point R for a knife edge or a roller
(contact C = R, or C = R − r·n̂ on the roller), perpendicular to the face for a flat face (C, the foot of the
perpendicular from I on the face). The profile is the contact point seen from the cam — the envelope of the
follower's positions in the cam's frame —, the pitch curve the trace point seen from the cam. The pressure angle is
the signed angle from the follower's direction of lift at the trace point (knife, roller) or the contact (flat) to
the normal n̂ (the direction the cam pushes the follower).

Radii of curvature (signed: + where the profile is convex, − concave), from exact derivatives of the law:

- pitch curve P(x) in the cam frame: ρ = −|P′|³ / (P′ × P″) (the follower goes round the cam clockwise as seen
  from the cam), the profile of a roller ρ − r, of a knife ρ;
- flat face: with the face normal at angle β(x) and distance h(x) from O in the cam frame, ρ = h + h_ββ
  = h + (h″·β′ − h′·β″)/β′³ (the envelope of a family of lines; a translating face across the slide gives the
  classical ρ = R_b + s + s″).
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from ..model.camming import TWO_PI, CamLaw


def _dot(a, b):
    return np.real(np.conj(a) * b)


def _cross(a, b):
    return np.imag(np.conj(a) * b)


@dataclass(frozen=True)
class Contact:
    """The cam–follower contact at cam turns ``x (n,)`` from the reference position (SI, complex points in the frame's
    coordinates): ``lift`` Δ, ``rate`` Δ′, ``rate2`` Δ″ of the follower's law (m or rad per rad of cam turn),
    ``trace`` R and ``contact`` C (the contact point), ``normal`` n̂ (unit, the direction the cam pushes the follower),
    ``centre`` I (the relative instant centre; inf + inf·i at a translation of the pair), ``pressure_angle`` (rad,
    signed), ``pitch`` and ``profile`` (the trace and contact points in the cam's frame), ``pitch_radius`` and
    ``profile_radius`` (signed radii of curvature, + convex)."""
    x: np.ndarray
    lift: np.ndarray
    rate: np.ndarray
    rate2: np.ndarray
    trace: np.ndarray
    contact: np.ndarray
    normal: np.ndarray
    centre: np.ndarray
    pressure_angle: np.ndarray
    pitch: np.ndarray
    profile: np.ndarray
    pitch_radius: np.ndarray
    profile_radius: np.ndarray


@dataclass(frozen=True)
class CamGeometry:
    """A cam and its follower at the reference position x = 0 (SI; points complex, in the frame's coordinates).

    ``law`` the lift s(φ); the law's angle is φ = ``phase`` + ``rotation``·x and the follower's lift from the
    reference Δ(x) = s(φ) − s(phase). ``motion`` 'translating' (the trace point moves by Δ along the unit
    ``direction``) or 'oscillating' (the follower turns by ``turn``·Δ about ``follower_pivot``). ``contact`` 'knife',
    'roller' (``roller_radius``) or 'flat' (the face through the trace point along ``face``, a unit direction at
    x = 0). ``pivot`` O and ``orientation`` (the unit direction of the cam frame's x axis at x = 0) place the cam
    frame; ``trace`` R₀ is the trace point at x = 0."""
    law: CamLaw
    motion: str
    contact: str
    pivot: complex
    orientation: complex
    trace: complex
    direction: complex = 1 + 0j
    follower_pivot: complex = 0j
    turn: float = 1.0
    face: complex = 1j
    roller_radius: float = 0.0
    phase: float = 0.0
    rotation: int = 1
    pressure_limit: float = math.radians(30.0)
    name: str = ""
    _cache: dict = field(default_factory=dict, init=False, repr=False, compare=False)

    # -- the follower's motion ------------------------------------------------------------------------------
    def move(self, x):
        """(Δ, Δ′, Δ″) of the follower's lift from the reference at cam turns ``x (...)`` (per rad of cam turn)."""
        x = np.asarray(x, dtype=float)
        s, s1, s2, _ = self.law.evaluate(self.phase + self.rotation * x)
        s0 = self.law.evaluate(np.asarray(self.phase))[0]
        return s - s0, self.rotation * s1, s2

    def at(self, x) -> Contact:
        """The contact at cam turns ``x (n,)`` (rad, ccw from the reference)."""
        x = np.atleast_1d(np.asarray(x, dtype=float))
        d, d1, d2 = self.move(x)
        O, R0 = self.pivot, self.trace
        if self.motion == "translating":
            u = self.direction
            R, R1, R2 = R0 + d * u, d1 * u + 0j, d2 * u + 0j
            w, w1, face = np.zeros_like(x), np.zeros_like(x), self.face * np.ones_like(x)
            along = u
        else:
            Of = self.follower_pivot
            t = self.turn
            R = Of + (R0 - Of) * np.exp(1j * t * d)
            w, w1 = t * d1, t * d2                                   # the follower's turn rate and its derivative
            R1, R2 = 1j * w * (R - Of), (1j * w1 - w * w) * (R - Of)
            face = self.face * np.exp(1j * t * d)
            along = Of
        centre, normal, contact, alpha = contact_frame(self.contact, self.motion, O, R, along, self.turn, face, d1,
                                                       self.roller_radius)
        e = self.orientation * np.exp(1j * x)                       # the cam frame's x axis after turning by x
        to_cam = np.conj(e)
        pitch, profile = to_cam * (R - O), to_cam * (contact - O)
        P1, P2 = to_cam * (R1 - 1j * (R - O)), to_cam * (R2 - 2j * R1 - (R - O))
        with np.errstate(divide="ignore", invalid="ignore"):
            rho_pitch = -np.abs(P1) ** 3 / _cross(P1, P2)
            if self.contact == "flat":
                n1, n2 = 1j * w * normal, (1j * w1 - w * w) * normal
                h = _dot(normal, R - O)
                h1 = _dot(n1, R - O) + _dot(normal, R1)
                h2 = _dot(n2, R - O) + 2 * _dot(n1, R1) + _dot(normal, R2)
                b1, b2 = w - 1.0, w1
                rho = h + (h2 * b1 - h1 * b2) / b1 ** 3
            else:
                rho = rho_pitch - (self.roller_radius if self.contact == "roller" else 0.0)
        return Contact(x, d, d1, d2, R, contact, normal, centre, alpha, pitch, profile, rho_pitch, rho)

    # -- summaries over the turn ----------------------------------------------------------------------------
    def turn_samples(self, n: int = 1440) -> Contact:
        """The contact over one cam turn, ``n`` samples x = 2π·k/n (cached)."""
        key = ("turn", n)
        if key not in self._cache:
            self._cache[key] = self.at(np.linspace(0.0, TWO_PI, n, endpoint=False))
        return self._cache[key]

    def pitch_curve(self, n: int = 1440) -> np.ndarray:
        """(n,) complex: the pitch curve (the trace point's path) in the cam frame (m)."""
        return self.turn_samples(n).pitch

    def profile(self, n: int = 1440) -> np.ndarray:
        """(n,) complex: the cam profile (the contact points) in the cam frame (m), in the order the follower meets
        them (clockwise round the cam)."""
        return self.turn_samples(n).profile

    def summary(self, n: int = 1440) -> dict:
        """The cam's checks over a turn (SI): ``base_radius`` (the smallest radius of the profile), ``prime_radius``
        (of the pitch curve), ``pressure_angle_max`` (|α| peak) and ``pressure_angle_at`` (the law's angle there),
        ``pressure_ok`` (below ``pressure_limit``), ``min_profile_radius`` (the smallest convex radius of curvature,
        or None), ``min_concave_radius`` (the smallest |ρ| of a concave part: the largest milling cutter, or None),
        ``roller_radius_limit`` (the largest roller without undercut: the smallest convex radius of the pitch
        curve), ``undercut`` (True where the profile has a cusp or a loop), ``stroke``."""
        c = self.turn_samples(n)
        i = int(np.argmax(np.abs(c.pressure_angle)))
        rho, rp = c.profile_radius, c.pitch_radius
        convex, concave = rho[rho > 0], rho[rho < 0]
        pitch_convex = rp[rp > 0]
        if self.contact == "flat":
            undercut = bool(np.any(rho <= 0))
        elif self.contact == "roller":
            undercut = bool(np.any((rp > 0) & (rp <= self.roller_radius)))
        else:
            undercut = bool(np.any(np.abs(rp) < 1e-12 * max(np.max(np.abs(c.pitch)), 1e-300)))
        return {
            "base_radius": float(np.min(np.abs(c.profile))),
            "prime_radius": float(np.min(np.abs(c.pitch))),
            "pressure_angle_max": float(np.abs(c.pressure_angle[i])),
            "pressure_angle_at": float((self.phase + self.rotation * c.x[i]) % TWO_PI),
            "pressure_limit": float(self.pressure_limit),
            "pressure_ok": bool(np.abs(c.pressure_angle[i]) <= self.pressure_limit),
            "min_profile_radius": float(np.min(convex)) if convex.size else None,
            "min_concave_radius": float(np.min(-concave)) if concave.size else None,
            "roller_radius_limit": float(np.min(pitch_convex)) if pitch_convex.size and self.contact != "flat" else None,
            "undercut": undercut,
            "stroke": float(self.law.stroke),
        }


def contact_frame(kind: str, motion: str, O, R, along, turn, face, rate, roller_radius: float):
    """(I, n̂, C, α) of a cam–follower contact, element-wise on arrays: the cam's pivot O, the trace point R,
    ``along`` the unit direction of increasing lift (translating) or the follower's pivot O_f (oscillating),
    ``turn`` the follower's sense of lift (oscillating), the face direction (flat), ``rate`` Δ′ = dΔ/dx of the lift
    per unit of the cam's ccw turn x; I the relative instant centre, n̂ the common normal, C the contact, α the
    pressure angle (signed, from the direction of lift to n̂)."""
    if motion == "translating":
        centre = O - 1j * rate * along
    else:
        w = turn * rate
        with np.errstate(divide="ignore", invalid="ignore"):
            centre = np.where(np.abs(1.0 - w) > 1e-15, (O - w * along) / (1.0 - w), complex(np.inf, np.inf))
    normal, contact = contact_point(kind, O, R, centre, face, roller_radius)
    at = contact if kind == "flat" else R
    if motion == "translating":
        lift_dir = along * np.ones_like(np.real(rate))
    else:
        lift_dir = 1j * turn * (at - along) / np.abs(at - along)
    alpha = np.arctan2(_cross(lift_dir, normal), _dot(lift_dir, normal))
    return centre, normal, contact, alpha


def contact_point(kind: str, O, R, centre, face, roller_radius: float):
    """(n̂, C): the common normal (unit, pointing away from the cam: n̂·(R − O) > 0) and the contact point, from the
    cam's pivot O, the trace point R, the relative instant centre I (``centre``), the face direction (flat) and the
    roller radius; arrays broadcast. A centre at infinity (the pair translates) leaves the normal radial."""
    if kind == "flat":
        n = 1j * face
        n = np.where(_dot(n, R - O) < 0, -n, n)
        finite = np.isfinite(centre)
        C = np.where(finite, centre + _dot(R - np.where(finite, centre, 0), n) * n, R)
        return n, C
    finite = np.isfinite(centre)
    v = np.where(finite, R - np.where(finite, centre, 0), R - O)
    n = v / np.abs(v)
    n = np.where(_dot(n, R - O) < 0, -n, n)
    return n, (R - roller_radius * n if kind == "roller" else R + 0 * n)
