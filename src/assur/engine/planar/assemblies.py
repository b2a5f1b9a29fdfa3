"""Every real assembly of a planar mechanism at given inputs: all combinations of its groups' assemblies.

The steps run in the plan's order on a batch of *rows*, one per partial assembly: a dyad doubles the rows (its two
closed-form branches, the plan's sign ±1 each), a Newton-solved group multiplies each row by its own assemblies
there (:mod:`assur.engine.planar.group_assemblies`: a triad's polynomial, any other group's certified
reduction), and a row that does not close is dropped. What remains at the last step is every assembly of the
mechanism at that input. See docs/assemblies.md.
"""
from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np

from ...kernels.jet import Jet, expi
from ..plan import BRANCHED
from ...errors import StructureError, UnbuildableError
from ...tolerances import DEFAULT
from .group_assemblies import group_assemblies, group_method, take_rows
from .steps import EXECUTORS, Context


@dataclass(frozen=True)
class Assembly:
    """One real assembly of a mechanism at one input.

    ``inputs (n_inputs,)`` (SI); ``branches``: one entry per branched group in the plan's order, the dyad's branch
    sign (±1, as the plan's ``branch`` of its step) or, for a Newton-solved group, ``(det sign, index)``: the sign
    of its certificate determinant (what the solver keeps, :func:`assur.engine.planar.newton_group.certificate_det`)
    and its place among that group's assemblies at this input (sorted by the angle of the group's parameter body);
    ``pos (n_points, 2)`` (m); ``angles (n_bodies,)`` the bodies' orientations (rad, in (−π, π]: two assemblies
    may place every point alike and differ only there, as an RPR dyad's two branches do when its slide passes
    through both hinges: the slider turned by half a turn); ``sketch``: the assembly :func:`assur.solve` returns
    here (the sketch's, followed from the sketch by continuation: its points and its bodies' orientations);
    ``closure``: the largest distance between a joint's positions on the bodies
    it joins, relative to the length scale (every loop closes when it is round-off); ``certified``: False where
    the enumeration could not tell two assemblies of a group apart (a group at or next to a singular position)."""
    inputs: np.ndarray
    branches: tuple
    pos: np.ndarray
    angles: np.ndarray
    sketch: bool
    closure: float
    certified: bool

    def as_dict(self) -> dict:
        return {"inputs": self.inputs.tolist(), "branches": [list(b) if isinstance(b, tuple) else b
                                                               for b in self.branches],
                "sketch": self.sketch, "closure": self.closure, "certified": self.certified,
                "positions": self.pos.tolist(), "angles": self.angles.tolist()}


