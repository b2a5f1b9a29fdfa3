"""The compiled backend: pack a plan into an op table and run it in one fused numba loop.

Covers one-input plans made of cranks and RRR, RRP and RPR dyads (walking legs, four-bars,
slider-cranks, slotted levers, passive cylinders); anything else (several inputs, PRP/PPR,
driven actuators, Newton groups) returns ``None`` and the numpy backend solves it. numba is
imported only when this backend runs.
"""
from __future__ import annotations

import numpy as np

from .compile import geometry
from .plan import SolvePlan


class _Packer:
    def __init__(self, plan: SolvePlan):
        from .kernels import compiled as K
        self.K = K
        self.plan = plan
        self.ops: list[list[int]] = []
        self.slots: list = []          # functions (w, lines, params) -> complex (n_designs,)
        self.placed: set[str] = set()
        self.pidx = {p: i for i, p in enumerate(plan.point_names)}
        self.g = plan.structure.graph

    def slot(self, fn) -> int:
        self.slots.append(fn)
        return len(self.slots) - 1

    def op(self, *row):
        r = [int(x) for x in row]
        self.ops.append(r + [0] * (self.K.OP_WIDTH - len(r)))

    def place_body(self, b):
        for p in self.g.bodies[b].points:
            if p not in self.placed:
                self.op(self.K.PLACE, b, self.pidx[p], self.slot(lambda w, L, P, b=b, p=p: w[(b, p)]))
                self.placed.add(p)

    def from_two(self, b, p1, p2):
        self.op(self.K.FROM_TWO, b, self.pidx[p1], self.pidx[p2],
                self.slot(lambda w, L, P, b=b, p=p1: w[(b, p)]),
                self.slot(lambda w, L, P, b=b, p1=p1, p2=p2: 1.0 / (w[(b, p2)] - w[(b, p1)])))
        self.place_body(b)

    def pack(self) -> bool:
        K, plan = self.K, self.plan
        if plan.n_inputs != 1 or plan.input_kinds[0] != "rotary":
            return False
        for st in plan.steps:
            if st.kind == "frame":
                for p in self.g.bodies[0].points:
                    self.op(K.FRAMEPT, self.pidx[p], self.slot(lambda w, L, P, p=p: w[(0, p)]))
                    self.placed.add(p)
            elif st.kind == "crank":
                pivot, arm, k, izero, sense = st.data
                b = st.bodies[0]
                self.op(K.CRANK, b, self.pidx[pivot], self.slot(lambda w, L, P, b=b, p=pivot: w[(b, p)]),
                        self.slot(lambda w, L, P, b=b, a=arm, p=pivot: np.conj((w[(b, a)] - w[(b, p)])
                                                                              / np.abs(w[(b, a)] - w[(b, p)]))),
                        self.slot(lambda w, L, P, i=izero: P[..., i] + 0j), sense,
                        self.slot(lambda w, L, P, b=b, a=arm, p=pivot, i=izero: np.exp(1j * P[..., i]) * np.conj(
                            (w[(b, a)] - w[(b, p)]) / np.abs(w[(b, a)] - w[(b, p)]))))
                self.place_body(b)
            elif st.kind == "RRR":
                sa, A, sb, B, J = st.data
                if sa.actuator is not None or sb.actuator is not None:
                    return False
                a, b = sa.body, sb.body
                self.op(K.RRR, self.pidx[A], self.slot(lambda w, L, P, a=a, A=A, J=J: np.abs(w[(a, J)] - w[(a, A)]) + 0j),
                        self.pidx[B], self.slot(lambda w, L, P, b=b, B=B, J=J: np.abs(w[(b, J)] - w[(b, B)]) + 0j),
                        self.pidx[J], st.branch)
                self.placed.add(J)
                self.from_two(a, A, J)
                self.from_two(b, B, J)
            elif st.kind == "RRP":
                sa, A, slider, line, J = st.data
                if sa.actuator is not None:
                    return False
                a = sa.body
                guide = plan.lines[line][2]
                self.op(K.RRP, self.pidx[A],
                        self.slot(lambda w, L, P, a=a, A=A, J=J: np.abs(w[(a, J)] - w[(a, A)]) + 0j), guide,
                        self.slot(lambda w, L, P, i=line: L[i][0]), self.slot(lambda w, L, P, i=line: L[i][1]),
                        self.slot(lambda w, L, P, i=line: L[i][1] / L[i][3]),
                        self.slot(lambda w, L, P, i=line, s=slider, J=J: w[(s, J)] - L[i][2]),
                        self.pidx[J], st.branch, slider, self.slot(lambda w, L, P, s=slider, J=J: w[(s, J)]))
                self.placed.add(J)
                self.from_two(a, A, J)
                self.place_body(slider)
            elif st.kind == "RPR":
                guide, gp, slider, sp, line = st.data

                def cvec(w, L, P, i=line, gd=guide, gp=gp, s=slider, sp=sp):
                    q, u, ref, us = L[i]
                    return ((q - w[(gd, gp)]) + (u / us) * (w[(s, sp)] - ref)) / u
                self.op(K.RPR, guide, self.pidx[gp], slider, self.pidx[sp],
                        self.slot(lambda w, L, P, gd=guide, p=gp: w[(gd, p)]), self.slot(cvec),
                        self.slot(lambda w, L, P, i=line: 1.0 / L[i][1]),
                        self.slot(lambda w, L, P, i=line: 1.0 / L[i][3]),
                        self.slot(lambda w, L, P, s=slider, p=sp: w[(s, p)]), st.branch)
                self.place_body(guide)
                self.place_body(slider)
            else:
                return False
        return True


