"""Kinetostatics of a spatial plan: the RSSR of paper 003 (a crank followed by R–S–S dyads).

The model
---------
Bodies: a crank (a revolute on the frame about its axis e1 at its pivot O), and per R–S–S dyad a
coupler A–B (a spherical joint at both ends, or a universal joint at one) and a rocker (a revolute on
the frame about its axis e2 at its pivot D). Mass properties come from ``Mechanism.dynamics``:

- ``mass`` (kg) at the centre of mass ``com``: None (the centroid of the link's points), ``"mid"``
  (the midpoint of its first two points), a point name, or sketch coordinates ``(x, y, z)`` (m) fixed
  to the body (their coordinates in the body's frame are taken once, in the sketch position of the
  file's design). A coupler between two spherical joints has no frame (it spins idly): its com must
  lie on the line A–B.
- ``inertia`` (kg·m²). A crank or rocker turns about a fixed axis: ``inertia`` is its moment of
  inertia about the hinge axis through the com (default: a slender bar m·L⊥²/12 for a binary link,
  L⊥ the part of the link perpendicular to the axis; the point masses m/k at its k points otherwise);
  its products of inertia are neglected (they load only the bearing moments, never the torque).
  A coupler is a slender bar: ``inertia`` is its transverse moment of inertia about the com (default
  m·L²/12, L = |B − A|) and it has no axial inertia, so its spin is irrelevant: its angular momentum is
  I·u × u̇ (u = (B − A)/L) and its d'Alembert couple −I·u × ü.
- Loads: gravity m·g at the com (a 3-vector), the d'Alembert force −m·a_com at the com and couple
  (−I·(α·e)·e for a hinged body), the file's loads: a force (3-vector, N) at a point, on the named
  link or the earliest-solved body at the point, optionally against the point's velocity or as a law
  of the first input; a torque (N·m, right-handed about the axis) on a crank or rocker, about its
  hinge axis. Loads on the frame carry nothing.

Unknowns and their solution
---------------------------
Each frame revolute carries a force (3) and a moment perpendicular to its axis (2); each spherical
end a force (3); a universal end also a moment m·n about n = Ort(pin × e_z2), the direction its
cross cannot turn about (its pin on the crank or rocker, e_z2 the coupler's second cross axis,
eqs. (27)–(30)); the motor a torque about the crank axis (1). The dyads are solved from the last to
the first, each in closed form:

1. The coupler's moment balance about A along u fixes the universal joint's moment,
   m = −u·M_A/(u·n) (for two spherical ends u·M_A is identically 0: the coupler's sixth equation is
   void); its transverse part fixes the transverse force at B, F_B⊥ = u × (M_A + m·n)/L, M_A the
   coupler's applied moment about A. A massless coupler has M_A = 0: it is a two-force member, its
   force along B − A.
2. The rocker's moment balance about its axis fixes the coupler's axial force s in F_B = F_B⊥ + s·u:
   s·e2·((B − D) × u) = e2·M_D − e2·((B − D) × F_B⊥), M_D the rocker's applied moment about D.
3. The coupler's force balance gives F_A = −F_B − F_coupler; the rocker's force and moment balance give
   its bearing force and moment.
4. Each crank's moment balance about its axis gives the motor torque, the rest its bearing.

The condition measure of a dyad is c = |u · Ort(e2 × (B − D))| (the coefficient of s in step 2,
made dimensionless): the sine of paper 003's effective transmission angle μ_T = asin(|u·t|), t the
direction of B's velocity. It goes to 0 where the coupler's line meets the rocker axis or is
perpendicular to B's path, where no coupler force can balance a moment on the rocker (a dead point
of the rocker as the driven link); for a universal joint also |u·n| (its moment about the coupler
axis). Samples where it is below ``tolerances.force_condition`` are ``singular``: NaN forces.

The sign convention is the package's (:mod:`.result`): a pair's reaction is the force (and moment)
that its earlier body (frame, crank, rocker, coupler in the solve order) exerts on its later body.
"""
from __future__ import annotations

import math
import weakref
from dataclasses import dataclass

import numpy as np

from ..engine import solve
from ..errors import SpecError
from ..model.dynamics import Dynamics
from ..tolerances import DEFAULT
from .result import Forces


