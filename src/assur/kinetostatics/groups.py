"""Kinetostatics group by group: the reactions of each Assur group from its own equilibrium.

The groups are solved from the last one attached back to the drivers (Artobolevsky's order): when
a group is solved, the loads of every later group on its bodies are already known. A dyad has two
closed forms, written once for every dyad kind:

* **inner revolute at J** (RRR, RRP, PRP): each side's moment about J fixes the part of an outer
  revolute's force across the side (p = −M_J/|X − J|); the rest is one unknown along X − J (a
  revolute) or along the normal n of an outer slide; the dyad's force balance
  μ_a·e_a + μ_b·e_b = G gives both (Cramer; the condition measure is |e_a × e_b|);
* **inner slide** (RPR, PPR): the sides' force balances along the slide, the dyad's balance across
  it and its moment balance (the condition measure is |cos| of the outer revolutes' line to the slide,
  or |sin| of the angle between the two slides).

A driven actuator's own slide (its force) follows from its rod's equilibrium; a crank's torque from
the crank's. Any other group (triads and higher) is a small linear solve per sample,
:func:`solve_group_linear`, which is also the global Newton–Euler matrix of :mod:`.oracle`.
"""
from __future__ import annotations

import numpy as np

from .motion import cross, dot
from .tables import ForcePair, ForceTables


class Wrenches:
    """Per-body resultant force (complex) and moment about the origin, each (...), accumulated as
    applied loads and solved reactions are added; and the solved unknowns ``lam`` by column."""

    def __init__(self, tables: ForceTables, motion, params, shape):
        self.tables, self.motion, self.params = tables, motion, params
        self.F = [np.zeros(shape, complex) for _ in range(tables.n_bodies)]
        self.M = [np.zeros(shape) for _ in range(tables.n_bodies)]
        self.lam = [None] * tables.n_unknowns
        self.shape = shape

    def add(self, body: int, force, at, moment=0.0):
        """A force (complex) acting at the point ``at`` (complex) and a couple on ``body``."""
        self.F[body] = self.F[body] + force
        self.M[body] = self.M[body] + cross(at, force) + moment

    def moment_about(self, bodies, X):
        """The resultant moment of ``bodies`` about the point X."""
        F = sum(self.F[b] for b in bodies)
        M = sum(self.M[b] for b in bodies)
        return F, M - cross(X, F)

    def basis(self, fp: ForcePair):
        """The wrench on the later body per unit of each unknown: [(force, moment about origin)]."""
        m = self.motion
        if fp.kind == "R":
            P = m.z[..., fp.point]
            return [(1.0 + 0j, -P.imag), (1j, P.real)]
        if fp.kind == "T":
            return [(0j, 1.0)]
        u, Q, _ = m.line(self.tables, self.params, fp.line)
        n = 1j * u
        out = [(n, cross(Q, n)), (0j, 1.0)]
        if fp.driven >= 0:
            out.append((u, cross(Q, u)))
        return out

    def set_pair(self, fp: ForcePair, values):
        """Record the unknowns of a pair and apply its wrench to both bodies."""
        basis = self.basis(fp)
        F = sum(v * f for v, (f, _) in zip(values, basis))
        M = sum(v * mo for v, (_, mo) in zip(values, basis))
        self.F[fp.later] = self.F[fp.later] + F
        self.M[fp.later] = self.M[fp.later] + M
        if fp.earlier:
            self.F[fp.earlier] = self.F[fp.earlier] - F
            self.M[fp.earlier] = self.M[fp.earlier] - M
        for c, v in zip(fp.columns, values):
            self.lam[c] = v


def solve_groups(W: Wrenches, *, closed: bool = True):
    """Solve every group from the last back to the drivers; returns the condition measure (...) (the
    smallest over the groups; 1 where every group is well conditioned)."""
    t = W.tables
    condition = np.ones(W.shape)
    for step, bodies, mine in reversed(t.groups):
        pairs = [t.pairs[k] for k in mine]
        c = None
        if closed:
            c = _closed(W, bodies, pairs)
        if c is None:
            c = solve_group_linear(W, bodies, pairs)
        condition = np.fmin(condition, c)
    return condition


def _units(W: Wrenches, bodies, pairs):
    """The group's units (bodies joined by a driven slide) and the driven slides inside them."""
    unit = {b: b for b in bodies}
    driven = [fp for fp in pairs if fp.kind == "P" and fp.driven >= 0 and fp.earlier in unit]
    for fp in driven:
        lo = min(unit[fp.earlier], unit[fp.later])
        for b in bodies:
            if unit[b] in (unit[fp.earlier], unit[fp.later]):
                unit[b] = lo
    members = {}
    for b in bodies:
        members.setdefault(unit[b], []).append(b)
    return unit, list(members.values()), driven


