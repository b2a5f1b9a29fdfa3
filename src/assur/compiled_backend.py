"""The compiled backend: pack a plan into an op table and run it in one fused numba loop.

Covers one-input plans made of cranks and RRR, RRP and RPR dyads (walking legs, four-bars,
slider-cranks, slotted levers, passive cylinders) on batches laid out as designs × inputs;
anything else (several inputs, PRP/PPR, driven actuators, Newton groups, a design per sample)
returns ``None`` and the numpy backend solves it. numba is imported only when this backend runs.
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
                self.op(K.CRANK, b, self.pidx[pivot], self.slot(lambda w, L, P, b=b, p=pivot: w[(b, p)]), sense,
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


def cache_dir():
    """Where generated kernels live: $ASSUR_CACHE_DIR, else $XDG_CACHE_HOME/assur/kernels, else ~/.cache."""
    import os
    from pathlib import Path
    base = os.environ.get("ASSUR_CACHE_DIR")
    if base:
        return Path(base)
    xdg = os.environ.get("XDG_CACHE_HOME")
    return (Path(xdg) if xdg else Path.home() / ".cache") / "assur" / "kernels"


def kernel(pk: _Packer, with_bodies: bool, order: int = 2):
    """The plan's generated straight-line kernel for a derivative order (compiled once, cached on
    disk by numba)."""
    key = f"_kernel_{'bodies' if with_bodies else 'points'}_{order}"
    point_out = [pk.pidx[p] for p in pk.plan.point_names]
    body_out = list(range(len(pk.plan.body_names))) if with_bodies else []
    return _load_source(pk, key, lambda: pk.K.generate_source(pk.ops, point_out, body_out, order))


def _load_source(pk: _Packer, key: str, make_source):
    """A generated kernel kept on the packer under ``key``: its source written once to the cache
    directory (a temporary one if that is not writable) and imported, so numba's disk cache applies."""
    k = pk.__dict__.get(key)
    if k is None:
        src = make_source()
        try:
            k = pk.K.load_kernel(src, cache_dir())
        except OSError:
            import tempfile
            from pathlib import Path
            k = pk.K.load_kernel(src, Path(tempfile.gettempdir()) / "assur-kernels")
        pk.__dict__[key] = k
    return k


def path_objective(plan: SolvePlan, params: np.ndarray, target_inputs: np.ndarray, target_xy: np.ndarray,
                   point: str, cycle_inputs: np.ndarray | None, tol: float):
    """Fused reduction of a path-synthesis objective; None if the plan is not covered.

    params (D, n_params); target_inputs (D or 1, N) input angles at the targets; target_xy (N, 2);
    cycle_inputs (M,) or None. Returns (D, 5): Σ squared distance, Σ distance (over the assembled
    targets), the number of targets and of cycle samples that cannot be assembled, and the sum over
    the cycle of the groups' shortfalls past their toggles (normalised radicands below −tol).
    """
    pk = packer(plan)
    if pk is None:
        return None
    idx = pk.pidx[point]
    kern = _load_source(pk, f"_objective_{idx}", lambda: pk.K.generate_objective_source(pk.ops, idx))
    designs = np.ascontiguousarray(params, dtype=float)
    G = _constants(pk, designs)
    q = np.ascontiguousarray(target_inputs, dtype=float)
    cyc = np.zeros(0) if cycle_inputs is None else np.ascontiguousarray(cycle_inputs, dtype=float)
    out = np.empty((designs.shape[0], 5))
    kern(G, np.cos(q), np.sin(q), np.ascontiguousarray(target_xy, dtype=float), np.cos(cyc), np.sin(cyc), tol, out)
    return out