@dataclass(frozen=True, slots=True)
class _Mass:
    """com = Σ weights·P[points] + R·offset (R the body frame; offset None: no frame term)."""
    mass: float
    points: tuple[int, ...]
    weights: tuple[float, ...]
    offset: tuple[float, float, float] | None
    inertia: float | None
    kind: str                  # 'hinged' | 'coupler'
    ends: tuple[int, int]      # the two points of the default inertia (bar) or the hinge (pivot, arm)
    all_points: tuple[int, ...]


@dataclass(frozen=True, slots=True)
class _Load:
    body: int
    point: int                 # -1 for a torque
    force: tuple | None
    torque: float | None
    law: object
    opposes: str | None


@dataclass(frozen=True)
class _Tables:
    """What the force solve of a spatial plan needs that no design or input changes.

    Pairs, in order: each crank's frame revolute, per dyad its ends A and B and its frame revolute D,
    then each crank's motor ('T')."""
    cranks: tuple            # (body, pivot index, input, sense)
    dyads: tuple             # (rocker, coupler, D, A, B, A's body, (U, pin body, pin local) or None)
    masses: tuple            # per body: _Mass or None
    loads: tuple
    gravity: tuple
    pair_kinds: tuple
    pair_names: tuple
    pair_bodies: tuple
    pair_points: tuple       # the point a pair's force acts at (-1: a motor)


_CACHE: "weakref.WeakKeyDictionary" = weakref.WeakKeyDictionary()


def spatial_forces(plan, params=None, inputs=None, *, speeds=None, accels=None, state=None,
                   tolerances=DEFAULT) -> Forces:
    """Reactions, motor torques and power of every sample of a spatial batch (the model: this module).

    Parameters and the sign convention as for :func:`assur.forces`. Returns a :class:`~.result.Forces`
    whose ``reactions`` are 3-vectors (..., n_pairs, 3), ``bearing_moments`` (..., n_pairs, 3) each
    pair's moment (a frame revolute's bearing moment, perpendicular to its axis; a universal joint's
    cross moment; zero at a spherical joint; a motor's torque vector T·e1), ``couples`` (..., n_pairs)
    their magnitudes (for a motor the torque T about the crank axis, right-handed),
    ``frame_force``/``frame_moment`` (..., 3) and ``condition`` the smallest dyad condition measure."""
    if state is None:
        state = solve(plan, params, inputs, speeds=speeds, accels=accels, order=2, tolerances=tolerances)
    elif state.plan is not plan or state.d2pos_dq2 is None:
        raise SpecError([("state", "must be a state of this plan solved with order=2 (accelerations)")])
    t = _tables(plan, tolerances)
    shape = state.shape
    pos = np.broadcast_to(state.pos, shape + state.pos.shape[-2:])
    frames = np.broadcast_to(state.body_frame, shape + state.body_frame.shape[-3:])
    nb, n_pairs, k = plan.n_bodies, len(t.pair_kinds), len(t.cranks)
    F = np.zeros(shape + (nb, 3))          # the applied load on each body: its resultant force …
    M = np.zeros(shape + (nb, 3))          # … and its moment about the origin
    R = np.zeros(shape + (n_pairs, 3))
    C = np.zeros(shape + (n_pairs, 3))
    cond = np.ones(shape)
    driver = np.empty(shape + (plan.n_inputs,))
    with np.errstate(invalid="ignore", divide="ignore"):
        _applied(t, state, pos, frames, F, M)
        for j in reversed(range(len(t.dyads))):
            cj = _dyad(t.dyads[j], pos, frames, F, M, R, C, k + 3 * j)
            cond = np.minimum(cond, cj)
        for i, (body, iO, inp, sense) in enumerate(t.cranks):
            O, e1 = pos[..., iO, :], frames[..., body, :, 2]
            MO = M[..., body, :] - np.cross(O, F[..., body, :])
            T = -_dot(e1, MO)
            R[..., i, :] = -F[..., body, :]
            C[..., i, :] = -(MO - _dot(e1, MO)[..., None] * e1)
            C[..., n_pairs - k + i, :] = T[..., None] * e1
            driver[..., inp] = sense * T
    valid = np.asarray(state.valid)
    singular = valid & ~(cond >= tolerances.force_condition)
    singular |= valid & ~(np.all(np.isfinite(R), axis=(-1, -2)) & np.all(np.isfinite(driver), axis=-1))
    ok = valid & ~singular
    qdot = np.asarray(state.qdot, dtype=float)
    power = np.einsum("...k,...k->...", driver, np.broadcast_to(qdot, driver.shape))
    frame_f = np.zeros(shape + (3,))
    frame_m = np.zeros(shape + (3,))
    frame = plan.body_names[0]
    for p, (a, _) in enumerate(t.pair_bodies):
        if a == frame:
            frame_f = frame_f - R[..., p, :]
            frame_m = frame_m - C[..., p, :]
            if t.pair_points[p] >= 0:
                frame_m = frame_m - np.cross(pos[..., t.pair_points[p], :], R[..., p, :])
    couples = np.linalg.norm(C, axis=-1)
    for i, (body, *_) in enumerate(t.cranks):
        couples[..., n_pairs - k + i] = _dot(C[..., n_pairs - k + i, :], frames[..., body, :, 2])
    bad = ~ok

    def masked(x, extra):
        return np.where(bad.reshape(shape + (1,) * extra), np.nan, x)

    return Forces(plan=plan, inputs=np.broadcast_to(state.inputs, shape + (plan.n_inputs,)), qdot=qdot,
                  pair_kinds=t.pair_kinds, pair_names=t.pair_names, pair_bodies=t.pair_bodies,
                  reactions=masked(R, 2), full_couples=masked(couples, 1), full_normal=np.full(shape + (n_pairs,), np.nan),
                  driver=masked(driver, 1), power=masked(power, 0), frame_force=masked(frame_f, 1),
                  frame_moment=masked(frame_m, 1), condition=np.where(valid, cond, np.nan),
                  valid=ok, singular=singular, method="groups", state=state, bearing_moments=masked(C, 2))


