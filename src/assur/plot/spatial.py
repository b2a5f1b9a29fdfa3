"""3D views of spatial mechanisms (paper 003, Fig. 2–3): the mechanism in several positions, the
paths of its points and their projections on the coordinate planes, and an animation.

- :func:`plotly_figure` — an interactive plotly figure (rotate, zoom, hover) with an animation
  (frames, a play button and a slider); :func:`write_html` saves it as one self-contained page
  (plotly.js inlined, no network access).
- :func:`figure` — a static matplotlib 3D figure (PNG, SVG, PDF): the 3D view and the rocker
  angles and transmission angles over the turn.
- :func:`animation` — a matplotlib 3D animation (GIF, MP4 or a jshtml page).

plotly and matplotlib are imported lazily inside the functions.
"""
from __future__ import annotations

import numpy as np

from ..analysis.sampling import CYCLE_STEPS
from ..errors import SpecError
from .draw import closed, file_scale, frame_rate, length_unit, mpl
from .figures import sample, study_of

COLORS = ("#1f77b4", "#d62728", "#2ca02c", "#9467bd", "#ff7f0e", "#8c564b", "#e377c2", "#17becf")


def _plotly():
    try:
        import plotly.graph_objects as go
    except ImportError as exc:  # pragma: no cover - an optional dependency
        raise ImportError("interactive 3D views need plotly: pip install plotly") from exc
    return go


def link_polylines(plan, pos_row, units: str = "file") -> list[np.ndarray]:
    """Each moving link as a polyline through its points (closed for three or more), (k, 3) each,
    in the file's length unit; a frame revolute's axis as a short segment through its point."""
    k = file_scale(plan, units)
    out = []
    for lk in plan.mechanism.links:
        if lk.name == "frame":
            continue
        idx = [plan.point_index(p) for p in lk.points]
        pts = pos_row[idx] * k
        if len(idx) >= 3:
            pts = np.vstack([pts, pts[:1]])
        out.append(pts)
    return out


def axis_segments(plan, params=None, units: str = "file") -> list[tuple[str, np.ndarray]]:
    """(point, (2, 3)) a segment along every frame revolute's axis (file units), 0.3 of the
    mechanism's size long."""
    from ..kernels.spatial import e_z2
    params = plan.defaults if params is None else params
    k = file_scale(plan, units)
    half = 0.15 * plan.length_scale * k
    out = []
    for st in plan.steps:
        if st.kind not in ("crank", "RSS"):
            continue
        p = st.pivot
        e = e_z2(params[plan.param_index(f"{p}.axis.gamma1")], params[plan.param_index(f"{p}.axis.gamma2")])
        c = np.array([params[plan.param_index(f"{p}.{a}")] for a in "xyz"]) * k
        out.append((p, np.stack([c - half * e, c + half * e])))
    return out


def _moving_points(plan) -> list[int]:
    frame = set(plan.mechanism.frame.points)
    return [i for i, p in enumerate(plan.point_names) if p not in frame]


def _planes(pts):
    """The three projection planes: just below the minimum of each coordinate of all points."""
    lo, hi = np.nanmin(pts, axis=0), np.nanmax(pts, axis=0)
    span = float(np.max(hi - lo)) or 1.0
    return lo - 0.08 * span, hi + 0.08 * span


def _segments_trace_xyz(polys):
    xs, ys, zs = [], [], []
    for p in polys:
        xs += list(p[:, 0]) + [None]
        ys += list(p[:, 1]) + [None]
        zs += list(p[:, 2]) + [None]
    return xs, ys, zs


