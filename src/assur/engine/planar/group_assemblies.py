"""Every assembly of one Newton-solved planar group, at a batch of placements of the bodies it is hinged to.

Two methods (docs/assemblies.md):

- a **triad** of revolutes (a ternary link held by three binary links, each hinged to a known point) is the planar
  three-legged platform: its assemblies are the real roots of a polynomial of degree 6 in exp(iφ), φ the ternary
  link's angle (:mod:`assur.kernels.triad`);
- any other group of revolutes is reduced to one parameter, the angle of one of its bodies about a known pivot, by
  cutting one of its binary links out so that the rest is a chain of dyads; the roots of the cut link's condition
  on every branch vector of the dyads are bracketed on a grid certified by interval arithmetic
  (:mod:`assur.kernels.reduction`).

Both give estimates that are polished by Newton's method on the group's own loop equations
(:mod:`assur.engine.planar.newton_group`), kept where they close to the Newton tolerance, and merged where two
come out closer than ``tolerances.assembly_separation`` of the length scale. A group with a prismatic pair (a
slider or an undriven actuator among its bodies) has no enumeration yet: :func:`group_method` returns None.
"""
from __future__ import annotations

import copy

import numpy as np

from ...kernels.jet import Jet
from ...kernels.newton import newton
from ...kernels.reduction import bracket, evaluate, sign_vectors
from ...kernels.triad import triad_roots
from .newton_group import _residual_and_jacobian, certificate_det

#: the interval grid's narrowest cell (rad of the reduction's parameter)
CELL_WIDTH = 1e-9
#: Newton iterations that polish one estimate
POLISH_ITERATIONS = 12


def _layout(plan, st):
    """(bodies {body: points}, outer points) of a group of revolute-jointed links, or None (a slider, block or
    actuator in the group, a slide on one of its bodies)."""
    g = plan.structure.graph
    group = set(st.bodies)
    if any(g.bodies[b].kind != "link" or len(g.bodies[b].points) < 2 for b in group):
        return None
    if any(rec[2] in group or rec[3] in group for rec in plan.lines):
        return None
    earlier = earlier_bodies(plan, st)
    outer = sorted({p for b in group for p in g.bodies[b].points if any(o in earlier for o in g.bodies_at(p))})
    return {b: tuple(g.bodies[b].points) for b in st.bodies}, tuple(outer)


def earlier_bodies(plan, st) -> set:
    """The bodies the plan's steps before ``st`` place (those the group is hinged to; a later group may be hinged to
    the group's own points)."""
    out = set()
    for other in plan.steps:
        if other is st or other == st:
            return out
        out |= set(other.bodies)
    return out


def triad_layout(plan, st):
    """(ternary body, ((leg, inner point, outer point) × 3)) of a triad of revolutes, else None."""
    lay = _layout(plan, st)
    if lay is None or len(st.bodies) != 4:
        return None
    bodies, outer = lay
    for t, pts in bodies.items():
        if len(pts) != 3 or any(p in outer for p in pts):
            continue
        legs = []
        for p in pts:
            others = [b for b in bodies if b != t and p in bodies[b]]
            if len(others) != 1 or len(bodies[others[0]]) != 2:
                break
            leg = others[0]
            far = next(q for q in bodies[leg] if q != p)
            if far not in outer:
                break
            legs.append((leg, p, far))
        if len(legs) == 3 and len({leg for leg, _, _ in legs}) == 3:
            return t, tuple(legs)
    return None


def reduction_layout(plan, st):
    """The one-parameter reduction of a group of revolutes with the fewest dyads: (driven body, pivot point, cut
    link, operations) with operations on point names and bodies (``("rot", point, body)``, ``("dyad", J, A, u, B,
    v)``, ``("place", point, P1, P2, body)``, ``("cut", X, Y, link)``), or None where no single cut leaves a chain
    of dyads."""
    lay = _layout(plan, st)
    if lay is None:
        return None
    bodies, outer = lay
    best = None
    for b0 in st.bodies:
        for pivot in (p for p in bodies[b0] if p in outer):
            for cut in (b for b in st.bodies if b != b0 and len(bodies[b]) == 2):
                ops = _dyadic_chain(bodies, outer, b0, pivot, cut)
                if ops is not None:
                    n = sum(op[0] == "dyad" for op in ops)
                    if best is None or n < best[0]:
                        best = (n, (b0, pivot, cut, tuple(ops)))
    return None if best is None else best[1]


