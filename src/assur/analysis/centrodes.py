"""Centrodes, the inflection circle, and a coupler point's centre of curvature by Euler–Savary and by Bobillier.

**Centrodes.** The instant centre P of a body j relative to a body i, seen from i over the run, is the *fixed*
centrode; seen from j, the *moving* centrode. The moving one rolls on the fixed one without slipping: at each instant
both pass through P, and the rate at which P runs along either (the pole velocity relative to i, Ṗ − v_i(P), or to
j, Ṗ − v_j(P)) is the same vector, since v_i(P) = v_j(P) at the centre. The pole velocity comes from the exact
accelerations: with P = P_i + i·w₀/Δω (:mod:`.instant_centres`),
Ṗ = Ṗ_i + i·(ẇ₀·Δω − w₀·Δω̇)/Δω², ẇ₀ = a_j(P_i) − a_i(P_i) + i·ω_j·(v_i(P_i) − v_j(P_i)) … (in the code).

**Inflection circle** (of j relative to the frame): the points of j whose paths have zero curvature at the instant.
With u = Ṗ/ω the pole velocity per unit turn, the acceleration of j's point X is a = (iα − ω²)(X − P) − iωṖ, and
v × a = 0 gives |X − P|² = (X − P)·(−i·u): the circle through P with diameter P J, J = P − i·u (the inflection
pole), diameter D = |u|.

**Euler–Savary.** A point X of j at distance r from P along the unit ray e: the ray meets the inflection circle at
distance d = (J − P)·e; the centre of curvature X₀ of X's path lies on the same ray at r₀ with
1/r − 1/r₀ = 1/d (Hartenberg & Denavit, *Kinematic Synthesis of Linkages*, §7.5: (1/r − 1/r₀)·sin ψ = 1/D).

**Bobillier** (a four-bar A₀ABB₀): the collineation axis runs from P to Q = AB ∩ A₀B₀, and the angle from the pole
tangent to PA equals the angle from PB to the collineation axis. The same theorem for the pair (A, C) gives a coupler
point C's centre of curvature with ruler and compass: the axis of (A, C) at that angle from PC, Q′ = AC ∩ that axis,
C₀ = A₀Q′ ∩ PC (:func:`bobillier`). The tests find the same C₀ three ways: Bobillier's construction, Euler–Savary
on the inflection circle, and the path's curvature v × a from the engine's jets.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np


def _flat(a, n, tail=()):
    return np.reshape(a, (n,) + tail)


def _cross(a, b):
    return np.imag(np.conj(a) * b)


def _dot(a, b):
    return np.real(np.conj(a) * b)


def _body_data(plan, state, b):
    """(n,) arrays of body b: a reference point's position, velocity, acceleration (complex), θ, ω, α, and the
    body frame's origin (its first point)."""
    n = int(np.prod(state.shape)) if state.shape else 1
    i = plan.point_index(plan.structure.graph.bodies[b].points[0])

    def c(a):
        a = _flat(a[..., i, :], n, (2,))
        return a[:, 0] + 1j * a[:, 1]
    z, v, a = c(state.pos), c(state.vel), c(state.acc)
    th = _flat(state.body_angle, n, (plan.n_bodies,))[:, b]
    w = _flat(state.body_omega, n, (plan.n_bodies,))[:, b]
    al = _flat(state.body_alpha, n, (plan.n_bodies,))[:, b]
    return z, v, a, th, w, al


def _body(plan, name):
    return plan.body_names.index(name) if isinstance(name, str) else int(name)


def pole(plan, state, moving, fixed=0):
    """(P, Ṗ, Δω, Δω̇): the instant centre of body ``moving`` relative to ``fixed`` (n,) complex, its velocity in the
    frame, the relative angular velocity and acceleration, from the exact velocities and accelerations of ``state``
    (order 2; its samples flattened)."""
    i, j = _body(plan, fixed), _body(plan, moving)
    zi, vi, ai, _, wi, ali = _body_data(plan, state, i)
    zj, vj, aj, _, wj, alj = _body_data(plan, state, j)
    # j's and i's velocity and acceleration at P_i (the point of i carried by each body)
    vj_at = vj + 1j * wj * (zi - zj)
    aj_at = aj + (1j * alj - wj * wj) * (zi - zj)
    w0 = vj_at - vi
    dw, ddw = wj - wi, alj - ali
    # d/dt of w₀ following the point P_i of body i: ẇ₀ = d/dt [v_j(P_i)] − a_i, with P_i moving at v_i
    w0_dot = aj_at + 1j * wj * (vi - vj_at) - ai
    with np.errstate(divide="ignore", invalid="ignore"):
        P = zi + 1j * w0 / dw
        Pdot = vi + 1j * (w0_dot * dw - w0 * ddw) / (dw * dw)
    return P, Pdot, dw, ddw


