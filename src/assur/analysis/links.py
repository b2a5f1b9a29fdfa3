"""The motion of the links over one crank turn, and the output member of a one-crank mechanism.

:func:`link_motions`: each moving link's angle range (or that it turns fully), its largest angular velocity and
acceleration, and whether that peak sits at a toggle of a crank that cannot turn fully.

:func:`output_link`: the output member a designer reads first: the last member of the file hinged to the frame
(a rocker: a crank-rocker's rocker, a quick-return mechanism's slotted lever) or sliding on a frame guide (a
slider-crank's slider, a shaper's ram), whichever the file names last (a slide after the links). A rocker's
swing or a slide's stroke, its two extreme positions (located where its rate vanishes, by a root solve) and the
time ratio: the crank angle of the slower stroke over that of the quicker one (≥ 1; at a constant crank speed, the
ratio of their times). For a four-bar crank-rocker (180° + α)/(180° − α), α the angle between the crank's two
positions at the rocker's extremes less 180°.

Angles are shown in (−π, π]: a swinging link's range is the one continuous arc it sweeps, with its middle in
(−π, π]. All values SI (rad, m, rad/s, rad/s², s).
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .overview import finite_or_none
from .sampling import TWO_PI, root_between, sign_changes

__all__ = ["Extreme", "LinkMotion", "OutputMember", "link_motions", "output_link", "wrap_angle"]


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


@dataclass(frozen=True)
class LinkMotion:
    """One moving link over the turn: ``angle_min``/``angle_max`` (rad; a swinging link's arc, None for a link
    that turns fully or when the crank cannot turn fully), ``turns`` (net revolutions per input turn; None for a
    spatial link or an incomplete turn), ``omega_max``/``alpha_max`` (largest |ω| rad/s, |α| rad/s²) and
    ``alpha_at_toggle`` (the largest |α| is reached next to a toggle of a crank that cannot turn fully: a value
    that grows without bound as the samples approach the toggle, not a property of the design)."""
    link: str
    angle_min: float | None = None
    angle_max: float | None = None
    turns: int | None = None
    omega_max: float | None = None
    alpha_max: float | None = None
    spatial: bool = False
    alpha_at_toggle: bool = False

    @property
    def translates(self) -> bool:
        """Whether the link keeps its orientation over the turn (a slider block on a frame guide)."""
        return self.turns == 0 and self.angle_min is not None and self.angle_max - self.angle_min <= 1e-12

    def as_dict(self) -> dict:
        if self.spatial:
            return {"omega_max": self.omega_max, "alpha_max": self.alpha_max}
        out = {"angle_min": self.angle_min, "angle_max": self.angle_max, "turns": self.turns,
               "omega_max": self.omega_max, "alpha_max": self.alpha_max}
        if self.alpha_at_toggle:
            out["alpha_at_toggle"] = True
        return out


def _moving_bodies(plan) -> list[int]:
    """Indices of the moving bodies of a plan (the frame, body 0, left out)."""
    return list(range(1, plan.n_bodies))


def _at_toggle(valid, i: int) -> bool:
    """Whether sample ``i`` of a cyclic run borders an unassembled sample."""
    n = len(valid)
    return not (valid[(i - 1) % n] and valid[(i + 1) % n])


def link_motions(cycle) -> dict[str, LinkMotion]:
    """{link: :class:`LinkMotion`} of every moving link over the turn of ``cycle`` (a Cycle or Study). A spatial
    link has no single angle: only |ω| and |α| (norms of the vectors). The angle ranges need every sample of the
    turn buildable."""
    plan = cycle.plan
    _, st = cycle.grid()
    valid = np.asarray(st.valid, dtype=bool)
    ok = bool(np.all(valid))
    out = {}
    if plan.dimension == 3:
        w, a = st.body_omega, st.body_alpha
        for b in _moving_bodies(plan):
            out[plan.body_names[b]] = LinkMotion(
                plan.body_names[b], spatial=True,
                omega_max=None if w is None else finite_or_none(np.nanmax(np.linalg.norm(w[:, b], axis=-1))),
                alpha_max=None if a is None else finite_or_none(np.nanmax(np.linalg.norm(a[:, b], axis=-1))))
        return out
    th, w, a = st.body_angle, st.body_omega, st.body_alpha
    for b in _moving_bodies(plan):
        lo = hi = turns = None
        if ok:
            u, turns = _arc(th[:, b])
            if turns == 0:
                lo, hi = float(u.min()), float(u.max())
        at_toggle = False
        if a is not None and not ok and np.isfinite(a[:, b]).any():
            at_toggle = _at_toggle(valid, int(np.nanargmax(np.abs(a[:, b]))))
        out[plan.body_names[b]] = LinkMotion(
            plan.body_names[b], lo, hi, turns,
            None if w is None else finite_or_none(np.nanmax(np.abs(w[:, b]))),
            None if a is None else finite_or_none(np.nanmax(np.abs(a[:, b]))), alpha_at_toggle=at_toggle)
    return out


# -- the output member ------------------------------------------------------------------------------------------
@dataclass(frozen=True)
class Extreme:
    """An extreme position of the output member: the ``input`` angle (rad) where it is reached, the member's
    ``value`` there (a rocker's angle, rad; a slide's position along its guide, m) and ``kind`` 'min' or 'max'."""
    input: float
    value: float
    kind: str


@dataclass(frozen=True)
class OutputMember:
    """The output member over the turn: ``link``, ``motion`` ('swing' of a rocker, 'slide' of a slider along its
    frame guide), ``value_min``/``value_max`` and ``range`` (a swing in rad or a stroke in m), the ``extremes``
    and, with exactly two, the crank angles of the slower (``forward_crank_angle``) and quicker
    (``return_crank_angle``) strokes, their times at the driver's speed, ``time_ratio`` (≥ 1) and ``forward``
    ('increasing' or 'decreasing' value). A slide's position is measured along its guide's direction from the
    guide's line point (the ``through`` point shifted by the offset)."""
    link: str
    motion: str
    value_min: float
    value_max: float
    extremes: tuple[Extreme, ...]
    forward: str | None = None
    forward_crank_angle: float | None = None
    return_crank_angle: float | None = None
    forward_time: float | None = None
    return_time: float | None = None
    time_ratio: float | None = None

    @property
    def range(self) -> float:
        return self.value_max - self.value_min

    def as_dict(self) -> dict:
        """The JSON form: a rocker's ``angle_min``/``angle_max``/``swing`` and its extremes' ``angle``; a slide's
        ``motion`` 'slide', ``position_min``/``position_max``/``stroke`` and its extremes' ``position``."""
        slide = self.motion == "slide"
        key = "position" if slide else "angle"
        out = {"link": self.link} | ({"motion": "slide"} if slide else {})
        out |= {f"{key}_min": self.value_min, f"{key}_max": self.value_max,
                ("stroke" if slide else "swing"): self.range,
                "extremes": [{"input": e.input, key: e.value, "kind": e.kind} for e in self.extremes]}
        if self.time_ratio is not None or self.forward is not None:
            out |= {"forward": self.forward, "forward_crank_angle": self.forward_crank_angle,
                    "return_crank_angle": self.return_crank_angle, "forward_time": self.forward_time,
                    "return_time": self.return_time, "time_ratio": self.time_ratio}
        return out


