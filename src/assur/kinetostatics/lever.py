"""Zhukovsky's lever: the velocity plan turned 90° as a rigid lever pivoted at its pole.

Every applied load (gravity and the d'Alembert inertia force m·(g − a_C) at the centre of mass C, the
inertia couple −I·α, the file's loads, extra point loads) is carried over to the image of its point of
application in the velocity plan turned 90° counter-clockwise, i·v. The moment of a force F about the pole
at the image i·v is (i·v) × F = −F·v, and a couple M on a body turning at ω counts −M·ω. The lever's moment
sum is therefore minus the virtual power of the applied loads, and the balance of the lever (without
friction) gives the driving effort: ``moment = Σ Q_k·q̇_k`` — the classical graphical check of a force
analysis.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..engine import solve
from ..engine.plan import require_plan
from .api import state_rows
from .groups import body_rows
from .kernel import cross
from .loads import applied_items
from .program import program_of
from .tables import force_tables


@dataclass(frozen=True)
class Lever:
    """The lever of a batch (shape ``...``).

    ``points (..., k)`` the applied forces' points (complex, m), ``images (..., k)`` their images i·v on the
    lever (m/s, the velocity plan turned 90° ccw), ``forces (..., k)`` the forces (N, complex), ``bodies (k,)``
    the body names, ``couple_moment (...)`` −Σ M·ω of the applied couples (W), ``moment (...)`` the lever's
    moment sum about the pole (W): Σ (i·v) × F − Σ M·ω, equal to Σ driver·q̇ without friction.
    """
    points: np.ndarray
    images: np.ndarray
    forces: np.ndarray
    bodies: tuple[str, ...]
    couple_moment: np.ndarray
    moment: np.ndarray


def lever(plan, params=None, inputs=None, *, speeds=None, point_loads=None, state=None) -> Lever:
    """Zhukovsky's lever of a planar plan at a batch of inputs (see the module docstring)."""
    require_plan(plan, planar=True)
    if state is None:
        state = solve(plan, params, inputs, speeds=speeds, order=2)
    shape = state.shape
    n = math.prod(shape)
    tables, prog = force_tables(plan), program_of(plan)
    z, v, a, p = state_rows(state, n)
    orient, omega, alpha = body_rows(prog, z, v, a, p)
    q0 = np.broadcast_to(state.inputs, shape + (plan.n_inputs,)).reshape(n, -1)[:, 0]
    with np.errstate(all="ignore"):
        items = applied_items(tables, prog, z, v, a, p, orient, omega, alpha, q0, point_loads, shape)
    graph = plan.structure.graph
    pts, imgs, fs, names = [], [], [], []
    couples = np.zeros(n)
    for body, force, at, moment in items:
        w = omega[body]
        couples = couples - np.asarray(moment, dtype=float) * w
        force = np.broadcast_to(np.asarray(force, complex), (n,))
        if not np.any(force):
            continue
        ref = plan.point_index(graph.bodies[body].points[0])
        at = np.broadcast_to(np.asarray(at, complex), (n,))
        vel = v[ref] + 1j * w * (at - z[ref])      # the velocity of the body's material point at ``at``
        pts.append(at)
        imgs.append(1j * vel)
        fs.append(force)
        names.append(plan.body_names[body])
    stack = (lambda x: np.stack(x, axis=-1).reshape(shape + (len(x),))) if pts \
        else (lambda x: np.zeros(shape + (0,), complex))
    points, images, forces_ = stack(pts), stack(imgs), stack(fs)
    couples = couples.reshape(shape)
    moment = np.sum(cross(images, forces_), axis=-1) + couples
    return Lever(points, images, forces_, tuple(names), couples, moment)
