"""Figures of a mechanism: point paths, kinematic diagrams, velocity and acceleration curves,
the body's path while a foot is planted, and an animation of one cycle.

matplotlib is imported lazily inside the functions (``import assur`` stays light) and always with
the non-interactive "Agg" backend. Geometry is drawn in the file's length unit; velocities in m/s
and accelerations in m/s²; crank angles in degrees.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..errors import SpecError, UnbuildableError
from ..io.units import LENGTH
from ..solve import solve

TWO_PI = 2.0 * math.pi


def _mpl():
    """matplotlib with the Agg backend (imported on first use)."""
    try:
        import matplotlib
    except ImportError as exc:  # pragma: no cover - matplotlib is a dependency
        raise ImportError("plots need matplotlib: pip install matplotlib") from exc
    if matplotlib.get_backend().lower() != "agg":
        matplotlib.use("Agg", force=True)
    import matplotlib.pyplot as plt
    return matplotlib, plt


# -- sampling -------------------------------------------------------------------------------------
@dataclass(frozen=True)
class Sweep:
    """A sampled run of a plan: ``inputs (n, n_inputs)`` (SI), the solved ``state`` (shape (n,)),
    the x-axis values ``axis`` in display units with its ``axis_label``, and ``cyclic`` (one full
    turn of a crank, endpoint excluded)."""
    plan: object
    inputs: np.ndarray
    state: object
    axis: np.ndarray
    axis_label: str
    cyclic: bool
    moving: int            # index of the input shown on the x axis

    @property
    def n(self) -> int:
        return len(self.inputs)


def input_unit(plan, k: int) -> str:
    return "°" if plan.input_kinds[k] == "rotary" else plan.mechanism.units.length


def sweep_inputs(plan, steps: int, ranges=None):
    """Input samples ``(steps, n_inputs)`` (SI) for a plan, the index of the input on the x axis and
    whether the run is one full turn.

    Without ``ranges``: one turn of the crank (q from 0 to 2π, endpoint excluded), or a linear driver's
    working stroke (its ``range``, else the span of its table ``law``; endpoints included); with several
    inputs, the one crank whose speed is not zero turns and the inputs of speed 0 (settings) are
    held at their sketch values. ``ranges``: one ``(start, stop)`` pair per input (SI: rad or m);
    each input runs linearly from start to stop (endpoints included). Raises SpecError when the
    run is not determined (a linear input without a range, several moving inputs)."""
    n = plan.n_inputs
    steps = int(steps)
    if steps < 1:
        raise SpecError([("steps", f"must be a positive number of samples: {steps}")])
    if n == 0:
        raise SpecError([("drivers", "the mechanism has no driver; nothing to sweep")])
    if ranges is not None:
        ranges = [tuple(map(float, r)) for r in ranges]
        if len(ranges) != n:
            raise SpecError([("--range", f"give one range per input ({n}: {', '.join(plan.input_names)}), "
                                         f"in driver order: {len(ranges)} given")])
        q = np.stack([np.linspace(a, b, steps) for a, b in ranges], axis=-1)
        moving = next((k for k, (a, b) in enumerate(ranges) if a != b), 0)
        return q, moving, False
    if n == 1:
        d0 = plan.mechanism.drivers[0]
        stroke = getattr(d0, "range", None) or (getattr(d0, "law", None) and (min(d0.law.values), max(d0.law.values)))
        if plan.input_kinds[0] != "rotary" and stroke is not None:   # the driver's working stroke
            return np.linspace(stroke[0], stroke[1], steps)[:, None], 0, False
        if plan.input_kinds[0] != "rotary":
            raise SpecError([("--range", f"the linear input '{plan.input_names[0]}' has no natural cycle and its "
                                         f"stroke is not known: give --range START STOP "
                                         f"(in {plan.mechanism.units.length})")])
        q = np.linspace(0.0, TWO_PI, steps, endpoint=False)[:, None]
        return q, 0, True
    moving = [k for k in range(n) if plan.speeds[k] != 0]
    if len(moving) == 1 and plan.input_kinds[moving[0]] == "rotary":
        k = moving[0]
        q = np.tile(np.asarray(plan.sketch_inputs, dtype=float), (steps, 1))
        q[:, k] = np.linspace(0.0, TWO_PI, steps, endpoint=False)
        return q, k, True
    raise SpecError([("--range", f"the mechanism has {n} inputs ({', '.join(plan.input_names)}) and one turn of "
                                 f"them is not determined: give --range START STOP once per input, in driver order "
                                 f"(angles in {plan.mechanism.units.angle}, lengths in {plan.mechanism.units.length})")])


def sample(plan, steps: int = 360, params=None, ranges=None) -> Sweep:
    """Solve a plan over one turn (or over ``ranges``); see :func:`sweep_inputs`."""
    q, moving, cyclic = sweep_inputs(plan, steps, ranges)
    state = solve(plan, params, q)
    unit = input_unit(plan, moving)
    if plan.input_kinds[moving] == "rotary":
        axis = np.degrees(q[:, moving])
        label = f"{plan.input_names[moving]} angle φ [°]"
    else:
        axis = q[:, moving] / LENGTH[plan.mechanism.units.length]
        label = f"{plan.input_names[moving]} length [{unit}]"
    return Sweep(plan, q, state, axis, label, cyclic, moving)


def tracked_point(plan) -> str:
    """The foot of a walking leg, else the last point of the file."""
    g = plan.mechanism.gait
    return g.foot if g is not None else plan.point_names[-1]


def gait_curves_or_none(plan, params=None, steps: int = 360):
    """Gait curves of a one-input leg, or None (no foot, several inputs, crank cannot turn fully)."""
    if plan.mechanism.gait is None or plan.n_inputs != 1 or plan.input_kinds[0] != "rotary":
        return None
    from ..analysis.gait import gait_curves
    try:
        return gait_curves(plan, params, steps=max(int(steps), 16))
    except (UnbuildableError, SpecError):
        return None


def _scale(plan) -> float:
    """Factor SI length → the file's length unit."""
    return 1.0 / LENGTH[plan.mechanism.units.length]


