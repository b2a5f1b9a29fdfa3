"""The law of paper 001 revisited (assur issue 15): the wheel-step mover's gear drive redesigned with the co-design law of
:mod:`assur.codesign.law`, so that the pitch curves have no corners.

The paper (docs/papers/001.md B2) makes the mover's horizontal speed constant over the **whole** step: the driving
angle ψ is proportional to the mover's displacement X(θ) (θ the hub angle, one step θ ∈ [−π/4, π/4]) and the law is
continued step by step, so dψ/dθ = K·X′(θ) has a kink at every step end and the pitch curves have corners there
(79.55° tangent jumps for the printed design, :class:`~assur.gears.law.WheelStepLaw`). Here the speed is exactly
constant over the central fraction f of each step's displacement (the window) and a C² transfer joins the windows
across the step ends (the co-design law's Hermite bridge + bumps): no kink, no corner.

Mapping onto the co-design machinery, whose "crank" q makes one turn per window + transfer and whose "motor" τ
turns ``driving_turns`` = 1 times per crank turn (g(q) = dτ/dq, ∫ g over a crank turn = 2π):

- one hub step ↔ one crank turn: q = S·θ + π (S = 4 steps per hub turn), so q = 0 and 2π are the step ends
  θ = ∓π/4, q = π the step centre θ = 0; the "foot" stride coordinate is the mover's displacement within the step,
  x(q) = X(θ) = (a − b + c)·θ + 1.5·b·sin 2θ ∈ [−X_01/2, X_01/2] (:meth:`assur.gears.wheelstep.Shoe.displacement`),
  evaluated exactly (not a spline: :class:`StepDisplacement`); the whole step is the support (contact arc
  [0, 2π]); the window is the central fraction f of X_01 (:func:`~assur.codesign.law.support_window`), the
  transfer the rest of the step near its two ends, where the paper has its corners;
- the real driving gear turns n = ``driving_turns`` times per hub turn (the paper: n = 2), i.e. n/S turns per
  step: ψ = (n/S)·(τ(q) − τ(π)), so ψ = 0 at the step centre (the paper's zero: the driver's smallest radius) and
  one driving turn is S/n whole steps (n ∈ {1, 2, 4}, as for WheelStepLaw);
- the gear package's law (driving ψ, driven θ) then has k = dθ/dψ = 1/G with G(θ) = dψ/dθ = n·g(q), and
  dG/dθ = n·S·g′(q), d²G/dθ² = n·S²·g″(q). On the window G = (n·k_c/S)·X′(θ) (k_c the co-design constant): the
  mover speed dX/dt = X′·θ̇ = ω_ψ·X′/G = ω_ψ·S/(n·k_c) is exactly constant.

Pitch curves at centre distance L: driving r1 = L/(1 + G), driven r2 = L·G/(1 + G); the closed-form checks of
:func:`assur.codesign.checks.pitch_terms` apply with G and its θ-derivatives in place of g (the hub angle is
the "crank" angle of that module with one crank turn per hub turn). One step covers every distinct stretch of both
curves (the driven curve is S identical quarters, the driving curve S/n identical parts). With u = 1/r the polar
convexity test u″ + u > 0 reads d²k/dθ² + k + 1 > 0 for the driven curve (u2 = (1 + k)/L) and d²G/dψ² + G + 1 > 0
for the driving one: across the transfer dk/dθ must turn from +|X″|/(K·X′²) at one window edge to its negative at
the next, which a narrow transfer (a wide window) cannot do without a concave stretch of the hub gear.

The search for the transfer, the measured mover speed and the paper's pair for comparison are
:mod:`assur.codesign.wheelstep`'s; the gear checks :func:`assur.codesign.checks.gear_checks`'s.
"""
from __future__ import annotations

import math

import numpy as np

from ..errors import GearError, SpecError
from ..gears.law import TransmissionLaw, WheelStepLaw
from ..gears.wheelstep import STEP_HALF_ANGLE, Shoe
from .law import CodesignLaw, FootLaw

TWO_PI = 2.0 * math.pi
#: hub steps per hub turn (a step is 2·STEP_HALF_ANGLE = 90° of hub angle)
STEPS = int(round(math.pi / STEP_HALF_ANGLE))


