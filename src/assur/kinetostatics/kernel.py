"""The force solve of one sample, or of a row of samples, written once.

Every function here is element-wise: called with rows (``z`` (n_points, N) complex, ``F`` (n_bodies, N) …)
it solves N samples at once with numpy; compiled by numba (:mod:`.compiled`) it solves one sample with
scalars (``z`` (n_points,) …). So the numpy and the compiled backends share one text of every formula.

The program (:func:`assur.kinetostatics.program.build_program`) is a set of flat integer and float tables;
the codes are the constants below. The dyads' two closed forms are described in :mod:`.groups`.
"""
from __future__ import annotations

import numpy as np

# body orientation recipes
ANG_STILL, ANG_POINTS, ANG_LINE = 0, 1, 2
# default inertia recipes
DEF_GIVEN, DEF_BAR, DEF_POLYGON = 0, 1, 2
# pair kinds
PAIR_R, PAIR_P, PAIR_T = 0, 1, 2
# group codes
G_CRANK, G_INNER_R, G_INNER_P, G_GENERIC = 1, 2, 3, 4
# columns of the group table
GR_CODE, GR_A0, GR_AN, GR_B0, GR_BN, GR_OA, GR_OB, GR_INNER, GR_D0, GR_DN, GR_LATER_B, GR_R_SIDE = range(12)


def cross(a, b):
    """a × b of complex vectors."""
    return (a.conjugate() * b).imag


def dot(a, b):
    return (a.conjugate() * b).real


def body_motion(ang_order, ang, ang_param, ang_off, z, v, a, p, orient, omega, alpha):
    """Every body's orientation e^{iθ} (complex unit), ω and α (written into ``orient``, ``omega``, ``alpha``
    (n_bodies, …)) from two of its points — with d = P_b − P_a: e^{iθ} = d/|d|, ω = Im(d′/d),
    α = Im(d″/d − (d′/d)²) — or from its guide (the guide's orientation turned by the line's angle)."""
    for i in range(ang_order.shape[0]):
        b = ang_order[i]
        how = ang[b, 0]
        if how == ANG_POINTS:
            d = z[ang[b, 2]] - z[ang[b, 1]]
            n2 = d.real * d.real + d.imag * d.imag
            inv = d.conjugate() / n2
            r1 = (v[ang[b, 2]] - v[ang[b, 1]]) * inv
            r2 = (a[ang[b, 2]] - a[ang[b, 1]]) * inv
            orient[b] = d / np.sqrt(n2)
            omega[b] = r1.imag
            alpha[b] = (r2 - r1 * r1).imag
        elif how == ANG_LINE:
            g = ang[b, 3]
            orient[b] = orient[g] * np.exp(1j * (p[ang_param[b]] + ang_off[b]))
            omega[b] = omega[g]
            alpha[b] = alpha[g]


def com_motion(b, cpts, cw, coff, z, v, a, orient, omega, alpha):
    """Body b's centre of mass: its position, velocity and acceleration (complex)."""
    c = z[cpts[b, 0]] * cw[b, 0]
    cv = v[cpts[b, 0]] * cw[b, 0]
    ca = a[cpts[b, 0]] * cw[b, 0]
    for k in range(1, cpts.shape[1]):
        if cpts[b, k] >= 0:
            c = c + z[cpts[b, k]] * cw[b, k]
            cv = cv + v[cpts[b, k]] * cw[b, k]
            ca = ca + a[cpts[b, k]] * cw[b, k]
    if coff[b] != 0:
        e = orient[b] * coff[b]
        c = c + e
        cv = cv + 1j * omega[b] * e
        ca = ca + (1j * alpha[b] - omega[b] * omega[b]) * e
    return c, cv, ca


def body_inertia(b, mass, inertia, idef, ipts, z, c):
    """Body b's moment of inertia about its centre of mass c: given, a slender bar m·L²/12, or the point-mass
    polygon Σ m/k·|P_k − c|²."""
    m = mass[b]
    if idef[b] == DEF_BAR:
        d = z[ipts[b, 1]] - z[ipts[b, 0]]
        return m * (d.real * d.real + d.imag * d.imag) / 12.0
    if idef[b] == DEF_POLYGON:
        n = 0
        for k in range(ipts.shape[1]):
            if ipts[b, k] >= 0:
                n += 1
        J = 0.0 * c.real
        for k in range(n):
            d = z[ipts[b, k]] - c
            J = J + (m / n) * (d.real * d.real + d.imag * d.imag)
        return J
    return inertia[b] + 0.0 * c.real