def _dyad(dy, pos, frames, F, M, R, C, p0):
    """Solve one R–S–S dyad's reactions in closed form (steps 1–3 of the module's text) into ``R`` and
    ``C`` at pairs p0 (A), p0 + 1 (B), p0 + 2 (D); pass its reactions on to the rocker and to A's body.
    Returns its condition measure (...)."""
    rocker, coupler, iD, iA, iB, a_body, uni = dy
    A, B, D = pos[..., iA, :], pos[..., iB, :], pos[..., iD, :]
    e2 = frames[..., rocker, :, 2]
    L = _norm(B - A)
    u = (B - A) / L[..., None]
    Fc = F[..., coupler, :]
    MA = M[..., coupler, :] - np.cross(A, Fc)
    K = MA
    cond = np.ones(L.shape)
    if uni is not None:                         # the cross's moment m·n balances the coupler's axial moment
        iU, pin_body, pin_local = uni
        pin = np.einsum("...ij,j->...i", frames[..., pin_body, :, :], np.asarray(pin_local))
        n = _unit(np.cross(pin, frames[..., coupler, :, 2]))
        un = _dot(u, n)
        mn = (-_dot(u, MA) / un)[..., None] * n
        cond = np.abs(un)
        K = MA + mn
        M[..., pin_body, :] -= mn
        C[..., p0 if iU == iA else p0 + 1, :] = mn
    FB_perp = np.cross(u, K) / L[..., None]
    r = B - D
    cond = np.minimum(cond, np.abs(_dot(u, _unit(np.cross(e2, r)))))
    MD = M[..., rocker, :] - np.cross(D, F[..., rocker, :])
    s = (_dot(e2, MD) - _dot(e2, np.cross(r, FB_perp))) / _dot(e2, np.cross(r, u))
    FB = FB_perp + s[..., None] * u
    FA = -FB - Fc
    F[..., rocker, :] -= FB
    M[..., rocker, :] -= np.cross(B, FB)
    MDt = M[..., rocker, :] - np.cross(D, F[..., rocker, :])
    R[..., p0, :], R[..., p0 + 1, :], R[..., p0 + 2, :] = FA, FB, -F[..., rocker, :]
    C[..., p0 + 2, :] = -(MDt - _dot(e2, MDt)[..., None] * e2)
    F[..., a_body, :] -= FA
    M[..., a_body, :] -= np.cross(A, FA)
    return cond