def check_turns(driving_turns) -> int:
    """n, the driving-gear turns per hub turn: 1, 2 or 4, else SpecError naming ``driving_turns``."""
    if isinstance(driving_turns, bool) or driving_turns not in (1, 2, 4):
        raise SpecError([("driving_turns", f"must be 1, 2 or 4 (driving-gear turns per hub turn, so that one "
                                           f"driving turn is a whole number of 90° hub steps): {driving_turns!r}")])
    return int(driving_turns)



# ---------------------------------------------------------------------------------------------------------------
# the mover's displacement as the co-design "foot"


class StepDisplacement:
    """The mover's displacement within one hub step as an exact function of the co-design crank angle:
    x(q) = X((q − π)/S), q ∈ [0, 2π) (the step θ ∈ [−π/4, π/4)), with X(θ) = A·θ + 1.5·b·sin 2θ, A = a − b + c
    (docs/papers/001.md B2). Called as ``spline(q, order)`` by :class:`~assur.codesign.law.FootLaw`:
    q (...) → d^order x/dq^order (...), m/rad^order, order 0 … 4."""

    def __init__(self, shoe: Shoe):
        self.shoe = shoe

    def __call__(self, q, order: int = 0):
        theta = (np.asarray(q, dtype=float) - math.pi) / STEPS
        if order == 0:
            return self.shoe.displacement(theta, periodic=False)
        if order == 1:
            rate = self.shoe.displacement_rate(theta, periodic=False)
        else:   # d^o/dθ^o of 1.5·b·sin 2θ = 1.5·b·2^o·sin(2θ + o·π/2)
            rate = 1.5 * self.shoe.b * 2.0 ** order * np.sin(2.0 * theta + order * math.pi / 2.0)
        return rate / STEPS ** order


def step_foot(shoe: Shoe, samples: int = 256) -> FootLaw:
    """The co-design :class:`~assur.codesign.law.FootLaw` of the mover over one hub step (module docstring):
    exact x(q) (:class:`StepDisplacement`), contact arc = the whole step [0, 2π], stride ends ∓X_01/2; ``samples``
    (N,) uniform values are stored for reference only."""
    exact = StepDisplacement(shoe)
    q = np.linspace(0.0, TWO_PI, int(samples), endpoint=False)
    half = 0.5 * shoe.budget.total
    return FootLaw(q, exact(q), exact, 0.0, TWO_PI, -half, half)


# ---------------------------------------------------------------------------------------------------------------
# the law of the gear pair


class WheelStepCodesignLaw(TransmissionLaw):
    """The redesigned wheel-step law as a :class:`~assur.gears.law.TransmissionLaw` (driving ψ, driven = hub θ):
    ψ(θ) = (n/S)·(τ(Sθ + π) − τ(π)) from a co-design law τ(q) over one step (module docstring).

    Attributes: ``codesign`` (the :class:`CodesignLaw`), ``shoe``, ``driving_turns`` n, ``fraction`` f,
    ``window`` (θ1, θ2): the hub angles of the window's ends in the step around θ = 0 (rad)."""

    def __init__(self, codesign: CodesignLaw, shoe: Shoe, driving_turns: int = 2):
        if codesign.driving_turns != 1 or codesign.sense != 1:
            raise GearError("the wheel-step co-design law needs one motor turn per step and a forward crank")
        self.codesign = codesign
        self.shoe = shoe
        self.driving_turns = check_turns(driving_turns)
        self.fraction = codesign.fraction
        self.window = ((codesign.q1 - math.pi) / STEPS, (codesign.q2 - math.pi) / STEPS)
        self._centre = float(codesign.motor_angle(math.pi))
        self.description = (f"wheel-step law (paper 001) redesigned: constant mover speed over the central "
                            f"{self.fraction:g} of each step, C² transfer across the step ends")

    def __repr__(self):
        return f"WheelStepCodesignLaw({self.codesign!r}, driving_turns={self.driving_turns})"

    def _q(self, theta):
        return STEPS * np.asarray(theta, dtype=float) + math.pi

    def ratio_terms(self, theta):
        """(G, dG/dθ, d²G/dθ²) at hub angles θ (...) → three (...) arrays; G = dψ/dθ = 1/k."""
        q, n = self._q(theta), self.driving_turns
        return (n * self.codesign.g(q), n * STEPS * self.codesign.dg(q), n * STEPS ** 2 * self.codesign.d2g(q))

    def in_window(self, theta) -> np.ndarray:
        """(...) bool: the hub angles θ (...) lie in a constant-speed window."""
        return self.codesign.in_window(self._q(theta))

    def phi_of(self, theta) -> np.ndarray:
        return (self.driving_turns / STEPS) * (self.codesign.motor_angle(self._q(theta)) - self._centre)

    def ratio_of_theta(self, theta) -> np.ndarray:
        return 1.0 / (self.driving_turns * self.codesign.g(self._q(theta)))

    def _hub(self, u):
        return (self.codesign.crank_angle(STEPS * np.asarray(u, dtype=float) / self.driving_turns + self._centre)
                - math.pi) / STEPS

    def _turn_theta(self, u):
        return self._hub(u)

    def _turn_ratio(self, u):
        return self.ratio_of_theta(self._hub(u))

    def corner_thetas(self) -> np.ndarray:
        """No kinks: (0,)."""
        return np.empty(0)


