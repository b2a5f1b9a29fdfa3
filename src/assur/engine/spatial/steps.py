"""The spatial step executors (crank, R–S–S dyad) by the vector method, on second-order jets, and
the loop-closure Newton oracle (``method="newton"``)."""
from __future__ import annotations

import numpy as np

from ...kernels import spatial as V
from ...kernels.jet import Jet
from ..options import continuation


def _positive(length):
    """A link length, NaN where it is not positive (a non-physical design is unbuildable, never mirrored)."""
    return np.where(length > 0, length, np.nan)


def _rss_fields(st):
    return (st.pivot, st.start, st.joint, st.coupler, st.rocker_length_param, st.rocker_axial_param,
            st.coupler_length_param, st.rocker_extra, st.coupler_extra)


# -- one pass ---------------------------------------------------------------------------------------------
class Context:
    """One pass over a batch: ``pos[point]`` (..., 3) arrays or jets, ``frames[body]`` (e_x, e_y, e_z),
    ``valid`` (...), ``status`` [(point, solver status (...))]."""

    def __init__(self, plan, params, q, order, tol):
        self.plan, self.params, self.q, self.order, self.tol = plan, params, q, order, tol
        self.pos: dict[str, object] = {}
        self.axis: dict[str, np.ndarray] = {}
        self.axis_frame: dict[str, np.ndarray] = {}
        self.frames: dict[int, tuple] = {}
        self.valid = np.True_
        self.status: list[tuple[str, np.ndarray]] = []

    def p(self, i):
        return self.params[..., i]

    def frame_of(self, point):
        if point not in self.axis_frame:
            i1 = self.plan.param_index(f"{point}.axis.gamma1")
            i2 = self.plan.param_index(f"{point}.axis.gamma2")
            E = V.axis_frame(self.p(i1), self.p(i2))
            self.axis_frame[point] = E
            self.axis[point] = E[..., :, 2]
        return self.axis_frame[point]

    def place_extra(self, origin, frame, extra):
        ex, ey, ez = frame
        for name, iu, iv, iw in extra:
            self.pos[name] = origin + V.scale(self.p(iu), ex) + V.scale(self.p(iv), ey) + V.scale(self.p(iw), ez)


def _frame(c: Context, st):
    for name, ix, iy, iz in st.points:
        c.pos[name] = np.stack([c.p(ix), c.p(iy), c.p(iz)], axis=-1)
    eye = np.eye(3)
    c.frames[0] = (eye[:, 0], eye[:, 1], eye[:, 2])


def _crank(c: Context, st):
    pivot, arm, k, il, ih, iz, sense, extra = (st.pivot, st.arm, st.input, st.length_param, st.axial_param,
                                                st.zero_param, st.sense, st.extra)
    E = c.frame_of(pivot)
    ex2, ey2, e = E[..., :, 0], E[..., :, 1], E[..., :, 2]
    theta = c.q[k] * float(sense) + c.p(iz)
    cs, sn = V.cos(theta), V.sin(theta)
    u_r = V.scale(cs, ex2) + V.scale(sn, ey2)
    u_t = V.scale(-1.0 * sn, ex2) + V.scale(cs, ey2)
    length, h = _positive(c.p(il)), c.p(ih)
    rho = np.sqrt(np.maximum(length * length - h * h, 0.0))
    O = c.pos[pivot]
    c.pos[arm] = O + V.scale(rho, u_r) + V.scale(h, e)
    c.frames[st.body] = (u_r, u_t, e)
    c.place_extra(O, c.frames[st.body], extra)


def _rss(c: Context, st):
    D, Ap, Bp, ci, ilr, ihr, ilc, r_extra, c_extra = _rss_fields(st)
    E = c.frame_of(D)
    e = E[..., :, 2]
    Dv, A = c.pos[D], c.pos[Ap]
    lr, h, lc = _positive(c.p(ilr)), c.p(ihr), _positive(c.p(ilc))
    v1 = A - Dv                                             # (7) P4_2 = P2 − P4
    d2 = V.dot(v1, v1)
    d = V.sqrt(d2)
    cos_a1 = (d2 + (lr * lr - lc * lc)) * V.reciprocal(d * (2.0 * lr))   # (23) cos α1
    cos_a2 = h / lr                                          # cos α2
    e43, status = V.unit_vector(v1, e, cos_a1, cos_a2, st.branch, parallel_tol=c.tol.parallel,
                                disc_tol=c.tol.radicand)    # (22)
    c.valid = c.valid & V.assembled(status)
    c.status.append((Bp, status))
    Bv = Dv + V.scale(lr, e43)                               # (24), (25)
    c.pos[Bp] = Bv
    _place_frames(c, st, Dv, e43, e, ci, r_extra, c_extra)


EXECUTORS = {"frame": _frame, "crank": _crank, "RSS": _rss}


def run(plan, params, q, order, tol, steps=None, method="closed", seeds=None) -> Context:
    """One pass of the steps (default: the plan's) on input jets ``q``; with ``method='newton'`` the
    dyads by the loop-closure oracle, warm-started from ``seeds``."""
    c = Context(plan, params, q, order, tol)
    with np.errstate(all="ignore"):
        for st in (plan.steps if steps is None else steps):
            if method == "newton" and st.kind == "RSS":
                _rss_newton(c, st, seeds)
            else:
                EXECUTORS[st.kind](c, st)
    return c