def _closed(W: Wrenches, bodies, pairs):
    """The closed forms of a crank or a dyad; None where the group is not one of those shapes."""
    if len(bodies) == 1 and len(pairs) == 2 and {fp.kind for fp in pairs} == {"R", "T"}:
        return _crank(W, bodies[0], pairs)
    unit, sides, driven = _units(W, bodies, pairs)
    if len(sides) != 2:
        return None
    inner = [fp for fp in pairs if fp.earlier in unit and fp not in driven]
    outer = [fp for fp in pairs if fp.earlier not in unit]
    if len(inner) != 1 or len(outer) != 2 or any(fp.kind == "T" or fp.driven >= 0 for fp in outer):
        return None
    side_of = lambda fp: 0 if unit[fp.later] == unit[sides[0][0]] else 1   # noqa: E731
    if {side_of(outer[0]), side_of(outer[1])} != {0, 1}:
        return None
    if side_of(outer[0]) == 1:
        outer = outer[::-1]
    if inner[0].kind == "R":
        cond = _inner_revolute(W, sides, outer, inner[0], unit)
    else:
        cond = _inner_slide(W, sides, outer, inner[0], unit)
    if cond is None:
        return None
    for fp in driven:
        _driven_slide(W, fp)
    return cond


def _crank(W: Wrenches, body, pairs):
    r = next(fp for fp in pairs if fp.kind == "R")
    T = next(fp for fp in pairs if fp.kind == "T")
    P = W.motion.z[..., r.point]
    F, MP = W.moment_about([body], P)
    W.set_pair(r, [-F.real, -F.imag])
    W.set_pair(T, [-MP])
    return np.ones(W.shape)


def _line(W, fp):
    return W.motion.line(W.tables, W.params, fp.line)


def _inner_revolute(W: Wrenches, sides, outer, inner: ForcePair, unit):
    J = W.motion.z[..., inner.point]
    K, e, finish = [], [], []
    for side, fp in zip(sides, outer):
        F_s, M_sJ = W.moment_about(side, J)
        if fp.kind == "R":
            d = W.motion.z[..., fp.point] - J
            with np.errstate(all="ignore"):
                dn = d / np.abs(d)
                K.append(1j * dn * (-M_sJ / np.abs(d)))
            e.append(dn)
            finish.append(None)
        else:
            u, Q, _ = _line(W, fp)
            n = 1j * u
            K.append(0j)
            e.append(n)
            finish.append((Q, n, M_sJ))
    F = sum(W.F[b] for s in sides for b in s)
    G = -(F + K[0] + K[1])
    det = cross(e[0], e[1])
    with np.errstate(all="ignore"):
        mu = (cross(G, e[1]) / det, cross(e[0], G) / det)
    forces = []
    for k, fp in enumerate(outer):
        f = K[k] + mu[k] * e[k]
        forces.append(f)
        if fp.kind == "R":
            W.set_pair(fp, [f.real, f.imag])
        else:
            Q, n, M_sJ = finish[k]
            W.set_pair(fp, [mu[k], -M_sJ - mu[k] * cross(Q - J, n)])
    # the inner revolute: side b's equilibrium (its outer reaction is now applied)
    b_side = 1 if unit[inner.later] == unit[sides[1][0]] else 0
    f_on_later = -sum(W.F[b] for b in sides[b_side])
    W.set_pair(inner, [f_on_later.real, f_on_later.imag])
    return np.abs(det)


def _inner_slide(W: Wrenches, sides, outer, inner: ForcePair, unit):
    u, Q, _ = _line(W, inner)
    n = 1j * u
    Fs = [sum(W.F[b] for b in s) for s in sides]
    F = Fs[0] + Fs[1]
    kinds = [fp.kind for fp in outer]
    if kinds == ["R", "R"]:
        Xa, Xb = (W.motion.z[..., fp.point] for fp in outer)
        _, M_tot = W.moment_about(sides[0] + sides[1], Xb)
        d = Xa - Xb
        alpha = -dot(u, Fs[0])
        with np.errstate(all="ignore"):
            beta = (-M_tot - alpha * cross(d, u)) / dot(d, u)
            cond = np.abs(dot(d, u)) / np.abs(d)
        Ra = alpha * u + beta * n
        Rb = -dot(u, Fs[1]) * u + (-dot(n, F) - beta) * n
        W.set_pair(outer[0], [Ra.real, Ra.imag])
        W.set_pair(outer[1], [Rb.real, Rb.imag])
    elif sorted(kinds) == ["P", "R"]:
        r = 0 if kinds[0] == "R" else 1
        p = 1 - r
        uo, Qo, _ = _line(W, outer[p])
        no = 1j * uo
        X = W.motion.z[..., outer[r].point]
        with np.errstate(all="ignore"):
            N_o = -dot(u, Fs[p]) / dot(u, no)
        cond = np.abs(dot(u, no))
        R = -dot(u, Fs[r]) * u + (-dot(n, F) - N_o * dot(n, no)) * n
        W.set_pair(outer[r], [R.real, R.imag])
        _, M_tot = W.moment_about(sides[0] + sides[1], Qo)      # N_o acts at Q_o: the couple balances the rest
        W.set_pair(outer[p], [N_o, -M_tot])
    else:
        return None
    # the inner slide: the later side's equilibrium about Q
    b_side = 1 if unit[inner.later] == unit[sides[1][0]] else 0
    f, MQ = W.moment_about(sides[b_side], Q)
    W.set_pair(inner, [-dot(n, f), -MQ])
    return cond