def paper_ratio_terms(law: WheelStepLaw, theta):
    """(G, G′, G″) of the paper's law (unrounded) at hub angles θ (...), each step's closed form (one-sided at the
    step ends): G = dψ/dθ = K·X′(θ), K = n·π/(2·X_01) (docs/papers/001.md B2), X′ = A + 3b·cos 2u, u the angle
    from the step centre."""
    if law.rounding > 0:
        raise GearError("paper_ratio_terms needs the paper's law (rounding = 0)")
    theta = np.asarray(theta, dtype=float)
    u = theta - np.round(theta / (2.0 * STEP_HALF_ANGLE)) * 2.0 * STEP_HALF_ANGLE
    shoe = law.shoe
    K = law.driving_turns * math.pi / (2.0 * shoe.budget.total)
    b = shoe.b
    return (K * shoe.displacement_rate(u, periodic=False), -6.0 * K * b * np.sin(2.0 * u),
            -12.0 * K * b * np.cos(2.0 * u))


def step_terms(law, theta):
    """(G, G′, G″) of a wheel-step law at hub angles θ (...): the redesigned law's closed form, or the paper's
    (:func:`paper_ratio_terms`). GearError for any other law."""
    if isinstance(law, WheelStepCodesignLaw):
        return law.ratio_terms(theta)
    if isinstance(law, WheelStepLaw):
        return paper_ratio_terms(law, theta)
    raise GearError(f"a co-designed law is needed (CodesignLaw, WheelStepCodesignLaw or the paper's WheelStepLaw): "
                    f"{law!r}")


def driven_perimeter(law, centre_distance: float, *, panels: int = 128, nodes: int = 8) -> float:
    """Perimeter (m) of the driven (hub) pitch curve, S·∫ √(r2² + (dr2/dθ)²) dθ over one step (r2 = L·G/(1 + G)),
    by Gauss–Legendre quadrature on ``panels`` panels of each smooth piece (window and the transfer's two halves;
    the paper's step is one piece). The driving curve is 1/n of it (both roll the same arc)."""
    x, w = np.polynomial.legendre.leggauss(nodes)
    ends = [-STEP_HALF_ANGLE, STEP_HALF_ANGLE]
    if isinstance(law, WheelStepCodesignLaw):
        ends = [-STEP_HALF_ANGLE, *law.window, STEP_HALF_ANGLE]
    total = 0.0
    for lo, hi in zip(ends[:-1], ends[1:]):
        edges = np.linspace(lo, hi, panels + 1)
        mid, half = 0.5 * (edges[1:] + edges[:-1]), 0.5 * (edges[1:] - edges[:-1])
        G, dG, _ = step_terms(law, (mid[:, None] + half[:, None] * x).ravel())
        ds = np.hypot(G / (1.0 + G), dG / (1.0 + G) ** 2)
        total += float(np.sum((half[:, None] * w).ravel() * ds))
    return STEPS * total * float(centre_distance)


__all__ = ["STEPS", "STEP_HALF_ANGLE", "StepDisplacement", "WheelStepCodesignLaw", "check_turns", "driven_perimeter",
           "paper_ratio_terms", "step_foot", "step_terms"]