def _dyadic_chain(bodies, outer, b0, pivot, cut):
    known = set(outer) | set(bodies[b0])
    ops = [("rot", p, b0) for p in bodies[b0] if p != pivot and p not in outer]
    placed = {b0, cut}
    while len(placed) < len(bodies):
        progress = False
        for u in bodies:
            if u in placed:
                continue
            have = [p for p in bodies[u] if p in known]
            if len(have) >= 2:
                ops += [("place", q, have[0], have[1], u) for q in bodies[u] if q not in known]
                known |= set(bodies[u])
                placed.add(u)
                progress = True
        if progress:
            continue
        for u in bodies:
            for v in bodies:
                if u >= v or u in placed or v in placed:
                    continue
                for J in (p for p in bodies[u] if p in bodies[v] and p not in known):
                    A = next((p for p in bodies[u] if p in known), None)
                    B = next((p for p in bodies[v] if p in known), None)
                    if A is not None and B is not None:
                        ops.append(("dyad", J, A, u, B, v))
                        known.add(J)
                        progress = True
                        break
                if progress:
                    break
            if progress:
                break
        if not progress:
            return None
    X, Y = bodies[cut]
    if X not in known or Y not in known:
        return None
    return ops + [("cut", X, Y, cut)]


def group_method(plan, st) -> str | None:
    """'triad', 'reduction' or None (no enumeration for this group: module docstring)."""
    if triad_layout(plan, st) is not None:
        return "triad"
    return "reduction" if reduction_layout(plan, st) is not None else None


# -- a batch of rows ------------------------------------------------------------------------------------------
def take_rows(c, idx, n: int):
    """A copy of the context ``c`` (positions only, batch (n,) or broadcastable) with its samples ``idx``."""
    def take(v):
        v = np.asarray(v)
        return v if v.ndim == 0 else np.broadcast_to(v, (n,) + v.shape[1:] if v.ndim > 1 else (n,))[idx]

    out = copy.copy(c)
    out.pos = {p: Jet(take(z.v)) for p, z in c.pos.items()}
    out.pose = {b: (Jet(take(o.v)), Jet(take(e.v))) for b, (o, e) in c.pose.items()}
    out.valid = take(c.valid)
    out.q = [Jet(take(q.v)) for q in c.q]
    out.w = {k: take(v) for k, v in c.w.items()}
    out.lines = [tuple(take(x) for x in rec) for rec in c.lines]
    out.params = c.params if np.ndim(c.params) <= 1 else np.broadcast_to(c.params, (n, c.params.shape[-1]))[idx]
    out.warm = {}
    return out


def before_group(c, st):
    """A copy of a context in which the group ``st`` (and maybe later steps) is solved, as it was before ``st``: the
    bodies of the earlier steps and the points they place only."""
    earlier = earlier_bodies(c.plan, st)
    out = copy.copy(c)
    out.pose = {b: v for b, v in c.pose.items() if b in earlier}
    g = c.plan.structure.graph
    out.pos = {p: z for p, z in c.pos.items() if any(b in earlier for b in g.bodies_at(p))}
    return out


def _at(v, rows, n):
    """A design's value at the samples ``rows`` (a scalar stays)."""
    v = np.asarray(v)
    return v if v.ndim == 0 else np.broadcast_to(v, (n,))[rows]


def _pose_from_two(z1, z2, w1, w2):
    """(x, y, θ) arrays of a body whose local points w1, w2 are at z1, z2."""
    e = (z2 - z1) / (w2 - w1)
    e = e / np.abs(e)
    o = z1 - e * w1
    return o.real, o.imag, np.angle(e)


def triad_legs(c, st, n):
    """A triad's data at n samples of the context ``c``: ``(t, legs, w, Q, ell)``, the ternary body ``t`` and its
    ``legs`` (triad_layout), its joints' local offsets ``w`` (n, 3) complex, the legs' far joints ``Q`` (n, 3)
    complex and the legs' lengths ``ell`` (n, 3)."""
    t, legs = triad_layout(c.plan, st)
    w = np.stack([np.broadcast_to(np.asarray(c.w[(t, p)]), (n,)) for _, p, _ in legs], axis=-1)
    Q = np.stack([np.broadcast_to(c.pos[far].v, (n,)) for _, _, far in legs], axis=-1)
    ell = np.stack([np.broadcast_to(np.abs(np.asarray(c.w[(leg, far)]) - np.asarray(c.w[(leg, p)])), (n,))
                    for leg, p, far in legs], axis=-1)
    return t, legs, w, Q, ell


