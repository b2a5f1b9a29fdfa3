"""Gear pairs in the force analysis: the tooth force along the line of action and the motor torque.

The groups solve a gear-driven link like a crank, with an unknown torque T_b (the gear's torque on it, a 'T'
pair, :mod:`.tables`). Here that torque is realised by the tooth force: a force F along the line of action
through the pitch point P (the instant centre of the two links' relative rotation)

    P = (O_a − y'·O_b) / (1 − y'),     y' = dθ_b/dθ_a from the pair's law,

inclined by the pressure angle α to the pitch curves' common tangent t (for non-circular pitch curves t is not
perpendicular to the centre line: with r_a the driving pitch radius, t ∝ r_a'·e − r_a·i·e, e the unit vector
O_a → O_b). The flank in contact is the one whose force turns b the way T_b does (a tooth only pushes), so
F = T_b / ((P − O_b) × d) > 0 with d = ±cos α·t̂ + sin α·n̂ (n̂ the pitch normal into b). F·d acts on b at P and
−F·d on a: b's pivot reaction drops by F·d, a's grows by it, and a's driving torque grows by (P − O_a) × F·d,
which equals T_b·y' for an ideal pair (virtual power). The frame's resultant load is unchanged.
"""
from __future__ import annotations

import math

import numpy as np

from ..model.gearing import gear_ends


def _cross(u, v):
    return np.imag(np.conj(u) * v)


def _pivot_pair(tables, body: int, pivot_index: int) -> int:
    return next(k for k, fp in enumerate(tables.pairs)
                if fp.kind == "R" and fp.later == body and fp.earlier == 0 and fp.point == pivot_index)


def gear_forces(plan, tables, z, inputs, lam, reac, driver) -> dict:
    """Apply every gear pair's tooth force to the results of one batch, in place.

    z (n_points, N) complex positions; inputs (N, n_inputs); lam (n_unknowns, N) the groups' unknowns;
    reac (N, n_pairs, 2) and driver (N, n_inputs) the result rows (updated). Returns, per gear pair name, a dict
    of arrays (N,): ``torque`` (the gear's torque on its driven link, N·m, ccw positive), ``tooth_force`` (N, ≥ 0),
    ``line_of_action`` (N,) complex unit vector (the force on the driven link), ``pitch_point`` (N,) complex."""
    m = plan.mechanism
    n_in = plan.n_inputs
    values, rates = [inputs[:, k] for k in range(n_in)], []
    for sl in plan.gear_slots:                       # each slot's rotation and law derivatives, in order
        x = sl.sense * (values[sl.source] - sl.sketch)
        y, y1, y2 = m.gears[sl.gear].relative(x)
        values.append(y)
        rates.append((y1, y2))
    steps = plan.steps_of("gear")
    out = {}
    for j in reversed(range(len(plan.gear_slots))):
        sl, st = plan.gear_slots[j], steps[j]
        gp = m.gears[sl.gear]
        y1, y2 = rates[j]
        # the driving link's own rate: its rotation per unit of the slot's source
        b = st.bodies[0]
        a = plan.structure.graph.index(gp.a)
        a_pivot = gear_ends(m, gp)[0][0]
        Oa, Ob = z[plan.point_index(a_pivot)], z[plan.point_index(st.pivot)]
        d = np.abs(Ob - Oa)
        e = (Ob - Oa) / d
        with np.errstate(all="ignore"):
            P = (Oa - y1 * Ob) / (1.0 - y1)
            ra = -y1 * d / (1.0 - y1)
            ra1 = -d * y2 / (1.0 - y1) ** 2
            t = ra1 * e - ra * 1j * e
            t = t / np.abs(t)
            n0 = 1j * t
            n0 = np.where(np.real(np.conj(n0) * (Ob - P)) < 0, -n0, n0)
            T = lam[tables.pairs[tables.gear_pairs[j]].columns[0]].copy()
            s = np.where(T * _cross(P - Ob, t) >= 0, 1.0, -1.0)
            dvec = s * math.cos(gp.pressure_angle) * t + math.sin(gp.pressure_angle) * n0
            F = T / _cross(P - Ob, dvec)
        Fv = F * dvec
        kb, ka = _pivot_pair(tables, b, plan.point_index(st.pivot)), _pivot_pair(tables, a, plan.point_index(a_pivot))
        reac[:, kb, 0] -= Fv.real
        reac[:, kb, 1] -= Fv.imag
        reac[:, ka, 0] += Fv.real
        reac[:, ka, 1] += Fv.imag
        extra = _cross(P - Oa, Fv)
        if sl.source < n_in:
            driver[:, sl.source] += sl.sense * extra
        else:                                        # the driving link is itself gear-driven: its gear's torque
            lam[tables.pairs[tables.gear_pairs[sl.source - n_in]].columns[0]] += extra
        out[gp.name] = {"torque": T, "tooth_force": np.abs(F), "line_of_action": dvec, "pitch_point": P}
    return out
