"""The pair reactions of the force analysis from the closure's multipliers, with their parameter derivatives.

Each multiplier is turned into the reaction :mod:`assur.kinetostatics` reports (the force of the pair's earlier body
on its later one, frame coordinates): a revolute's −(λ_x + i·λ_y), a slide's normal force along its line's normal.
A gear- or cam-driven link's drive (a torque, or a follower's force along its slide) is then realised by the tooth or
contact force exactly as :mod:`assur.kinetostatics.gearing` and :mod:`assur.kinetostatics.camming` do, on series, so
that the pivots' reactions and their derivatives are those of the realised forces.
"""
from __future__ import annotations

import math

import numpy as np

from ...model.camming import cam_ends
from ...model.gearing import gear_ends
from .forces import Multipliers, _at
from .implicit import Motion
from .series import Series, abs_complex


def _dot(a, b):
    return (a.conj() * b).real if isinstance(a, Series) else np.real(np.conj(a) * b)


def _cross(a, b):
    return (a.conj() * b).imag if isinstance(a, Series) else np.imag(np.conj(a) * b)


def _value(x):
    """The value of a series, (n,) (or the constant itself)."""
    return x.v[0][..., 0, 0] if isinstance(x, Series) else np.asarray(x)


def _pivot_pair(t, body: int, point: int) -> int:
    return next(k for k, fp in enumerate(t.pairs)
                if fp.kind == "R" and fp.later == body and fp.earlier == 0 and fp.point == point)


def reactions(plan, motion: Motion, mult: Multipliers) -> list:
    """Per force-table pair, its reaction as a complex series (value and ∂/∂p in ε₁), realised at gear and cam pairs;
    None for a motor's torque pair."""
    cl = motion.closure
    t = cl.tables
    n = mult.value.shape[0]
    lam = [Series([mult.value[:, c, None, None]], [mult.derivative[:, :, c, None]]) for c in range(cl.n)]
    X = [Series([x.v[0]], [x.e1[0]]) for x in motion.X]
    p = [x.truncate(1) for x in motion.params]
    world, pose = _at(motion.closure, X, p)
    w, lines = cl.geometry(p)
    out = [None] * len(t.pairs)
    line_pair = {fp.line: k for k, fp in enumerate(t.pairs) if fp.kind == "P"}
    constraint_of = {}
    for c, (kind, key, comp) in enumerate(cl.labels):
        if kind == "R" and comp == 0:
            out[key] = (lam[c] + lam[c + 1] * 1j) * -1.0
        elif kind == "P" and comp == 1:
            rec = plan.lines[key]
            k = line_pair[key]
            qq, u, ref, us = lines[key]
            U = pose[rec[2]][1] * u
            N = lam[c] if t.pairs[k].later == rec[3] else lam[c] * -1.0
            out[k] = N * U * 1j
            constraint_of[("P", key)] = (c, N, U)
        elif kind in ("T", "S"):
            constraint_of[(kind, id(key))] = c
    _realise_cams(plan, motion, lam, out, world, pose, lines, constraint_of, n)
    _realise_gears(plan, motion, lam, out, world, constraint_of, n)
    return out


def _realise_gears(plan, motion, lam, out, world, constraint_of, n):
    m, t = plan.mechanism, motion.closure.tables
    if not plan.gear_slots:
        return
    rates = _slot_rates(plan, motion, n)
    steps = plan.steps_of("gear")
    n_in = plan.n_inputs
    for j in reversed(range(len(plan.gear_slots))):
        sl, st = plan.gear_slots[j], steps[j]
        gp = m.gears[sl.gear]
        y1, y2 = rates[n_in + j]
        b = st.bodies[0]
        a = plan.structure.graph.index(gp.a)
        a_pivot = gear_ends(m, gp)[0][0]
        Oa, Ob = world(0, a_pivot), world(0, st.pivot)
        d = abs_complex(Ob - Oa)
        e = (Ob - Oa) / d
        P = (Oa - Ob * y1) * (1.0 / (1.0 - y1))
        ra = d * (-y1 / (1.0 - y1))
        ra1 = d * (-y2 / (1.0 - y1) ** 2)
        tt = e * ra1 - e * ra * 1j
        tt = tt / abs_complex(tt)
        n0 = tt * 1j
        flip = np.where(_value(_dot(n0, Ob - P)) < 0, -1.0, 1.0)
        n0 = n0 * flip
        T = lam[constraint_of[("T", id(st))]] * -1.0
        s = np.where(_value(T) * _value(_cross(P - Ob, tt)) >= 0, 1.0, -1.0)
        dvec = tt * (s * math.cos(gp.pressure_angle)) + n0 * math.sin(gp.pressure_angle)
        F = T / _cross(P - Ob, dvec)
        Fv = dvec * F
        kb = _pivot_pair(t, b, plan.point_index(st.pivot))
        ka = _pivot_pair(t, a, plan.point_index(a_pivot))
        out[kb] = out[kb] - Fv
        out[ka] = out[ka] + Fv