def mass_load(b, mass, inertia, idef, ipts, cpts, cw, coff, gravity, z, v, a, orient, omega, alpha):
    """Body b's gravity and d'Alembert inertia: the force m·(g − a_C) at its centre of mass C, the couple −I·α;
    returns (force, C, couple)."""
    c, cv, ca = com_motion(b, cpts, cw, coff, z, v, a, orient, omega, alpha)
    J = body_inertia(b, mass, inertia, idef, ipts, z, c)
    return mass[b] * (gravity - ca), c, -J * alpha[b]


def mass_loads(massive, mass, inertia, idef, ipts, cpts, cw, coff, gravity, z, v, a, orient, omega, alpha, F, M):
    """Gravity and d'Alembert inertia of every massive body, added to ``F``, ``M``."""
    for i in range(massive.shape[0]):
        b = massive[i]
        f, c, couple = mass_load(b, mass, inertia, idef, ipts, cpts, cw, coff, gravity, z, v, a, orient, omega,
                                 alpha)
        F[b] = F[b] + f
        M[b] = M[b] + cross(c, f) + couple


def point_loads(lpts, lforce, torque, z, F, M):
    """The constant loads: forces ``lforce`` at points (``lpts`` rows: body, point) and torques per body."""
    for i in range(lpts.shape[0]):
        b = lpts[i, 0]
        f = lforce[i]
        F[b] = F[b] + f
        M[b] = M[b] + cross(z[lpts[i, 1]], f)
    for b in range(torque.shape[0]):
        if torque[b] != 0:
            M[b] = M[b] + torque[b]


def line_uq(ln, i, z, p, orient):
    """Slide line i: its unit direction u and the slider's reference point Q."""
    Q = z[ln[i, 3]]
    if ln[i, 0] == 1:
        d = Q - z[ln[i, 4]]
        u = d / np.abs(d)
    else:
        u = orient[ln[i, 1]] * np.exp(1j * p[ln[i, 2]])
    return u, Q


def set_pair(pr, ln, k, x0, x1, x2, z, p, orient, F, M, lam):
    """Record pair k's unknowns (x0, x1[, x2]) and apply its wrench: + on the later body, − on the earlier."""
    kind = pr[k, 0]
    c = pr[k, 6]
    if kind == PAIR_R:
        f = x0 + 1j * x1
        mo = cross(z[pr[k, 3]], f)
        lam[c] = x0
        lam[c + 1] = x1
    elif kind == PAIR_T:
        f = 0j * x0
        mo = x0
        lam[c] = x0
    else:
        u, Q = line_uq(ln, pr[k, 4], z, p, orient)
        n = 1j * u
        f = x0 * n
        mo = x0 * cross(Q, n) + x1
        lam[c] = x0
        lam[c + 1] = x1
        if pr[k, 5] >= 0:
            f = f + x2 * u
            mo = mo + x2 * cross(Q, u)
            lam[c + 2] = x2
    later, earlier = pr[k, 2], pr[k, 1]
    F[later] = F[later] + f
    M[later] = M[later] + mo
    if earlier != 0:
        F[earlier] = F[earlier] - f
        M[earlier] = M[earlier] - mo


def side_sum(gb, s0, n, F, M):
    """The resultant force and moment (about the origin) of the bodies gb[s0 : s0 + n]."""
    Fs = F[gb[s0]] + 0j
    Ms = M[gb[s0]] + 0.0
    for k in range(1, n):
        Fs = Fs + F[gb[s0 + k]]
        Ms = Ms + M[gb[s0 + k]]
    return Fs, Ms


def crank(gr, g, gb, pr, ln, z, p, orient, F, M, lam):
    """A crank: the pivot's reaction balances the crank's force, the motor torque its moment about the pivot."""
    b = gb[gr[g, GR_A0]]
    r, t = gr[g, GR_OA], gr[g, GR_INNER]
    P = z[pr[r, 3]]
    Fs = F[b] + 0j
    MP = M[b] - cross(P, Fs)
    set_pair(pr, ln, r, -Fs.real, -Fs.imag, 0.0, z, p, orient, F, M, lam)
    set_pair(pr, ln, t, -MP, 0.0, 0.0, z, p, orient, F, M, lam)
    return 1.0 + 0.0 * MP


