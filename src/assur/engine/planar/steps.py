"""The planar step executors: each Assur group by its closed form on second-order jets.

A :class:`Context` holds one pass over a batch: the bodies' local geometry, the input jets and
the poses and point positions placed so far. Each executor reads its step record's named fields
and places the bodies it solves. :func:`_run` runs a step table once;
:mod:`assur.engine.planar.continuation` continues Newton-solved groups from the sketch.
"""
from __future__ import annotations

import numpy as np

from ...kernels import planar
from ...kernels.jet import Jet, expi
from .cam_steps import cam_slide, slot_jet
from .geometry import geometry
from .newton_group import solve_group


class Context:
    """One pass over a batch: ``w`` local coordinates, ``lines`` slide lines, ``q`` input jets,
    ``pose[body] = (origin, e = exp(iθ))`` and ``pos[point]`` complex jets, ``valid`` (...), ``margins``: None,
    or a list that the closed forms append their margins to (:mod:`assur.kernels.planar`), and ``ambiguous``: None,
    or (...) bool, the samples the continuation found on two assemblies, one each way round (not valid).

    The compiled kernels run these executors on symbols (:mod:`.traced`): they are element-wise code (a choice per
    sample is ``np.where``), and read the inputs through :meth:`turn` and constants through :meth:`const`."""
    margins = None
    ambiguous = None

    def __init__(self, plan, params, q_jets, order, tol):
        self.plan, self.order, self.tol = plan, order, tol
        self.w, self.lines = geometry(plan, params)
        self.params = params
        self.q = with_gear_slots(plan, q_jets)
        self.pose: dict[int, tuple[Jet, Jet]] = {}
        self.pos: dict[str, Jet] = {}
        self.valid = np.True_
        self.g = plan.structure.graph
        self.warm: dict = {}

    def const(self, v):
        return Jet.const(v, self.order)

    def turn(self, k: int, sense: int, factor) -> Jet:
        """exp(i·sense·q_k)·factor as a jet in input k (``factor``: a complex constant of each design)."""
        return expi(self.q[k] * float(sense)) * factor

    def place(self, body, o, e):
        self.pose[body] = (o, e)
        for p in self.g.bodies[body].points:
            if p not in self.pos:
                self.pos[p] = o + e * self.w[(body, p)]

    def from_two(self, body, p1, p2):
        """Pose of a body from the world positions of two of its points."""
        w1, w2 = self.w[(body, p1)], self.w[(body, p2)]
        e = (self.pos[p2] - self.pos[p1]) * (1.0 / (w2 - w1))
        self.place(body, self.pos[p1] - e * w1, e)

    def radius(self, side, a, j):
        if side.actuator is not None:
            return self.q[side.actuator[2]]
        return np.abs(self.w[(side.body, j)] - self.w[(side.body, a)])

    def place_side(self, side, a, j):
        if side.actuator is None:
            self.from_two(side.body, a, j)
            return
        cyl, rod, k = side.actuator
        e = (self.pos[j] - self.pos[a]) / self.q[k]
        self.place(cyl, self.pos[a], e)
        self.place(rod, self.pos[j], e)

    def world_line(self, idx):
        """World line of slide idx, and the slider's orientation: (Q, U, e_slider, ref, u_slider)."""
        rec = self.plan.lines[idx]
        q, u, ref, us = self.lines[idx]
        og, eg = self.pose[rec[2]]
        return og + eg * q, eg * u, eg * (u / us), ref, us

    def flag(self, valid):
        self.valid = self.valid & valid


def with_gear_slots(plan, q_jets) -> list:
    """The input jets followed by one jet per gear slot of the plan: the driven link's rotation from the sketch
    through the pair's law (chain rule: y' = L'·x', y'' = L''·x'² + L'·x''), then one per cam slot (the follower's
    move, :func:`.cam_steps.slot_jet`)."""
    out = list(q_jets)
    for sl in getattr(plan, "gear_slots", ()):
        x = (out[sl.source] - sl.sketch) * sl.sense
        y, y1, y2 = plan.mechanism.gears[sl.gear].relative(x.v)
        d = None if x.d is None else y1 * x.d
        dd = None if (x.dd is None or x.d is None) else y2 * (x.d * x.d) + y1 * x.dd
        out.append(Jet(y, d, dd))
    for sl in getattr(plan, "cam_slots", ()):
        out.append(slot_jet(plan, sl, (out[sl.source] - sl.sketch) * sl.sense))
    return out


def _frame(c: Context, st):
    c.place(0, c.const(0j), c.const(1 + 0j))
    for p in c.g.bodies[0].points:
        c.pos[p] = c.const(c.w[(0, p)])


