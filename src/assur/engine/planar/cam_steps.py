"""Cam pairs in the planar engine: the compile-time step of a cam-driven follower and its executor.

A cam-driven follower needs no new solver, as a gear-driven link: its move is a *cam slot*
(:class:`~assur.engine.plan.CamSlot`), a jet in the inputs computed before the steps run from the cam's rotation
through the pair's law (chain rule: y′ = L′·x′, y″ = L″·x′² + L′·x″; :func:`slot_jet`). An oscillating follower
is then a crank step about its pivot (:class:`~assur.engine.plan.CamStep`, executed as a crank), a translating one
a slide along its frame line (:class:`~assur.engine.plan.CamSlideStep`, :func:`cam_slide`). Its velocities and
accelerations are therefore exact derivatives of the law in the motor's angle, and any group attached to the
follower is solved as usual: a cam-driven rocker drives further Assur groups.
"""
from __future__ import annotations

import cmath

import numpy as np

from ...errors import SpecError, StructureError
from ...kernels.jet import Jet
from ..plan import CamSlideStep, CamSlot, CamStep


def slot_jet(plan, slot: CamSlot, x: Jet) -> Jet:
    """The follower's move from the sketch as a jet, for the cam's rotation ``x`` (a jet) from the sketch."""
    cp = plan.mechanism.cams[slot.cam]
    y, y1, y2 = cp.relative(x.v)
    k = slot.lift_sign
    d = None if x.d is None else k * y1 * x.d
    dd = None if (x.dd is None or x.d is None) else k * (y2 * (x.d * x.d) + y1 * x.dd)
    return Jet(k * y, d, dd)


def cam_slide(c, st):
    """Place a translating follower: its reference point at ``start + slot`` along its frame line, not turning."""
    body = st.bodies[0]
    Q, U, es, ref, _ = c.world_line(st.line)
    t = c.q[st.input] + c.params[..., st.start_param]
    c.place(body, Q + U * t - es * ref, es)


def _source(m, steps, cam_body):
    """(source slot, sense, sketch input) of the step that turns the cam link, or None."""
    for st in steps:
        if st.bodies != (cam_body,):
            continue
        if st.kind == "crank":
            return st.input, float(m.drivers[st.input].sense), None
        if st.kind in ("gear", "cam"):
            return st.input, 1.0, 0.0
    return None


def cam_step(m, B, grp, steps, gear_slots, cam_slots, sketch_inputs):
    """The step of a cam-driven follower, appending the pair's slot to ``cam_slots``: the cam must be a driven crank,
    a gear-driven link or an oscillating follower of another cam (a link turning about a frame pivot whose whole
    rotation the solver knows). ``B`` the compiler's builder (parameters, lines, sketch)."""
    g = B.g
    pair = g.pairs[grp.outer[1][1]]
    k = next(i for i, cp in enumerate(m.cams) if cp.name == pair.name)
    cp = m.cams[k]
    a, b = pair.bodies
    src = _source(m, steps, a)
    if src is None:
        raise StructureError(f"cam pair '{cp.name}': its cam '{cp.cam}' must be a driven crank, a gear-driven link or "
                             f"another cam's oscillating follower (a link the drive turns directly)")
    source, sense, sketch = src
    if sketch is None:
        sketch = float(sketch_inputs[source])
    cam_pivot = next(p for p in g.bodies[a].points if p in set(g.bodies[0].points))
    O, R = B.sketch(cam_pivot), B.sketch(cp.point)
    slot = len(m.drivers) + len(gear_slots) + len(cam_slots)
    own = g.pairs[grp.outer[0][1]]
    where = f"cams[{k}].point"
    if own.kind == "R":                          # oscillating about a frame pivot
        pivot = own.point
        arm = cp.point if cp.point != pivot else next(p for p in g.bodies[b].points if p != pivot)
        sign = float(np.sign(((R - O).conjugate() * 1j * (R - B.sketch(pivot))).real))
        if sign == 0 or abs(R - B.sketch(pivot)) == 0:
            raise SpecError([(where, f"the sketch puts the trace point {cp.point} where turning the follower about "
                                     f"{pivot} moves it along the circle about the cam's pivot {cam_pivot}: a lift "
                                     f"cannot carry it away from the cam")])
        zero = B.param(f"{cp.name}.zero", cmath.phase(B.sketch(arm) - B.sketch(pivot)), "angle")
        cam_slots.append(CamSlot(k, source, sense, sketch, sign))
        return CamStep((b,), pivot, arm, slot, zero, 1, k)
    line = B.line_of[own.name]
    rec = B.lines[line]
    pr = next(p for p in m.prismatic if p.name == own.name)
    U = cmath.exp(1j * pr.angle)
    Q = B.sketch(pr.through) + 1j * U * pr.offset
    ref = B.sketch(rec[7])
    sign = float(np.sign(((R - O).conjugate() * U).real))
    if sign == 0:
        raise SpecError([(where, f"the sketch puts the trace point {cp.point} level with the cam's pivot {cam_pivot} "
                                 f"across the slide '{own.name}': a lift cannot carry it away from the cam")])
    start = B.param(f"{cp.name}.start", ((ref - Q).conjugate() * U).real)
    cam_slots.append(CamSlot(k, source, sense, sketch, sign))
    return CamSlideStep((b,), line, slot, start, k)