def _constants(pk: _Packer, designs: np.ndarray) -> np.ndarray:
    """The kernel's per-design constants G (n_designs, n_slots, 2); the last small set is memoised
    (repeated solves of one design skip this work)."""
    key = designs.tobytes() if designs.size <= 4096 else None
    memo = pk.__dict__.get("_memo")
    if key is not None and memo is not None and memo[0] == key:
        return memo[1]
    w, lines = geometry(pk.plan, designs)
    G = np.empty((designs.shape[0], len(pk.slots), 2))
    for i, fn in enumerate(pk.slots):
        v = np.broadcast_to(np.asarray(fn(w, lines, designs), dtype=complex), designs.shape[:1])
        G[:, i, 0], G[:, i, 1] = v.real, v.imag
    if key is not None:
        G.setflags(write=False)
        pk.__dict__["_memo"] = (key, G)
    return G


def separable(pshape: tuple, ishape: tuple, shape: tuple):
    """Split the batch shape into (design axes, input axes): the params vary only over the leading
    axes and the inputs only over the trailing ones. Returns k (the split) or None."""
    n = len(shape)
    ps = (1,) * (n - len(pshape)) + tuple(pshape)
    qs = (1,) * (n - len(ishape)) + tuple(ishape)
    for k in range(n + 1):
        if all(x == 1 for x in ps[k:]) and all(x == 1 for x in qs[:k]):
            return k
    return None


def solve_compiled(plan: SolvePlan, params: np.ndarray, inputs: np.ndarray, tol: float,
                   rates=(1.0, 1.0, 0.0), with_bodies: bool = False, order: int = 2, shape=None):
    """Run the plan's kernel; None if the plan or the batch layout is not covered.

    params (..., n_params), inputs (..., 1); shapes broadcast to ``shape``; the params must vary
    over leading axes only and the inputs over trailing axes only (designs × inputs). Returns
    ``(buffer (6·n_out, D, N), (pos, first, second), valid)`` where the three are float views
    (shape + (n_out, 2)) of the buffer: the position and, with ``rates = (w1, w2, w3)``,
    ``w1·d/dq`` and ``w2·d²/dq² + w3·d/dq`` (velocity and acceleration for (ω, ω², α)).
    """
    pk = packer(plan)
    if pk is None:
        return None
    if shape is None:
        shape = np.broadcast_shapes(params.shape[:-1], inputs.shape[:-1])
    k = separable(params.shape[:-1], inputs.shape[:-1], shape)
    if k is None:
        return None
    n, n_params = len(shape), params.shape[-1]
    lead, trail = shape[:k], shape[k:]
    if params.ndim == 1:                       # one design (the common single-design call)
        designs = params.reshape(1, n_params)
    else:
        p_pad = params.reshape((1,) * (n - (params.ndim - 1)) + params.shape)
        designs = np.broadcast_to(p_pad[(slice(None),) * k + (0,) * (n - k)], lead + (n_params,))
        designs = np.ascontiguousarray(designs.reshape(-1, n_params))
    if inputs.shape[:-1] == trail:
        q = np.ascontiguousarray(inputs.reshape(-1), dtype=float)
    else:
        q_pad = inputs[..., 0].reshape((1,) * (n - (inputs.ndim - 1)) + inputs.shape[:-1])
        q = np.ascontiguousarray(np.broadcast_to(q_pad[(0,) * k], trail).reshape(-1), dtype=float)
    G = _constants(pk, designs)
    cq, sq = np.cos(q), np.sin(q)
    n_out = len(plan.point_names) + (len(plan.body_names) if with_bodies else 0)
    D, N = designs.shape[0], q.size
    out = np.empty((6 * n_out, D, N))         # rows of derivatives above ``order`` stay unwritten
    valid = np.empty((D, N), dtype=np.bool_)
    w1, w2, w3 = (float(r) for r in rates)
    kernel(pk, with_bodies, order)(G, cq, sq, tol, w1, w2, w3, out, valid)
    rows = out.reshape((n_out, 6) + shape)
    axes = tuple(range(2, 2 + n)) + (0, 1)     # (n_out, 2, *shape) → (*shape, n_out, 2), a view
    views = tuple(rows[:, 2 * j:2 * j + 2].transpose(axes) for j in range(3))
    return out, views, valid.reshape(shape)