def _closed(a, cyclic):
    """Append the first sample to close a cyclic curve."""
    return np.concatenate([a, a[:1]], axis=0) if cyclic and len(a) else a


# -- the kinematic diagram ---------------------------------------------------------------------
def _link_polygons(plan):
    m = plan.mechanism
    idx = {p: i for i, p in enumerate(plan.point_names)}
    return [(lk.name, [idx[p] for p in lk.points]) for lk in m.links if lk.name != "frame"]


def _joint_counts(plan):
    g = plan.structure.graph
    return {p: len(b) for p, b in g.joints}


def _line_direction(plan, pr, pos, params):
    """World direction (radians) of a prismatic pair's line at one position row (SI, (n_points, 2))."""
    p = plan.defaults if params is None else np.asarray(params, dtype=float)
    ang = float(p[plan.param_index(f"{pr.name}.angle")])
    if pr.guide == "frame":
        return ang
    lk = plan.mechanism.link(pr.guide)
    i0, i1 = plan.point_index(lk.points[0]), plan.point_index(lk.points[1])
    d = pos[i1] - pos[i0]
    return ang + math.atan2(d[1], d[0])


def _line_point(plan, pr, pos, params, direction):
    p = plan.defaults if params is None else np.asarray(params, dtype=float)
    off = float(p[plan.param_index(f"{pr.name}.offset")])
    t = pos[plan.point_index(pr.through)]
    return t + off * np.array([-math.sin(direction), math.cos(direction)])


class _Canvas:
    """Collects segments and polygons, then adds them to an axes as a few collections (fast)."""

    def __init__(self):
        self.lines: dict[tuple, list] = {}
        self.polys: dict[tuple, list] = {}

    def line(self, pts, color, width, alpha=1.0, z=2.0):
        self.lines.setdefault((color, float(width), float(alpha), float(z)), []).append(np.asarray(pts, dtype=float))

    def poly(self, pts, face, edge, width, alpha=1.0, z=2.0):
        self.polys.setdefault((face, edge, float(width), float(alpha), float(z)), []).append(
            np.asarray(pts, dtype=float))

    def flush(self, ax):
        from matplotlib.collections import LineCollection, PolyCollection
        from matplotlib.colors import to_rgba

        def rgba(c, alpha):
            r = to_rgba(c)
            return (r[0], r[1], r[2], r[3] * alpha)
        out = []
        for (face, edge, width, alpha, z), ps in self.polys.items():
            pc = PolyCollection(ps, facecolors=[rgba(face, alpha)], edgecolors=[rgba(edge, alpha)], linewidths=width,
                                zorder=z)
            ax.add_collection(pc, autolim=False)
            out.append(pc)
        for (color, width, alpha, z), ls in self.lines.items():
            lc = LineCollection(ls, colors=[rgba(color, alpha)], linewidths=width, zorder=z, capstyle="round",
                                joinstyle="round")
            ax.add_collection(lc, autolim=False)
            out.append(lc)
        return out


