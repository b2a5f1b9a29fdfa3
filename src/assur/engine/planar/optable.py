"""The planar plan as an op table for the fused compiled backend.

``build_op_table(plan)`` writes, at compile time, the rows the generated numba kernel runs
(``ops (n_ops, OP_WIDTH)``, codes and operands in :mod:`assur.kernels.codegen`) and the recipes of
their per-design complex constants (``slots (n_slots, SLOT_WIDTH)``: a slot kind from
``SLOT_KINDS`` and its operands: body, point and line indices). ``slot_constants(plan, designs)``
evaluates the recipes for a population ``designs (D, n_params)`` → ``G (D, n_slots, 2)``.

The table covers one-input crank plans made of RRR, RRP and RPR dyads without driven actuators
(walking legs, four-bars, slider-cranks, slotted levers, passive cylinders); for any other plan it
is None and the numpy backend solves it.
"""
from __future__ import annotations

import numpy as np

from ...kernels.codegen import CRANK, FRAMEPT, FROM_TWO, OP_WIDTH, PLACE, RPR, RRP, RRR
from .geometry import geometry

#: slot kinds: the position is the code in ``slots[:, 0]``; the operands follow
SLOT_KINDS = (
    "w",            # body, point: the point's local coordinate
    "radius",       # body, A, J: |w_J − w_A|
    "crank",        # body, arm, pivot, zero param: exp(i·zero)·conj(unit(w_arm − w_pivot))
    "inverse",      # body, p1, p2: 1 / (w_p2 − w_p1)
    "line_point",   # line: q
    "line_dir",     # line: u
    "line_turn",    # line: u / u_slider
    "line_offset",  # line, slider, J: w_J − ref
    "rpr",          # line, guide, guide point, slider, slider point: ((q − w_gp) + (u/u_s)(w_sp − ref)) / u
    "inv_dir",      # line: 1 / u
    "inv_turn",     # line: 1 / u_slider
)
SLOT_WIDTH = 6


class _Table:
    def __init__(self, plan):
        self.plan = plan
        self.ops: list[list[int]] = []
        self.slots: list[list[int]] = []
        self.placed: set[str] = set()
        self.pidx = {p: i for i, p in enumerate(plan.point_names)}
        self.g = plan.structure.graph

    def slot(self, kind: str, *operands) -> int:
        row = [SLOT_KINDS.index(kind)] + [int(x) for x in operands]
        self.slots.append(row + [0] * (SLOT_WIDTH - len(row)))
        return len(self.slots) - 1

    def op(self, *row):
        r = [int(x) for x in row]
        self.ops.append(r + [0] * (OP_WIDTH - len(r)))

    def place_body(self, b):
        for p in self.g.bodies[b].points:
            if p not in self.placed:
                self.op(PLACE, b, self.pidx[p], self.slot("w", b, self.pidx[p]))
                self.placed.add(p)

    def from_two(self, b, p1, p2):
        i1, i2 = self.pidx[p1], self.pidx[p2]
        self.op(FROM_TWO, b, i1, i2, self.slot("w", b, i1), self.slot("inverse", b, i1, i2))
        self.place_body(b)

    def build(self) -> bool:
        plan, P = self.plan, self.pidx
        if plan.n_inputs != 1 or plan.input_kinds[0] != "rotary":
            return False
        for st in plan.steps:
            if st.kind == "frame":
                for p in self.g.bodies[0].points:
                    self.op(FRAMEPT, P[p], self.slot("w", 0, P[p]))
                    self.placed.add(p)
            elif st.kind == "crank":
                b = st.bodies[0]
                self.op(CRANK, b, P[st.pivot], self.slot("w", b, P[st.pivot]), st.sense,
                        self.slot("crank", b, P[st.arm], P[st.pivot], st.zero_param))
                self.place_body(b)
            elif st.kind == "RRR":
                if st.side_a.actuator is not None or st.side_b.actuator is not None:
                    return False
                a, b, A, B, J = st.side_a.body, st.side_b.body, st.point_a, st.point_b, st.joint
                self.op(RRR, P[A], self.slot("radius", a, P[A], P[J]), P[B], self.slot("radius", b, P[B], P[J]),
                        P[J], st.branch)
                self.placed.add(J)
                self.from_two(a, A, J)
                self.from_two(b, B, J)
            elif st.kind == "RRP":
                if st.side_a.actuator is not None:
                    return False
                a, A, J, line, slider = st.side_a.body, st.point_a, st.joint, st.line, st.slider
                guide = plan.lines[line][2]
                self.op(RRP, P[A], self.slot("radius", a, P[A], P[J]), guide,
                        self.slot("line_point", line), self.slot("line_dir", line), self.slot("line_turn", line),
                        self.slot("line_offset", line, slider, P[J]),
                        P[J], st.branch, slider, self.slot("w", slider, P[J]))
                self.placed.add(J)
                self.from_two(a, A, J)
                self.place_body(slider)
            elif st.kind == "RPR":
                guide, gp, slider, sp, line = st.guide, P[st.guide_point], st.slider, P[st.slider_point], st.line
                self.op(RPR, guide, gp, slider, sp, self.slot("w", guide, gp),
                        self.slot("rpr", line, guide, gp, slider, sp), self.slot("inv_dir", line),
                        self.slot("inv_turn", line), self.slot("w", slider, sp), st.branch)
                self.place_body(guide)
                self.place_body(slider)
            else:
                return False
        return True