def enumerate_assemblies(plan, params, inputs, tol, solved=None, solved_angles=None) -> list[Assembly]:
    """Every assembly of the plan at one design ``params (n_params,)`` and one input vector ``inputs
    (n_inputs,)``; ``solved`` (n_points, 2) the positions :func:`assur.solve` gives there (NaN when it gives none)
    and ``solved_angles`` (n_bodies,) its bodies' orientations mark the sketch's: the assembly within
    ``tolerances.assembly_separation`` of the length scale of both (an orientation's difference, in rad, times the
    length scale). Sorted by their branch identities."""
    q = [Jet(np.asarray(float(v))) for v in inputs]
    c = Context(plan, np.asarray(params, dtype=float), q, 0, tol)
    ids: list[tuple] = [()]
    certified = np.ones(1, dtype=bool)
    c = take_rows(c, np.zeros(1, dtype=int), 1)
    with np.errstate(all="ignore"):
        for st in plan.steps:
            n = len(ids)
            if n == 0:
                break
            if st.kind in BRANCHED:
                rows = np.repeat(np.arange(n), 2)
                c = take_rows(c, rows, n)
                EXECUTORS[st.kind](c, replace(st, branch=np.tile([1.0, -1.0], n)))
                ids = [i + (s,) for i in ids for s in (1, -1)]
                certified = certified[rows]
            elif st.kind == "newton":
                if group_method(plan, st) is None:
                    names = ", ".join(plan.body_names[b] for b in st.bodies)
                    raise StructureError(f"the assemblies of the group {names} are not enumerated: it has a prismatic "
                                         "pair, or no single cut link leaves a chain of dyads (docs/assemblies.md)")
                poses, found, sign, cert, enumerated = group_assemblies(c, st, n, tol)
                if not enumerated.all():
                    names = ", ".join(plan.body_names[b] for b in st.bodies)
                    raise UnbuildableError(f"the assemblies of the group {names} cannot be enumerated at this input: "
                                           "the certified grid's enclosures do not tighten (a continuum of "
                                           "assemblies, or a position too singular for it; docs/assemblies.md)")
                rows, k = np.nonzero(found)
                c = take_rows(c, rows, n)
                x = poses[rows, k]
                for j, b in enumerate(st.bodies):
                    c.place(b, Jet(x[:, 3 * j] + 1j * x[:, 3 * j + 1]), expi(Jet(x[:, 3 * j + 2])))
                ids = [ids[r] + ((int(sign[r, kk]), int(kk)),) for r, kk in zip(rows, k)]
                certified = certified[rows] & cert[rows]
            else:
                EXECUTORS[st.kind](c, st)
            keep = np.flatnonzero(np.broadcast_to(np.asarray(c.valid, dtype=bool), (len(ids),)) & _finite(c, len(ids)))
            if len(keep) < len(ids):
                c = take_rows(c, keep, len(ids))
                ids = [ids[i] for i in keep]
                certified = certified[keep]
    n = len(ids)
    if n == 0:
        return []
    z = np.stack([np.broadcast_to(c.pos[p].v, (n,)) for p in plan.point_names], axis=-1)
    angles = np.stack([np.broadcast_to(np.angle(c.pose[b][1].v), (n,)) if b in c.pose else np.zeros(n)
                       for b in range(len(plan.body_names))], axis=-1)
    closure = _closure(plan, c, n)
    sep = tol.assembly_separation * plan.length_scale
    out = []
    for r in range(n):
        pos = np.stack([z[r].real, z[r].imag], axis=-1)
        near = solved is not None and np.all(np.isfinite(solved)) and float(np.max(np.abs(pos - solved))) <= sep
        if near and solved_angles is not None:
            near = bool(np.all(np.abs(_turn(angles[r], solved_angles)) * plan.length_scale <= sep))
        out.append(Assembly(np.array(inputs, dtype=float), ids[r], pos, angles[r], bool(near), float(closure[r]),
                            bool(certified[r])))
    return sorted(out, key=lambda a: _order(a.branches))


def twins(plan, found, i, tol=DEFAULT):
    """(the other assemblies in ``found`` that place every point where ``found[i]`` does, the bodies turned in one
    of them from where ``found[i]`` has them), within ``tolerances.assembly_separation`` of the length scale (an
    orientation's difference, in rad, times the length scale); None when no other does. An RPR dyad whose slide
    passes through both hinges has two such branches: its bodies half a turn apart."""
    sep = tol.assembly_separation * plan.length_scale
    a = found[i]
    same = [k for k, o in enumerate(found) if k != i and float(np.max(np.abs(o.pos - a.pos), initial=0.0)) <= sep]
    if not same:
        return None
    turn = np.stack([_turn(found[k].angles, a.angles) for k in same])
    bodies = [b for b in range(len(plan.body_names)) if np.any(np.abs(turn[:, b]) * plan.length_scale > sep)]
    return same, bodies


def _turn(angles, other):
    """(...) how far ``angles`` are turned from ``other`` (rad), the short way round: in [−π, π)."""
    return np.remainder(angles - other + np.pi, 2.0 * np.pi) - np.pi


def _finite(c, n):
    ok = np.ones(n, dtype=bool)
    for z in c.pos.values():
        ok &= np.broadcast_to(np.isfinite(z.v), (n,))
    return ok


def _order(branches):
    return tuple((-b if not isinstance(b, tuple) else b[1]) for b in branches)


def _closure(plan, c, n):
    """(n,) the largest distance between a point's position and where each body carrying it puts it, relative to
    the length scale."""
    g = plan.structure.graph
    worst = np.zeros(n)
    for b, (o, e) in c.pose.items():
        for p in g.bodies[b].points:
            if p in c.pos and (b, p) in c.w:
                d = np.abs(o.v + e.v * c.w[(b, p)] - c.pos[p].v)
                worst = np.maximum(worst, np.broadcast_to(d, (n,)))
    return worst / plan.length_scale