def triad_root_poses(c, st, n):
    """The roots of a triad's polynomial at n samples of the context ``c``: ``(t, legs, w, Q, phi, p)``, as
    :func:`triad_legs` and per root its angle ``phi`` (n, 6) and reference point ``p`` (n, 6) complex, NaN where the
    polynomial has fewer real roots."""
    t, legs, w, Q, ell = triad_legs(c, st, n)
    phi, p = triad_roots(w, Q, ell)
    return t, legs, w, Q, phi, p


def _triad_estimates(c, st, n):
    """(rows (C,), x (C, 12)): the triad's candidate assemblies from its polynomial."""
    t, legs, w, Q, phi, p = triad_root_poses(c, st, n)
    rows, k = np.nonzero(np.isfinite(phi))
    phi, p = phi[rows, k], p[rows, k]
    e = np.exp(1j * phi)
    poses = {t: (p.real, p.imag, phi)}
    for j, (leg, inner, far) in enumerate(legs):
        poses[leg] = _pose_from_two(Q[rows, j], p + e * w[rows, j], _at(c.w[(leg, far)], rows, n),
                                    _at(c.w[(leg, inner)], rows, n))
    return rows, _stack_poses(st, poses, len(rows)), phi


def _stack_poses(st, poses, m):
    x = np.empty((m, 3 * len(st.bodies)))
    for i, b in enumerate(st.bodies):
        for j in range(3):
            x[:, 3 * i + j] = np.broadcast_to(poses[b][j], (m,))
    return x


def _reduction_program(c, layout, n):
    """The program of :mod:`assur.kernels.reduction` with this context's numbers; its known slots."""
    b0, pivot, cut, ops = layout
    w = lambda b, p: complex(np.asarray(c.w[(b, p)]))       # noqa: E731 - one design per enumeration
    prog, j = [], 0
    for op in ops:
        if op[0] == "rot":
            prog.append(("rot", op[1], pivot, w(b0, op[1]) - w(b0, pivot)))
        elif op[0] == "dyad":
            _, J, A, u, B, v = op
            prog.append(("dyad", J, A, abs(w(u, J) - w(u, A)), B, abs(w(v, J) - w(v, B)), j))
            j += 1
        elif op[0] == "place":
            _, q, P1, P2, body = op
            prog.append(("place", q, P1, P2, (w(body, q) - w(body, P1)) / (w(body, P2) - w(body, P1))))
        else:
            prog.append(("cut", op[1], op[2], abs(w(cut, op[1]) - w(cut, op[2]))))
    known = {p: np.broadcast_to(c.pos[p].v, (n,)) for p in c.pos if any(p == q for q in _slots(ops, pivot))}
    return prog, j, known


def _slots(ops, pivot):
    """The points a reduction reads before it computes them (the known ones)."""
    made = {op[1] for op in ops if op[0] in ("rot", "dyad", "place")}
    read = {pivot}
    for op in ops:
        if op[0] == "dyad":
            read |= {op[2], op[4]}
        elif op[0] == "place":
            read |= {op[2], op[3]}
        elif op[0] == "cut":
            read |= {op[1], op[2]}
    return read - made


def _reduction_estimates(c, st, n):
    """(rows (C,), x (C, 3k), φ (C,), certified (n,), enumerated (n,)): candidates from the certified grid;
    ``certified`` False for a row where some cluster of the grid has no sign change (two roots closer than the cell
    width, a root at a dyad's own toggle) or that is not ``enumerated`` (the grid gave it up: its enclosures do not
    tighten, a continuum of assemblies or a position too singular for the grid; no candidate)."""
    layout = reduction_layout(c.plan, st)
    if np.ndim(c.params) > 1:
        raise ValueError("the reduction enumerates one design at a time")
    b0, pivot, cut, ops = layout
    prog, n_dyads, known = _reduction_program(c, layout, n)
    sample, sgn, lo, hi, change, untightened = bracket(prog, n_dyads, known, n, width=CELL_WIDTH)
    certified = ~untightened
    certified[sample[~change]] = False
    phi = 0.5 * (lo + hi)
    signs = sign_vectors(n_dyads)[sgn]
    Z, _, _ = evaluate(prog, {k: v[sample] for k, v in known.items()}, np.cos(phi), np.sin(phi), signs)
    pos = {p: re + 1j * im for p, (re, im) in Z.items()}
    poses = {}
    for b in st.bodies:
        pts = c.plan.structure.graph.bodies[b].points
        poses[b] = _pose_from_two(pos[pts[0]], pos[pts[1]], _at(c.w[(b, pts[0])], sample, n),
                                  _at(c.w[(b, pts[1])], sample, n))
    return sample, _stack_poses(st, poses, len(sample)), np.mod(phi, 2 * np.pi), certified, ~untightened