def plotly_figure(plan, steps: int = CYCLE_STEPS, *, positions: int = 6, frames: int = 36, params=None, ranges=None,
                  sweep=None, units: str = "file"):
    """An interactive 3D figure: the mechanism in ``positions`` positions (faded), the paths of the
    moving points with their projections on the planes x = x₀, y = y₀, z = z₀ (paper 003 Fig. 2–3),
    the revolute axes, and the mechanism animated over ``frames`` positions (play button and slider).
    ``sweep``: the solved run the paths and positions come from (default: :func:`~assur.plot.figures.sample`
    of ``steps`` over one turn or ``ranges``)."""
    go = _plotly()
    study = study_of(plan, params, steps, ranges)
    plan, params = study.plan, study.params
    sw = sweep if sweep is not None else study.sweep
    st = sw.state
    k = file_scale(plan, units)
    unit = length_unit(plan, units)
    pos = st.pos * k
    if not np.isfinite(pos).any():
        raise SpecError([("mechanism", "no position of the sweep can be assembled: nothing to draw")])
    lo, hi = _planes(pos.reshape(-1, 3))
    moving = _moving_points(plan)
    data = []
    # the animated mechanism: trace 0 (replaced by each frame)
    anim = study.frame_sweep(frames) if sweep is None else sample(plan, frames, params, ranges)
    apos = anim.state.pos * k

    def mech_trace(i, name="mechanism"):
        row = apos[i]
        xs, ys, zs = _segments_trace_xyz(link_polylines(plan, row / k, units)) if anim.state.valid[i] else ([], [], [])
        return go.Scatter3d(x=xs, y=ys, z=zs, mode="lines+markers", name=name,
                            line=dict(color="#222", width=7), marker=dict(size=4, color="#222"),
                            hovertemplate="%{x:.4g}, %{y:.4g}, %{z:.4g}<extra></extra>")

    first = int(np.argmax(anim.state.valid)) if anim.state.valid.any() else 0
    data.append(mech_trace(first))
    # faded positions
    idx = np.unique(np.linspace(0, sw.n - 1, positions, endpoint=not sw.cyclic).round().astype(int))
    for j, i in enumerate(idx):
        if not st.valid[i]:
            continue
        xs, ys, zs = _segments_trace_xyz(link_polylines(plan, st.pos[i], units))
        label = f"{sw.axis[i]:.0f}°" if plan.input_kinds[sw.moving] == "rotary" else f"{sw.axis[i]:.4g}"
        data.append(go.Scatter3d(x=xs, y=ys, z=zs, mode="lines", name=f"position {label}",
                                 line=dict(color="rgba(40,40,40,0.4)", width=4), legendgroup="positions",
                                 showlegend=j == 0, hoverinfo="skip"))
    # paths and projections
    for c, pi in enumerate(moving):
        col = COLORS[c % len(COLORS)]
        path = closed(pos[:, pi], sw.cyclic)
        name = plan.point_names[pi]
        data.append(go.Scatter3d(x=path[:, 0], y=path[:, 1], z=path[:, 2], mode="lines", name=f"path of {name}",
                                 line=dict(color=col, width=4),
                                 hovertemplate=f"{name}: " + "%{x:.4g}, %{y:.4g}, %{z:.4g}<extra></extra>"))
        for axis in range(3):
            proj = path.copy()
            proj[:, axis] = lo[axis]
            data.append(go.Scatter3d(x=proj[:, 0], y=proj[:, 1], z=proj[:, 2], mode="lines",
                                     name=f"projections of {name}", legendgroup=f"proj{name}",
                                     showlegend=axis == 0, line=dict(color=col, width=2, dash="dot"),
                                     opacity=0.6, hoverinfo="skip"))
    for p, seg in axis_segments(plan, params, units):
        data.append(go.Scatter3d(x=seg[:, 0], y=seg[:, 1], z=seg[:, 2], mode="lines", name=f"axis at {p}",
                                 line=dict(color="#888", width=3, dash="dash"), hoverinfo="skip", showlegend=False))
    fr = [go.Frame(data=[mech_trace(i)], traces=[0], name=str(i)) for i in range(anim.n)]
    lab = [(f"{anim.axis[i]:.0f}°" if plan.input_kinds[anim.moving] == "rotary" else f"{anim.axis[i]:.4g}")
           for i in range(anim.n)]
    fig = go.Figure(data=data, frames=fr)
    fig.update_layout(
        title=plan.mechanism.name or "spatial mechanism",
        scene=dict(xaxis=dict(title=f"x [{unit}]", range=[lo[0], hi[0]]),
                   yaxis=dict(title=f"y [{unit}]", range=[lo[1], hi[1]]),
                   zaxis=dict(title=f"z [{unit}]", range=[lo[2], hi[2]]), aspectmode="cube",
                   camera=dict(up=dict(x=0, y=1, z=0), eye=dict(x=1.6, y=0.9, z=1.4))),
        margin=dict(l=0, r=0, t=40, b=0), height=700, legend=dict(itemsizing="constant"),
        updatemenus=[dict(type="buttons", showactive=False, x=0.02, y=0.02, xanchor="left", yanchor="bottom",
                          buttons=[dict(label="▶ play", method="animate",
                                        args=[None, dict(frame=dict(duration=80, redraw=True), fromcurrent=True,
                                                         mode="immediate", transition=dict(duration=0))]),
                                   dict(label="❚❚ pause", method="animate",
                                        args=[[None], dict(frame=dict(duration=0, redraw=False), mode="immediate")])])],
        sliders=[dict(active=first, x=0.18, y=0.02, len=0.8, currentvalue=dict(prefix=f"{anim.axis_label}: "),
                      steps=[dict(method="animate", label=lab[i],
                                  args=[[str(i)], dict(mode="immediate", frame=dict(duration=0, redraw=True))])
                             for i in range(anim.n)])])
    return fig