def driven_slides(gr, g, gd, pr, ln, z, p, orient, F, M, lam):
    """Each driven actuator's slide from its later body's equilibrium: N, M and the actuator's force."""
    for i in range(gr[g, GR_DN]):
        k = gd[gr[g, GR_D0] + i]
        u, Q = line_uq(ln, pr[k, 4], z, p, orient)
        later = pr[k, 2]
        f = F[later] + 0j
        MQ = M[later] - cross(Q, f)
        set_pair(pr, ln, k, -dot(1j * u, f), -MQ, -dot(u, f), z, p, orient, F, M, lam)


def side_unknown(pr, ln, o, M_J, J, z, p, orient):
    """A side of a dyad hinged at J, by its outer pair o: (K, e, Q) — the part of the pair's force that the
    side's moment about J fixes, the direction of the one unknown left, and the slide's reference point.
    A revolute at X: K = p·i·ê with p = −M_J/|X − J| across ê = (X − J)/|X − J|, the unknown along ê; a slide:
    K = 0, the unknown along its normal n (its couple follows from the moment afterwards)."""
    if pr[o, 0] == PAIR_R:
        d = z[pr[o, 3]] - J
        ad = np.abs(d)
        e = d / ad
        return 1j * e * (-M_J / ad), e, J
    u, Q = line_uq(ln, pr[o, 4], z, p, orient)
    e = 1j * u
    return 0j * e, e, Q


def set_side(pr, ln, o, K, mu, e, M_J, Q, J, z, p, orient, F, M, lam):
    """Record a dyad side's outer pair o from the solved unknown mu: a revolute's force K + mu·e, or a slide's
    normal force mu with the couple that balances the side's moment about J."""
    if pr[o, 0] == PAIR_R:
        f = K + mu * e
        set_pair(pr, ln, o, f.real, f.imag, 0.0, z, p, orient, F, M, lam)
    else:
        set_pair(pr, ln, o, mu, -M_J - mu * cross(Q - J, e), 0.0, z, p, orient, F, M, lam)


def inner_revolute(gr, g, gb, gd, pr, ln, z, p, orient, F, M, lam):
    """A dyad whose sides are hinged to each other at J (RRR, RRP, PRP): the closed form of :mod:`.groups`."""
    a0, an, b0, bn = gr[g, GR_A0], gr[g, GR_AN], gr[g, GR_B0], gr[g, GR_BN]
    oa, ob, ir = gr[g, GR_OA], gr[g, GR_OB], gr[g, GR_INNER]
    J = z[pr[ir, 3]]
    Fa, Ma = side_sum(gb, a0, an, F, M)
    Fb, Mb = side_sum(gb, b0, bn, F, M)
    MaJ = Ma - cross(J, Fa)
    MbJ = Mb - cross(J, Fb)
    Ka, ea, Qa = side_unknown(pr, ln, oa, MaJ, J, z, p, orient)
    Kb, eb, Qb = side_unknown(pr, ln, ob, MbJ, J, z, p, orient)
    G = -(Fa + Fb + Ka + Kb)
    det = cross(ea, eb)
    set_side(pr, ln, oa, Ka, cross(G, eb) / det, ea, MaJ, Qa, J, z, p, orient, F, M, lam)
    set_side(pr, ln, ob, Kb, cross(ea, G) / det, eb, MbJ, Qb, J, z, p, orient, F, M, lam)
    if gr[g, GR_LATER_B] == 1:
        Fl, Ml = side_sum(gb, b0, bn, F, M)
    else:
        Fl, Ml = side_sum(gb, a0, an, F, M)
    set_pair(pr, ln, ir, -Fl.real, -Fl.imag, 0.0, z, p, orient, F, M, lam)
    driven_slides(gr, g, gd, pr, ln, z, p, orient, F, M, lam)
    return np.abs(det)


