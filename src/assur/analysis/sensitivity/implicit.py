"""Implicit differentiation of the closure: the bodies' motion and its derivatives by every parameter, exactly.

The engine gives the positions X₀ of a batch (its bodies' origins and angles). With the closure Φ(X, p, q(t)) = 0
(:mod:`.closure`) along the time path q(t) = q₀ + q̇·t + q̈·t²/2 and the parameters p + ε·δ (δ each unit direction),
every Taylor coefficient of X(t, ε) follows from one linear solve with the Jacobian A = ∂Φ/∂X at the sample: the
coefficient of tᵏ (and of tᵏε) of Φ evaluated with the unknown coefficient set to zero is −A times it. So

    X(t) = X₀ + Ẋ·t + Ẍ·t²/2     (the velocities and accelerations, checked against the engine's jets)
    ∂X/∂p, ∂Ẋ/∂p, ∂Ẍ/∂p          (the sensitivities of positions, velocities and accelerations)

with no step to choose: the derivatives are those of the closure, to round-off.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ...kernels.jet import Jet
from .closure import Closure
from .series import Series

#: Taylor coefficients in time kept (the value, the velocity, half the acceleration)
ORDER = 3


def _solve(A, r):
    """x with A·x = r for A (N, n, n) and r (N, n, D) (NaN where A is singular)."""
    with np.errstate(all="ignore"):
        ok = np.all(np.isfinite(A), axis=(-1, -2)) & np.all(np.isfinite(r), axis=(-1, -2))
        safe = np.where(ok[:, None, None], A, np.eye(A.shape[-1]))
        try:
            x = np.linalg.solve(safe, np.where(ok[:, None, None], r, 0.0))
        except np.linalg.LinAlgError:
            x = np.stack([np.linalg.lstsq(a, b, rcond=None)[0] for a, b in zip(safe, np.where(ok[:, None, None], r,
                                                                                             0.0))])
    return np.where(ok[:, None, None], x, np.nan)


def body_coordinates(plan, state, n: int) -> np.ndarray:
    """(n, 3·(B − 1)) the moving bodies' origins (their first points) and angles from a solved state."""
    g = plan.structure.graph
    pos = np.reshape(state.pos, (n, -1, 2))
    ang = np.reshape(state.body_angle, (n, -1))
    cols = []
    for b in range(1, plan.n_bodies):
        i = plan.point_index(g.bodies[b].points[0])
        cols += [pos[:, i, 0], pos[:, i, 1], ang[:, b]]
    return np.stack(cols, axis=-1)


def input_series(plan, inputs, qdot, qddot, K: int = ORDER) -> list[Series]:
    """The inputs q(t) = q₀ + q̇·t + q̈·t²/2 and every gear and cam slot (through the engine's own slot jets), as
    series of the batch (n,)."""
    from ...engine.planar.steps import with_gear_slots
    n = inputs.shape[0]
    qd = np.broadcast_to(np.asarray(qdot, float), (plan.n_inputs,))
    qdd = np.broadcast_to(np.asarray(qddot, float), (plan.n_inputs,))
    jets = [Jet(inputs[:, k], np.full(n, qd[k]), np.full(n, qdd[k])) for k in range(plan.n_inputs)]
    out = []
    for j in with_gear_slots(plan, jets):
        coeffs = [j.v, j.d, 0.5 * j.dd][:K]
        out.append(Series([np.asarray(c, float)[:, None, None] for c in coeffs]))
    return out


@dataclass(frozen=True)
class Motion:
    """The closure's solution over a batch of n samples: ``X`` the bodies' coordinates as series (list of 3(B−1)
    :class:`~.series.Series`: value and time coefficients, ∂/∂p in ``e1`` with D = n_params directions), ``params``
    the parameter series, ``q`` the input-and-slot series, ``A`` (n, m, m) the Jacobian, ``closure``."""
    closure: Closure
    X: list
    params: list
    q: list
    A: np.ndarray


def _params(values, directions: bool, K: int) -> list[Series]:
    n, P = values.shape
    eye = np.eye(P)
    out = []
    for k in range(P):
        s = Series([values[:, k, None, None]] + [np.zeros((n, 1, 1)) for _ in range(K - 1)])
        if directions:
            s.e1 = [np.broadcast_to(eye[k][None, :, None], (n, P, 1))] + [np.zeros((n, P, 1)) for _ in range(K - 1)]
        out.append(s)
    return out


def solve_motion(plan, state, *, with_params: bool = True) -> Motion:
    """The motion of the bodies of a solved planar ``state`` (its samples flattened) as series: positions,
    velocities, accelerations and, with ``with_params``, their derivatives by every parameter."""
    cl = Closure(plan)
    n = int(np.prod(state.shape)) if state.shape else 1
    X0 = body_coordinates(plan, state, n)
    inputs = np.broadcast_to(np.asarray(state.inputs, float), tuple(state.shape) + (plan.n_inputs,)).reshape(n, -1)
    params = np.broadcast_to(np.asarray(state.params, float), tuple(state.shape) + (plan.n_params,)).reshape(n, -1)
    m = cl.n
    # the Jacobian: the ε₁ parts along the unit directions of X
    eye = np.eye(m)
    Xj = []
    for j in range(m):
        s = Series([X0[:, j, None, None]])
        s.e1 = [np.broadcast_to(eye[j][None, :, None], (n, m, 1))]
        Xj.append(s)
    r = cl.residual(Xj, _params(params, False, 1), [x.truncate(1) for x in input_series(plan, inputs, 0.0, 0.0, 1)])
    A = np.stack([np.broadcast_to(ri.e1[0][..., 0], (n, m)) if ri.e1 is not None else np.zeros((n, m))
                  for ri in r], axis=1)                                            # (n, equations, unknowns)
    q = input_series(plan, inputs, state.qdot, state.qddot, ORDER)
    # the time coefficients, one order at a time
    coeffs = [[X0[:, j]] for j in range(m)]
    P0 = _params(params, False, ORDER)
    for k in range(1, ORDER):
        X = [Series([c[:, None, None] for c in coeffs[j]] + [np.zeros((n, 1, 1))]) for j in range(m)]
        r = cl.residual(X, [x.truncate(k + 1) for x in P0], [x.truncate(k + 1) for x in q])
        rk = np.stack([np.broadcast_to(ri.v[k][..., 0, 0], (n,)) for ri in r], axis=-1)
        xk = _solve(A, -rk[..., None])[..., 0]
        for j in range(m):
            coeffs[j].append(xk[:, j])
    X = [Series([c[:, None, None] for c in coeffs[j]]) for j in range(m)]
    if not with_params:
        return Motion(cl, X, P0, q, A)
    Pp = _params(params, True, ORDER)
    D = plan.n_params
    dcoef = [[] for _ in range(m)]
    for k in range(ORDER):
        Xs = []
        for j in range(m):
            s = Series(X[j].v)
            s.e1 = [c for c in dcoef[j]] + [np.zeros((n, D, 1))] + [np.zeros((n, D, 1))] * (ORDER - k - 1)
            Xs.append(s)
        r = cl.residual(Xs, Pp, q)
        rk = np.stack([np.broadcast_to(ri.e1[k][..., 0], (n, D)) if ri.e1 is not None else np.zeros((n, D))
                       for ri in r], axis=1)                                       # (n, equations, D)
        xk = _solve(A, -rk)
        for j in range(m):
            dcoef[j].append(xk[:, j, :, None])
    for j in range(m):
        X[j].e1 = dcoef[j]
    return Motion(cl, X, Pp, q, A)
