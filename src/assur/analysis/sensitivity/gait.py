"""Exact derivatives of a walking leg's gait metrics by every parameter (the envelope theorem at refined extremes).

With the foot's stride coordinate x(q, p) and height v(q, p) (q the crank angle):

- the step length x_max − x_min and the lift v_max − v_min are differences of extremes over the turn; at an extreme
  q* (∂f/∂q = 0) the extreme value moves as ∂f/∂p (the envelope theorem);
- the contact arc runs between the stride's extremes q_a, q_b; an end moves as dq_e/dp = −(∂²x/∂q∂p)/(∂²x/∂q²), so the
  duty factor (the arc's share of the turn) moves as (dq_end/dp − dq_start/dp)/2π, and the sag (v's range over the
  arc) by the envelope theorem at an interior extreme, or by ∂v/∂p + ∂v/∂q·dq_e/dp at an end of the arc. Where two
  candidates share the extreme and move apart (the two ends of a symmetric path, as a Chebyshev lambda's), the sag
  has a kink: its derivative is NaN.

The extremes are refined by Newton's method on the exact derivatives (each step one solve at that input).
"""
from __future__ import annotations

import math

import numpy as np

from ...kernels.arcs import in_arc
from .forces import _at
from .implicit import solve_motion
from .outputs import Output

TWO_PI = 2.0 * math.pi


class _Foot:
    def __init__(self, study):
        self.study = study
        plan = study.plan
        g = plan.mechanism.gait
        self.g = complex(*g.ground)
        self.u = complex(*g.up_vector)
        self.i = plan.point_index(g.foot)
        self.b = plan.point_body[self.i]
        self.name = g.foot
        self.w = float(plan.speeds[0])

    def at(self, q) -> dict:
        """x, v and their q-derivatives (value, ∂/∂q, ∂²/∂q², ∂/∂p, ∂²/∂q∂p) at inputs ``q (k,)``."""
        st = self.study.state_at(np.atleast_1d(np.asarray(q, dtype=float)))
        mo = solve_motion(self.study.plan, st)
        world, _ = _at(mo.closure, mo.X, mo.params)
        z = world(self.b, self.name)
        w = self.w
        out = {}
        for key, axis in (("x", self.g), ("v", self.u)):
            proj = lambda c: np.real(np.conj(axis) * c)   # noqa: E731
            out[key] = (proj(z.v[0][:, 0, 0]), proj(z.v[1][:, 0, 0]) / w, proj(z.v[2][:, 0, 0]) * 2 / (w * w),
                        proj(z.e1[0][..., 0]), proj(z.e1[1][..., 0]) / w)
        return out

    def refine(self, key: str, q0: float, iterations: int = 8) -> tuple[float, tuple]:
        """(q*, the derivatives there) of the extreme of ``key`` near ``q0`` (Newton on ∂f/∂q)."""
        q = float(q0)
        for _ in range(iterations):
            f = self.at(q)[key]
            step = f[1][0] / f[2][0]
            q -= step
            if abs(step) < 1e-15:
                break
        return q % TWO_PI, self.at(q)[key]


def gait_outputs(study) -> dict[str, Output]:
    """{'gait.step', 'gait.lift', 'gait.sag', 'gait.duty'}: each Output (a float and (n_params,) derivatives), or {}
    when the study has no arc-support gait."""
    gm = study.gait
    if gm is None or gm.support != "arc":
        return {}
    F = _Foot(study)
    q = study.q
    P = study.state.pos[:, F.i]
    x, v = P @ np.array(study.plan.mechanism.gait.ground), P @ np.array(study.plan.mechanism.gait.up_vector)
    qa, fa = F.refine("x", q[int(np.argmin(x))])
    qb, fb = F.refine("x", q[int(np.argmax(x))])
    qvmin, gmin = F.refine("v", q[int(np.argmin(v))])
    qvmax, gmax = F.refine("v", q[int(np.argmax(v))])
    out = {"gait.step": Output("gait.step", "gait", "m", fb[0][0] - fa[0][0], fb[3][0] - fa[3][0]),
           "gait.lift": Output("gait.lift", "gait", "m", gmax[0][0] - gmin[0][0], gmax[3][0] - gmin[3][0])}
    # the contact arc: from its start to its end (q_a or q_b), and how each end moves
    def apart(a, b):
        return abs(((a - b + math.pi) % TWO_PI) - math.pi)

    ea, eb = (qa, -fa[4][0] / fa[2][0]), (qb, -fb[4][0] / fb[2][0])
    start, end = (ea, eb) if apart(qa, gm.contact_start) <= apart(qb, gm.contact_start) else (eb, ea)
    width = (end[0] - start[0]) % TWO_PI
    out["gait.duty"] = Output("gait.duty", "gait", "1", width / TWO_PI, (end[1] - start[1]) / TWO_PI)
    # the sag: v's range over the arc; the candidates are the arc's two ends (moving with it) and the interior roots
    # of ∂v/∂q refined from the samples' extremes (the envelope theorem there)
    inside = in_arc(q, start[0], width)
    qs, vs = q[inside], v[inside]
    cands = []
    for e in (start, end):
        f = F.at(e[0])["v"]
        cands.append((f[0][0], f[3][0] + f[1][0] * e[1]))
    for pick in (np.argmin, np.argmax):
        qi, fe = F.refine("v", qs[int(pick(vs))])
        if 0.0 < (qi - start[0]) % TWO_PI < width:
            cands.append((fe[0][0], fe[3][0]))
    tie = 1e-9 * max(abs(out["gait.lift"].value), 1e-300)
    values = []
    for best in (min(cands, key=lambda c: c[0]), max(cands, key=lambda c: c[0])):
        rivals = [c for c in cands if abs(c[0] - best[0]) <= tie and not np.allclose(c[1], best[1], rtol=1e-9,
                                                                                       atol=1e-12)]
        # an extreme shared by two candidates that move apart (both ends of a symmetric arc): a kink, no derivative
        values.append((best[0], np.full_like(best[1], np.nan) if rivals else best[1]))
    (vmin, dmin), (vmax, dmax) = values
    out["gait.sag"] = Output("gait.sag", "gait", "m", vmax - vmin, dmax - dmin)
    return out