def inner_slide(gr, g, gb, gd, pr, ln, z, p, orient, F, M, lam):
    """A dyad whose sides slide on each other (RPR, PPR): the closed form of :mod:`.groups`."""
    a0, an, b0, bn = gr[g, GR_A0], gr[g, GR_AN], gr[g, GR_B0], gr[g, GR_BN]
    oa, ob, ip = gr[g, GR_OA], gr[g, GR_OB], gr[g, GR_INNER]
    u, Q = line_uq(ln, pr[ip, 4], z, p, orient)
    n = 1j * u
    Fa, Ma = side_sum(gb, a0, an, F, M)
    Fb, Mb = side_sum(gb, b0, bn, F, M)
    Ft = Fa + Fb
    r_side = gr[g, GR_R_SIDE]
    if r_side == 2:                          # both outer pairs revolute
        Xa, Xb = z[pr[oa, 3]], z[pr[ob, 3]]
        M_tot = Ma + Mb - cross(Xb, Ft)
        d = Xa - Xb
        al = -dot(u, Fa)
        beta = (-M_tot - al * cross(d, u)) / dot(d, u)
        cond = np.abs(dot(d, u)) / np.abs(d)
        Ra = al * u + beta * n
        Rb = -dot(u, Fb) * u + (-dot(n, Ft) - beta) * n
        set_pair(pr, ln, oa, Ra.real, Ra.imag, 0.0, z, p, orient, F, M, lam)
        set_pair(pr, ln, ob, Rb.real, Rb.imag, 0.0, z, p, orient, F, M, lam)
    else:                                     # one revolute (side r_side), one slide
        orr, op = (oa, ob) if r_side == 0 else (ob, oa)
        Fr, Fp = (Fa, Fb) if r_side == 0 else (Fb, Fa)
        uo, Qo = line_uq(ln, pr[op, 4], z, p, orient)
        no = 1j * uo
        No = -dot(u, Fp) / dot(u, no)
        cond = np.abs(dot(u, no))
        R = -dot(u, Fr) * u + (-dot(n, Ft) - No * dot(n, no)) * n
        set_pair(pr, ln, orr, R.real, R.imag, 0.0, z, p, orient, F, M, lam)
        Fa2, Ma2 = side_sum(gb, a0, an, F, M)
        Fb2, Mb2 = side_sum(gb, b0, bn, F, M)
        M_tot = Ma2 + Mb2 - cross(Qo, Fa2 + Fb2)        # N_o acts at Q_o: the couple balances the rest
        set_pair(pr, ln, op, No, -M_tot, 0.0, z, p, orient, F, M, lam)
    if gr[g, GR_LATER_B] == 1:
        Fl, Ml = side_sum(gb, b0, bn, F, M)
    else:
        Fl, Ml = side_sum(gb, a0, an, F, M)
    set_pair(pr, ln, ip, -dot(n, Fl), -(Ml - cross(Q, Fl)), 0.0, z, p, orient, F, M, lam)
    driven_slides(gr, g, gd, pr, ln, z, p, orient, F, M, lam)
    return cond


def outputs(pr, ln, drv, sense, slide_of, z, p, orient, lam, reac, slides, frame, driver):
    """The result rows of a solved sample: per pair the reaction force (x, y); per slide and motor (the pairs
    with ``slide_of[k] = j ≥ 0``) ``slides[j] = (N, M)``, the normal force and the couple (a motor: its torque);
    the resultant load on the frame (x, y, moment about the origin); each input's driving effort."""
    frame[0] = 0.0 * frame[0]
    frame[1] = 0.0 * frame[1]
    frame[2] = 0.0 * frame[2]
    for k in range(pr.shape[0]):
        kind = pr[k, 0]
        c = pr[k, 6]
        j = slide_of[k]
        if kind == PAIR_R:
            f = lam[c] + 1j * lam[c + 1]
            mo = cross(z[pr[k, 3]], f)
        elif kind == PAIR_T:
            f = 0j * lam[c]
            mo = lam[c]
            slides[j, 0] = np.nan + 0.0 * lam[c]
            slides[j, 1] = lam[c]
        else:
            u, Q = line_uq(ln, pr[k, 4], z, p, orient)
            f = lam[c] * 1j * u
            mo = cross(Q, f) + lam[c + 1]
            slides[j, 0] = lam[c]
            slides[j, 1] = lam[c + 1]
            if pr[k, 5] >= 0:
                fu = lam[c + 2] * u
                mo = mo + cross(Q, fu)
                frame[0] = frame[0] - (fu.real if pr[k, 1] == 0 else 0.0 * fu.real)
                frame[1] = frame[1] - (fu.imag if pr[k, 1] == 0 else 0.0 * fu.imag)
        reac[k, 0] = f.real
        reac[k, 1] = f.imag
        if pr[k, 1] == 0:
            frame[0] = frame[0] - f.real
            frame[1] = frame[1] - f.imag
            frame[2] = frame[2] - mo
    for i in range(drv.shape[0]):
        k = drv[i]
        c = pr[k, 6]
        if pr[k, 0] == PAIR_T:
            driver[i] = sense[i] * lam[c]
        else:
            driver[i] = lam[c + 2]