def _crank(c: Context, st):
    body = st.bodies[0]
    d = c.w[(body, st.arm)] - c.w[(body, st.pivot)]
    # θ = sense·q + zero: e = exp(i·sense·q) · exp(i·zero)·conj(unit arm), the second factor a design's constant
    e = c.turn(st.input, st.sense, expi(c.params[..., st.zero_param]) * np.conj(d / np.abs(d)))
    c.place(body, c.pos[st.pivot] - e * c.w[(body, st.pivot)], e)


def _rrr(c: Context, st):
    sa, A, sb, B, J = st.side_a, st.point_a, st.side_b, st.point_b, st.joint
    z, ok = planar.circle_circle(c.pos[A], c.radius(sa, A, J), c.pos[B], c.radius(sb, B, J), st.branch, c.tol.radicand,
                                  c.margins)
    c.flag(ok)
    c.pos[J] = z
    c.place_side(sa, A, J)
    c.place_side(sb, B, J)


def _rrp(c: Context, st):
    sa, A, slider, J = st.side_a, st.point_a, st.slider, st.joint
    Q, U, es, ref, _ = c.world_line(st.line)
    Qj = Q + es * (c.w[(slider, J)] - ref)
    z, ok = planar.circle_line(c.pos[A], c.radius(sa, A, J), Qj, U, st.branch, c.tol.radicand, c.margins)
    c.flag(ok)
    c.pos[J] = z
    c.place_side(sa, A, J)
    c.place(slider, z - es * c.w[(slider, J)], es)


def _rpr(c: Context, st):
    guide, gp, slider, sp = st.guide, st.guide_point, st.slider, st.slider_point
    q, u, ref, us = c.lines[st.line]
    cvec = (q - c.w[(guide, gp)]) + (u / us) * (c.w[(slider, sp)] - ref)
    cc = cvec / u
    eu, ok = planar.rotation_from_slide(c.pos[sp] - c.pos[gp], np.real(cc), np.imag(cc), st.branch, c.tol.radicand,
                                        c.margins)
    c.flag(ok)
    eg = eu * (1.0 / u)
    c.place(guide, c.pos[gp] - eg * c.w[(guide, gp)], eg)
    es = eu * (1.0 / us)
    c.place(slider, c.pos[sp] - es * c.w[(slider, sp)], es)


def _prp(c: Context, st):
    a, b, J = st.body_a, st.body_b, st.joint
    Qa, Ua, ea, refa, _ = c.world_line(st.line_a)
    Qb, Ub, eb, refb, _ = c.world_line(st.line_b)
    z, ok = planar.line_line(Qa + ea * (c.w[(a, J)] - refa), Ua, Qb + eb * (c.w[(b, J)] - refb), Ub, c.tol.parallel)
    c.flag(ok)
    c.pos[J] = z
    c.place(a, z - ea * c.w[(a, J)], ea)
    c.place(b, z - eb * c.w[(b, J)], eb)


def _ppr(c: Context, st):
    a, A, b, lo, li = st.body_a, st.point_a, st.body_b, st.outer_line, st.inner_line
    Qo, Uo, eb, refo, _ = c.world_line(lo)
    rec_i = c.plan.lines[li]
    qi, ui, refi, usi = c.lines[li]
    if rec_i[2] == b:        # b guides a: e_a = e_b·u/u_s
        ea = eb * (ui / usi)
    else:                    # a guides b: e_b = e_a·u/u_s
        ea = eb * (usi / ui)
    oa = c.pos[A] - ea * c.w[(a, A)]
    c.place(a, oa, ea)
    if rec_i[2] == b:
        Q2, U2 = oa + ea * refi - eb * qi, eb * ui
    else:
        Q2, U2 = oa + ea * qi - eb * refi, ea * ui
    ob, ok = planar.line_line(Qo - eb * refo, Uo, Q2, U2, c.tol.parallel)
    c.flag(ok)
    c.place(b, ob, eb)


EXECUTORS = {"frame": _frame, "crank": _crank, "gear": _crank, "RRR": _rrr, "RRP": _rrp, "RPR": _rpr, "PRP": _prp, "PPR": _ppr,
             "newton": solve_group, "cam": _crank, "cam_slide": cam_slide}
CLOSED_FORMS = ("RRR", "RRP", "RPR", "PRP", "PPR")


def _run(plan, steps, params, q_jets, order, tol, method, warm):
    c = Context(plan, params, q_jets, order, tol)
    c.warm = warm
    with np.errstate(all="ignore"):
        for st in steps:
            kind = st.kind
            if method == "newton" and kind in CLOSED_FORMS:
                kind = "newton"
            EXECUTORS[kind](c, st)
    return c