@dataclass(frozen=True)
class Centrodes:
    """The centrodes of body ``moving`` relative to body ``fixed`` over a run of n samples: ``world`` (n,) the
    instant centre in the frame, ``fixed_curve`` (n,) in the fixed body's own frame (its first point at the origin,
    its second on +x), ``moving_curve`` (n,) in the moving body's, and ``rate`` (n,) the pole velocity relative to the
    fixed body (m/s, in the frame's orientation): the common velocity of the contact point along both curves."""
    moving: str
    fixed: str
    world: np.ndarray
    fixed_curve: np.ndarray
    moving_curve: np.ndarray
    rate: np.ndarray


def centrodes(plan, state, moving, fixed=0) -> Centrodes:
    """The fixed and moving centrodes of body ``moving`` relative to ``fixed`` (names or indices) over ``state``."""
    i, j = _body(plan, fixed), _body(plan, moving)
    P, Pdot, _, _ = pole(plan, state, j, i)
    zi, vi, _, thi, wi, _ = _body_data(plan, state, i)
    zj, _, _, thj, _, _ = _body_data(plan, state, j)
    rate = Pdot - (vi + 1j * wi * (P - zi))
    return Centrodes(plan.body_names[j], plan.body_names[i], P, np.exp(-1j * thi) * (P - zi),
                     np.exp(-1j * thj) * (P - zj), rate)


@dataclass(frozen=True)
class Inflection:
    """The inflection circle of a body relative to the frame at n samples: ``pole`` P, ``tangent`` (unit, the pole
    tangent: along the pole velocity), ``inflection_pole`` J (P − i·Ṗ/ω), ``centre`` (P + J)/2 and ``diameter`` |J − P|
    (m); ``omega`` the body's angular velocity."""
    pole: np.ndarray
    tangent: np.ndarray
    inflection_pole: np.ndarray
    centre: np.ndarray
    diameter: np.ndarray
    omega: np.ndarray


def inflection_circle(plan, state, body) -> Inflection:
    """The inflection circle of ``body`` relative to the frame over ``state``."""
    P, Pdot, w, _ = pole(plan, state, body, 0)
    with np.errstate(divide="ignore", invalid="ignore"):
        u = Pdot / w
        J = P - 1j * u
        t = Pdot / np.abs(Pdot)
    return Inflection(P, t, J, 0.5 * (P + J), np.abs(u), w)


def euler_savary(infl: Inflection, X) -> np.ndarray:
    """(n,) the centre of curvature of the path of the point at ``X`` (n,) (complex, of the inflection circle's body)
    by the Euler–Savary equation 1/r − 1/r₀ = 1/d on the ray from the pole (d: where the ray meets the inflection
    circle); inf where X lies on the circle."""
    X = np.asarray(X)
    d = X - infl.pole
    r = np.abs(d)
    e = d / r
    dd = _dot(infl.inflection_pole - infl.pole, e)
    with np.errstate(divide="ignore", invalid="ignore"):
        r0 = 1.0 / (1.0 / r - 1.0 / dd)
    return infl.pole + r0 * e


def curvature_centre(plan, state, point) -> np.ndarray:
    """(n,) the centre of curvature of ``point``'s path in the frame, X + i·v·|v|²/(v × a), from the state's exact
    velocity and acceleration."""
    n = int(np.prod(state.shape)) if state.shape else 1
    k = plan.point_index(point)
    z, v, a = (_flat(x[..., k, :], n, (2,)) for x in (state.pos, state.vel, state.acc))
    z, v, a = (x[:, 0] + 1j * x[:, 1] for x in (z, v, a))
    with np.errstate(divide="ignore", invalid="ignore"):
        return z + 1j * v * np.abs(v) ** 2 / _cross(v, a)


def _meet(p1, d1, p2, d2):
    """The intersection of the lines p1 + s·d1 and p2 + t·d2 (complex, element-wise)."""
    with np.errstate(divide="ignore", invalid="ignore"):
        s = _cross(p2 - p1, d2) / _cross(d1, d2)
    return p1 + s * d1


def bobillier(A0, A, B0, B, C):
    """Bobillier's construction on a four-bar A₀ABB₀ (the coupler carrying A, B and C; A₀, B₀ on the frame), points
    complex (n,) or scalars: (P, pole tangent (unit), collineation axis (unit), C₀ the centre of curvature of C's
    path). Ruler and compass only: no velocity enters."""
    P = _meet(A0, A - A0, B0, B - B0)
    Q = _meet(A, B - A, A0, B0 - A0)
    axis = (Q - P) / np.abs(Q - P)
    # Bobillier: ∠(t, PA) = ∠(PB, axis)  ⇒  t = PA turned back by ∠(PB, axis)
    ea, eb = (A - P) / np.abs(A - P), (B - P) / np.abs(B - P)
    t = ea / (axis / eb)
    # the pair (A, C): its collineation axis is PC turned by ∠(t, PA)
    ec = (C - P) / np.abs(C - P)
    axis_c = ec * (ea / t)
    Qc = _meet(A, C - A, P, axis_c)
    C0 = _meet(A0, Qc - A0, P, ec)
    return P, t, axis, C0