def _ground_symbol(cv: _Canvas, xy, size, color="0.2", z=2.0):
    """A textbook fixed-pivot symbol: a triangle on a hatched base line below the point."""
    x, y = xy
    s = size
    cv.poly([[x, y], [x - s, y - 1.6 * s], [x + s, y - 1.6 * s]], "white", color, 1.0, z=z)
    base = y - 1.6 * s
    cv.line([[x - 1.6 * s, base], [x + 1.6 * s, base]], color, 1.2, z=z)
    for k in np.linspace(-1.4, 1.4, 6):
        cv.line([[x + k * s, base], [x + (k - 0.5) * s, base - 0.6 * s]], color, 0.8, z=z)


def _guide(cv: _Canvas, centre, direction, half, size, color="0.2", hatch=True, z=1.0):
    u = np.array([math.cos(direction), math.sin(direction)])
    nrm = np.array([-u[1], u[0]])
    cv.line([centre - half * u, centre + half * u], color, 1.2, z=z)
    if hatch:
        off = -0.9 * size * nrm
        for t in np.linspace(-half, half, max(int(2 * half / (0.8 * size)), 4)):
            p = centre + t * u
            cv.line([p, p + off - 0.5 * size * u], color, 0.7, z=z)


def _block(cv: _Canvas, centre, direction, size, color, alpha=1.0, z=4.0):
    """A slider block: a small rectangle centred on the pin, along the line."""
    u = np.array([math.cos(direction), math.sin(direction)])
    n = np.array([-u[1], u[0]])
    w, h = 1.5 * size, 0.8 * size
    cv.poly([centre + w * u + h * n, centre - w * u + h * n, centre - w * u - h * n, centre + w * u - h * n],
            "white", color, 1.4, alpha, z=z)


def _default_size(plan):
    return 0.03 * plan.length_scale * _scale(plan)


def frame_guides(ax, plan, pos_all, *, params=None, size=None):
    """Draw the frame's slide lines once, spanning the travel of their sliders over ``pos_all``
    ((n, n_points, 2), SI; drawn in the file's length unit)."""
    k = _scale(plan)
    size = size if size is not None else _default_size(plan)
    cv = _Canvas()
    finite = np.all(np.isfinite(pos_all.reshape(len(pos_all), -1)), axis=-1)
    if not finite.any():   # no position can be assembled: no guide to draw
        return cv.flush(ax)
    row = pos_all[int(np.argmax(finite))]   # the first position that assembles
    for pr in plan.mechanism.prismatic:
        if pr.guide != "frame":
            continue
        d = _line_direction(plan, pr, row, params)
        u = np.array([math.cos(d), math.sin(d)])
        q0 = _line_point(plan, pr, row, params, d) * k
        ref = pr.point if pr.point is not None else plan.mechanism.link(pr.link).points[0]
        pts = pos_all[:, plan.point_index(ref)] * k
        pts = pts[np.all(np.isfinite(pts), axis=-1)]
        t = (pts - q0) @ u if len(pts) else np.zeros(1)
        lo, hi = float(t.min()) - 3 * size, float(t.max()) + 3 * size
        _guide(cv, q0 + 0.5 * (lo + hi) * u, d, 0.5 * (hi - lo), size)
    return cv.flush(ax)


