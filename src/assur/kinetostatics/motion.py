"""The motion the force analysis needs, from a solved state's points alone.

Bodies' orientations, angular velocities and accelerations follow from two of their points
(θ = arg d, ω = Im(d′/d), α = Im(d″/d − (d′/d)²) with d = P_b − P_a), or from their guide's; the
centres of mass and their accelerations from the mass recipes. Everything is complex (x + iy) with
the state's batch shape ``(...)``; per-body arrays are lists indexed by body.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .tables import ForceTables


def _complex(a) -> np.ndarray:
    """(..., n, 2) real → (..., n) complex."""
    return a[..., 0] + 1j * a[..., 1]


def cross(a, b):
    """The planar cross product a × b of complex vectors (...)."""
    return (np.conj(a) * b).imag


def dot(a, b):
    return (np.conj(a) * b).real


@dataclass
class Motion:
    """Points ``z``, ``v``, ``a`` (..., n_points) complex; per body ``theta``, ``omega``, ``alpha`` (lists of
    (...) arrays or floats); per massive body ``com``, ``com_acc`` (complex) and ``inertia`` (real)."""
    z: np.ndarray
    v: np.ndarray
    a: np.ndarray
    theta: list
    omega: list
    alpha: list
    com: dict
    com_vel: dict
    com_acc: dict
    inertia: dict

    def line(self, tables: ForceTables, params, k: int):
        """(u, Q, Q_vel): the unit direction of slide line ``k`` in the frame (...) complex and the slider's
        reference point and its velocity."""
        kind, name, gb, slider, through, ia, io, ref, u_slider = tables.plan.lines[k]
        pidx = tables.plan.point_index(ref)
        if kind == "actuator":
            a = tables.plan.point_index(through)
            d = self.z[..., pidx] - self.z[..., a]
            u = d / np.abs(d)
        else:
            u = np.exp(1j * (self.theta[gb] + params[..., ia]))
        return u, self.z[..., pidx], self.v[..., pidx]


def motion(tables: ForceTables, state, params) -> Motion:
    """The :class:`Motion` of a solved planar ``state`` (solved with order 2)."""
    z, v, a = _complex(state.pos), _complex(state.vel), _complex(state.acc)
    nb = tables.n_bodies
    theta, omega, alpha = [0.0] * nb, [0.0] * nb, [0.0] * nb
    done = [False] * nb

    def solve_body(b):
        if done[b]:
            return
        rec = tables.angles[b]
        if rec.how == "points":
            d = z[..., rec.b] - z[..., rec.a]
            with np.errstate(all="ignore"):
                r1 = (v[..., rec.b] - v[..., rec.a]) / d
                r2 = (a[..., rec.b] - a[..., rec.a]) / d
            theta[b], omega[b], alpha[b] = np.angle(d), r1.imag, (r2 - r1 * r1).imag
        elif rec.how == "line":
            solve_body(rec.guide)
            theta[b] = theta[rec.guide] + params[..., rec.angle_param] + rec.offset
            omega[b], alpha[b] = omega[rec.guide], alpha[rec.guide]
        done[b] = True

    for b in range(nb):
        solve_body(b)
    com, com_vel, com_acc, inertia = {}, {}, {}, {}
    for b, bm in enumerate(tables.masses):
        if bm is None:
            continue
        c = sum(w * z[..., p] for w, p in zip(bm.weights, bm.points))
        cv = sum(w * v[..., p] for w, p in zip(bm.weights, bm.points))
        ca = sum(w * a[..., p] for w, p in zip(bm.weights, bm.points))
        if bm.offset:
            e = np.exp(1j * theta[b]) * bm.offset
            c = c + e
            cv = cv + 1j * omega[b] * e
            ca = ca + (1j * alpha[b] - omega[b] ** 2) * e
        com[b], com_vel[b], com_acc[b] = c, cv, ca
        if bm.inertia is not None:
            inertia[b] = bm.inertia
        elif bm.default == "bar":
            inertia[b] = bm.mass * np.abs(z[..., bm.points[1]] - z[..., bm.points[0]]) ** 2 / 12.0 \
                if len(bm.points) == 2 else _bar(tables, b, z, bm.mass)
        elif bm.default == "polygon":
            pts = tables.plan.structure.graph.bodies[b].points
            k = len(pts)
            inertia[b] = sum(bm.mass / k * np.abs(z[..., tables.plan.point_index(p)] - c) ** 2 for p in pts)
        else:
            inertia[b] = 0.0
    return Motion(z, v, a, theta, omega, alpha, com, com_vel, com_acc, inertia)


def _bar(tables, b, z, mass):
    """m·L²/12 of a binary link whose com recipe does not name both its points."""
    pts = tables.plan.structure.graph.bodies[b].points
    i, j = tables.plan.point_index(pts[0]), tables.plan.point_index(pts[1])
    return mass * np.abs(z[..., j] - z[..., i]) ** 2 / 12.0