# -- the applied loads -----------------------------------------------------------------------------------
def _applied(t: _Tables, state, pos, frames, F, M) -> None:
    """Gravity, d'Alembert inertia and the file's loads on every body, added to ``F`` and ``M``."""
    shape = state.shape
    acc = np.broadcast_to(state.acc, pos.shape)
    g = np.asarray(t.gravity, dtype=float)
    for b, bm in enumerate(t.masses):
        if bm is None:
            continue
        com = sum(w * pos[..., i, :] for i, w in zip(bm.points, bm.weights))
        a = sum(w * acc[..., i, :] for i, w in zip(bm.points, bm.weights))
        if bm.offset is not None:
            off = np.asarray(bm.offset)
            a = a + np.einsum("...ij,j->...i", _frame_acc(state, b), off)
            com = com + np.einsum("...ij,j->...i", frames[..., b, :, :], off)
        f = bm.mass * (g - a)
        F[..., b, :] += f
        M[..., b, :] += np.cross(com, f)
        P, Q = pos[..., bm.ends[0], :], pos[..., bm.ends[1], :]
        if bm.kind == "coupler":
            L = _norm(Q - P)
            u = (Q - P) / L[..., None]
            udd = (acc[..., bm.ends[1], :] - acc[..., bm.ends[0], :]) / L[..., None]
            inertia = bm.mass * L * L / 12.0 if bm.inertia is None else bm.inertia
            M[..., b, :] -= np.asarray(inertia)[..., None] * np.cross(u, udd)
        else:
            e = frames[..., b, :, 2]
            if bm.inertia is not None:
                inertia = bm.inertia
            elif len(bm.all_points) == 2:
                inertia = bm.mass * _sq_perp(Q - P, e) / 12.0
            else:
                inertia = sum(bm.mass / len(bm.all_points) * _sq_perp(pos[..., i, :] - com, e) for i in bm.all_points)
            alpha = np.broadcast_to(state.body_alpha, shape + (len(t.masses), 3))[..., b, :]
            M[..., b, :] -= (np.asarray(inertia) * _dot(alpha, e))[..., None] * e
    if not t.loads:
        return
    vel = np.broadcast_to(state.vel, pos.shape)
    inputs = np.broadcast_to(state.inputs, shape + (state.plan.n_inputs,))
    for ld in t.loads:
        value = _load_value(ld, inputs, state.plan)
        if ld.point < 0:
            e = frames[..., ld.body, :, 2]
            M[..., ld.body, :] += np.asarray(value)[..., None] * e
            continue
        f = np.broadcast_to(value, shape + (3,))
        if ld.opposes == "velocity":
            v = vel[..., ld.point, :]
            speed = _norm(v)
            f = np.where(speed[..., None] > 0, -_norm(f)[..., None] * v / np.where(speed > 0, speed, 1.0)[..., None],
                         0.0)
        F[..., ld.body, :] += f
        M[..., ld.body, :] += np.cross(pos[..., ld.point, :], f)


def _frame_acc(state, b):
    """(..., 3, 3) the second time derivative of body ``b``'s frame."""
    d1 = state.dframe_dq[..., b, :, :, :]
    d2 = state.d2frame_dq2[..., b, :, :, :, :]
    return (np.einsum("...ijk,...k->...ij", d1, state.qddot)
            + np.einsum("...ijkl,...k,...l->...ij", d2, state.qdot, state.qdot))


def _load_value(ld: _Load, inputs, plan):
    """A force (3,) or (..., 3), or a torque () or (...): constant, or the law at the first input."""
    if ld.law is None:
        return np.asarray(ld.force, dtype=float) if ld.torque is None else float(ld.torque)
    q = inputs[..., 0]
    xs = np.asarray(ld.law.inputs, dtype=float)
    ys = np.asarray(ld.law.values, dtype=float)
    period = 2 * math.pi if plan.input_kinds[0] == "rotary" else None
    cols = [np.interp(q, xs, ys[:, j], period=period) for j in range(ys.shape[1])]
    return cols[0] if ys.shape[1] == 1 else np.stack(cols, axis=-1)