def draw_mechanism(ax, plan, pos_row, *, params=None, color="C0", alpha=1.0, linewidth=2.2, labels=False,
                   pivots=True, guides=True, frame_guide=True, foot=None, size=None, zorder=3):
    """Draw the mechanism at one position ``pos_row`` ((n_points, 2), SI) on ``ax`` in the file's
    length unit: links as lines (binary) or filled polygons (ternary and more), revolute joints as
    small circles, frame pivots as ground symbols, slider blocks as small rectangles on their
    guide lines, actuators as a cylinder and a rod. ``frame_guide``: draw a short piece of a frame
    slide line at the block (pass False when :func:`frame_guides` drew the whole travel).
    Returns the list of artists drawn (an animation removes them for the next frame)."""
    from matplotlib.colors import to_rgba
    k = _scale(plan)
    pos = np.asarray(pos_row, dtype=float)
    P = pos * k
    if not np.all(np.isfinite(P)):
        return []
    size = size if size is not None else _default_size(plan)
    m = plan.mechanism
    counts = _joint_counts(plan)
    frame_pts = set(m.frame.points)
    col = to_rgba(color)
    z = float(zorder)
    cv = _Canvas()
    # links
    for name, ids in _link_polygons(plan):
        xy = P[ids]
        if len(ids) == 2:
            cv.line(xy, col, linewidth, alpha, z)
        elif len(ids) > 2:
            cv.poly(xy, to_rgba(color, 0.12 * alpha), col, linewidth, 1.0, z)
    # actuators: a cylinder from the first point, a rod from the second
    for ac in m.actuators:
        a, b = P[plan.point_index(ac.between[0])], P[plan.point_index(ac.between[1])]
        sa, sb = (np.asarray(m.sketch(p)[:2]) * k for p in ac.between)
        body = 0.6 * float(np.hypot(*(sb - sa)))
        d = b - a
        L = float(np.hypot(*d))
        if L > 0:
            u = d / L
            cv.line([a, a + min(body, L) * u], col, 2.6 * linewidth, alpha, z)
            cv.line([b - min(body, L) * u, b], to_rgba("0.35"), 0.8 * linewidth, alpha, z + 0.2)
    # prismatic pairs
    for pr in m.prismatic:
        d = _line_direction(plan, pr, pos, params)
        ref = pr.point if pr.point is not None else m.link(pr.link).points[0]
        c = P[plan.point_index(ref)]
        if guides and pr.guide != "frame":
            _guide(cv, c, d, 4 * size, size, color=col, hatch=False, z=z - 0.2)
        elif guides and pr.guide == "frame" and frame_guide:
            q0 = _line_point(plan, pr, pos, params, d) * k
            u = np.array([math.cos(d), math.sin(d)])
            _guide(cv, q0 + float((c - q0) @ u) * u, d, 5 * size, size)
        _block(cv, c, d, size, col, alpha, z=z + 0.5)
    # ground symbols at the frame pivots
    if pivots:
        for p in m.frame.points:
            if counts.get(p, 0) > 1:
                _ground_symbol(cv, P[plan.point_index(p)], size)
    out = cv.flush(ax)
    # joints and points
    joint = [i for i, p in enumerate(plan.point_names) if counts.get(p, 0) > 1 or p in frame_pts]
    plain = [i for i, p in enumerate(plan.point_names) if i not in joint]
    if joint:
        out += ax.plot(P[joint, 0], P[joint, 1], marker="o", markersize=5.5, markerfacecolor="white",
                       markeredgecolor="0.1", markeredgewidth=1.2, alpha=alpha, zorder=z + 1, linestyle="none")
    if plain:
        out += ax.plot(P[plain, 0], P[plain, 1], marker="o", markersize=3.5, color=col, alpha=alpha,
                       zorder=z + 1, linestyle="none")
    if foot is not None:
        i = plan.point_index(foot)
        out += ax.plot(P[i:i + 1, 0], P[i:i + 1, 1], marker="o", markersize=7, markerfacecolor="crimson",
                       markeredgecolor="0.1", alpha=alpha, zorder=z + 1.5, linestyle="none")
    if labels:
        for i, p in enumerate(plan.point_names):
            out.append(ax.annotate(p, tuple(P[i]), xytext=(5, 5), textcoords="offset points", fontsize=9,
                                   zorder=z + 2))
    return out


def _set_limits(ax, pts, margin=0.08):
    pts = pts[np.all(np.isfinite(pts), axis=-1)]
    if not len(pts):
        return
    lo, hi = pts.min(axis=0), pts.max(axis=0)
    span = float(max(hi - lo)) or 1.0
    pad = margin * span + 1e-12
    ax.set_xlim(lo[0] - pad, hi[0] + pad)
    ax.set_ylim(lo[1] - pad, hi[1] + pad)
    ax.set_aspect("equal", adjustable="box")


