"""Transmission angles of the dyads, dead-centre positions of the cranks, buildable ranges.

Transmission angle μ of a dyad (0 at a toggle, where the group locks; 90° is ideal):
- RRR: the angle at the inner joint J between the two links, J→A and J→B, in [0°, 180°];
- RRP: the angle between the rod A→J and the guide's normal, in [0°, 90°];
- RPR: the angle between the line joining the two outer revolutes and the slide's normal, [0°, 90°];
- PRP, PPR: the angle between the two slide lines, in [0°, 90°].
Dead centres of a crank: the input angles where the crank is collinear with the link hinged at
its arm ("extended" or "folded"); a follower driven by the crank reverses there.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..engine import geometry
from ..engine.plan import require_plan
from ..errors import float_array
from ..kernels.runs import cyclic_runs
from ..tolerances import DEFAULT as TOL
from .sampling import TWO_PI, root_between, sign_changes


def _angle(a, b):
    """Angle between planar vectors given as complex arrays, in [0, π]."""
    return np.abs(np.angle(np.conj(a) * b))


def _acute(a, b):
    t = _angle(a, b)
    return np.minimum(t, math.pi - t)


#: the closed-form dyads that have a transmission angle (a group solved by Newton iterations has none)
TRANSMISSION_KINDS = ("RRR", "RRP", "RPR", "PRP", "PPR")


def has_transmission(plan) -> bool:
    """Whether any group of the plan is a dyad with a transmission angle (:data:`TRANSMISSION_KINDS`)."""
    return any(st.kind in TRANSMISSION_KINDS for st in plan.steps)


def transmission_angles(plan, state, params=None) -> dict[str, np.ndarray]:
    """μ (rad) of each closed-form dyad, keyed by the point the dyad solves; arrays of state.shape."""
    require_plan(plan)
    if getattr(state, "pos", None) is None:
        from ..errors import ArgumentTypeError
        raise ArgumentTypeError([("state", f"must be a State of this plan (assur.solve(plan, …)), not "
                                           f"{type(state).__name__}")])
    z = state.pos[..., 0] + 1j * state.pos[..., 1]
    idx = {p: i for i, p in enumerate(plan.point_names)}
    P = lambda name: z[..., idx[name]]  # noqa: E731
    params = plan.defaults if params is None else float_array(params, "params", "numbers (the design parameters)")
    _, lines = geometry(plan, params)
    theta = None if all(st.kind not in ("RRP", "RPR", "PRP", "PPR") for st in plan.steps) \
        else state.body_angle      # body angles only where a slide's direction is needed
    out = {}
    for st in plan.steps:
        if st.kind == "RRR":
            A, B, J = st.point_a, st.point_b, st.joint
            out[J] = _angle(P(A) - P(J), P(B) - P(J))
        elif st.kind == "RRP":
            A, line, J = st.point_a, st.line, st.joint
            guide = plan.lines[line][2]
            u = lines[line][1] * np.exp(1j * theta[..., guide])
            out[J] = _acute(P(J) - P(A), 1j * u)
        elif st.kind == "RPR":
            guide, gp, sp, line = st.guide, st.guide_point, st.slider_point, st.line
            u = lines[line][1] * np.exp(1j * theta[..., guide])
            out[st.key_point] = _acute(P(sp) - P(gp), 1j * u)
        elif st.kind in ("PRP", "PPR"):
            la, lb = (st.line_a, st.line_b) if st.kind == "PRP" else (st.outer_line, st.inner_line)
            ua = lines[la][1] * np.exp(1j * theta[..., plan.lines[la][2]])
            ub = lines[lb][1] * np.exp(1j * theta[..., plan.lines[lb][2]])
            out[st.key_point or f"step{plan.steps.index(st)}"] = _acute(ua, ub)
    return out


@dataclass(frozen=True)
class DeadCentre:
    driver: str
    angle: float      # the input's angle (rad): the motor's for a crank driven through gears
    kind: str         # 'extended' | 'folded'
    link: str         # the link hinged at the crank's arm
    crank: str = ""   # the crank (a link turning about a frame pivot: the driver's, or one driven through gears)

    def _repr_html_(self) -> str:
        from ..model.display import dataclass_table
        return dataclass_table(self, "Dead centre", units={"angle": "rad"})


def _crank_followers(plan) -> list[tuple]:
    """(pivot, arm, follower point, follower link, crank link) of every crank of a one-input planar plan (a
    driver's crank, or a link turned through gears) whose arm carries another link."""
    g = plan.structure.graph
    out = []
    for crank in plan.steps:
        if crank.kind not in ("crank", "gear"):
            continue
        for b in g.bodies_at(crank.arm):
            body = g.bodies[b]
            if body.kind == "link" and b != crank.bodies[0]:
                others = [p for p in body.points if p != crank.arm]
                if others:
                    out.append((crank.pivot, crank.arm, others[0], body.name, plan.body_names[crank.bodies[0]]))
                    break
    return out


def dead_centres(cycle, *, refine: bool = True) -> list[DeadCentre]:
    """The input angles where a crank is collinear with the link hinged at its arm, over the turn of ``cycle`` (a
    :class:`~assur.analysis.sampling.Cycle` or Study of a one-input planar plan). Every crank counts: the
    driver's, and a link turned through gears, whose dead centres are found in the motor's angle.

    The collinearity is bracketed between the samples of the cycle's solved turn, and each root refined by Brent's
    method to :attr:`~assur.tolerances.Tolerances.root_angle` (``refine``; else the linear interpolation of the
    collinearity between its two samples, an error of O(h²) in the angle, h = 2π/steps). Sorted by crank, then
    angle."""
    plan = cycle.plan
    if plan.n_inputs != 1 or plan.input_kinds[0] != "rotary":
        return []
    q, state = cycle.grid()
    steps = len(q)
    out = []
    for pivot, arm, J, link, crank in _crank_followers(plan):
        io, ia, ij = (plan.point_index(p) for p in (pivot, arm, J))

        def collinearity(pos, io=io, ia=ia, ij=ij):
            z = pos[..., 0] + 1j * pos[..., 1]
            a, b = z[..., ia] - z[..., io], z[..., ij] - z[..., ia]
            c = np.conj(a) * b
            return c.imag, c.real

        def cross_dot(t, collinearity=collinearity):
            return collinearity(cycle.state_at(np.atleast_1d(t), order=0).pos)

        cr, dt = collinearity(state.pos)
        for i in sign_changes(q, cr):
            a, b = q[i], q[i] + (q[1] - q[0])
            if refine:
                root = root_between(lambda t, f=cross_dot: float(f(t)[0][0]), a, b)
                d = float(cross_dot(root)[1][0])
            else:
                j = (i + 1) % steps
                w = cr[i] / (cr[i] - cr[j])
                root, d = a + w * (b - a), float(dt[i] + w * (dt[j] - dt[i]))
            out.append(DeadCentre(plan.input_names[0], float(root % TWO_PI), "extended" if d > 0 else "folded",
                                  link, crank))
    return out


def buildable_ranges(cycle):
    """Input intervals over the turn of ``cycle`` (a :class:`~assur.analysis.sampling.Cycle` or Study) where the
    mechanism assembles, with their ends refined by bisection on buildability to
    :attr:`~assur.tolerances.Tolerances.toggle_angle` (the toggle positions where a group locks).
    Returns (ranges [(start, end)] in rad, number of unbuildable samples, steps)."""
    q, state = cycle.grid()
    valid = state.valid
    steps = len(q)
    h = q[1] - q[0]

    def ok(t):
        return bool(cycle.state_at(np.array([t]), order=0).valid[0])

    def edge(good, bad):
        for _ in range(60):
            mid = 0.5 * (good + bad)
            if ok(mid):
                good = mid
            else:
                bad = mid
            if abs(bad - good) < TOL.toggle_angle:
                break
        return good

    out = []
    runs = cyclic_runs(valid)
    for a, b in runs:
        if len(runs) == 1 and valid.all():
            out.append((0.0, TWO_PI))
            continue
        start = edge(q[a], q[a] - h)
        end = edge(q[b], q[b] + h)
        out.append((float(start % TWO_PI), float(end % TWO_PI)))
    return out, int(np.count_nonzero(~valid)), steps
