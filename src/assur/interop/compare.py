"""Whether two descriptions are the same mechanism: the test of a round trip assur → another format → assur.

Two planar descriptions are the same when they have the same points and links (names and membership), the same
frame, the same dimensions (every distance within each link), the same slots, the same drivers (link, pivot, arm,
signed speed) and the same assembly: every point at the same place over a whole turn of each crank, given as the
absolute crank direction (so a different ``zero`` or ``sense`` that describes the same motion is the same). What
a format cannot carry is compared only when asked (``dynamics``, ``gait``).
"""
from __future__ import annotations

import math

import numpy as np

from ..model.mechanism import FRAME, Mechanism


def differences(a: Mechanism, b: Mechanism, *, tol: float = 1e-9, samples: int = 72, names: bool = True,
                speeds: bool = True) -> list[str]:
    """What differs between ``a`` and ``b`` (empty: the same mechanism). ``tol`` is relative to the mechanism's
    size for lengths and positions, absolute (rad) for angles and relative for speeds. ``names=False`` compares
    points and links by their order instead of their names (a format that does not keep names); ``speeds=False``
    leaves the drivers' speeds out (a format that rounds them)."""
    out: list[str] = []
    scale = max(a.length_scale, b.length_scale)
    atol = tol * scale
    pa, pb = dict(a.points), dict(b.points)
    if names:
        rename = {n: n for n in pa}
        lrename = {lk.name: lk.name for lk in a.links}
    else:
        rename = dict(zip(a.point_names, b.point_names))
        lrename = dict(zip([lk.name for lk in a.links], [lk.name for lk in b.links]))
    if set(rename.values()) != set(pb) or len(pa) != len(pb):
        return [f"points differ: {sorted(pa)} vs {sorted(pb)}"]
    la, lb = {lk.name: lk for lk in a.links}, {lk.name: lk for lk in b.links}
    if {lrename.get(n) for n in la} != set(lb):
        return [f"links differ: {sorted(la)} vs {sorted(lb)}"]
    for n, lk in la.items():
        other = lb[lrename[n]]
        if {rename[p] for p in lk.points} != set(other.points):
            out.append(f"link {n}: points {lk.points} vs {other.points}")
    if out:
        return out
    sa, sb = _assembled(a), _assembled(b)
    for p in a.link(FRAME).points:
        if math.dist(sa[p], sb[rename[p]]) > atol:
            out.append(f"frame point {p}: {sa[p]} vs {sb[rename[p]]}")
    for n, lk in la.items():
        for i, p in enumerate(lk.points):
            for q in lk.points[i + 1:]:
                da, db = math.dist(sa[p], sa[q]), math.dist(sb[rename[p]], sb[rename[q]])
                if abs(da - db) > atol:
                    out.append(f"link {n}: |{p} {q}| = {da!r} vs {db!r}")
    if len(a.prismatic) != len(b.prismatic):
        out.append(f"{len(a.prismatic)} vs {len(b.prismatic)} prismatic pairs")
    else:
        key = {(pr.point or pr.link): pr for pr in b.prismatic}
        for pr in a.prismatic:
            other = key.get(rename.get(pr.point) if pr.point else lrename.get(pr.link))
            if other is None or lrename.get(pr.guide, pr.guide) != other.guide:
                out.append(f"prismatic {pr.name}: no matching pair")
    da = list(a.drivers)
    db = {(d.link if d.kind == "rotary" else d.actuator): d for d in b.drivers}
    for d in da:
        other = db.get(lrename.get(d.link) if d.kind == "rotary" else d.actuator)
        if other is None or other.kind != d.kind:
            out.append(f"driver {d.name}: no matching driver")
            continue
        if d.kind == "rotary":
            if (rename[d.pivot], rename[d.arm]) != (other.pivot, other.arm):
                out.append(f"driver {d.name}: pivot/arm {d.pivot}/{d.arm} vs {other.pivot}/{other.arm}")
            if speeds and abs(d.sense * d.speed - other.sense * other.speed) > tol * max(abs(d.speed), 1e-300):
                out.append(f"driver {d.name}: speed {d.sense * d.speed!r} vs {other.sense * other.speed!r} rad/s")
    if len(b.drivers) != len(a.drivers):
        out.append(f"{len(a.drivers)} vs {len(b.drivers)} drivers")
    if not out:
        out += _motion(a, b, rename, atol, samples)
    return out


def _assembled(m: Mechanism) -> dict:
    from .common import assembled
    from ..io.units import LENGTH
    L = LENGTH[m.units.length]
    return {n: (x * L, y * L) for n, (x, y) in assembled(m).items()}


def _motion(a: Mechanism, b: Mechanism, rename: dict, atol: float, samples: int) -> list[str]:
    """Positions over a turn of every crank (absolute directions matched), or the sketch input of a linear one."""
    from ..engine import compile as compile_, solve
    pa, pb = compile_(a), compile_(b)
    if any(d.kind != "rotary" for d in a.drivers) or not a.drivers:
        qa, qb = pa.sketch_inputs[None, :], pb.sketch_inputs[None, :]
    else:
        th = np.linspace(0.0, 2 * np.pi, samples, endpoint=False)
        qa = np.empty((samples, len(a.drivers)))
        qb = np.empty((samples, len(a.drivers)))
        by = {d.link: d for d in b.drivers}
        for k, d in enumerate(a.drivers):
            e = by.get(d.link) or b.drivers[k]
            j = b.drivers.index(e)
            absolute = d.zero + d.sense * pa.sketch_inputs[k] + th
            qa[:, k] = (absolute - d.zero) / d.sense
            qb[:, j] = (absolute - e.zero) / e.sense
    sa = solve(pa, inputs=qa, order=0, on_unbuildable="nan")
    sb = solve(pb, inputs=qb, order=0, on_unbuildable="nan")
    out = []
    for n in a.point_names:
        xa = np.asarray(sa.pos)[..., pa.point_index(n), :]
        xb = np.asarray(sb.pos)[..., pb.point_index(rename[n]), :]
        both = np.isfinite(xa).all(-1) & np.isfinite(xb).all(-1)
        if (np.isfinite(xa).all(-1) != np.isfinite(xb).all(-1)).any():
            out.append(f"point {n}: assembles at different inputs")
        elif both.any() and np.max(np.abs(xa[both] - xb[both])) > atol:
            out.append(f"point {n}: positions differ by {np.max(np.abs(xa[both] - xb[both])):.3g} m over a turn")
    return out


__all__ = ["differences"]
