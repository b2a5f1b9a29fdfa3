"""The equation of motion with the force analysis' Coulomb joint friction, solved for q̈ at every evaluation.

Friction couples the reactions (which grow with q̇² and q̈) back into the driving effort, so the reduced
equation is no longer linear in q̈. At (q, q̇) the acceleration is the root of

    g(q̈) = Q_d(q, q̇, q̈) + J_motor·q̈ − Q_motor(q̇) = 0,

Q_d the driving effort of the force analysis with friction (:func:`assur.forces` with ``friction=True``: a
revolute's couple r_f·|R| and a slide's μ·|N| against the relative motion, iterated to its fixed point) and J_motor
the rotor's and flywheel's inertia. g is nearly linear (slope ≈ J*), so a secant iteration from the frictionless
q̈ converges in a few steps. Friction vanishes at rest (q̇ = 0: no sticking is modelled).
"""
from __future__ import annotations

import numpy as np

from ..kinetostatics.api import forces

#: secant iterations at most, and the relative change of q̈ that ends them
ITERATIONS, CHANGE = 12, 1e-13


def _residual(eq, q: float, w: float, a: float, Qm: float) -> float:
    f = forces(eq.plan, eq.params, np.array([[q]]), speeds=[w], accels=[a], friction=True, backend="numpy")
    return float(f.driver[0, 0]) + eq.extra_inertia * a - Qm


def friction_acceleration(eq, q: float, w: float) -> float:
    """q̈ at (q, q̇ = w) of the equation with friction (module docstring)."""
    q, w = float(q), float(w)
    Qm = float(eq.motor(np.array(w))[0])
    J = float(eq.terms(np.array(q))[0])
    a0 = float(eq.acceleration(q, w))
    g0 = _residual(eq, q, w, a0, Qm)
    a1 = a0 - g0 / J
    for _ in range(ITERATIONS):
        g1 = _residual(eq, q, w, a1, Qm)
        if g1 == g0 or a1 == a0:
            break
        a0, a1, g0 = a1, a1 - g1 * (a1 - a0) / (g1 - g0), g1
        if abs(a1 - a0) <= CHANGE * max(abs(a1), 1e-300):
            break
    return a1


__all__ = ["friction_acceleration"]