# -- the tables ------------------------------------------------------------------------------------------
def _tables(plan, tol) -> _Tables:
    hit = _CACHE.get(plan)
    if hit is None or hit[0] != tol:
        hit = (tol, _build(plan, tol))
        _CACHE[plan] = hit
    return hit[1]


def _build(plan, tol) -> _Tables:
    m = plan.mechanism
    dyn = m.dynamics or Dynamics()
    names = plan.body_names
    pidx = {p: i for i, p in enumerate(plan.point_names)}
    cranks, dyads, hinged = [], [], {}
    for st in plan.steps:
        if st.kind == "crank":
            cranks.append((st.body, pidx[st.pivot], st.input, int(st.sense)))
            hinged[st.body] = (st.pivot, st.arm)
        elif st.kind == "RSS":
            kind = plan.body_frames[st.coupler]
            uni = None
            if kind[0] == "coupler":
                _, U, _, pin_body, pin_local = kind
                uni = (pidx[U], pin_body, tuple(float(c) for c in pin_local))
            a_body = plan.point_body[pidx[st.start]]
            if a_body == 0:
                raise SpecError([(f"links.{names[st.coupler]}", f"the coupler's end {st.start} is on the frame: "
                                                                 "the force analysis needs it on a moving link")])
            dyads.append((st.body, st.coupler, pidx[st.pivot], pidx[st.start], pidx[st.joint], a_body, uni))
            hinged[st.body] = (st.pivot, st.joint)
    kinds, pnames, pbodies, ppoints = [], [], [], []

    def pair(kind, name, a, b, point):
        kinds.append(kind)
        pnames.append(name)
        pbodies.append((names[a], names[b]))
        ppoints.append(point)

    for body, iO, _, _ in cranks:
        pair("R", plan.point_names[iO], 0, body, iO)
    for rocker, coupler, iD, iA, iB, a_body, uni in dyads:
        for i, earlier in ((iA, a_body), (iB, rocker)):
            pair("U" if uni is not None and uni[0] == i else "S", plan.point_names[i], earlier, coupler, i)
        pair("R", plan.point_names[iD], 0, rocker, iD)
    for body, iO, inp, _ in cranks:
        pair("T", plan.input_names[inp], 0, body, -1)
    g = tuple(float(x) for x in dyn.gravity)
    if len(g) != 3:
        if any(g):
            raise SpecError([("dynamics.gravity", f"must be [x, y, z] in a spatial mechanism: {list(g)!r}")])
        g = (0.0, 0.0, 0.0)
    sketch = None
    masses = [None] * plan.n_bodies
    for b in range(1, plan.n_bodies):
        mp = dyn.mass_of(names[b])
        if mp.mass <= 0 and not mp.inertia:
            continue
        if sketch is None:
            sketch = solve(plan, plan.defaults, plan.sketch_inputs, order=0, tolerances=tol)
        masses[b] = _mass(plan, b, mp, hinged, pidx, sketch, tol)
    loads = tuple(_resolve_load(plan, k, ld, hinged, pidx) for k, ld in enumerate(dyn.loads))
    return _Tables(tuple(cranks), tuple(dyads), tuple(masses), tuple(x for x in loads if x is not None), g,
                   tuple(kinds), tuple(pnames), tuple(pbodies), tuple(ppoints))