def group_assemblies(c, st, n: int, tol):
    """Every assembly of the group ``st`` at each of the ``n`` samples of the context ``c`` (a 1-D batch).

    Returns ``(poses (n, K, 3k), found (n, K), det_sign (n, K), certified (n,), enumerated (n,))``: the bodies'
    (x, y, θ) in the order of ``st.bodies``, K the largest count, NaN and False past each sample's own count;
    assemblies of a sample sorted by the angle of the method's parameter body; ``certified`` False where the
    enumeration cannot tell two assemblies apart (a group at or next to a singular position); ``enumerated`` False
    where it gave the sample up (no assembly listed: :func:`_reduction_estimates`). Raises ValueError where the
    group has no enumeration (:func:`group_method`)."""
    method = group_method(c.plan, st)
    if method is None:
        raise ValueError("no enumeration of the assemblies of a group with a prismatic pair")
    if method == "triad":
        rows, x, key = _triad_estimates(c, st, n)
        certified, enumerated = np.ones(n, dtype=bool), np.ones(n, dtype=bool)
    else:
        rows, x, key, certified, enumerated = _reduction_estimates(c, st, n)
    scale = c.plan.length_scale
    k = len(rows)
    if k:
        cr = take_rows(c, rows, n)
        x, ok, J = newton(lambda y: _residual_and_jacobian(cr, st, y, (k,)), x, tol.newton_residual * scale,
                          POLISH_ITERATIONS)
        det = certificate_det(cr, st, J)
    else:
        ok, det = np.zeros(0, dtype=bool), np.zeros(0)
    rows, x, key, det = rows[ok], x[ok], key[ok], det[ok]
    z = group_points(c, st, x, rows, n)                                 # (C, P) complex
    per_row: list[list[int]] = [[] for _ in range(n)]
    for i in np.lexsort((key, rows)):
        per_row[rows[i]].append(i)
    K = max([len(r) for r in per_row] + [0])
    poses = np.full((n, K, 3 * len(st.bodies)), np.nan)
    found = np.zeros((n, K), dtype=bool)
    sign = np.zeros((n, K), dtype=int)
    sep = tol.assembly_separation * scale
    for r, idx in enumerate(per_row):
        kept: list[int] = []
        for i in idx:
            if all(np.max(np.abs(z[i] - z[j])) > sep for j in kept):
                kept.append(i)
            else:
                certified[r] = False
        for slot, i in enumerate(kept):
            poses[r, slot], found[r, slot], sign[r, slot] = x[i], True, int(np.sign(det[i]))
    K = int(found.sum(axis=1).max()) if n and K else 0
    return poses[:, :K], found[:, :K], sign[:, :K], certified, enumerated


def group_points(c, st, x, rows, n: int):
    """(..., P) complex world positions of every point of the group's bodies for poses ``x (..., 3k)`` of the
    samples ``rows (...)`` of a context of ``n`` samples (their designs)."""
    g = c.plan.structure.graph
    out = []
    for i, b in enumerate(st.bodies):
        for p in g.bodies[b].points:
            w = np.asarray(c.w[(b, p)])
            w = w if w.ndim == 0 else np.broadcast_to(w, (n,))[rows]
            out.append((x[..., 3 * i] + 1j * x[..., 3 * i + 1]) + np.exp(1j * x[..., 3 * i + 2]) * w)
    return np.stack(out, axis=-1) if out else np.zeros(np.shape(x)[:-1] + (0,), dtype=complex)


def assembly_distances(c, st, x, poses, found):
    """For the solved group poses ``x (n, 3k)`` of a context of n samples and that group's assemblies ``poses (n, K,
    3k)`` (``found (n, K)``): (n,) the distance (m) to the nearest assembly (itself, to round-off, when the sample is
    an assembly) and (n,) to the second nearest (the nearest other one): what tells a sample on its own assembly
    from one next to another's. Inf where there is none."""
    n = x.shape[0]
    rows = np.arange(n)
    zs = group_points(c, st, x, rows, n)                                              # (n, P)
    zk = group_points(c, st, poses, rows[:, None], n) if poses.shape[1] else np.zeros((n, 0, zs.shape[-1]))
    d = np.where(found, np.max(np.abs(zk - zs[:, None, :]), axis=-1, initial=0.0), np.inf)   # (n, K)
    d = np.sort(d, axis=-1)
    inf = np.full(n, np.inf)
    return (d[:, 0] if d.shape[1] else inf), (d[:, 1] if d.shape[1] > 1 else inf)