def html_fragment(fig, include_plotlyjs=True, div_id: str | None = None) -> str:
    """The figure as an HTML ``<div>`` (plotly.js inlined when ``include_plotlyjs``)."""
    return fig.to_html(include_plotlyjs=include_plotlyjs, full_html=False, div_id=div_id,
                       config={"displaylogo": False})


def write_html(fig, path, title: str = "") -> None:
    """A self-contained page (plotly.js inlined: it opens without network access)."""
    from pathlib import Path
    text = fig.to_html(include_plotlyjs=True, full_html=True, config={"displaylogo": False})
    if title:
        import html
        text = text.replace("<head>", f"<head><title>{html.escape(title)}</title>", 1)
    Path(path).write_text(text, encoding="utf-8")


# -- matplotlib ---------------------------------------------------------------------------------------
def _draw3d(ax, plan, sw, positions, lo, hi, units: str = "file"):
    k = file_scale(plan, units)
    st = sw.state
    pos = st.pos * k
    for c, pi in enumerate(_moving_points(plan)):
        col = COLORS[c % len(COLORS)]
        path = closed(pos[:, pi], sw.cyclic)
        ax.plot(path[:, 0], path[:, 1], path[:, 2], color=col, lw=1.6, label=f"path of {plan.point_names[pi]}")
        for axis in range(3):
            proj = path.copy()
            proj[:, axis] = lo[axis]
            ax.plot(proj[:, 0], proj[:, 1], proj[:, 2], color=col, lw=0.8, ls=":", alpha=0.7)
    idx = np.unique(np.linspace(0, sw.n - 1, positions, endpoint=not sw.cyclic).round().astype(int))
    for j, i in enumerate(idx):
        if st.valid[i]:
            for poly in link_polylines(plan, st.pos[i], units):
                ax.plot(poly[:, 0], poly[:, 1], poly[:, 2], color="0.25", lw=2.0, alpha=0.25 + 0.5 * (j == 0),
                        marker="o", ms=2.5)
    for p, seg in axis_segments(plan, units=units):
        ax.plot(seg[:, 0], seg[:, 1], seg[:, 2], color="0.5", lw=1.0, ls="--")
    unit = length_unit(plan, units)
    ax.set_xlabel(f"x [{unit}]")
    ax.set_ylabel(f"y [{unit}]")
    ax.set_zlabel(f"z [{unit}]")
    ax.set_xlim(lo[0], hi[0])
    ax.set_ylim(lo[1], hi[1])
    ax.set_zlim(lo[2], hi[2])
    ax.set_box_aspect((1, 1, 1))