def build_op_table(plan):
    """``(ops (n_ops, OP_WIDTH), slots (n_slots, SLOT_WIDTH))`` int64 arrays, or None where the plan is
    outside the compiled backend's scope."""
    t = _Table(plan)
    if not t.build():
        return None
    return np.array(t.ops, dtype=np.int64), np.array(t.slots, dtype=np.int64)


def _slot_value(plan, row, w, L, P):
    """The complex constant of one slot recipe (arrays over the designs)."""
    kind, o = SLOT_KINDS[int(row[0])], [int(x) for x in row[1:]]
    name = plan.point_names
    if kind == "w":
        return w[(o[0], name[o[1]])]
    if kind == "radius":
        b, A, J = o[0], name[o[1]], name[o[2]]
        return np.abs(w[(b, J)] - w[(b, A)]) + 0j
    if kind == "crank":
        b, a, p, i = o[0], name[o[1]], name[o[2]], o[3]
        return np.exp(1j * P[..., i]) * np.conj((w[(b, a)] - w[(b, p)]) / np.abs(w[(b, a)] - w[(b, p)]))
    if kind == "inverse":
        b = o[0]
        return 1.0 / (w[(b, name[o[2]])] - w[(b, name[o[1]])])
    q, u, ref, us = L[o[0]]
    if kind == "line_point":
        return q
    if kind == "line_dir":
        return u
    if kind == "line_turn":
        return u / us
    if kind == "line_offset":
        return w[(o[1], name[o[2]])] - ref
    if kind == "rpr":
        gd, gp, s, sp = o[1], name[o[2]], o[3], name[o[4]]
        return ((q - w[(gd, gp)]) + (u / us) * (w[(s, sp)] - ref)) / u
    if kind == "inv_dir":
        return 1.0 / u
    return 1.0 / us   # inv_turn


def slot_constants(plan, designs: np.ndarray) -> np.ndarray:
    """The per-design constants of the plan's op table.

    Parameters
    ----------
    designs : ndarray (D, n_params)

    Returns
    -------
    G : ndarray (D, n_slots, 2)
        Real and imaginary parts of every slot's constant.
    """
    w, lines = geometry(plan, designs)
    G = np.empty((designs.shape[0], len(plan.slots), 2))
    with np.errstate(all="ignore"):          # a non-physical design's NaN constants: its samples are invalid
        for i, row in enumerate(plan.slots):
            v = np.broadcast_to(np.asarray(_slot_value(plan, row, w, lines, designs), dtype=complex),
                                designs.shape[:1])
            G[:, i, 0], G[:, i, 1] = v.real, v.imag
    return G
