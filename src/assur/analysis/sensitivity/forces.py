"""The reactions and driving efforts as Lagrange multipliers of the closure, with their derivatives by every parameter.

At equilibrium (d'Alembert), for every virtual displacement δX of the bodies, Σ_c λ_c·δΦ_c + δW = 0, with W the
virtual work of the applied loads (gravity and inertia at each centre of mass, the file's loads). So Aᵀλ = −Q, with
A = ∂Φ/∂X and Q = ∂W/∂X, and each multiplier is a reaction: at a revolute, minus the force of the earlier body on
the later; at a slide, its normal force and couple; at a crank, minus its motor's torque. Differentiating along a
parameter direction δ with λ held, (Aᵀλ + Q)_δ is the mixed ε₁ε₂ part of λ·Φ + W evaluated with the virtual
displacements as ε₂ and the parameters (with the motion's own derivatives) as ε₁, so
λ_δ = −A⁻ᵀ·(Aᵀλ + Q)_δ — exactly, in one solve per sample.

The loads are those of :mod:`assur.kinetostatics` (its mass recipes and the file's ``[[loads]]``), without friction;
gear and cam pairs are carried by their drive unknowns (the torque on a gear- or cam-driven link, a translating
follower's drive along its slide), which is what the motor's torque sees (the tooth and contact forces only move
load between pivots: :mod:`assur.kinetostatics.gearing`, :mod:`assur.kinetostatics.camming`).
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ...kinetostatics.loads import point_body
from .implicit import Motion, _solve
from .series import Series, abs_complex


def coefficient(x: Series, k: int, factor: float = 1.0) -> Series:
    """The k-th time coefficient of ``x`` (value and ε₁ part) times ``factor``, as a series of one term."""
    return Series([x.v[k] * factor], None if x.e1 is None else [x.e1[k] * factor])


def _at(cl, X: list, p: list):
    """(world(b, point) → position series, pose) of the closure ``cl`` at coordinates ``X`` and parameters ``p``."""
    w, _ = cl.geometry(p)
    from .series import expi
    pose = {0: (0j, 1 + 0j)}
    for j, b in enumerate(cl.moving):
        pose[b] = (X[3 * j] + X[3 * j + 1] * 1j, expi(X[3 * j + 2]))

    def world(b, point):
        o, e = pose[b]
        return o + e * w[(b, point)]
    return world, pose


def angle_of(X: list, cl, b: int):
    """The series of body b's angle (0 for the frame)."""
    return 0.0 if b == 0 else X[3 * cl.moving.index(b) + 2]


def _loads(motion: Motion, plan, inputs):
    """The loads of the force analysis at the motion (value and ε₁ parts, one time coefficient): a list of
    (body, force, point name or None, couple); the force acts at the body's point, or at its centre of mass given
    by (points, weights, offset) when the point name is a tuple."""
    from ...kinetostatics.tables import force_tables
    t = force_tables(plan)
    cl = motion.closure
    world, pose = _at(motion.closure, motion.X, motion.params)
    g = complex(*t.dynamics.gravity[:2])
    items = []
    for b, bm in enumerate(t.masses):
        if bm is None:
            continue
        pts = [plan.point_names[i] for i in bm.points]
        C = sum((world(b, q) * wt for q, wt in zip(pts, bm.weights)), 0j)
        if bm.offset:
            C = C + pose[b][1] * bm.offset
        aC = coefficient(C, 2, 2.0)
        theta = angle_of(motion.X, cl, b)
        alpha = coefficient(theta, 2, 2.0) if isinstance(theta, Series) else 0.0
        if bm.inertia is not None or bm.default == "zero":
            J = bm.inertia or 0.0
        else:
            own = [p for p in plan.structure.graph.bodies[b].points]
            P = [coefficient(world(b, q), 0) for q in own]
            c0 = coefficient(C, 0)
            if bm.default == "bar":
                d = P[1] - P[0]
                J = (d * d.conj()).real * (bm.mass / 12.0)
            else:
                J = sum((((q - c0) * (q - c0).conj()).real * (bm.mass / len(P)) for q in P), 0.0)
        items.append((b, (aC * -1.0 + g) * bm.mass, ("com", pts, bm.weights, bm.offset), J * alpha * -1.0))
    q0 = inputs[:, 0]
    for load in t.dynamics.loads:
        value = _load_value(plan, load, q0)
        if load.force is None and load.point is None:
            from ...kinetostatics.tables import body_index
            items.append((body_index(plan, load.link), 0j, None, value))
            continue
        b = point_body(t, load.point, load.link)
        f = value
        if load.opposes == "velocity":
            v = coefficient(world(b, load.point), 1)
            f = v * (-np.abs(value)) / abs_complex(v)
        items.append((b, f, load.point, 0.0))
    return items


def _load_value(plan, load, q):
    if load.law is None:
        return complex(*load.force[:2]) if load.force is not None else float(load.torque)
    xs, ys = np.asarray(load.law.inputs, float), np.asarray(load.law.values, float)
    period = 2 * math.pi if plan.input_kinds[0] == "rotary" else None
    cols = [np.interp(q, xs, ys[:, j], period=period) for j in range(ys.shape[1])]
    v = cols[0] + 1j * cols[1] if ys.shape[1] == 2 else cols[0]
    return np.asarray(v)


