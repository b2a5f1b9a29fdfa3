"""The motion of the links over one crank turn: each moving link's angle range (or that it turns fully), its
largest angular velocity and acceleration, and the output link of a one-crank mechanism whose last link
swings (a crank-rocker's rocker, a quick-return mechanism's slotted lever): its swing, its two extreme
positions and the time ratio.

Angles are shown in (−π, π]: a swinging link's range is the one continuous arc it sweeps, with its middle
in (−π, π] (so a range may end a little beyond ±π rather than be split in two). The time ratio is the
crank angle of the slower stroke over that of the quicker one (≥ 1; at a constant crank speed, the ratio of
their times): for a four-bar crank-rocker, (180° + α)/(180° − α) with α the angle between the crank's two
positions at the rocker's extremes less 180°. All values SI (rad, rad/s, rad/s²).
"""
from __future__ import annotations

import numpy as np

from .overview import finite_or_none
from .sampling import TWO_PI, root_between, sign_changes

__all__ = ["link_motions", "output_link", "wrap_angle"]


def wrap_angle(theta):
    """An angle (rad, array or float) mapped into (−π, π]."""
    w = np.pi - np.mod(np.pi - np.asarray(theta, dtype=float), TWO_PI)
    return float(w) if np.ndim(w) == 0 else w


def _arc(theta):
    """(unwrapped θ (n,), net turns over the cycle) of a sampled turn θ (n,) without NaN; the unwrapped
    curve is shifted so that the middle of its range lies in (−π, π]."""
    u = np.unwrap(theta)
    net = (u[-1] - u[0]) + wrap_angle(theta[0] - theta[-1])    # the last sample back to the first
    turns = int(round(net / TWO_PI))
    if turns == 0:
        mid = 0.5 * (u.min() + u.max())
        u = u + (wrap_angle(mid) - mid)
    return u, turns


def _moving_bodies(plan) -> list[int]:
    """Indices of the moving bodies of a plan (the frame, body 0, left out)."""
    return list(range(1, plan.n_bodies))


def link_motions(cycle) -> dict:
    """Per moving link of the cycle's plan: ``angle_min``/``angle_max`` (rad; a swinging link's arc, None
    for a link that turns fully), ``turns`` (net revolutions per turn of the input), ``omega_max``, ``alpha_max``
    (largest |ω| rad/s, |α| rad/s²). A spatial link has no single angle: only |ω| and |α| (norms of the
    vectors). Needs every sample of the turn buildable for the angle ranges (else they are None)."""
    plan = cycle.plan
    _, st = cycle.grid()
    ok = bool(np.all(st.valid))
    out = {}
    if plan.dimension == 3:
        w, a = st.body_omega, st.body_alpha
        for b in _moving_bodies(plan):
            out[plan.body_names[b]] = {
                "omega_max": None if w is None else finite_or_none(np.nanmax(np.linalg.norm(w[:, b], axis=-1))),
                "alpha_max": None if a is None else finite_or_none(np.nanmax(np.linalg.norm(a[:, b], axis=-1)))}
        return out
    th, w, a = st.body_angle, st.body_omega, st.body_alpha
    for b in _moving_bodies(plan):
        entry = {"angle_min": None, "angle_max": None, "turns": None}
        if ok:
            u, turns = _arc(th[:, b])
            entry["turns"] = turns
            if turns == 0:
                entry["angle_min"], entry["angle_max"] = float(u.min()), float(u.max())
        entry["omega_max"] = None if w is None else finite_or_none(np.nanmax(np.abs(w[:, b])))
        entry["alpha_max"] = None if a is None else finite_or_none(np.nanmax(np.abs(a[:, b])))
        out[plan.body_names[b]] = entry
    return out


def _output_body(plan) -> int | None:
    """The output link: the last link of the file hinged to the frame that no driver turns, None without
    one."""
    m = plan.mechanism
    frame_points = {p for p, b in zip(plan.point_names, plan.point_body) if b == 0}
    driven = {getattr(d, "link", None) for d in m.drivers}
    for link in reversed(m.links):
        if link.name in driven or link.name not in plan.body_names:
            continue
        b = plan.body_names.index(link.name)
        if b != 0 and frame_points.intersection(link.points):
            return b
    return None


def output_link(cycle) -> dict | None:
    """The output link of a one-crank planar mechanism whose last link hinged to the frame swings, over
    the cycle's turn: ``link``, ``angle_min``/``angle_max`` and ``swing`` (rad), ``extremes`` (each
    ``input`` angle, output ``angle``, ``kind`` 'min' or 'max', located where the link's ω vanishes by a
    root solve), and with exactly two extremes the crank angles of the two strokes (``forward_crank_angle``
    the slower, ``return_crank_angle``), their times at the driver's speed, ``time_ratio`` (≥ 1) and
    ``forward`` ('increasing' or 'decreasing' angle). None when there is no such link, when it turns
    fully or when the crank cannot turn fully."""
    plan = cycle.plan
    if plan.dimension != 2 or plan.n_inputs != 1 or plan.input_kinds[0] != "rotary":
        return None
    b = _output_body(plan)
    if b is None:
        return None
    q, st = cycle.grid()
    if not np.all(st.valid):
        return None
    u, turns = _arc(st.body_angle[:, b])
    if turns != 0:
        return None
    shift = float(u[0] - st.body_angle[0, b])

    def rate(t):
        return float(cycle.state_at(np.array(t), order=1).dangle_dq[..., b, 0].ravel()[0])

    def on_arc(theta):   # a wrapped angle on the swing's continuous arc
        mid = 0.5 * (u.min() + u.max())
        return mid + wrap_angle(theta + shift - mid)

    d1 = st.dangle_dq[:, b, 0]
    extremes = []
    for i in sign_changes(q, d1):
        lo = q[i]
        hi = q[i + 1] if i + 1 < len(q) else q[0] + TWO_PI
        t = root_between(rate, lo, hi) % TWO_PI
        s1 = cycle.state_at(np.array(t), order=0)
        extremes.append({"input": float(t), "angle": float(on_arc(s1.body_angle[..., b].ravel()[0])),
                         "kind": "max" if d1[i] > 0 else "min"})
    extremes.sort(key=lambda e: e["input"])
    out = {"link": plan.body_names[b], "angle_min": float(u.min()), "angle_max": float(u.max()),
           "swing": float(u.max() - u.min()), "extremes": extremes}
    if extremes:
        angles = [e["angle"] for e in extremes]
        out["angle_min"], out["angle_max"] = min(out["angle_min"], *angles), max(out["angle_max"], *angles)
        out["swing"] = out["angle_max"] - out["angle_min"]
    kinds = sorted(e["kind"] for e in extremes)
    if kinds == ["max", "min"]:
        lo = next(e for e in extremes if e["kind"] == "min")["input"]
        hi = next(e for e in extremes if e["kind"] == "max")["input"]
        speed = float(plan.speeds[0])
        rising = (hi - lo) % TWO_PI if speed >= 0 else (lo - hi) % TWO_PI   # crank angle while the angle grows
        falling = TWO_PI - rising
        fwd, ret = max(rising, falling), min(rising, falling)
        out.update({"forward": "increasing" if rising >= falling else "decreasing",
                    "forward_crank_angle": fwd, "return_crank_angle": ret,
                    "forward_time": fwd / abs(speed) if speed else None,
                    "return_time": ret / abs(speed) if speed else None,
                    "time_ratio": fwd / ret if ret > 0 else None})
    return out