def _shade_contact(ax, axis, contact, color="tab:green", alpha=0.10, label=None):
    """Shade the contact arc (a mask over the samples) on a plot against the crank angle."""
    if contact is None or not np.any(contact):
        return
    step = axis[1] - axis[0] if len(axis) > 1 else 1.0
    from ..analysis.sampling import intervals
    for i, j in intervals(contact):
        a, b = axis[i], axis[j] + step
        if j < i:  # wraps around
            ax.axvspan(a, axis[-1] + step, color=color, alpha=alpha, linewidth=0, label=label)
            ax.axvspan(axis[0], b, color=color, alpha=alpha, linewidth=0)
        else:
            ax.axvspan(a, b, color=color, alpha=alpha, linewidth=0, label=label)
        label = None


def diagram_indices(sweep: Sweep, positions: int = 6) -> list[int]:
    """Up to ``positions`` sample indices, evenly spread over the valid samples."""
    ok = np.nonzero(sweep.state.valid)[0]
    if not len(ok):
        return []
    if sweep.cyclic:
        want = np.arange(positions) * sweep.n / positions
        return sorted({int(ok[np.argmin(np.abs(ok - w))]) for w in want})
    pick = np.linspace(0, len(ok) - 1, min(positions, len(ok)))
    return sorted({int(ok[int(round(p))]) for p in pick})