def _mass(plan, b, mp, hinged, pidx, sketch, tol) -> _Mass:
    m = plan.mechanism
    name = plan.body_names[b]
    pts = m.link(name).points
    path = f"links.{name}.com"
    if b in hinged:
        kind, ends = "hinged", hinged[b]
    else:
        kind = "coupler"
        ends = next((st.start, st.joint) for st in plan.steps if st.kind == "RSS" and st.coupler == b)
    ends = (pidx[ends[0]], pidx[ends[1]])
    all_points = tuple(pidx[p] for p in pts)
    com = mp.com
    offset = None
    if com is None:
        points, weights = all_points, (1.0 / len(pts),) * len(pts)
    elif com == "mid":
        points, weights = (pidx[pts[0]], pidx[pts[1]]), (0.5, 0.5)
    elif isinstance(com, str):
        if com not in pts:
            raise SpecError([(path, f"'{com}' is not a point of link '{name}' ({', '.join(pts)})")])
        points, weights = (pidx[com],), (1.0,)
    else:
        c = np.asarray(com, dtype=float)
        if c.shape != (3,):
            raise SpecError([(path, f"must be [x, y, z] in a spatial mechanism: {list(com)!r}")])
        R0 = sketch.body_frame.reshape((-1,) + sketch.body_frame.shape[-3:])[0, b]
        P0 = sketch.pos.reshape((-1,) + sketch.pos.shape[-2:])[0, pidx[pts[0]]]
        if np.all(np.isfinite(R0)):
            points, weights, offset = (pidx[pts[0]],), (1.0,), tuple(float(x) for x in R0.T @ (c - P0))
        else:                                   # a coupler spinning idly: its com must be on its line
            A, B = (sketch.pos.reshape((-1,) + sketch.pos.shape[-2:])[0, i] for i in ends)
            L = float(np.linalg.norm(B - A))
            s = float(np.dot(c - A, B - A)) / (L * L)
            if np.linalg.norm(c - A - s * (B - A)) > tol.axis_offset * L:
                raise SpecError([(path, f"the coupler '{name}' spins idly about its line between two spherical "
                                        "joints: its centre of mass must lie on that line (or make one joint "
                                        "universal)")])
            points, weights = ends, (1.0 - s, s)
    if mp.inertia is not None and mp.inertia < 0:
        raise SpecError([(f"links.{name}.inertia", f"must not be negative: {mp.inertia!r}")])
    return _Mass(float(mp.mass), points, weights, offset, mp.inertia, kind, ends, all_points)


def _resolve_load(plan, k, ld, hinged, pidx) -> _Load | None:
    m = plan.mechanism
    path = f"loads[{k}]"
    names = plan.body_names
    law = ld.law
    torque = ld.torque is not None or (law is not None and ld.force is None and ld.point is None)
    if torque:
        if ld.link is None or ld.link not in names:
            raise SpecError([(f"{path}.link", f"a torque needs the link it acts on: {ld.link!r}")])
        b = names.index(ld.link)
        if b == 0:
            return None
        if b not in hinged:
            raise SpecError([(f"{path}.link", f"a torque on a spatial mechanism acts about a hinged link's axis "
                                              f"(a crank or a rocker); '{ld.link}' has no fixed axis")])
        if law is not None and np.asarray(law.values).shape[-1] != 1:
            raise SpecError([(f"{path}.law", "a torque law needs one value per input")])
        return _Load(b, -1, None, None if law is not None else float(ld.torque), law, None)
    if ld.point is None or ld.point not in pidx:
        raise SpecError([(f"{path}.point", f"a force needs the point it acts at: {ld.point!r}")])
    if law is None and (ld.force is None or len(ld.force) != 3):
        raise SpecError([(f"{path}.force", f"must be [x, y, z] in a spatial mechanism: {ld.force!r}")])
    if law is not None and np.asarray(law.values).shape[-1] != 3:
        raise SpecError([(f"{path}.law", "a force law of a spatial mechanism needs [x, y, z] values")])
    if ld.link is not None:
        if ld.link not in names:
            raise SpecError([(f"{path}.link", f"no link {ld.link!r}")])
        b = names.index(ld.link)
        if ld.point not in m.link(ld.link).points:
            raise SpecError([(f"{path}.point", f"'{ld.point}' is not a point of link '{ld.link}'")])
    else:
        try:
            b = names.index(m.load_body(ld.point))       # the one body there, else the rule's error
        except ValueError as exc:
            raise SpecError([(f"{path}.link", str(exc))]) from None
    if b == 0:
        return None
    return _Load(b, pidx[ld.point], None if law is not None else tuple(float(x) for x in ld.force), None, law,
                 ld.opposes)


# -- small vector helpers ----------------------------------------------------------------------------------
def _dot(a, b):
    return np.sum(a * b, axis=-1)


def _norm(a):
    return np.sqrt(_dot(a, a))


def _unit(a):
    return a / _norm(a)[..., None]


def _sq_perp(v, e):
    """|v − (v·e)e|² (e a unit vector)."""
    return _dot(v, v) - _dot(v, e) ** 2
