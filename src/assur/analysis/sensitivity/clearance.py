"""Joint clearance by the effective-link model, against a Monte Carlo of randomly oriented clearance links.

A revolute joint with diametral clearance c lets its pin sit anywhere within c/2 of the hole's centre. Under load the
pin rests against the wall, on the side the joint's force pushes it: the *effective link* (Earles & Wu; Tsai & Lai,
*Mechanism and Machine Theory* 43 (2008)) is a massless link of length c/2 from the hole's centre toward the
reaction, δ = (c/2)·R̂, R the force of the joint's earlier body on its later body (:mod:`assur.kinetostatics`'s
convention): the later body's pin centre sits at −δ from the hole's, so the closure's joint equation becomes
pos_earlier − pos_later = δ.

The output error follows to first order from the exact derivatives of the outputs by each joint's offset
(G_j = ∂P/∂δ_j, 2 × 2, from the implicit differentiation of the closure with the offsets as parameters):

- effective-link error e = Σ_j G_j·δ_j over the cycle (the loaded mechanism's actual error);
- worst case over every orientation of every clearance link: Σ_j (c_j/2)·‖G_j‖₂ (the spectral norm);
- where a reaction passes near zero (|R| below ``loss`` of its peak) the pin crosses its clearance: contact is lost
  there and the effective link flips (flagged, with the inputs).

The Monte Carlo draws every clearance link's direction uniformly and solves the closure exactly (Newton's method
from the nominal position), so the comparison includes the model's nonlinearity.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ...errors import SpecError
from .closure import Closure
from .implicit import _params, _solve, body_coordinates, input_series
from .series import Series

#: a reaction below this fraction of its peak over the cycle counts as crossing zero (contact loss)
LOSS = 0.02


class _OffsetClosure(Closure):
    """The closure with a prescribed offset pos_earlier − pos_later = δ_k at some revolute pairs."""

    def __init__(self, plan, offsets: dict):
        super().__init__(plan)
        self.offsets = offsets            # {force-table pair index: complex series or array (n,)}

    def residual(self, X, p, q):
        out = super().residual(X, p, q)
        row = 0
        for k, e, l, point in self.revolutes:
            d = self.offsets.get(k)
            if d is not None:
                out[row] = out[row] - (d.real if isinstance(d, Series) else np.real(d))
                out[row + 1] = out[row + 1] - (d.imag if isinstance(d, Series) else np.imag(d))
            row += 2
        return out


def _joint_rows(cl: Closure):
    return {k: i for i, (k, e, l, point) in enumerate(cl.revolutes)}


def offset_derivatives(plan, state, point: str):
    """G (n, J, 2, 2): ∂(x, y of ``point``)/∂(δx, δy) of every revolute pair j of the force tables (J of them, in
    :attr:`Closure.revolutes` order), at a solved state (its samples flattened)."""
    n = int(np.prod(state.shape)) if state.shape else 1
    cl = Closure(plan)
    X0 = body_coordinates(plan, state, n)
    inputs = np.broadcast_to(np.asarray(state.inputs, float), tuple(state.shape) + (plan.n_inputs,)).reshape(n, -1)
    params = np.broadcast_to(np.asarray(state.params, float), tuple(state.shape) + (plan.n_params,)).reshape(n, -1)
    m = cl.n
    eye = np.eye(m)
    Xj = []
    for j in range(m):
        s = Series([X0[:, j, None, None]])
        s.e1 = [np.broadcast_to(eye[j][None, :, None], (n, m, 1))]
        Xj.append(s)
    P = _params(params, False, 1)
    q = [x.truncate(1) for x in input_series(plan, inputs, 0.0, 0.0, 1)]
    r = cl.residual(Xj, P, q)
    A = np.stack([np.broadcast_to(ri.e1[0][..., 0], (n, m)) if ri.e1 is not None else np.zeros((n, m))
                  for ri in r], axis=1)
    J = len(cl.revolutes)
    # ∂Φ/∂δ: −1 on the joint's two rows; dX/dδ = A⁻¹ at those rows
    rhs = np.zeros((n, m, 2 * J))
    for j in range(J):
        rhs[:, 2 * j, 2 * j] = 1.0
        rhs[:, 2 * j + 1, 2 * j + 1] = 1.0
    dX = _solve(A, rhs)                                                    # (n, m, 2J)
    # the point's position from the body coordinates: P = o_b + e_b·w (its Jacobian by X at the sample)
    b = plan.point_body[plan.point_index(point)]
    from .forces import _at
    Xs = []
    for j in range(m):
        s = Series([X0[:, j, None, None]])
        s.e1 = [np.broadcast_to(eye[j][None, :, None], (n, m, 1))]
        Xs.append(s)
    world, _ = _at(cl, Xs, P)
    z = world(b, point)
    dP = z.e1[0][..., 0] if z.e1 is not None else np.zeros((n, m))          # (n, m) complex
    g = np.einsum("nm,nmk->nk", dP, dX)                                     # (n, 2J) complex
    G = np.stack([np.stack([g[:, 0::2].real, g[:, 1::2].real], -1),
                  np.stack([g[:, 0::2].imag, g[:, 1::2].imag], -1)], axis=-2)   # (n, J, 2, 2): rows x, y
    return G, cl


@dataclass(frozen=True)
class Clearance:
    """The clearance analysis of ``point`` over the run: ``joints`` (J,) the revolute pairs' names, ``radius`` (J,)
    c/2 (m); per input (n,): ``effective`` (n, 2) the effective-link error, ``worst`` (n,) the bound over every
    orientation; ``monte_carlo`` (n,) the largest |error| of the random orientations (exact solves) or None;
    ``contact_loss`` {joint: inputs (rad or m) where its reaction is below ``LOSS`` of its peak}."""
    point: str
    joints: tuple[str, ...]
    radius: np.ndarray
    effective: np.ndarray
    worst: np.ndarray
    monte_carlo: np.ndarray | None
    contact_loss: dict


def joint_names(plan, cl: Closure) -> list[str]:
    names = [point for _, _, _, point in cl.revolutes]
    return [p if names.count(p) == 1 else f"{p}@{plan.body_names[l]}" for (_, _, l, p) in cl.revolutes]


def clearance(study, point: str, clearances, *, samples: int = 200, seed: int = 1, loss: float = LOSS) -> Clearance:
    """The effective-link model of ``clearances`` ({joint: diametral clearance (m)}, or one number for every revolute
    pair; a joint of three bodies as ``P@later``) on ``point``'s path over the run, with a Monte Carlo of ``samples``
    random orientations (0: none)."""
    plan = study.plan
    if not study.has_loads:
        raise SpecError([("clearance", "the effective-link model needs the joints' reactions: give the file masses "
                                       "or loads")])
    state = study.state
    G, cl = offset_derivatives(plan, state, point)
    names = joint_names(plan, cl)
    if isinstance(clearances, dict):
        unknown = sorted(set(clearances) - set(names))
        if unknown:
            raise SpecError([("clearance", f"unknown joint {unknown[0]!r} (revolute joints: {', '.join(names)})")])
        c = np.array([float(clearances.get(nm, 0.0)) for nm in names])
    else:
        c = np.full(len(names), float(clearances))
    if np.any(c < 0):
        raise SpecError([("clearance", "a clearance must be ≥ 0")])
    r = 0.5 * c
    f = study.forces
    R = np.stack([f.reactions[:, k, 0] + 1j * f.reactions[:, k, 1] for k, _, _, _ in cl.revolutes], -1)   # (n, J)
    mag = np.abs(R)
    with np.errstate(invalid="ignore", divide="ignore"):
        Rhat = np.where(mag > 0, R / mag, 0.0)
    d = r[None, :] * Rhat                                                   # the offsets δ (n, J) complex
    dvec = np.stack([d.real, d.imag], -1)                                    # (n, J, 2)
    effective = np.einsum("njab,njb->na", G, dvec)
    norms = np.linalg.norm(G, ord=2, axis=(-2, -1))                          # (n, J)
    worst = np.sum(norms * r[None, :], axis=-1)
    q = study.q
    peak = np.nanmax(mag, axis=0)
    lost = {}
    for j, nm in enumerate(names):
        if c[j] > 0 and peak[j] > 0:
            flagged = np.nan_to_num(mag[:, j], nan=np.inf) < loss * peak[j]
            if flagged.any():
                lost[nm] = [float(x) for x in q[flagged]]
    mc = _monte_carlo(study, cl, point, r, samples, seed) if samples else None
    return Clearance(point, tuple(names), r, effective, worst, mc, lost)


def _monte_carlo(study, cl: Closure, point: str, r, samples: int, seed: int) -> np.ndarray:
    """(n,) the largest |error| of ``point`` over ``samples`` random orientations of the clearance links, each solved
    exactly by Newton's method on the closure with the offsets."""
    plan = study.plan
    state = study.state
    n = len(study.q)
    rng = np.random.default_rng(seed)
    X0 = body_coordinates(plan, state, n)
    params = np.broadcast_to(np.asarray(state.params, float), (n, plan.n_params))
    inputs = np.asarray(state.inputs, float).reshape(n, -1)
    b = plan.point_body[plan.point_index(point)]
    i = plan.point_index(point)
    nominal = state.pos[:, i, 0] + 1j * state.pos[:, i, 1]
    live = [j for j in range(len(r)) if r[j] > 0]
    worst = np.zeros(n)
    S = samples
    ang = rng.uniform(0.0, 2 * np.pi, (S, len(live)))
    Xb = np.repeat(X0[None], S, axis=0).reshape(S * n, -1)
    pb = np.repeat(params[None], S, axis=0).reshape(S * n, -1)
    ib = np.repeat(inputs[None], S, axis=0).reshape(S * n, -1)
    offsets = {}
    for a, j in enumerate(live):
        offsets[cl.revolutes[j][0]] = np.repeat(r[j] * np.exp(1j * ang[:, a]), n)
    ocl = _OffsetClosure(plan, offsets)
    m = ocl.n
    eye = np.eye(m)
    P = _params(pb, False, 1)
    q = [x.truncate(1) for x in input_series(plan, ib, 0.0, 0.0, 1)]
    X = Xb.copy()
    for _ in range(20):
        Xs = []
        for j in range(m):
            s = Series([X[:, j, None, None]])
            s.e1 = [np.broadcast_to(eye[j][None, :, None], (len(X), m, 1))]
            Xs.append(s)
        res = ocl.residual(Xs, P, q)
        F = np.stack([np.broadcast_to(ri.v[0][..., 0, 0], (len(X),)) for ri in res], -1)
        A = np.stack([np.broadcast_to(ri.e1[0][..., 0], (len(X), m)) if ri.e1 is not None else np.zeros((len(X), m))
                      for ri in res], axis=1)
        dx = _solve(A, -F[..., None])[..., 0]
        X = X + dx
        if np.nanmax(np.abs(dx)) < 1e-14 * plan.length_scale:
            break
    from .forces import _at
    world, _ = _at(ocl, [Series([X[:, j, None, None]]) for j in range(m)], P)
    z = world(b, point).v[0][:, 0, 0].reshape(S, n)
    err = np.abs(z - nominal[None, :])
    worst = np.nanmax(err, axis=0)
    return worst
