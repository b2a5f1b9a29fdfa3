"""The closure of a planar plan in maximal coordinates, on :class:`~.series.Series`: one residual for the whole
mechanism, whose implicit differentiation gives every derivative by the parameters (:mod:`.implicit`) and whose
Lagrange multipliers are the reactions (:mod:`.forces`).

Unknowns: per moving body b (in the plan's body order) its origin (x_b, y_b) — its first point — and its angle θ_b.
Equations (in this order, each named in :attr:`Closure.labels`):

- per revolute pair of the force tables (earlier body e, later body l, point P): pos_e(P) − pos_l(P) = 0 (x, y);
- per slide line (guide g, slider s, as :mod:`assur.engine.planar.newton_group`): Im(Ū·e_s·u_s) = 0 (aligned) and
  Im(Ū·d) = 0 (the slider's reference point on the line, d = o_s + e_s·ref − o_g − e_g·q), and for a driven
  actuator Re(Ū·d) − q = 0 (its length is the input);
- per crank (and gear- or cam-driven link) b: Im(ē_b·E) = 0 with E = exp(i·(sense·q + zero))·conj(unit(w_arm − w_pivot)),
  q the input or the slot; per translating cam follower: Re(Ū·(o_s + e_s·ref − Q)) − (start + slot) = 0.

The local coordinates w follow from the parameters by the engine's own recipes (:mod:`assur.engine.planar.geometry`),
written again here on series so that their derivatives are exact.
"""
from __future__ import annotations

import numpy as np

from ...kinetostatics.tables import force_tables
from .series import Series, abs_complex, expi


class Closure:
    """The residual of a planar plan (see the module's docstring)."""

    def __init__(self, plan):
        self.plan = plan
        g = plan.structure.graph
        self.moving = list(range(1, plan.n_bodies))
        self.n = 3 * len(self.moving)
        t = force_tables(plan)
        self.tables = t
        self.revolutes = [(k, fp.earlier, fp.later, plan.point_names[fp.point]) for k, fp in enumerate(t.pairs)
                          if fp.kind == "R"]
        driven = {d.actuator: k for k, d in enumerate(plan.mechanism.drivers) if d.kind == "linear"}
        self.driven = driven
        self.turning = [st for st in plan.steps if st.kind in ("crank", "gear", "cam")]
        self.sliding = [st for st in plan.steps if st.kind == "cam_slide"]
        labels = []
        for k, e, l, p in self.revolutes:
            labels += [("R", k, 0), ("R", k, 1)]
        for i, rec in enumerate(plan.lines):
            labels += [("P", i, 0), ("P", i, 1)]
            if rec[0] == "actuator" and rec[1] in driven:
                labels.append(("P", i, 2))
        for st in self.turning:
            labels.append(("T", st, 0))
        for st in self.sliding:
            labels.append(("S", st, 0))
        self.labels = labels
        if len(labels) != self.n:
            raise ValueError(f"the closure has {len(labels)} equations for {self.n} unknowns")
        self.g = g

    # -- geometry ------------------------------------------------------------------------------------------
    def geometry(self, p: list):
        """(w, lines) as :func:`assur.engine.planar.geometry.geometry`, from the parameters ``p`` (a list of
        series, one per parameter)."""
        w = {}
        for bi, rec in enumerate(self.plan.geometry_program):
            if rec[0] == "frame":
                for name, ix, iy in rec[1]:
                    w[(bi, name)] = p[ix] + p[iy] * 1j
            elif rec[0] == "point":
                w[(bi, rec[1])] = 0j
            else:
                _, p0, p1, il, placed = rec
                w[(bi, p0)] = 0j
                w[(bi, p1)] = p[il] + 0j
                for name, org, tow, idist, iang in placed:
                    a, b = w[(bi, org)], w[(bi, tow)]
                    d = b - a
                    if not isinstance(d, Series):
                        d = Series.const(np.asarray(d, complex), p[0].K) + 0j
                    w[(bi, name)] = a + p[idist] * expi(p[iang]) * (d / abs_complex(d))
        lines = []
        for rec in self.plan.lines:
            kind, name, gb, slider, through, ia, io, ref, u_slider = rec
            if kind == "actuator":
                lines.append((0j, 1 + 0j, 0j, 1 + 0j))
                continue
            u = expi(p[ia])
            lines.append((w[(gb, through)] + u * p[io] * 1j, u, w[(slider, ref)], u_slider))
        return w, lines

    # -- the residual --------------------------------------------------------------------------------------
    def residual(self, X: list, p: list, q: list) -> list:
        """The residual components (real series, in the order of :attr:`labels`) at body coordinates ``X`` (3 per
        moving body), parameters ``p`` and inputs-and-slots ``q`` (series: the plan's inputs, then its gear and
        cam slots)."""
        plan = self.plan
        w, lines = self.geometry(p)
        pose = {0: (0j, 1 + 0j)}
        for j, b in enumerate(self.moving):
            pose[b] = (X[3 * j] + X[3 * j + 1] * 1j, expi(X[3 * j + 2]))

        def world(b, point):
            o, e = pose[b]
            return o + e * w[(b, point)]

        out = []
        for k, e, l, point in self.revolutes:
            z = world(e, point) - world(l, point)
            out += [z.real, z.imag]
        for i, rec in enumerate(plan.lines):
            kind, name, guide, slider = rec[:4]
            qq, u, ref, us = lines[i]
            og, eg = pose[guide]
            os_, es = pose[slider]
            U = eg * u
            Ub = U.conj() if isinstance(U, Series) else np.conj(U)
            out.append((Ub * (es * us)).imag)
            d = os_ + es * ref - og - eg * qq
            out.append((Ub * d).imag)
            if kind == "actuator" and name in self.driven:
                out.append((Ub * d).real - q[self.driven[name]])
        for st in self.turning:
            b = st.bodies[0]
            dw = w[(b, st.arm)] - w[(b, st.pivot)]
            if not isinstance(dw, Series):
                dw = Series.const(np.asarray(dw, complex), X[0].K) + 0j
            E = expi(q[st.input] * float(st.sense) + p[st.zero_param]) * (dw.conj() / abs_complex(dw))
            out.append((pose[b][1].conj() * E).imag)
        for st in self.sliding:
            b = st.bodies[0]
            qq, u, ref, us = lines[st.line]
            Q, U = qq, u                                      # the follower's line is on the frame
            o, e = pose[b]
            r = o + e * ref - Q
            out.append((U.conj() * r).real - (p[st.start_param] + q[st.input]))
        return out
