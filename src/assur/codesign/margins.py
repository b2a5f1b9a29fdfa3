"""The fast margins of a co-designed law's transfer coefficients, shared by the walking leg's and the wheel-step
drive's searches: the gear checks of :mod:`assur.codesign.checks` as closed forms on fixed samples, each a margin
≥ 0 when met, and the scalar objective the searches minimise.

Margins (:data:`MARGIN_NAMES`, dimensionless unless named): ``convex_driving`` and ``convex_driven`` min κ·L over
each pitch curve; ``pressure_angle`` μ_max − max μ (rad); ``ratio_low`` G_min − lo, ``ratio_high`` hi − G_max;
``undercut_driving``/``undercut_driven`` 1 − (m/sin²α)·max|κ| (the module as given, not yet adjusted to a whole
tooth count); and, with a torque limit, ``torque`` 1 − (peak motor torque)/limit (:mod:`assur.codesign.torque`).
Convexity and pressure angle do not depend on L (r ∝ L, κ ∝ 1/L).

The ratio on the samples is linear in the transfer coefficients c (n_bumps,) for a given k, and k is affine in c
(the closure), so a law is G = k·window on the window samples and G = k·H + Σ c_j·B_j on the transfer samples with
the arrays ``window``, ``hermite`` (3, P) and ``bumps`` (3, n_bumps, P) (value and two derivatives along the driven
angle) prepared once by the caller.
"""
from __future__ import annotations

import numpy as np

from ..errors import SpecError
from .checks import pitch_terms

#: the gear margins, in order (a torque limit appends ``"torque"``)
MARGIN_NAMES = ("convex_driving", "convex_driven", "pressure_angle", "ratio_low", "ratio_high", "undercut_driving",
                "undercut_driven")
#: the margin vector of a coefficient set for which the law does not exist (k ≤ 0 or G ≤ 0 somewhere), offset by
#: how far it is from existing
INVALID = -100.0


class TransferMargins:
    """The margins (:data:`MARGIN_NAMES`) and the objective of the transfer coefficients c (n_bumps,) on fixed
    samples: ``window`` (3, Pw) the window's ratio for k = 1, ``hermite`` (3, Pt) and ``bumps`` (3, n_bumps, Pt) the
    transfer's (each: value, first and second derivative along the driven angle), ``k0`` and ``dk`` (n_bumps,) the
    closure k = k0 + dk·c; ``centre_distance`` L (m), ``undercut_limit`` m/sin²α (m), ``max_pressure_angle`` (rad),
    ``ratio_bounds`` (lo, hi); ``torque``: an optional callable (G, G′, G″) → the peak motor torque (N·m) with its
    ``limit`` (N·m), which adds the margin ``"torque"``."""

    def __init__(self, window, hermite, bumps, k0, dk, *, centre_distance, undercut_limit, max_pressure_angle,
                 ratio_bounds, torque=None, torque_limit=None):
        self.window, self.hermite, self.bumps, self.k0, self.dk = window, hermite, bumps, k0, dk
        self.L, self.limit, self.mu_max, self.bounds = centre_distance, undercut_limit, max_pressure_angle, ratio_bounds
        self.torque, self.torque_limit = torque, torque_limit
        self.names = MARGIN_NAMES + (("torque",) if torque is not None else ())

    def ratio_samples(self, c):
        """(k, (3, Pw + Pt)): G, G′, G″ on the window samples then the transfer samples."""
        c = np.asarray(c, dtype=float).reshape(-1)
        k = self.k0 + float(self.dk @ c)
        transfer = k * self.hermite + np.einsum("j,ojp->op", c, self.bumps)
        return k, np.concatenate([k * self.window, transfer], axis=1)

    def _evaluate(self, c):
        """(margins (len(names),), pitch terms or None): :meth:`margins` and the terms they came from (None for a
        law that does not exist), so that :meth:`objective` reads the same terms instead of computing them again."""
        k, (g, dg, d2g) = self.ratio_samples(c)
        g_min = float(g.min())
        if not (k > 0 and g_min > 0):
            return np.full(len(self.names), INVALID + min(k, g_min)), None
        t = pitch_terms(g, dg, d2g, self.L)
        lo, hi = self.bounds
        out = [float(t["kappa_driving"].min() * self.L), float(t["kappa_driven"].min() * self.L),
               self.mu_max - float(np.arctan(t["tan_pressure"]).max()), g_min - lo, hi - float(g.max()),
               1.0 - self.limit * float(np.abs(t["kappa_driving"]).max()),
               1.0 - self.limit * float(np.abs(t["kappa_driven"]).max())]
        if self.torque is not None:
            out.append(1.0 - self.torque(g, dg, d2g) / self.torque_limit)
        return np.array(out), t

    def margins(self, c) -> np.ndarray:
        """The margins of :attr:`names` (≥ 0 met) for the coefficients c (n_bumps,). A law that does not exist
        (k ≤ 0 or G ≤ 0) gives every margin −100 + min(k, min G) (≤ −100)."""
        return self._evaluate(c)[0]

    def objective(self, c) -> float:
        """Scalar to minimise: the total violation V = Σ max(0, −margin) + the mean concave depth of both curves
        (mean of max(0, −κ·L)) when V > 0, else −min(margins) (the worst margin, maximised)."""
        m, t = self._evaluate(c)
        if t is None:
            return float(1e3 - m[0])
        depth = sum(float(np.mean(np.maximum(0.0, -t[f"kappa_{n}"] * self.L))) for n in ("driving", "driven"))
        violation = float(np.sum(np.maximum(0.0, -m))) + depth
        return violation if violation > 0 else -float(np.min(m))


def check_spread(spread) -> float:
    """The search box's half width about the smoothest bridge, a positive number, else SpecError naming it."""
    if not (np.isfinite(spread) and spread > 0):
        raise SpecError([("spread", f"must be a positive number: {spread!r}")])
    return float(spread)


def search_transfer(objective, start, *, spread: float, seed, maxiter: int, popsize: int):
    """(best c, message, evaluations): scipy's differential evolution of ``objective`` over c ∈ ``start`` ±
    ``spread`` (seeded, starting from ``start``, polished); the start itself when nothing beats it."""
    from scipy.optimize import differential_evolution
    res = differential_evolution(objective, [(c - spread, c + spread) for c in start], x0=start, seed=seed,
                                 maxiter=int(maxiter), popsize=int(popsize), tol=1e-10, polish=True)
    best = np.asarray(res.x, dtype=float) if res.fun <= objective(start) else start
    return best, str(res.message), int(res.nfev)


__all__ = ["INVALID", "MARGIN_NAMES", "TransferMargins", "check_spread", "search_transfer"]