def _slot_rates(plan, motion, n):
    """Per input and slot, (dy/dx, d²y/dx²) of the slot by its own driving rotation (the law's L′, L″)."""
    from ...kernels.jet import Jet
    from ...engine.planar.steps import with_gear_slots
    out = [(None, None)] * plan.n_inputs
    m = plan.mechanism
    vals = [x.v[0][:, 0, 0] for x in motion.q]
    for j, sl in enumerate(plan.gear_slots):
        x = sl.sense * (vals[sl.source] - sl.sketch)
        _, y1, y2 = m.gears[sl.gear].relative(x)
        out.append((y1, y2))
    return out


def _realise_cams(plan, motion, lam, out, world, pose, lines, constraint_of, n):
    """The contact force of each cam pair (:mod:`assur.kinetostatics.camming`) on series."""
    from ...cams.mechanism import cam_turns
    m, t = plan.mechanism, motion.closure.tables
    if not plan.cam_slots:
        return
    inputs = np.stack([x.v[0][:, 0, 0] for x in motion.q[:plan.n_inputs]], axis=-1)
    turns = cam_turns(plan, inputs)
    for j in reversed(range(len(plan.cam_slots))):
        sl = plan.cam_slots[j]
        cp = m.cams[sl.cam]
        st = next(s for s in plan.steps if s.kind in ("cam", "cam_slide") and s.cam == sl.cam)
        _, s1, _, _ = cp.law.evaluate(cp.phase + cp.rotation * turns[sl.cam])
        rate = cp.rotation * s1
        pivot = cam_ends(m, cp)[0]
        O = world(0, pivot)
        follower = st.bodies[0]
        R = world(follower, cp.point)
        if st.kind == "cam_slide":
            along = pose[0][1] * lines[st.line][1] * sl.lift_sign
            centre = O - along * rate * 1j
            face = along * 1j * complex(math.cos(cp.face_angle), math.sin(cp.face_angle))
        else:
            Of = world(0, st.pivot)
            wr = sl.lift_sign * rate
            centre = (O - Of * wr) * (1.0 / (1.0 - wr))
            arm = R - Of
            face = arm / abs_complex(arm) * complex(math.cos(cp.face_angle), math.sin(cp.face_angle))
        if cp.contact == "flat":
            nn = face * 1j
            nn = nn * np.where(_value(_dot(nn, R - O)) < 0, -1.0, 1.0)
            C = centre + nn * _dot(R - centre, nn)
        else:
            v = R - centre
            nn = v / abs_complex(v)
            nn = nn * np.where(_value(_dot(nn, R - O)) < 0, -1.0, 1.0)
            C = R - nn * cp.roller_radius
        if st.kind == "cam":
            T = lam[constraint_of[("T", id(st))]] * -1.0
            F = T / _cross(C - Of, nn)
            kf = _pivot_pair(t, follower, plan.point_index(st.pivot))
            out[kf] = out[kf] - nn * F
        else:
            k = t.cam_pairs[j]
            c, N, U = constraint_of[("P", st.line)]
            u = pose[0][1] * lines[st.line][1]
            Fd = lam[constraint_of[("S", id(st))]]
            F = Fd / _dot(nn, u)
            Nn = N - F * _dot(nn, u * 1j)
            out[k] = Nn * u * 1j
        kc = _pivot_pair(t, plan.structure.graph.index(cp.cam), plan.point_index(pivot))
        out[kc] = out[kc] + nn * F