def _output_candidate(plan):
    """('swing', body) or ('slide', body, line index): the last member of the file hinged to the frame that no
    driver turns, or sliding on a frame guide (the slides after the links, in file order); None without one."""
    m = plan.mechanism
    frame_points = {p for p, b in zip(plan.point_names, plan.point_body) if b == 0}
    driven = {getattr(d, "link", None) for d in m.drivers}
    found = None
    for link in m.links:
        if link.name in driven or link.name not in plan.body_names:
            continue
        b = plan.body_names.index(link.name)
        if b != 0 and frame_points.intersection(link.points):
            found = ("swing", b)
    for k, rec in enumerate(plan.lines):
        kind, name, guide_body, slider = rec[:4]
        if kind == "prismatic" and guide_body == 0 and slider != 0:
            found = ("slide", slider, k)
    return found


def output_link(cycle) -> OutputMember | None:
    """The :class:`OutputMember` of a one-crank planar mechanism over the turn of ``cycle`` (a Cycle or Study;
    the module docstring); None without one, for a rocker that turns fully, or when the crank cannot turn fully."""
    plan = cycle.plan
    if plan.dimension != 2 or plan.n_inputs != 1 or plan.input_kinds[0] != "rotary":
        return None
    found = _output_candidate(plan)
    if found is None:
        return None
    q, st = cycle.grid()
    if not np.all(st.valid):
        return None
    if found[0] == "swing":
        b = found[1]
        u, turns = _arc(st.body_angle[:, b])
        if turns != 0:
            return None
        shift = float(u[0] - st.body_angle[0, b])
        mid = 0.5 * (u.min() + u.max())

        def value(s):   # a wrapped angle on the swing's continuous arc
            return mid + wrap_angle(s.body_angle[..., b] + shift - mid)

        def rate(s):
            return s.dangle_dq[..., b, 0]
        lo, hi, d1 = float(u.min()), float(u.max()), st.dangle_dq[:, b, 0]
        link = plan.body_names[b]
    else:
        from ..engine import geometry
        _, slider, k = found
        line_point, direction = geometry(plan, cycle.params)[1][k][:2]
        ref = plan.point_index(plan.lines[k][7])
        along = np.array([direction.real, direction.imag])
        origin = np.array([line_point.real, line_point.imag])

        def value(s):
            return (s.pos[..., ref, :] - origin) @ along

        def rate(s):
            return s.dpos_dq[..., ref, :, 0] @ along
        vals = value(st)
        lo, hi, d1 = float(vals.min()), float(vals.max()), rate(st)
        link = plan.body_names[slider]
    return _member(cycle, link, found[0], q, d1, lo, hi, value, rate)


