"""The applied loads on every body: gravity, D'Alembert inertia, the file's loads, extra point loads and
Coulomb friction (from a previous estimate of the reactions).

Inertia: a body of mass m and inertia I about its centre of mass C carries the force −m·a_C at C and
the couple −I·α (d'Alembert); gravity m·g at C. A force load at a point acts on the link it names or,
without one, on the earliest-solved body at the point. Friction, per pair, opposes the relative motion:
a revolute's couple −r_f·|R|·sign(ω_later − ω_earlier) on the later body (r_f the friction-circle
radius), a slide's force −μ·|N|·sign(v_rel)·u at the slider's reference point (v_rel the slider's velocity
along the line relative to the guide); the equal and opposite load acts on the other body.
"""
from __future__ import annotations

import math

import numpy as np

from .groups import Wrenches
from .motion import dot
from .tables import ForceTables, body_index


def apply_body_loads(W: Wrenches, inputs) -> None:
    """Gravity, inertia and the file's loads, added to ``W``. ``inputs (..., n_inputs)``."""
    t, mo = W.tables, W.motion
    g = complex(*t.dynamics.gravity[:2])
    for b, bm in enumerate(t.masses):
        if bm is None:
            continue
        c = mo.com[b]
        W.add(b, bm.mass * (g - mo.com_acc[b]), c, -mo.inertia[b] * mo.alpha[b])
    for load in t.dynamics.loads:
        value = _load_value(t, load, inputs)
        if load.torque is not None or (load.law is not None and load.force is None and load.point is None):
            W.add(body_index(t.plan, load.link), 0j, 0j, value)
            continue
        k = t.plan.point_index(load.point)
        f = value
        if load.opposes == "velocity":
            v = mo.v[..., k]
            speed = np.abs(v)
            with np.errstate(all="ignore"):
                f = np.where(speed > 0, -np.abs(value) * v / speed, 0j)
        W.add(point_body(t, load.point, load.link), f, mo.z[..., k])


def point_body(t: ForceTables, point: str, link: str | None = None) -> int:
    """The body a load at ``point`` acts on: ``link`` when given, else the earliest-solved body there."""
    if link is not None:
        return body_index(t.plan, link)
    at = t.plan.structure.graph.bodies_at(point)
    return min(at, key=lambda b: t.order[b])


def _load_value(t: ForceTables, load, inputs):
    """The load's force (complex) or torque (real), constant or interpolated at the first input."""
    if load.law is None:
        if load.force is not None:
            return complex(load.force[0], load.force[1])
        return float(load.torque)
    q = inputs[..., 0]
    xs = np.asarray(load.law.inputs, dtype=float)
    ys = np.asarray(load.law.values, dtype=float)
    period = 2 * math.pi if t.plan.input_kinds[0] == "rotary" else None
    cols = [np.interp(q, xs, ys[:, j], period=period) for j in range(ys.shape[1])]
    return cols[0] + 1j * cols[1] if ys.shape[1] == 2 else cols[0]


def friction_loads(W: Wrenches, previous: Wrenches) -> None:
    """The Coulomb friction loads from the reactions of ``previous``, added to ``W``."""
    t, mo = W.tables, W.motion
    fr = t.dynamics.friction
    for fp in t.pairs:
        if fp.kind == "R":
            r = fr.radius_at(fp.name)
            if not r:
                continue
            R = np.hypot(previous.lam[fp.columns[0]], previous.lam[fp.columns[1]])
            w_rel = _value(mo.omega[fp.later]) - _value(mo.omega[fp.earlier])
            couple = -r * R * np.sign(w_rel)
            W.add(fp.later, 0j, 0j, couple)
            W.add(fp.earlier, 0j, 0j, -couple)
        elif fp.kind == "P":
            mu = fr.mu_of(fp.name)
            if not mu:
                continue
            rec = t.plan.lines[fp.line]
            guide, slider, through = rec[2], rec[3], rec[4]
            u, Q, vQ = mo.line(t, W.params, fp.line)
            k = t.plan.point_index(through)
            v_guide = mo.v[..., k] + 1j * mo.omega[guide] * (Q - mo.z[..., k])
            v_rel = dot(vQ - v_guide, u)
            N = np.abs(previous.lam[fp.columns[0]])
            f = -mu * N * np.sign(v_rel) * u
            W.add(slider, f, Q)
            W.add(guide, -f, Q)


def _value(x):
    return np.asarray(x, dtype=float)