def figure(plan, steps: int = CYCLE_STEPS, *, positions: int = 6, params=None, ranges=None, dpi: int = 100,
           sweep=None, units: str = "file"):
    """A static figure: the 3D view (positions, paths, projections) and, per R–S–S dyad, the rocker
    angle θ4 and the transmission angles μ_int, μ_T over the sweep. ``sweep``: the solved run to draw
    (default: :func:`~assur.plot.figures.sample` of ``steps`` over one turn or ``ranges``)."""
    _, plt = mpl()
    from ..analysis.spatial import dyads, mu_int, mu_t, rocker_angle
    if sweep is None:
        study = study_of(plan, params, steps, ranges)
        plan, params, sweep = study.plan, study.params, study.sweep
    sw = sweep
    pos = sw.state.pos * file_scale(plan, units)
    if not np.isfinite(pos).any():
        raise SpecError([("mechanism", "no position of the sweep can be assembled: nothing to draw")])
    lo, hi = _planes(pos.reshape(-1, 3))
    fig = plt.figure(figsize=(12, 6), dpi=dpi)
    ax = fig.add_subplot(1, 2, 1, projection="3d")
    _draw3d(ax, plan, sw, positions, lo, hi, units)
    ax.view_init(elev=20, azim=-60, vertical_axis="y")
    ax.legend(fontsize=7, loc="upper left")
    fig.suptitle(plan.mechanism.name or "spatial mechanism", fontsize=11)
    gs = fig.add_gridspec(2, 2)
    a1 = fig.add_subplot(gs[0, 1])
    a2 = fig.add_subplot(gs[1, 1], sharex=a1)
    for c, g in enumerate(dyads(plan, sw.state, params)):
        th = rocker_angle(g)
        ok = np.isfinite(th)
        thu = np.full_like(th, np.nan)
        thu[ok] = np.unwrap(th[ok])
        a1.plot(sw.axis, np.degrees(thu), color=COLORS[c], label=f"θ4 of {g.rocker} ({g.point})")
        a2.plot(sw.axis, np.degrees(mu_int(g)), color=COLORS[c], label=f"μ_int at {g.point}")
        a2.plot(sw.axis, np.degrees(mu_t(g)), color=COLORS[c], ls="--", label=f"μ_T at {g.point}")
    a1.set_ylabel("rocker angle [°]")
    a2.set_ylabel("transmission angle [°]")
    a2.set_xlabel(sw.axis_label)
    for a in (a1, a2):
        a.grid(True, alpha=0.3)
        a.legend(fontsize=8)
    fig.tight_layout(rect=(0, 0, 1, 0.95))
    return fig


def animation(plan, frames: int = 60, fps: float = 20.0, *, params=None, ranges=None, figsize=(6.4, 6.4),
              dpi: int = 100, path=None, units: str = "file"):
    """A matplotlib 3D animation of ``frames`` positions over one turn with the traced paths; ``path``: the
    solved run the paths are drawn from (default :data:`~assur.analysis.sampling.CYCLE_STEPS` samples of
    the same run). Returns ``(figure, animation)``."""
    fps = frame_rate(fps)
    _, plt = mpl()
    from matplotlib.animation import FuncAnimation
    study = study_of(plan, params, CYCLE_STEPS, ranges)
    plan, params = study.plan, study.params
    sw = study.frame_sweep(frames)
    dense = path if path is not None else study.sweep
    k = file_scale(plan, units)
    pos = dense.state.pos * k
    if not np.isfinite(pos).any():
        raise SpecError([("mechanism", "no position of the sweep can be assembled: nothing to draw")])
    lo, hi = _planes(pos.reshape(-1, 3))
    fig = plt.figure(figsize=figsize, dpi=dpi)
    ax = fig.add_subplot(projection="3d")
    _draw3d(ax, plan, dense, 0, lo, hi, units)   # paths and projections; the moving links are drawn per frame
    ax.view_init(elev=20, azim=-60, vertical_axis="y")
    lines = [ax.plot([], [], [], color="tab:blue", lw=2.5, marker="o", ms=4)[0]
             for _ in link_polylines(plan, dense.state.pos[0], units)]
    info = ax.text2D(0.02, 0.97, "", transform=ax.transAxes, va="top", fontsize=9)

    def update(i):
        st = sw.state
        polys = link_polylines(plan, st.pos[i], units) if st.valid[i] else [np.empty((0, 3))] * len(lines)
        for ln, p in zip(lines, polys):
            ln.set_data(p[:, 0], p[:, 1])
            ln.set_3d_properties(p[:, 2])
        status = "" if st.valid[i] else "  (cannot be assembled)"
        info.set_text(f"{plan.input_names[sw.moving]} = {sw.axis[i]:.0f}°{status}"
                      if plan.input_kinds[sw.moving] == "rotary" else f"{sw.axis[i]:.4g}{status}")
        return lines + [info]

    anim = FuncAnimation(fig, update, frames=sw.n, interval=1000.0 / float(fps), blit=False, repeat=True)
    return fig, anim


__all__ = ["plotly_figure", "write_html", "html_fragment", "figure", "animation", "link_polylines"]