def _driven_slide(W: Wrenches, fp: ForcePair):
    """A driven actuator's slide from its later body's equilibrium: N, M and the actuator force F."""
    u, Q, _ = _line(W, fp)
    f, MQ = W.moment_about([fp.later], Q)
    W.set_pair(fp, [-dot(1j * u, f), -MQ, -dot(u, f)])


def solve_group_linear(W: Wrenches, bodies, pairs, scale: float | None = None):
    """The group's equilibrium as one linear system per sample: 3 equations per body (force, and moment
    about the group's first point over the length scale), one column per unknown. Returns the condition
    measure: the Hadamard ratio |det A| / Π‖row‖ of the scaled matrix (1 for orthogonal rows)."""
    L = W.tables.plan.length_scale if scale is None else scale
    rows = {b: 3 * k for k, b in enumerate(bodies)}
    cols = [(fp, j, c) for fp in pairs for j, c in enumerate(fp.columns)]
    n_eq, n_un = 3 * len(bodies), len(cols)
    if n_eq != n_un:
        raise ValueError(f"group {bodies}: {n_eq} equations, {n_un} unknowns")
    X = W.motion.z[..., W.tables.plan.point_index(W.tables.plan.structure.graph.bodies[bodies[0]].points[0])]
    A = np.zeros(W.shape + (n_eq, n_un))
    rhs = np.zeros(W.shape + (n_eq,))
    for b in bodies:
        r = rows[b]
        F, MX = W.moment_about([b], X)
        rhs[..., r], rhs[..., r + 1], rhs[..., r + 2] = -F.real, -F.imag, -MX / L
    for k, (fp, j, c) in enumerate(cols):
        f, mo = W.basis(fp)[j]
        mX = mo - cross(X, f)
        unit_scale = L if (fp.kind == "T" or (fp.kind == "P" and j == 1)) else 1.0   # couples as forces × L
        for body, sign in ((fp.later, 1.0), (fp.earlier, -1.0)):
            if body in rows:
                r = rows[body]
                A[..., r, k] += sign * np.real(f)
                A[..., r + 1, k] += sign * np.imag(f)
                A[..., r + 2, k] += sign * mX / L * unit_scale
    x, cond = linear_solve(A, rhs)
    by_pair: dict = {}
    for k, (fp, j, c) in enumerate(cols):
        unit_scale = L if (fp.kind == "T" or (fp.kind == "P" and j == 1)) else 1.0
        by_pair.setdefault(id(fp), (fp, []))[1].append(x[..., k] * unit_scale)
    for fp, values in by_pair.values():
        W.set_pair(fp, values)
    return cond


def linear_solve(A, rhs):
    """Batched ``A x = rhs`` with A (..., n, n): x (..., n) and the Hadamard ratio (...); NaN where a sample's
    matrix is not finite or exactly singular (never an exception for one bad sample)."""
    with np.errstate(all="ignore"):
        finite = np.all(np.isfinite(A), axis=(-1, -2)) & np.all(np.isfinite(rhs), axis=-1)
        safe = np.where(finite[..., None, None], A, np.eye(A.shape[-1]))
        det = np.linalg.det(safe)
        norms = np.prod(np.linalg.norm(safe, axis=-1), axis=-1)
        ratio = np.where(finite, np.abs(det) / np.where(norms > 0, norms, 1.0), np.nan)
        ok = finite & (ratio > 0)
        safe = np.where(ok[..., None, None], safe, np.eye(A.shape[-1]))
        x = np.linalg.solve(safe, np.where(ok[..., None], rhs, 0.0)[..., None])[..., 0]
    x = np.where(ok[..., None], x, np.nan)
    return x, np.where(ok, ratio, np.where(finite, 0.0, np.nan))