# -- the figure ------------------------------------------------------------------------------------
def mechanism_figure(plan, steps: int = 360, *, params=None, ranges=None, positions: int = 6, sweep=None,
                     figsize=None, dpi: int = 100):
    """One figure: (a) point paths, (b) kinematic diagram in several positions, (c) velocity and
    (d) acceleration of the foot (or of the last point) against the input, and for a walking leg
    (e) the frame pivot's path while the foot is planted. Returns a matplotlib Figure."""
    _, plt = _mpl()
    from matplotlib.gridspec import GridSpec
    sw = sweep if sweep is not None else sample(plan, steps, params, ranges)
    st = sw.state
    k = _scale(plan)
    unit = plan.mechanism.units.length
    foot = tracked_point(plan)
    fi = plan.point_index(foot)
    gc = gait_curves_or_none(plan, params, max(sw.n, 16)) if sw.cyclic else None
    has_e = gc is not None
    fig = plt.figure(figsize=figsize or ((16, 10) if has_e else (14, 10)), dpi=dpi)
    # fixed margins (tight_layout costs more than drawing the figure)
    gs = GridSpec(2, 6, figure=fig, height_ratios=[1.25, 1.0], left=0.055, right=0.985, bottom=0.065, top=0.9,
                  wspace=1.0, hspace=0.28)
    ax_a = fig.add_subplot(gs[0, 0:3])
    ax_b = fig.add_subplot(gs[0, 3:6])
    if has_e:
        ax_c, ax_d, ax_e = fig.add_subplot(gs[1, 0:2]), fig.add_subplot(gs[1, 2:4]), fig.add_subplot(gs[1, 4:6])
    else:
        ax_c, ax_d, ax_e = fig.add_subplot(gs[1, 0:3]), fig.add_subplot(gs[1, 3:6]), None
    title = plan.mechanism.name or "mechanism"
    bad = int(st.n_unbuildable)
    sub = f"{sw.n} samples" + (f", {bad} cannot be assembled" if bad else "")
    fig.suptitle(f"{title}  ({sub})", fontsize=13)
    pos = st.pos * k                                      # (n, n_points, 2) file units
    contact = None
    if gc is not None and len(gc.contact) == sw.n:
        contact = gc.contact
    # (a) paths
    frame_pts = set(plan.mechanism.frame.points)
    for i, p in enumerate(plan.point_names):
        if p in frame_pts:
            continue
        xy = _closed(pos[:, i], sw.cyclic)
        if i == fi:
            continue
        ax_a.plot(xy[:, 0], xy[:, 1], color="0.55", linewidth=1.0)
        j = int(np.argmax(np.isfinite(xy[:, 0]))) if np.isfinite(xy[:, 0]).any() else None
        if j is not None:
            ax_a.annotate(p, xy[j], xytext=(4, 4), textcoords="offset points", fontsize=8, color="0.3")
    fxy = _closed(pos[:, fi], sw.cyclic)
    ax_a.plot(fxy[:, 0], fxy[:, 1], color="tab:blue", linewidth=2.2, label=f"{foot} path")
    if contact is not None:
        cxy = np.where(contact[:, None], pos[:, fi], np.nan)
        # keep the arc continuous across the wrap
        cxy = _closed(cxy, sw.cyclic)
        ax_a.plot(cxy[:, 0], cxy[:, 1], color="tab:green", linewidth=4.0, alpha=0.8, label="contact arc")
    for p in frame_pts:
        xy = pos[0, plan.point_index(p)]
        if np.all(np.isfinite(xy)):
            ax_a.plot(*xy, marker="^", color="0.2", markersize=7, linestyle="none")
            ax_a.annotate(p, xy, xytext=(4, -10), textcoords="offset points", fontsize=8, color="0.3")
    ax_a.set_title("(a) paths of the points" + (f" (foot {foot})" if plan.mechanism.gait else ""))
    ax_a.set_xlabel(f"x [{unit}]")
    ax_a.set_ylabel(f"y [{unit}]")
    ax_a.grid(True, alpha=0.3)
    ax_a.legend(loc="best", fontsize=8)
    _set_limits(ax_a, pos.reshape(-1, 2))
    # (b) the diagram in several positions
    idx = diagram_indices(sw, positions)
    cmap = plt.get_cmap("viridis")
    frame_guides(ax_b, plan, st.pos, params=params)
    ax_b.plot(fxy[:, 0], fxy[:, 1], color="0.6", linewidth=1.0, linestyle="--", zorder=1)
    shown = []
    for n_, i in enumerate(idx):
        col = cmap(0.9 * n_ / max(len(idx) - 1, 1))
        draw_mechanism(ax_b, plan, st.pos[i], params=params, color=col, alpha=0.95, linewidth=1.8,
                       labels=(n_ == 0), pivots=(n_ == 0), frame_guide=False, foot=foot)
        ax_b.annotate(str(n_ + 1), pos[i, fi], xytext=(6, -12), textcoords="offset points", fontsize=9,
                      color=col, fontweight="bold")
        shown.append(f"{sw.axis[i]:.0f}" if plan.input_kinds[sw.moving] == "rotary" else f"{sw.axis[i]:.4g}")
    if not idx:
        ax_b.text(0.5, 0.5, "no position can be assembled", transform=ax_b.transAxes, ha="center")
    where = ""
    if shown:
        where = (f"\npositions 1–{len(idx)} at φ = {', '.join(shown)}°" if plan.input_kinds[sw.moving] == "rotary"
                 else f"\npositions 1–{len(idx)} at {plan.input_names[sw.moving]} = {', '.join(shown)} {unit}")
    ax_b.set_title(f"(b) kinematic diagram{where}", fontsize=11)
    ax_b.set_xlabel(f"x [{unit}]")
    ax_b.set_ylabel(f"y [{unit}]")
    ax_b.grid(True, alpha=0.3)
    _set_limits(ax_b, pos.reshape(-1, 2))
    # (c) velocity, (d) acceleration of the foot
    x = sw.axis
    vel, acc = st.vel[:, fi], st.acc[:, fi]
    for ax, val, name, u_ in ((ax_c, vel, "v", "m/s"), (ax_d, acc, "a", "m/s²")):
        ax.plot(x, np.hypot(val[:, 0], val[:, 1]), color="k", linewidth=1.8, label=f"|{name}|")
        ax.plot(x, val[:, 0], color="tab:red", linewidth=1.2, label=f"{name}x")
        ax.plot(x, val[:, 1], color="tab:blue", linewidth=1.2, label=f"{name}y")
        ax.axhline(0.0, color="0.5", linewidth=0.6)
        _shade_contact(ax, x, contact)
        if bad:
            _shade_contact(ax, x, ~st.valid, color="tab:red", alpha=0.12, label="cannot be assembled")
        ax.set_xlabel(sw.axis_label)
        ax.set_ylabel(f"{'velocity' if name == 'v' else 'acceleration'} of {foot} [{u_}]")
        if sw.cyclic and plan.input_kinds[sw.moving] == "rotary":
            ax.set_xlim(0, 360)
            ax.set_xticks(np.arange(0, 361, 60))
        ax.grid(True, alpha=0.3)
        ax.legend(loc="best", fontsize=8)
    ax_c.set_title(f"(c) velocity of {foot}" + (" (green: contact arc)" if contact is not None else ""))
    ax_d.set_title(f"(d) acceleration of {foot}")
    # (e) the body's path while the foot is planted
    if ax_e is not None:
        pivot = plan.mechanism.frame.points[0]
        bx, bv = gc.body_x * k, gc.body_v * k
        ax_e.plot(bx, bv, color="tab:purple", linewidth=2.0)
        ax_e.plot(bx[:1], bv[:1], marker="o", color="tab:purple", linestyle="none", label="touch-down")
        ax_e.plot(bx[-1:], bv[-1:], marker="s", color="tab:purple", linestyle="none", label="lift-off")
        ax_e.set_title(f"(e) path of the frame pivot {pivot} while {foot} is planted")
        ax_e.set_xlabel(f"horizontal displacement [{unit}]")
        ax_e.set_ylabel(f"vertical displacement [{unit}]")
        ax_e.grid(True, alpha=0.3)
        ax_e.legend(loc="best", fontsize=8)
        span = float(np.ptp(bv)) if len(bv) else 0.0
        if span < 1e-9:
            ax_e.set_ylim(-1, 1)
    return fig


