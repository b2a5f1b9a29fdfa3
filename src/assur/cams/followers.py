"""Followers: a cam and its follower as a :class:`~assur.cams.geometry.CamGeometry`, by hand or from a mechanism.

By hand (the cam's pivot at the origin, its frame's x axis along +x at the reference position, lengths in m)::

    translating(law, base_radius=0.04, offset=0.005, contact="roller", roller_radius=0.01)
    oscillating(law, base_radius=0.04, pivot_distance=0.1, arm_length=0.08, contact="roller", roller_radius=0.01)

A translating follower moves along a vertical line x = ``offset``, lifting upward; its trace point is at height
√(R_p² − e²) + s above the cam's pivot (R_p = base radius + roller radius, the prime circle). An oscillating
follower turns about (``pivot_distance``, 0); its trace point at lift 0 lies on the prime circle ``arm_length``
from the pivot, above the centre line, and a lift turns it away from the cam. A flat face lies across the slide (or
along the arm) at ``base_radius`` from the pivot at lift 0.

From a mechanism: :func:`from_plan` reads a ``[[cams]]`` pair at the plan's sketch inputs (one design), so that
x = 0 is the sketch position and x the cam's counter-clockwise turn from it.
"""
from __future__ import annotations

import cmath
import math

import numpy as np

from ..errors import SpecError
from ..model.camming import CamLaw, cam_ends
from .geometry import CamGeometry


def _lift_at(law: CamLaw, phase: float) -> float:
    return float(law.evaluate(np.asarray(phase))[0])


def translating(law: CamLaw, base_radius: float, *, offset: float = 0.0, contact: str = "roller",
                roller_radius: float = 0.0, face_angle: float = 0.0, rotation: int = 1, phase: float = 0.0,
                pressure_limit: float = math.radians(30.0)) -> CamGeometry:
    """A translating follower on the line x = ``offset`` (lifting along +y) of a cam turning about the origin."""
    prime = base_radius + (roller_radius if contact == "roller" else 0.0)
    if contact == "flat":
        y0 = base_radius
    else:
        if not prime > abs(offset):
            raise SpecError([("offset", f"the follower's line misses the prime circle (|offset| {abs(offset):.6g} m ≥ "
                                        f"{prime:.6g} m)")])
        y0 = math.sqrt(prime * prime - offset * offset)
    R0 = complex(offset, y0 + _lift_at(law, phase))
    return CamGeometry(law, "translating", contact, 0j, 1 + 0j, R0, direction=1j,
                       face=cmath.exp(1j * face_angle), roller_radius=roller_radius, phase=phase, rotation=rotation,
                       pressure_limit=pressure_limit)


def oscillating(law: CamLaw, base_radius: float, *, pivot_distance: float, arm_length: float,
                contact: str = "roller", roller_radius: float = 0.0, face_angle: float = 0.0, rotation: int = 1,
                phase: float = 0.0, pressure_limit: float = math.radians(45.0)) -> CamGeometry:
    """An oscillating follower pivoted at (``pivot_distance``, 0), its trace point ``arm_length`` from the pivot
    (the lift ``law`` in rad)."""
    prime = base_radius + (roller_radius if contact == "roller" else 0.0)
    d, arm = pivot_distance, arm_length
    Of = complex(d, 0.0)
    if contact == "flat":
        # the face along the arm direction passes at base_radius from the cam's pivot: the arm's angle γ below the
        # centre line with d·sin γ = base_radius; the trace point arm_length along it
        if not 0 < base_radius < d:
            raise SpecError([("base_radius", "a flat-faced oscillating follower needs 0 < base_radius < pivot_distance")])
        gamma = math.asin(base_radius / d)
        Rb = Of + arm * cmath.exp(1j * (math.pi - gamma))
    else:
        c = (prime * prime - arm * arm + d * d) / (2 * d)
        h2 = prime * prime - c * c
        if h2 <= 0:
            raise SpecError([("arm_length", "the arm cannot reach the prime circle from the pivot")])
        Rb = complex(c, math.sqrt(h2))
    turn = 1.0 if ((Rb.conjugate() * 1j * (Rb - Of)).real > 0) else -1.0
    R0 = Of + (Rb - Of) * cmath.exp(1j * turn * _lift_at(law, phase))
    face = cmath.exp(1j * face_angle) * (Rb - Of) / abs(Rb - Of)
    face = face * cmath.exp(1j * turn * _lift_at(law, phase))
    return CamGeometry(law, "oscillating", contact, 0j, 1 + 0j, R0, follower_pivot=Of, turn=turn, face=face,
                       roller_radius=roller_radius, phase=phase, rotation=rotation, pressure_limit=pressure_limit)


def _pair_index(mechanism, cam) -> int:
    names = [cp.name for cp in mechanism.cams]
    if isinstance(cam, int):
        if not 0 <= cam < len(names):
            raise SpecError([("cam", f"no cam pair {cam} (the mechanism has {len(names)})")])
        return cam
    if cam not in names:
        raise SpecError([("cam", f"unknown cam pair {cam!r} (known: {', '.join(names) or 'none'})")])
    return names.index(cam)


def from_plan(plan, cam=0, params=None) -> CamGeometry:
    """The geometry of the mechanism's cam pair ``cam`` (a name or an index) at one design ``params (n_params,)``
    (default the plan's), placed as at the plan's sketch inputs: x = 0 is the sketch position."""
    from ..engine.planar.continuation import context_at
    m = plan.mechanism
    k = _pair_index(m, cam)
    cp = m.cams[k]
    params = plan.defaults if params is None else np.asarray(params, dtype=float)
    i = next(j for j, st in enumerate(plan.steps) if st.kind in ("cam", "cam_slide") and st.cam == k)
    st = plan.steps[i]
    slot = next(s for s in plan.cam_slots if s.cam == k)
    c = context_at(plan, plan.steps[:i + 1], params, plan.sketch_inputs)
    pos = {p: complex(z.v) for p, z in c.pos.items()}
    pivot, arm = cam_ends(m, cp)
    O = pos[pivot]
    orient = (pos[arm] - O) / abs(pos[arm] - O)
    R = pos[cp.point]
    common = dict(roller_radius=cp.roller_radius, phase=cp.phase, rotation=cp.rotation,
                  pressure_limit=cp.pressure_limit, name=cp.name)
    if st.kind == "cam_slide":
        U = complex(c.world_line(st.line)[1].v)
        direction = slot.lift_sign * U
        face = 1j * direction * cmath.exp(1j * cp.face_angle)
        return CamGeometry(cp.law, "translating", cp.contact, O, orient, R, direction=direction, face=face, **common)
    Of = pos[st.pivot]
    face = cmath.exp(1j * cp.face_angle) * (R - Of) / abs(R - Of)
    return CamGeometry(cp.law, "oscillating", cp.contact, O, orient, R, follower_pivot=Of, turn=slot.lift_sign,
                       face=face, **common)
