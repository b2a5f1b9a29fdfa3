"""Cam pairs in the force analysis: the contact force along the common normal, and the cam's torque.

The groups solve a cam-driven follower like a gear-driven link: an oscillating follower with an unknown torque T_f
about its pivot (a 'T' pair), a translating one with an unknown drive force F_d along its slide (its slide pair's
third unknown, as a driven actuator's). Here that unknown is realised by the contact force F·n̂ at the contact C,
along the common normal n̂ (:func:`assur.cams.geometry.contact_frame`, the normal through the pair's relative
instant centre): F = T_f / ((C − O_f) × n̂), or F = F_d / (n̂·u). The follower's pivot reaction drops by F·n̂ (or its
slide takes the rest of the wrench: N′ = N − F·(n̂·n), M′ = M − (C − Q) × F·n̂), −F·n̂ acts on the cam at C: the
cam's pivot reaction grows by F·n̂ and its drive by (C − O) × F·n̂ (= T_f·dψ/dφ, or F_d·ds/dφ, for the ideal
contact: virtual power). The frame's resultant load is unchanged. F < 0 means the cam would have to pull: the
follower leaves the cam unless a spring or a groove holds it (``lost``).
"""
from __future__ import annotations

import numpy as np

from .gearing import _cross, _pivot_pair


def cam_forces(plan, tables, state, lam, reac, slides, driver, slide_of) -> dict:
    """Apply every cam pair's contact force to the results of one batch of N samples, in place.

    ``state`` the batch's State (flattened to N samples by the caller's shape); lam (n_unknowns, N); reac
    (N, n_pairs, 2); slides (N, n_slides, 2); driver (N, n_inputs); ``slide_of`` (n_pairs,) each pair's row in
    ``slides``. Returns per cam pair name a dict of arrays (N,): ``contact_force`` (N, ≥ 0 while the cam pushes),
    ``normal`` (complex unit), ``contact`` (complex point), ``pressure_angle`` (rad), ``lost`` (bool: F < 0)."""
    from ..cams.mechanism import contacts
    from ..model.camming import cam_ends
    m = plan.mechanism
    n = reac.shape[0]
    cons = contacts(plan, state)
    pidx = plan.point_index
    n_in = plan.n_inputs
    n_gear = len(plan.gear_slots)
    out = {}
    for j in reversed(range(len(plan.cam_slots))):
        sl = plan.cam_slots[j]
        cp = m.cams[sl.cam]
        k = tables.cam_pairs[j]
        fp = tables.pairs[k]
        con = cons[cp.name]
        C, nn = con.contact.reshape(n), con.normal.reshape(n)
        follower = fp.later
        with np.errstate(all="ignore"):
            if fp.kind == "T":
                Of = state_point(state, pidx(next(s.pivot for s in plan.steps if s.kind == "cam" and s.cam == sl.cam)), n)
                T = lam[fp.columns[0]].copy()
                F = T / _cross(C - Of, nn)
                kf = _pivot_pair(tables, follower, pidx(next(s.pivot for s in plan.steps
                                                             if s.kind == "cam" and s.cam == sl.cam)))
                reac[:, kf, 0] -= (F * nn).real
                reac[:, kf, 1] -= (F * nn).imag
                lam[fp.columns[0]] = 0.0
            else:
                c0 = fp.columns[0]
                rec = plan.lines[fp.line]
                u = np.exp(1j * np.broadcast_to(state_params(state, n)[:, rec[5]], (n,)))
                Q = state_point(state, pidx(rec[7]), n)
                Fd = lam[c0 + 2].copy()
                F = Fd / np.real(np.conj(nn) * u)
                N = lam[c0] - F * np.real(np.conj(nn) * 1j * u)
                M = lam[c0 + 1] - _cross(C - Q, F * nn)
                lam[c0], lam[c0 + 1], lam[c0 + 2] = N, M, 0.0
                reac[:, k, 0] = (N * 1j * u).real
                reac[:, k, 1] = (N * 1j * u).imag
                slides[:, slide_of[k], 0] = N
                slides[:, slide_of[k], 1] = M
        Fv = F * nn
        pivot = cam_ends(m, cp)[0]
        O = state_point(state, pidx(pivot), n)
        cam_body = plan.structure.graph.index(cp.cam)
        kc = _pivot_pair(tables, cam_body, pidx(pivot))
        reac[:, kc, 0] += Fv.real
        reac[:, kc, 1] += Fv.imag
        extra = _cross(C - O, Fv)
        if sl.source < n_in:
            driver[:, sl.source] += sl.sense * extra
        elif sl.source < n_in + n_gear:           # a gear-driven cam: its gear's torque
            lam[tables.pairs[tables.gear_pairs[sl.source - n_in]].columns[0]] += extra
        else:                                      # another cam's oscillating follower
            lam[tables.pairs[tables.cam_pairs[sl.source - n_in - n_gear]].columns[0]] += extra
        out[cp.name] = {"contact_force": F, "normal": nn, "contact": C,
                        "pressure_angle": con.pressure_angle.reshape(n), "lost": F < 0}
    return out


def state_point(state, i: int, n: int) -> np.ndarray:
    """(n,) complex position of point ``i`` over the state's n samples."""
    p = np.reshape(state.pos[..., i, :], (n, 2))
    return p[:, 0] + 1j * p[:, 1]


def state_params(state, n: int) -> np.ndarray:
    """(n, n_params) the state's parameters, one row per sample."""
    p = np.asarray(state.params, dtype=float)
    return np.broadcast_to(p, state.shape + p.shape[-1:]).reshape(n, -1)