def timeline_figure(plan, metrics, phases, steps: int = 360, figsize=(7, 2.4), dpi: int = 100):
    """Feet on the ground of a walking module over one crank turn (a step plot)."""
    _, plt = _mpl()
    from ..analysis.gait import module_timeline
    q, count = module_timeline(metrics, phases, steps)
    fig, ax = plt.subplots(figsize=figsize, dpi=dpi)
    ax.step(np.degrees(q), count, where="post", color="tab:green", linewidth=2)
    ax.fill_between(np.degrees(q), count, step="post", color="tab:green", alpha=0.2)
    ax.set_xlim(0, 360)
    ax.set_xticks(np.arange(0, 361, 60))
    ax.set_ylim(0, max(len(phases), 1) + 0.3)
    ax.set_yticks(range(0, len(phases) + 1))
    ax.set_xlabel("crank angle φ [°]")
    ax.set_ylabel("feet on ground")
    ax.set_title(f"walking module: {len(phases)} legs at phases "
                 + ", ".join(f"{math.degrees(p):.0f}°" for p in phases))
    ax.grid(True, alpha=0.3)
    fig.tight_layout()
    return fig


# -- animation ---------------------------------------------------------------------------------
def animation(plan, frames: int = 60, fps: float = 20.0, *, params=None, ranges=None, figsize=(6.4, 6.4),
              dpi: int = 100):
    """A matplotlib FuncAnimation of one turn (or of ``ranges``) with the traced path of the foot
    (or of the last point). Returns ``(figure, animation)``."""
    _, plt = _mpl()
    from matplotlib.animation import FuncAnimation
    sw = sample(plan, frames, params, ranges)
    st = sw.state
    k = _scale(plan)
    unit = plan.mechanism.units.length
    foot = tracked_point(plan)
    fi = plan.point_index(foot)
    # a dense path for the faint full trace
    dense = sample(plan, max(4 * frames, 180), params, ranges) if frames < 180 else sw
    full = _closed(dense.state.pos[:, fi] * k, dense.cyclic)
    fig, ax = plt.subplots(figsize=figsize, dpi=dpi)
    pos_all = np.concatenate([st.pos.reshape(-1, 2), dense.state.pos.reshape(-1, 2)]) * k
    ax.plot(full[:, 0], full[:, 1], color="0.75", linewidth=1.0, linestyle="--", zorder=1)
    frame_guides(ax, plan, dense.state.pos, params=params)
    (trace,) = ax.plot([], [], color="tab:blue", linewidth=2.0, zorder=2)
    ax.set_xlabel(f"x [{unit}]")
    ax.set_ylabel(f"y [{unit}]")
    ax.grid(True, alpha=0.3)
    ax.set_title(plan.mechanism.name or "mechanism", fontsize=11)
    _set_limits(ax, pos_all, margin=0.12)
    xl, yl = ax.get_xlim(), ax.get_ylim()
    info = ax.text(0.02, 0.97, "", transform=ax.transAxes, va="top", fontsize=9)
    drawn: list = []
    dpos = dense.state.pos[:, fi] * k

    def upto(i):
        """Dense samples traced by frame i."""
        if dense is sw:
            return i + 1
        if sw.cyclic:
            return int(round(i * dense.n / sw.n)) + 1
        return int(round(i * (dense.n - 1) / max(sw.n - 1, 1))) + 1

    def update(i):
        for a in drawn:
            a.remove()
        drawn.clear()
        if st.valid[i]:
            drawn.extend(draw_mechanism(ax, plan, st.pos[i], params=params, color="tab:blue", labels=True,
                                        frame_guide=False, foot=foot))
            status = ""
        else:
            status = "  (cannot be assembled)"
        j = upto(i)
        trace.set_data(dpos[:j, 0], dpos[:j, 1])
        if plan.input_kinds[sw.moving] == "rotary":
            info.set_text(f"φ = {sw.axis[i]:.0f}°{status}")
        else:
            info.set_text(f"{plan.input_names[sw.moving]} = {sw.axis[i]:.4g} {unit}{status}")
        ax.set_xlim(xl)
        ax.set_ylim(yl)
        return drawn + [trace, info]

    anim = FuncAnimation(fig, update, frames=sw.n, interval=1000.0 / float(fps), blit=False, repeat=True)
    return fig, anim


