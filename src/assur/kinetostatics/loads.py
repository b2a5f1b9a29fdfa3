"""The loads applied before the groups are solved, on numpy rows (n_bodies, N): the file's varying loads
(a law over the input, a force against a point's velocity), extra point loads (a foot's ground reaction)
and Coulomb friction from a previous estimate of the reactions. Gravity, d'Alembert inertia and the
constant loads are applied by :func:`assur.kinetostatics.kernel.mass_loads` and ``point_loads``.

Inertia: a body of mass m and inertia I about its centre of mass C carries the force −m·a_C at C and the
couple −I·α (d'Alembert); gravity m·g at C. A force load at a point acts on the link it names or, without
one, on the one body at the point, or on the slider where a slider meets other bodies (a ram's pin: the ram);
a point where several links meet without a slider needs ``link`` (docs/format.md, "Loads"). Friction, per pair, opposes the relative motion: a
revolute's couple −r_f·|R|·sign(ω_later − ω_earlier) on the later body (r_f the friction-circle radius), a
slide's force −μ·|N|·sign(v_rel)·u at the slider's reference point (v_rel the slider's velocity along the
line relative to the guide; the couple a slide carries is taken without friction); the equal and
opposite load acts on the other body.
"""
from __future__ import annotations

import math

import numpy as np

from ..errors import SpecError
from . import kernel as K
from .tables import ForceTables, body_index


def point_body(t: ForceTables, point: str, link: str | None = None, where: str = "point_loads") -> int:
    """The body a load at ``point`` acts on: ``link`` when given, else the one body there, else the slider there
    (:meth:`assur.model.mechanism.Mechanism.load_body`); SpecError at ``where`` when several bodies meet at the
    point and none is a slider."""
    try:
        name = t.plan.mechanism.load_body(point, link)
    except ValueError as exc:
        raise SpecError([(where, str(exc))]) from None
    return body_index(t.plan, name)


def _add(F, M, b, force, at, moment=0.0):
    F[b] = F[b] + force
    M[b] = M[b] + K.cross(at, force) + moment


def applied_items(t: ForceTables, prog, z, v, a, p, orient, omega, alpha, q0, point_loads, shape, *,
                  kernel_loads: bool = True):
    """Every applied load on the rows of N samples, as (body, force (N,) complex, point of application (N,)
    complex, couple (N,)): with ``kernel_loads`` gravity, d'Alembert inertia and the constant loads (the ones
    :mod:`.kernel` applies itself), then the file's varying loads (a law over the first input ``q0 (N,)``, a force
    against a point's velocity) and the extra ``point_loads`` ((point, force (..., 2)) broadcast to ``shape``)."""
    items = []
    if kernel_loads:
        for b in prog.massive:
            f, c, couple = K.mass_load(b, prog.mass, prog.inertia, prog.idef, prog.ipts, prog.cpts, prog.cw,
                                       prog.coff, prog.gravity, z, v, a, orient, omega, alpha)
            items.append((int(b), f, c, couple))
    for i, load in enumerate(t.dynamics.loads):
        if not (kernel_loads or load.law is not None or load.opposes is not None):
            continue
        value = _load_value(t, load, q0)
        if load.force is None and load.point is None:
            items.append((body_index(t.plan, load.link), 0j, 0j, value))
            continue
        k = t.plan.point_index(load.point)
        f = value
        if load.opposes == "velocity":
            vk = v[k]
            speed = np.abs(vk)
            with np.errstate(all="ignore"):
                f = np.where(speed > 0, -np.abs(value) * vk / speed, 0j)
        items.append((point_body(t, load.point, load.link, f"loads[{i}].link"), f, z[k], 0.0))
    for j, (point, force, *link) in enumerate(point_loads or ()):
        f = np.broadcast_to(np.asarray(force, dtype=float), shape + (2,)).reshape(-1, 2)
        k = t.plan.point_index(point)
        body = point_body(t, point, link[0] if link else None, f"point_loads[{j}]")
        items.append((body, f[:, 0] + 1j * f[:, 1], z[k], 0.0))
    return items


def add_items(items, F, M) -> None:
    """Apply ``items`` (from :func:`applied_items`) to the rows ``F``, ``M``."""
    for body, force, at, couple in items:
        _add(F, M, body, force, at, couple)


def _load_value(t: ForceTables, load, q):
    """The load's force (complex) or torque (real), constant or interpolated at the first input."""
    if load.law is None:
        if load.force is not None:
            return complex(load.force[0], load.force[1])
        return float(load.torque)
    xs = np.asarray(load.law.inputs, dtype=float)
    ys = np.asarray(load.law.values, dtype=float)
    period = 2 * math.pi if t.plan.input_kinds[0] == "rotary" else None
    cols = [np.interp(q, xs, ys[:, j], period=period) for j in range(ys.shape[1])]
    return cols[0] + 1j * cols[1] if ys.shape[1] == 2 else cols[0]


def friction_loads(t: ForceTables, prog, z, v, p, orient, omega, lam, F, M) -> None:
    """The Coulomb friction loads from the reactions ``lam (n_unknowns, N)``, added to the rows ``F``, ``M``."""
    fr = t.dynamics.friction
    for fp in t.pairs:
        if fp.kind == "R":
            r = fr.radius_at(fp.name)
            if not r:
                continue
            R = np.hypot(lam[fp.columns[0]], lam[fp.columns[1]])
            couple = -r * R * np.sign(omega[fp.later] - omega[fp.earlier])
            M[fp.later] += couple
            if fp.earlier:
                M[fp.earlier] -= couple
        elif fp.kind == "P":
            mu = fr.mu_of(fp.name)
            if not mu:
                continue
            rec = t.plan.lines[fp.line]
            guide, slider, through = rec[2], rec[3], t.plan.point_index(rec[4])
            u, Q = K.line_uq(prog.ln, fp.line, z, p, orient)
            vQ = v[prog.ln[fp.line, 3]]
            v_guide = v[through] + 1j * omega[guide] * (Q - z[through])
            v_rel = K.dot(u, vQ - v_guide)
            f = -mu * np.abs(lam[fp.columns[0]]) * np.sign(v_rel) * u
            _add(F, M, slider, f, Q)
            if guide:
                _add(F, M, guide, -f, Q)
