"""Drawing a planar mechanism on matplotlib axes: links, joints, frame pivots, slider blocks and guides,
actuators; and the matplotlib plumbing the figures share (the Agg backend, PNG bytes, closing).

matplotlib is imported lazily inside the functions (``import assur`` stays light) and always with the
non-interactive "Agg" backend. Geometry is drawn in the file's length unit.
"""
from __future__ import annotations

import math

import numpy as np

from ..io.units import LENGTH


def mpl():
    """matplotlib with the Agg backend (imported on first use); in a notebook its inline backend (Agg too)
    stays, so that figures display."""
    try:
        import matplotlib
    except ImportError as exc:  # pragma: no cover - matplotlib is a dependency
        raise ImportError("plots need matplotlib: pip install matplotlib") from exc
    backend = matplotlib.get_backend().lower()
    if backend != "agg" and "backend_inline" not in backend:
        matplotlib.use("Agg", force=True)
    import matplotlib.pyplot as plt
    return matplotlib, plt


#: the frame rates an animation takes (frames per second): a frame lasts from a millisecond to 100 s
FPS_RANGE = (0.01, 1000.0)


def frame_rate(fps) -> float:
    """``fps`` as a float, SpecError unless a number in :data:`FPS_RANGE`."""
    from ..errors import SpecError
    try:
        v = float(fps)
    except (TypeError, ValueError):
        v = math.nan
    if not FPS_RANGE[0] <= v <= FPS_RANGE[1]:
        raise SpecError([("fps", f"must be a number of frames per second from {FPS_RANGE[0]:g} to "
                                 f"{FPS_RANGE[1]:g}: {fps!r}")])
    return v


def file_scale(plan, units: str = "file") -> float:
    """Factor SI length → the drawing's length unit: the file's (``units="file"``) or metres (``"si"``)."""
    return 1.0 if units == "si" else 1.0 / LENGTH[plan.mechanism.units.length]


def length_unit(plan, units: str = "file") -> str:
    """The drawing's length unit: the file's (``units="file"``) or ``m`` (``"si"``)."""
    return "m" if units == "si" else plan.mechanism.units.length


def closed(a, cyclic):
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


def _default_size(plan, scale=None):
    return 0.03 * plan.length_scale * (file_scale(plan) if scale is None else scale)


def frame_guides(ax, plan, pos_all, *, params=None, size=None, scale=None):
    """Draw the frame's slide lines once, spanning the travel of their sliders over ``pos_all``
    ((n, n_points, 2), SI; drawn in the file's length unit, or times ``scale`` when given)."""
    k = file_scale(plan) if scale is None else scale
    size = size if size is not None else _default_size(plan, k)
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
                   pivots=True, guides=True, frame_guide=True, foot=None, size=None, zorder=3, scale=None):
    """Draw the mechanism at one position ``pos_row`` ((n_points, 2), SI) on ``ax`` in the file's
    length unit: links as lines (binary) or filled polygons (ternary and more), revolute joints as
    small circles, frame pivots as ground symbols, slider blocks as small rectangles on their
    guide lines, actuators as a cylinder and a rod. ``frame_guide``: draw a short piece of a frame
    slide line at the block (pass False when :func:`frame_guides` drew the whole travel).
    ``scale``: SI → drawn length (default: the file's unit). Returns the list of artists drawn (an animation
    removes them for the next frame)."""
    from matplotlib.colors import to_rgba
    k = file_scale(plan) if scale is None else scale
    pos = np.asarray(pos_row, dtype=float)
    P = pos * k
    if not np.all(np.isfinite(P)):
        return []
    size = size if size is not None else _default_size(plan, k)
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
    _gear_curves(cv, plan, pos, k, col, alpha, z)
    _cam_profiles(cv, plan, pos, params, k, col, alpha, z)
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