def save_animation(anim, path, fps: float = 20.0, dpi: int = 100, progress=None, title: str = "animation"):
    """Save an animation by the file's extension: .gif (Pillow), .mp4 (ffmpeg from imageio-ffmpeg),
    .html (a self-contained page from ``to_jshtml``). ``progress(i, n)`` is called per frame
    (GIF and MP4)."""
    matplotlib, _ = _mpl()
    from pathlib import Path
    path = Path(path)
    ext = path.suffix.lower()
    if ext == ".gif":
        from matplotlib.animation import PillowWriter
        anim.save(str(path), writer=PillowWriter(fps=fps), dpi=dpi, progress_callback=progress)
    elif ext == ".mp4":
        try:
            import imageio_ffmpeg
        except ImportError:
            raise ImportError("MP4 output needs ffmpeg from imageio-ffmpeg: install assur[video] "
                              "(pip install 'assur[video]')") from None
        matplotlib.rcParams["animation.ffmpeg_path"] = imageio_ffmpeg.get_ffmpeg_exe()
        from matplotlib.animation import FFMpegWriter
        anim.save(str(path), writer=FFMpegWriter(fps=fps, codec="libx264",
                                                 extra_args=["-pix_fmt", "yuv420p"]), dpi=dpi,
                  progress_callback=progress)
    elif ext in (".html", ".htm"):
        path.write_text(html_page(jshtml(anim, fps), title=title), encoding="utf-8")
    else:
        raise ValueError(f"unknown animation format {ext!r} (use .gif, .mp4 or .html)")


# the player's icons without the font-awesome style sheet that to_jshtml links from a CDN
_ICONS = {"fa-minus": "&minus;", "fa-fast-backward": "&#x23EE;&#xFE0E;", "fa-step-backward": "&#x2759;&#x25C0;&#xFE0E;",
          "fa-flip-horizontal": "&#x25C0;&#xFE0E;", "fa-pause": "&#x2759;&#x2759;", "fa-play": "&#x25B6;&#xFE0E;",
          "fa-step-forward": "&#x25B6;&#xFE0E;&#x2759;", "fa-fast-forward": "&#x23ED;&#xFE0E;", "fa-plus": "+"}


def jshtml(anim, fps: float = 20.0, default_mode: str = "loop") -> str:
    """``anim.to_jshtml()`` made self-contained: the frames are embedded (base64 PNG) and the
    link to the icon font on a CDN is replaced by plain Unicode symbols (no network access)."""
    import re
    text = anim.to_jshtml(fps=fps, default_mode=default_mode)
    text = re.sub(r'<link[^>]*href="https?://[^"]*"[^>]*>', "", text)

    def icon(mt):
        classes = mt.group(1).split()
        for key in ("fa-flip-horizontal", *_ICONS):
            if key in classes:
                return f'<span aria-hidden="true">{_ICONS[key]}</span>'
        return ""
    return re.sub(r'<i class="([^"]*)"></i>', icon, text)


def html_page(body: str, title: str = "") -> str:
    import html as _html
    return ("<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n"
            f"<title>{_html.escape(title)}</title>\n</head>\n<body>\n{body}\n</body>\n</html>\n")


def figure_png(fig, dpi: int = 100) -> bytes:
    """A figure as PNG bytes."""
    import io
    buf = io.BytesIO()
    fig.savefig(buf, format="png", dpi=dpi)
    return buf.getvalue()


def close(fig):
    _, plt = _mpl()
    plt.close(fig)
