"""A mechanism's cam pairs over a solved run: the cam's turn, the follower's lift, the contact and its normal per
sample, from the state's positions (so that every sample may have its own design) and the exact law.

:func:`contacts` is what the force analysis (the contact force along the common normal), the figures (the profile
turning with its cam) and the reports read.
"""
from __future__ import annotations

import cmath
from dataclasses import dataclass

import numpy as np

from ..kernels.jet import Jet
from ..model.camming import cam_ends
from .geometry import contact_frame


@dataclass(frozen=True)
class PairContact:
    """One cam pair over a batch (arrays of the batch's shape): ``x`` the cam's ccw turn from the sketch, ``lift``
    s(φ) (the law's lift, m or rad), ``rate`` and ``rate2`` dΔ/dx and d²Δ/dx², ``trace``, ``contact``, ``normal``
    (unit, the cam's push on the follower), ``centre`` (the relative instant centre) and ``pressure_angle``."""
    name: str
    x: np.ndarray
    lift: np.ndarray
    rate: np.ndarray
    rate2: np.ndarray
    trace: np.ndarray
    contact: np.ndarray
    normal: np.ndarray
    centre: np.ndarray
    pressure_angle: np.ndarray


def cam_turns(plan, inputs) -> dict[int, np.ndarray]:
    """{cam pair index: the cam's ccw turn from the sketch} for inputs ``(..., n_inputs)``."""
    from ..engine.planar.steps import with_gear_slots
    inputs = np.asarray(inputs, dtype=float)
    q = [Jet(inputs[..., k]) for k in range(plan.n_inputs)]
    slots = with_gear_slots(plan, q)
    return {sl.cam: (slots[sl.source].v - sl.sketch) * sl.sense for sl in plan.cam_slots}


def contacts(plan, state) -> dict[str, PairContact]:
    """{cam pair name: :class:`PairContact`} over a solved planar ``state``."""
    m = plan.mechanism
    if not m.cams:
        return {}
    turns = cam_turns(plan, np.broadcast_to(state.inputs, state.shape + (plan.n_inputs,)))
    params = np.broadcast_to(np.asarray(state.params, dtype=float), state.shape + (plan.n_params,))
    z = state.pos[..., 0] + 1j * state.pos[..., 1]
    out = {}
    for sl in plan.cam_slots:
        cp = m.cams[sl.cam]
        st = next(s for s in plan.steps if s.kind in ("cam", "cam_slide") and s.cam == sl.cam)
        x = turns[sl.cam]
        phi = cp.phase + cp.rotation * x
        s, s1, s2, _ = cp.law.evaluate(phi)
        rate, rate2 = cp.rotation * s1, s2
        O = z[..., plan.point_index(cam_ends(m, cp)[0])]
        R = z[..., plan.point_index(cp.point)]
        if st.kind == "cam_slide":
            angle = params[..., plan.lines[st.line][5]]
            along = sl.lift_sign * np.exp(1j * angle)
            face = 1j * along * cmath.exp(1j * cp.face_angle)
        else:
            along = z[..., plan.point_index(st.pivot)]
            face = cmath.exp(1j * cp.face_angle) * (R - along) / np.abs(R - along)
        with np.errstate(all="ignore"):
            centre, normal, contact, alpha = contact_frame(cp.contact, cp.motion, O, R, along, sl.lift_sign, face,
                                                           rate, cp.roller_radius)
        out[cp.name] = PairContact(cp.name, x, s, rate, rate2, R, contact, normal, centre, alpha)
    return out