def _gear_curves(cv: "_Canvas", plan, pos, k, col, alpha, z):
    """Each gear pair's pitch curves, turned with their links (a link's turn: its pivot → arm direction now
    against the sketch)."""
    from ..model.gearing import gear_ends, pitch_points
    m = plan.mechanism
    for gp in m.gears:
        ends = []
        for pivot, arm in gear_ends(m, gp):
            now = pos[plan.point_index(arm)] - pos[plan.point_index(pivot)]
            then = np.asarray(m.sketch(arm)[:2]) - np.asarray(m.sketch(pivot)[:2])
            turn = complex(*now) / complex(*then)
            ends.append((complex(*pos[plan.point_index(pivot)]), turn / abs(turn), complex(*m.sketch(pivot)[:2])))
        curves = pitch_points(gp, ends[0][2], ends[1][2])
        for (centre, turn, _), curve in zip(ends, curves):
            w = centre + turn * curve
            xy = np.column_stack([w.real, w.imag]) * k
            cv.line(np.vstack([xy, xy[:1]]), col, 1.0, 0.8 * alpha, z - 0.5)


def cam_outline(plan, index: int, params=None, samples: int = 720):
    """(profile, pitch) (samples,) complex in the cam's frame (origin its pivot, x along pivot → arm in the sketch)
    of cam pair ``index`` at ``params`` (kept for the last few designs: an animation draws it every frame)."""
    key = (None if params is None else tuple(np.asarray(params, dtype=float).tolist()), index, samples)
    cache = _CAM_CACHE.setdefault(plan, {})
    if key not in cache:
        from ..cams.followers import from_plan
        g = from_plan(plan, index, params)
        c = g.turn_samples(samples)
        if len(cache) > 8:
            cache.clear()
        cache[key] = (c.profile, c.pitch, g)
    return cache[key]


import weakref  # noqa: E402

_CAM_CACHE: "weakref.WeakKeyDictionary" = weakref.WeakKeyDictionary()


def _cam_profiles(cv: "_Canvas", plan, pos, params, k, col, alpha, z):
    """Each cam pair's profile turned with its cam (its pivot → arm direction now against the sketch), the pitch
    curve dashed, and the follower's roller (a circle at the trace point) or flat face (a segment through it)."""
    m = plan.mechanism
    if not m.cams:
        return
    from ..model.camming import cam_ends
    for j, cp in enumerate(m.cams):
        profile, pitch, g = cam_outline(plan, j, params)
        pivot, arm = cam_ends(m, cp)
        O = complex(*pos[plan.point_index(pivot)])
        now = complex(*pos[plan.point_index(arm)]) - O
        turn = now / abs(now) / g.orientation
        w = (O + turn * g.orientation * profile) * k
        cv.poly(np.column_stack([w.real, w.imag]), "0.85", col, 1.0, 0.9 * alpha, z - 0.6)
        R = complex(*pos[plan.point_index(cp.point)]) * k
        if cp.contact == "roller":
            t = np.exp(1j * np.linspace(0.0, 2 * math.pi, 48))
            c = R + cp.roller_radius * k * t
            cv.poly(np.column_stack([c.real, c.imag]), "white", col, 1.0, alpha, z + 0.2)
        elif cp.contact == "flat":
            if cp.motion == "translating":
                face = 1j * g.direction
            else:
                Of = complex(*pos[plan.point_index(next(p for p in m.link(cp.follower).points
                                                        if p in set(m.frame.points)))]) * k
                face = (R - Of) / abs(R - Of)
            face = face * complex(math.cos(cp.face_angle), math.sin(cp.face_angle))
            half = 0.6 * abs(g.trace - g.pivot) * k
            cv.line([[(R - half * face).real, (R - half * face).imag], [(R + half * face).real, (R + half * face).imag]],
                    col, 2.0, alpha, z + 0.2)


def set_limits(ax, pts, margin=0.08):
    """Equal-aspect limits of ``ax`` around the finite points ``pts (n, 2)``, padded by ``margin`` of their span."""
    pts = pts[np.all(np.isfinite(pts), axis=-1)]
    if not len(pts):
        return
    lo, hi = pts.min(axis=0), pts.max(axis=0)
    span = float(max(hi - lo)) or 1.0
    pad = margin * span + 1e-12
    ax.set_xlim(lo[0] - pad, hi[0] + pad)
    ax.set_ylim(lo[1] - pad, hi[1] + pad)
    ax.set_aspect("equal", adjustable="box")


def figure_png(fig, dpi: int = 100) -> bytes:
    """A figure as PNG bytes."""
    import io
    buf = io.BytesIO()
    fig.savefig(buf, format="png", dpi=dpi)
    return buf.getvalue()


def close(fig):
    """Release a figure (pyplot keeps every open figure)."""
    _, plt = mpl()
    plt.close(fig)
