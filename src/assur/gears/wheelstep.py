"""Wheel-step mover of paper 001 (Skoybeda & Zhukavets 2024): support-shoe profile and displacement budget.

Equation numbers are the paper's. Symbols (the paper's Fig. 3): ``a`` hub axis to crank axes,
``b`` crank length, ``c`` shoe-bar length, ``phi`` the hub angle; one step is ``phi ∈ [−π/4, π/4]``.
All lengths in metres, angles in radians; every function is vectorised over ``phi`` (any shape ``(...)``).

Profile, eqs. (1)–(3):  ``Y1 = 4b cos φ − a``, ``Y2 = a − 2b(1 + cos² φ) + c``,
``X = Y2 sin φ``, ``Y = Y1 + Y2 cos φ``; polar form ``ρ = |(X, Y)|``, ``α = atan2(X, Y)`` (from the OY axis).
Curvature radius, eqs. (7)–(9): ``R = Y2 − Y1′ sin φ = a + c − b(6 cos² φ − 2)``, ``R_min = a − 4b + c``.
Displacements, eqs. (4), (5), (6) as corrected to agree with (10), and (10): ``X_I = 6b``,
``X_II = (a − b + c)π/2 − 3b``, ``X_01 = (a − b + c)π/2 + 3b``.
Mover displacement over a step: ``X(φ) = (a − b + c)φ + 1.5 b sin 2φ`` = rolling part ∫₀^φ R + crank
part ``3b sin 2φ`` (not printed in the paper; this form regenerates its Table 1).

The shoe lives with the gears because the paper's gear law (:class:`assur.gears.law.WheelStepLaw`, and a gear
file's ``kind = "wheelstep"`` law) is defined on its displacement X(φ); the mover's drive redesigned together with
it is :mod:`assur.codesign.wheelstep`.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..errors import SpecError

#: half the hub angle of one step (rad): a step is φ ∈ [−STEP_HALF_ANGLE, +STEP_HALF_ANGLE]
STEP_HALF_ANGLE = math.pi / 4


def bar_length_for(r_min: float, a: float, b: float) -> float:
    """Design rule from eq. (9): the shoe-bar length ``c = R_min − a + 4b`` (m) that gives the wanted R_min."""
    return r_min - a + 4.0 * b


@dataclass(frozen=True, slots=True)
class DisplacementBudget:
    """Horizontal displacement of the mover over one step φ ∈ [−π/4, π/4] (m)."""
    crank: float          #: X_I = 6b, rotation of crank and bar, eq. (5)
    rolling: float        #: X_II = (a − b + c)π/2 − 3b, rolling of the shoe, corrected eq. (6) / eq. (10)
    total: float          #: X_01 = X_I + X_II, eq. (4)

    @property
    def rolling_share(self) -> float:
        """X_II / X_01 (a fraction; the paper prints it in per cent)."""
        return self.rolling / self.total


@dataclass(frozen=True, slots=True)
class Shoe:
    """The crank mechanism's geometry: ``a``, ``b``, ``c`` in metres (Fig. 3). Validated on construction."""
    a: float
    b: float
    c: float

    def __post_init__(self):
        problems = []
        for name in ("a", "b", "c"):
            v = getattr(self, name)
            if not (isinstance(v, (int, float)) and math.isfinite(v) and v > 0):
                problems.append((name, f"must be a finite length > 0 m: {v!r}"))
        if not problems and self.r_min <= 0:
            problems.append(("c", f"gives R_min = a − 4b + c = {self.r_min:.6g} m ≤ 0: the shoe profile is not "
                                  f"convex at φ = 0 (need c > 4b − a = {4 * self.b - self.a:.6g} m)"))
        if problems:
            raise SpecError(problems)

    @classmethod
    def from_r_min(cls, a: float, b: float, r_min: float) -> "Shoe":
        """The shoe whose bar length follows the design rule c = R_min − a + 4b."""
        return cls(a, b, bar_length_for(r_min, a, b))

    # ---- profile, eqs. (1)–(3) --------------------------------------------------------------------------
    def y1(self, phi):
        """Eq. (2), (...) → (...), m."""
        return 4.0 * self.b * np.cos(phi) - self.a

    def y2(self, phi):
        """Eq. (3), (...) → (...), m."""
        return self.a - 2.0 * self.b * (1.0 + np.cos(phi) ** 2) + self.c

    def profile(self, phi) -> np.ndarray:
        """Eq. (1): profile points (X, Y) in the frame of Fig. 3 (origin B1), (...) → (..., 2), m."""
        phi = np.asarray(phi, dtype=float)
        y2 = self.y2(phi)
        return np.stack([y2 * np.sin(phi), self.y1(phi) + y2 * np.cos(phi)], axis=-1)

    def profile_polar(self, phi) -> tuple[np.ndarray, np.ndarray]:
        """Polar form: (ρ, α) with ρ = |(X, Y)| (m) and α = atan2(X, Y) from the OY axis (rad), each (...)."""
        xy = self.profile(phi)
        return np.hypot(xy[..., 0], xy[..., 1]), np.arctan2(xy[..., 0], xy[..., 1])

    def profile_tangent(self, phi) -> np.ndarray:
        """d(X, Y)/dφ from eqs. (1)–(3) differentiated term by term, (...) → (..., 2), m/rad.

        Equals R(φ)·(cos φ, −sin φ); kept separate so tests can check that identity."""
        phi = np.asarray(phi, dtype=float)
        s, c = np.sin(phi), np.cos(phi)
        dy1 = -4.0 * self.b * s
        dy2 = 4.0 * self.b * c * s
        y2 = self.y2(phi)
        return np.stack([dy2 * s + y2 * c, dy1 + dy2 * c - y2 * s], axis=-1)

    # ---- curvature, eqs. (7)–(9) ------------------------------------------------------------------------
    def curvature_radius(self, phi):
        """Eq. (8): R(φ) = a + c − b(6 cos² φ − 2), (...) → (...), m. Equal to eq. (7) identically."""
        return self.a + self.c - self.b * (6.0 * np.cos(phi) ** 2 - 2.0)

    def curvature_radius_eq7(self, phi):
        """Eq. (7): R(φ) = Y2 − (dY1/dφ)·sin φ, (...) → (...), m."""
        return self.y2(phi) + 4.0 * self.b * np.sin(phi) ** 2

    @property
    def r_min(self) -> float:
        """Eq. (9): R_min = R(0) = a − 4b + c, m."""
        return self.a - 4.0 * self.b + self.c

    @property
    def r_step_end(self) -> float:
        """R(±π/4) = a + c − b, the largest curvature radius over a step, m."""
        return self.a + self.c - self.b

    # ---- displacements, eqs. (4)–(6), (10) --------------------------------------------------------------
    @property
    def budget(self) -> DisplacementBudget:
        """X_I, X_II (corrected eq. (6)) and X_01 over one step."""
        crank = 6.0 * self.b
        rolling = (self.a - self.b + self.c) * math.pi / 2.0 - 3.0 * self.b
        return DisplacementBudget(crank=crank, rolling=rolling, total=crank + rolling)

    def rolling_eq10(self) -> float:
        """Eq. (10): X_II = 3b(π/2 − 1) + R_min·π/2, m (the same number as the corrected eq. (6))."""
        return 3.0 * self.b * (math.pi / 2.0 - 1.0) + self.r_min * math.pi / 2.0

    def rolling_displacement(self, phi):
        """Rolling part of the displacement from φ = 0: ∫₀^φ R dφ = (a − b + c)φ − 1.5 b sin 2φ, (...), m."""
        phi = np.asarray(phi, dtype=float)
        return (self.a - self.b + self.c) * phi - 1.5 * self.b * np.sin(2.0 * phi)

    def crank_displacement(self, phi):
        """Crank part of the displacement from φ = 0: 3b sin 2φ (totals X_I = 6b over a step), (...), m.

        Not printed in the paper; inferred because it regenerates Table 1."""
        return 3.0 * self.b * np.sin(2.0 * np.asarray(phi, dtype=float))

    def displacement(self, phi, *, periodic: bool = True):
        """Mover's horizontal displacement X(φ) from φ = 0, (...) → (...), m.

        Within a step X = (a − b + c)φ + 1.5 b sin 2φ. ``periodic=True`` repeats the step: X(φ + π/2) = X(φ) + X_01
        (the mover over many steps); ``periodic=False`` extends the closed form analytically beyond |φ| ≤ π/4
        (it stays increasing since dX/dφ ≥ R_min > 0; used by the sector march of :mod:`assur.gears.sectors`)."""
        phi = np.asarray(phi, dtype=float)
        if periodic:
            step = np.round(phi / (2.0 * STEP_HALF_ANGLE))
            u = phi - step * 2.0 * STEP_HALF_ANGLE
            return step * self.budget.total + self._step_x(u)
        return self._step_x(phi)

    def displacement_rate(self, phi, *, periodic: bool = True):
        """dX/dφ = a − b + c + 3b cos 2φ (periodic: of the step's reduced angle), (...), m/rad."""
        phi = np.asarray(phi, dtype=float)
        if periodic:
            phi = phi - np.round(phi / (2.0 * STEP_HALF_ANGLE)) * 2.0 * STEP_HALF_ANGLE
        return self.a - self.b + self.c + 3.0 * self.b * np.cos(2.0 * phi)

    def _step_x(self, u):
        return (self.a - self.b + self.c) * u + 1.5 * self.b * np.sin(2.0 * u)