# -- the Newton loop-closure oracle ---------------------------------------------------------------------
def _place_frames(c: Context, st, Dv, e43, e, ci, r_extra, c_extra):
    """The rocker's hinge frame from its unit arm ``e43`` and axis ``e``, and the coupler's frame of eqs.
    (27)–(30) (a universal joint's pin fixed in the link on its other side; NaN for a coupler that spins
    idly), with the further points of both."""
    u_r = V.ort(e43 - V.scale(V.dot(e43, e), e))
    c.frames[st.body] = (u_r, V.cross(e, u_r), e)
    c.place_extra(Dv, c.frames[st.body], r_extra)
    kind = c.plan.body_frames[ci]
    if kind[0] == "coupler":
        _, U, other, pin_body, pin_local = kind
        fr = c.frames[pin_body]
        pin = V.scale(pin_local[0], fr[0]) + V.scale(pin_local[1], fr[1]) + V.scale(pin_local[2], fr[2])
        ex = V.ort(c.pos[U] - c.pos[other])                  # (27)
        ez = V.ort(V.cross(pin, ex))                         # (29), β1 = β2 = 90°, Wp = +1
        ey = V.cross(ez, ex)                                 # (30)
        c.frames[ci] = (ex, ey, ez)
        c.place_extra(c.pos[U], c.frames[ci], c_extra)
    else:
        nan = np.full(3, np.nan)
        c.frames[ci] = (nan, nan, nan)


def _rss_newton(c: Context, st, seeds):
    """B from the loop-closure equations (B − D)·e = h, |B − D|² = l_r², |B − A|² = l_c² by Newton,
    warm-started from ``seeds[B]`` (the previous continuation stage); its derivatives by implicit
    differentiation (docs/papers/003.md §6): J·B' = (0, 0, (B − A)·A'),
    J·B'' = (0, −|B'|², (B − A)·A'' − |B' − A'|²), J = [eᵀ; (B − D)ᵀ; (B − A)ᵀ]."""
    D, Ap, Bp, ci, ilr, ihr, ilc, r_extra, c_extra = _rss_fields(st)
    E = c.frame_of(D)
    e = E[..., :, 2]
    Dv = np.asarray(c.pos[D])
    Aj = c.pos[Ap]
    A = V.value(Aj)
    lr, h, lc = _positive(c.p(ilr)), c.p(ihr), _positive(c.p(ilc))
    shape = np.broadcast_shapes(A.shape, Dv.shape, e.shape)
    x = np.array(np.broadcast_to(seeds[Bp], shape), dtype=float)
    x, ok = V.newton_rss(A, Dv, e, lr, h, lc, x, tol=c.tol.newton_residual * c.plan.length_scale,
                         iterations=c.tol.newton_iterations)
    seeds[Bp] = x
    c.valid = c.valid & ok
    Bv = np.where(ok[..., None], x, np.nan)
    J = np.stack([np.broadcast_to(e, shape), Bv - Dv, Bv - A], axis=-2)
    if isinstance(Aj, Jet) and Aj.d is not None:
        Ad = Aj.d
        rhs = np.stack([np.zeros(shape[:-1]), np.zeros(shape[:-1]), np.sum((Bv - A) * Ad, -1)], -1)
        with np.errstate(all="ignore"):
            Bd = np.linalg.solve(J, rhs[..., None])[..., 0]
            Bdd = None
            if Aj.dd is not None:
                rhs2 = np.stack([np.zeros(shape[:-1]), -np.sum(Bd * Bd, -1),
                                 np.sum((Bv - A) * Aj.dd, -1) - np.sum((Bd - Ad) ** 2, -1)], -1)
                Bdd = np.linalg.solve(J, rhs2[..., None])[..., 0]
        Bj = Jet(Bv, Bd, Bdd)
    else:
        Bj = Bv
    c.pos[Bp] = Bj
    _place_frames(c, st, Dv, V.scale(1.0 / lr, Bj - Dv), e, ci, r_extra, c_extra)


def execute_newton(plan, params, q, order, tol) -> Context:
    """Continue every sample from the sketch input to its own in stages of at most 10° of crank
    (:func:`assur.engine.options.continuation`), Newton warm-started from the previous stage (the
    first from the sketch)."""
    seeds = {st.key_point: np.asarray(plan.mechanism.sketch(st.key_point), dtype=float)
             for st in plan.steps if st.kind == "RSS"}
    q_s = plan.sketch_inputs
    m, deltas, dp = continuation(plan, [qj.v for qj in q], params, tol)
    for i in range(1, m):
        t = i / m
        q_stage = [Jet(q_s[k] + t * deltas[k]) for k in range(len(q))]
        run(plan, plan.defaults + t * dp if dp is not None else params, q_stage, 0, tol, method="newton", seeds=seeds)
    q_final = [Jet(q_s[k] + deltas[k], qj.d, qj.dd) for k, qj in enumerate(q)]
    return run(plan, params, q_final, order, tol, method="newton", seeds=seeds)