def _member(cycle, link, motion, q, d1, lo, hi, value, rate) -> OutputMember:
    """The extremes (roots of the rate between the samples where it changes sign) and the strokes' time ratio."""
    extremes = []
    for i in sign_changes(q, d1):
        a = q[i]
        b = q[i + 1] if i + 1 < len(q) else q[0] + TWO_PI
        t = root_between(lambda x: float(rate(cycle.state_at(np.array(x), order=1)).ravel()[0]), a, b) % TWO_PI
        s1 = cycle.state_at(np.array(t), order=0)
        extremes.append(Extreme(float(t), float(np.ravel(value(s1))[0]), "max" if d1[i] > 0 else "min"))
    extremes.sort(key=lambda e: e.input)
    if extremes:
        lo = min(lo, *(e.value for e in extremes))
        hi = max(hi, *(e.value for e in extremes))
    kinds = sorted(e.kind for e in extremes)
    timing = {}
    if kinds == ["max", "min"]:
        e_lo = next(e for e in extremes if e.kind == "min").input
        e_hi = next(e for e in extremes if e.kind == "max").input
        speed = float(cycle.plan.speeds[0])
        rising = (e_hi - e_lo) % TWO_PI if speed >= 0 else (e_lo - e_hi) % TWO_PI   # crank angle while it grows
        falling = TWO_PI - rising
        fwd, ret = max(rising, falling), min(rising, falling)
        timing = {"forward": "increasing" if rising >= falling else "decreasing",
                  "forward_crank_angle": fwd, "return_crank_angle": ret,
                  "forward_time": fwd / abs(speed) if speed else None,
                  "return_time": ret / abs(speed) if speed else None,
                  "time_ratio": fwd / ret if ret > 0 else None}
    return OutputMember(link, motion, float(lo), float(hi), tuple(extremes), **timing)