def packer(plan: SolvePlan) -> _Packer | None:
    """The plan's op table, built once and kept on the (frozen) plan object."""
    cached = plan.__dict__.get("_compiled_packer", False)
    if cached is False:
        p = _Packer(plan)
        cached = p if p.pack() else None
        object.__setattr__(plan, "_compiled_packer", cached)
    return cached


def available() -> bool:
    try:
        import numba  # noqa: F401
    except ImportError:
        return False
    return True


def solve_compiled(plan: SolvePlan, params: np.ndarray, inputs: np.ndarray, tol: float):
    """(z, dz, d2z, valid) as the numpy backend returns them, or None if the plan is not covered.

    params (..., n_params), inputs (..., 1); shapes broadcast."""
    pk = packer(plan)
    if pk is None:
        return None
    shape = np.broadcast_shapes(params.shape[:-1], inputs.shape[:-1])
    designs = params.reshape(-1, params.shape[-1])
    w, lines = geometry(plan, designs)
    G = np.empty((designs.shape[0], len(pk.slots), 2))
    for i, fn in enumerate(pk.slots):
        v = np.broadcast_to(np.asarray(fn(w, lines, designs), dtype=complex), designs.shape[:1])
        G[:, i, 0], G[:, i, 1] = v.real, v.imag
    design_of = np.broadcast_to(np.arange(designs.shape[0]).reshape(params.shape[:-1]), shape).ravel()
    q = np.ascontiguousarray(np.broadcast_to(inputs[..., 0], shape).ravel(), dtype=float)
    n_points, n_bodies = len(plan.point_names), len(plan.body_names)
    m = n_points + n_bodies
    out = np.empty((3, q.size, m, 2))
    point_out = np.array([pk.pidx[p] for p in plan.point_names], dtype=np.int64)
    body_out = np.arange(n_bodies, dtype=np.int64)
    valid = pk.K.run(np.array(pk.ops, dtype=np.int64), G, np.ascontiguousarray(design_of, dtype=np.int64), q,
                     point_out, body_out, tol, n_points, n_bodies, out)
    cz = out.view(np.complex128)[..., 0]            # (3, S, m)
    z = cz[0].reshape(shape + (m,))
    dz = cz[1].reshape(shape + (m, 1))
    d2z = cz[2].reshape(shape + (m, 1, 1))
    return z, dz, d2z, valid.reshape(shape)