def _virtual_work(motion: Motion, plan, items, X2, p2):
    """W at the displaced coordinates ``X2`` (ε₂ the virtual displacements) with the loads held."""
    world, pose = _at(motion.closure, X2, p2)
    cl = motion.closure
    W = 0.0
    for b, f, where, couple in items:
        if where is None:
            r = None
        elif isinstance(where, tuple):
            _, pts, weights, offset = where
            r = sum((world(b, q) * wt for q, wt in zip(pts, weights)), 0j)
            if offset:
                r = r + pose[b][1] * offset
        else:
            r = world(b, where)
        if r is not None and not (isinstance(f, complex) and f == 0):
            fb = f.conj() if isinstance(f, Series) else np.conj(f)
            W = W + (r * fb).real
        if not (isinstance(couple, float) and couple == 0.0):
            th = angle_of(X2, cl, b)
            if isinstance(th, Series):
                W = W + th * couple
    return W


@dataclass(frozen=True)
class Multipliers:
    """λ (n, m) and ∂λ/∂p (n, P, m) of the closure's equations (:attr:`~.closure.Closure.labels`), and the driving
    efforts Q_q = −Σ_c λ_c·∂Φ_c/∂q (n, n_inputs) with their derivatives (n, P, n_inputs): the generalised forces the
    drivers supply (a crank's torque in its input's sense, an actuator's force), gear and cam pairs included."""
    value: np.ndarray
    derivative: np.ndarray
    effort: np.ndarray
    effort_derivative: np.ndarray


def _input_seeds(plan, motion: Motion, inputs):
    """The inputs and slots at one time coefficient with ε₂ seeds on the inputs: a slot's ε₂ part is its rate by
    each input (the engine's slot jets along each input)."""
    from ...engine.planar.steps import with_gear_slots
    from ...kernels.jet import Jet
    n, k_in = inputs.shape[0], plan.n_inputs
    rates = []
    for k in range(k_in):
        jets = [Jet(inputs[:, i], np.full(n, 1.0 if i == k else 0.0), None) for i in range(k_in)]
        rates.append([j.d for j in with_gear_slots(plan, jets)])
    out = []
    for s, x in enumerate(motion.q):
        d = np.stack([np.broadcast_to(rates[k][s], (n,)) for k in range(k_in)], axis=-1)
        y = Series([x.v[0]])
        y.e2 = [d[:, None, :]]
        out.append(y)
    return out


def multipliers(motion: Motion, plan, inputs) -> Multipliers:
    """The closure's Lagrange multipliers at the motion, and their derivatives by the parameters."""
    cl = motion.closure
    m = cl.n
    n = motion.A.shape[0]
    items = _loads(motion, plan, inputs)
    eye = np.eye(m)
    X2 = []
    for j, x in enumerate(motion.X):
        s = Series([x.v[0]], [x.e1[0]])
        s.e2 = [np.broadcast_to(eye[j][None, None, :], (n, 1, m))]
        X2.append(s)
    p2 = [x.truncate(1) for x in motion.params]
    q2 = [x.truncate(1) for x in motion.q]
    W = _virtual_work(motion, plan, items, X2, p2)
    D = plan.n_params
    Q = np.zeros((n, m)) if not isinstance(W, Series) or W.e2 is None else np.broadcast_to(W.e2[0][:, 0, :], (n, m))
    lam = _solve(np.swapaxes(motion.A, -1, -2), -Q[..., None])[..., 0]
    r = cl.residual(X2, p2, q2)
    L = sum((ri * lam[:, c] for c, ri in enumerate(r)), 0.0)
    Z = np.zeros((n, D, m))
    for part in (L, W):
        if isinstance(part, Series) and part.e12 is not None:
            Z = Z + np.broadcast_to(part.e12[0], (n, D, m))
    dlam = np.swapaxes(_solve(np.swapaxes(motion.A, -1, -2), -np.swapaxes(Z, -1, -2)), -1, -2)   # (n, D, m)
    # the driving efforts: Q_q = −Σ λ_c ∂Φ_c/∂q, and their derivatives (λ's own and Φ's mixed ones)
    Xq = [Series([x.v[0]], [x.e1[0]]) for x in motion.X]
    rq = cl.residual(Xq, p2, _input_seeds(plan, motion, inputs))
    k_in = plan.n_inputs
    dq = np.stack([np.broadcast_to(ri.e2[0][:, 0, :], (n, k_in)) if ri.e2 is not None else np.zeros((n, k_in))
                   for ri in rq], axis=1)                                               # (n, m, n_in)
    G = sum((ri * lam[:, c] for c, ri in enumerate(rq)), 0.0)
    mixed = np.broadcast_to(G.e12[0], (n, D, k_in)) if isinstance(G, Series) and G.e12 is not None else 0.0
    effort = -np.einsum("nm,nmk->nk", lam, dq)
    deffort = -(np.einsum("ndm,nmk->ndk", dlam, dq) + mixed)
    return Multipliers(lam, dlam, effort, deffort)
