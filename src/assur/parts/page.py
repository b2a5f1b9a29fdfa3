"""The parts page (offline plotly, as :mod:`assur.plot.spatial`): the layer chart, the exploded assembly in 3D, the
assembly moving over the run, the clearance over the run of the tightest pairs, the minimality certificate and the
bill of materials. :func:`report_section` gives the same as an HTML fragment for ``assur report``.
"""
from __future__ import annotations

import html

import numpy as np

from .api import LAYERED

MM = 1000.0
#: frames of the moving assembly, and pairs in the clearance figure
FRAMES = 48
TIGHTEST = 8
COLORS = {"plate": "#4c78a8", "gear": "#f58518", "block": "#54a24b", "cylinder": "#b279a2", "rod": "#9d755d",
          "pin": "#555555", "washer": "#bab0ac", "base": "#d0d0d0", "top": "#d0d0d0", "standoff": "#999999",
          "motor_mount": "#e45756"}
#: the layered parts are coloured by their layer
LAYER_COLORS = ("#4c78a8", "#f58518", "#54a24b", "#b279a2", "#e45756", "#72b7b2", "#eeca3b", "#9d755d", "#ff9da6",
                "#79706e")


def color_of(part) -> str:
    if part.kind in LAYERED and isinstance(part.layer, int) and part.layer >= 0:
        return LAYER_COLORS[part.layer % len(LAYER_COLORS)]
    return COLORS[part.kind]


def _triangles(ring: np.ndarray) -> np.ndarray:
    """(t, 3) vertex indices of a triangulation of the simple polygon ``ring`` (k, 2)."""
    import shapely
    poly = shapely.Polygon(ring)
    if hasattr(shapely, "constrained_delaunay_triangles"):
        tris = shapely.get_parts(shapely.constrained_delaunay_triangles(poly))
    else:      # pragma: no cover - shapely < 2.1
        tris = [t for t in shapely.get_parts(shapely.delaunay_triangles(poly)) if poly.contains(t.centroid)]
    index = {(float(x), float(y)): i for i, (x, y) in enumerate(ring)}
    out = []
    for t in tris:
        c = np.asarray(t.exterior.coords)[:3]
        try:
            out.append([index[(float(x), float(y))] for x, y in c])
        except KeyError:
            continue
    return np.asarray(out, dtype=int).reshape(-1, 3)


def prism(ring: np.ndarray):
    """(i, j, k) index arrays of the closed prism over ``ring`` (k, 2): bottom vertices 0..k−1, top k..2k−1."""
    k = len(ring)
    cap = _triangles(ring)
    side = [[a, (a + 1) % k, k + a] for a in range(k)] + [[(a + 1) % k, k + (a + 1) % k, k + a] for a in range(k)]
    faces = np.vstack([cap[:, ::-1], cap + k, np.asarray(side)])
    return faces[:, 0], faces[:, 1], faces[:, 2]


def _ring(part) -> np.ndarray:
    import shapely
    region = part.shape.region()
    region = shapely.Polygon(region.simplify(0.05 * max(part.thickness, 1e-4)).exterior)
    ring = np.asarray(region.exterior.coords)[:-1]
    return ring


def _scale(result):
    """(the length unit's name, its factor from m) for the figures: the file's length unit."""
    from ..io.units import LENGTH
    u = result.mechanism.units.length
    return u, 1.0 / LENGTH[u]


def _list(a):
    return np.round(np.asarray(a, dtype=float), 4).tolist()


def layer_chart(result) -> dict:
    """A bar chart of every part's height range, by kind (a plotly figure as a dict)."""
    data = []
    for kind in COLORS:
        ps = [p for p in result.parts if p.kind == kind]
        if not ps:
            continue
        data.append(dict(type="bar", y=[p.name for p in ps], x=_list([(p.z[1] - p.z[0]) * MM for p in ps]),
                         base=_list([p.z[0] * MM for p in ps]), orientation="h", name=kind,
                         marker=dict(color=COLORS[kind]),
                         customdata=[[str(p.layer), p.body_name] for p in ps],
                         hovertemplate="%{y}: z from %{base:.2f} mm, %{x:.2f} mm thick; layer %{customdata[0]}, "
                                       "moves with %{customdata[1]}<extra></extra>"))
    layout = dict(title=dict(text=f"{result.layers} layers: every part's height (mm)"), barmode="overlay",
                  xaxis=dict(title=dict(text="z [mm]")), yaxis=dict(automargin=True),
                  height=max(320, 18 * len(result.parts) + 120),
                  margin=dict(l=10, r=10, t=40, b=40))
    return dict(data=data, layout=layout)


def _mesh_of(result, part, meshes: bool):
    """(vertices (v, 3) at the sketch pose in mm, (i, j, k)) of a part: its tessellated solid or its prism."""
    if meshes:
        v, t = result.meshes()[part.name]
        return v, (t[:, 0], t[:, 1], t[:, 2])
    ring = result.frames.at_sketch(part.body, _ring(part)) * MM
    z0, z1 = part.z[0] * MM, part.z[1] * MM
    v = np.vstack([np.column_stack([ring, np.full(len(ring), z0)]), np.column_stack([ring, np.full(len(ring), z1)])])
    return v, prism(ring)


def _mesh_trace(v, ijk, name, color, **extra) -> dict:
    i, j, k = ijk
    return dict(type="mesh3d", x=_list(v[:, 0]), y=_list(v[:, 1]), z=_list(v[:, 2]), i=np.asarray(i).tolist(),
                j=np.asarray(j).tolist(), k=np.asarray(k).tolist(), name=name, color=color, flatshading=True,
                **extra)


def _scene(result, factor: float) -> dict:
    """A 3D scene holding the whole assembly over the run: x, y to scale, z stretched to a third of the width."""
    zs = np.array([p.z for p in result.parts]) * MM
    base = next((p for p in result.parts if p.kind == "base"), None)
    ring = result.frames.at_sketch(0, base.shape.polygons[0]) * MM if base is not None else np.zeros((1, 2))
    lo, hi = ring.min(axis=0), ring.max(axis=0)
    zlo, zhi = float(zs.min()) * factor, float(zs.max()) * factor
    span = max(hi - lo)
    return dict(aspectmode="manual", aspectratio=dict(x=(hi[0] - lo[0]) / span, y=(hi[1] - lo[1]) / span, z=0.35),
                xaxis=dict(title=dict(text="x [mm]"), range=[float(lo[0]), float(hi[0])]),
                yaxis=dict(title=dict(text="y [mm]"), range=[float(lo[1]), float(hi[1])]),
                zaxis=dict(title=dict(text="z [mm]"), range=[zlo, zhi]),
                camera=dict(eye=dict(x=0.35, y=-1.35, z=1.1)))


def exploded_view(result, meshes: bool = True) -> dict:
    """The assembly at the sketch pose, its layers pulled apart (each part's height times a factor)."""
    size = result.mechanism.length_scale * MM
    factor = max(1.0, 0.06 * size / (result.settings.pitch * MM))
    data = []
    for p in result.parts:
        v, ijk = _mesh_of(result, p, meshes)
        v = v.copy()
        v[:, 2] += (factor - 1.0) * 0.5 * (p.z[0] + p.z[1]) * MM
        data.append(_mesh_trace(v, ijk, p.name, color_of(p), opacity=0.55 if p.kind in ("base", "top") else 1.0,
                                hovertemplate=f"{p.name} (layer {p.layer})<extra></extra>", showlegend=False))
    layout = dict(title=dict(text=f"exploded assembly (heights × {factor:.0f}; mm)"), scene=_scene(result, factor),
                  height=650,
                  margin=dict(l=0, r=0, t=40, b=0))
    return dict(data=data, layout=layout)


def moving_assembly(result, frames: int = FRAMES) -> dict:
    """The assembly (each part as the prism of its footprint) moving over the run: a play button and a slider."""
    F = result.frames
    idx = np.unique(np.linspace(0, F.n - 1, min(frames, F.n)).round().astype(int))
    moving = [p for p in result.parts if p.body != 0]
    static = [p for p in result.parts if p.body == 0]
    shapes = {}
    for p in moving:
        ring = _ring(p)
        shapes[p.name] = (ring, prism(ring))

    def trace(p, i, full=True):
        ring, ijk = shapes[p.name]
        w = F.to_world(p.body, ring, F.origin[i:i + 1, p.body], F.angle[i:i + 1, p.body])[0] * MM
        v = np.vstack([np.column_stack([w, np.full(len(w), p.z[0] * MM)]),
                       np.column_stack([w, np.full(len(w), p.z[1] * MM)])])
        if not full:        # a frame only moves the vertices
            return dict(type="mesh3d", x=_list(v[:, 0]), y=_list(v[:, 1]), z=_list(v[:, 2]))
        return _mesh_trace(v, ijk, p.name, color_of(p), hovertemplate=f"{p.name}<extra></extra>")
    data = [trace(p, idx[0]) for p in moving]
    for p in static:
        v, ijk = _mesh_of(result, p, False)
        data.append(_mesh_trace(v, ijk, p.name, COLORS[p.kind], opacity=0.35, hoverinfo="skip"))
    labels = [result.input_text(F.q[i]) for i in idx]
    fr = [dict(data=[trace(p, i, False) for p in moving], traces=list(range(len(moving))), name=str(n))
          for n, i in enumerate(idx)]
    layout = dict(
        title=dict(text="the assembly over the run"), height=650, margin=dict(l=0, r=0, t=40, b=0),
        scene=_scene(result, 1.0),
        updatemenus=[dict(type="buttons", showactive=False, x=0.02, y=0.02, xanchor="left", yanchor="bottom",
                          buttons=[dict(label="▶ play", method="animate",
                                        args=[None, dict(frame=dict(duration=80, redraw=True), fromcurrent=True,
                                                         mode="immediate", transition=dict(duration=0))]),
                                   dict(label="❚❚ pause", method="animate",
                                        args=[[None], dict(frame=dict(duration=0, redraw=False), mode="immediate")])])],
        sliders=[dict(active=0, x=0.18, y=0.02, len=0.8, currentvalue=dict(prefix="input: "),
                      steps=[dict(method="animate", label=labels[n],
                                  args=[[str(n)], dict(mode="immediate", frame=dict(duration=0, redraw=True))])
                             for n in range(len(idx))])])
    return dict(data=data, layout=layout, frames=fr)


def tightest_pairs(result, count: int = TIGHTEST):
    """The ``count`` pairs that matter (two parts of one layer; a pin and a part in a layer it crosses) with the
    least certified gaps, each with its exact distance (m) at every sample: [(verdict, distances (n,))]."""
    from .conflicts import _distances, frame_arrays, items_of
    layer = {p.name: p.layer for p in result.parts}
    relevant = []
    for v in result.conflicts.parts:
        if layer.get(v.a) == layer.get(v.b):
            relevant.append(v)
    for v in result.conflicts.pins:
        lo, hi = layer[v.a]
        if lo < layer[v.b] < hi:
            relevant.append(v)
    relevant.sort(key=lambda v: v.gap)
    chosen = relevant[:count]
    F = frame_arrays(result.frames)
    items = {it.name: it for it in items_of([p for p in result.parts if p.kind in LAYERED or p.kind == "pin"])}
    out = []
    for v in chosen:
        d = _distances(F, items[v.a], items[v.b], np.ones(result.frames.n, bool))
        out.append((v, d))
    return out


def clearance_figure(result, pairs) -> dict:
    from ..io.units import ANGLE, LENGTH
    F = result.frames
    rotary = result.plan.input_kinds[0] == "rotary"
    u = result.mechanism.units
    x = F.q / (ANGLE[u.angle] if rotary else LENGTH[u.length])
    data = [dict(type="scatter", x=_list(x), y=_list(d * MM), mode="lines", name=f"{v.a} – {v.b}",
                 hovertemplate="%{y:.3f} mm<extra>" + html.escape(f"{v.a} – {v.b}") + "</extra>") for v, d in pairs]
    c = result.settings.clearance * MM
    data.append(dict(type="scatter", x=[float(x[0]), float(x[-1])], y=[c, c], mode="lines", name="clearance",
                     line=dict(color="#c00", dash="dash")))
    layout = dict(title=dict(text="clearance over the run of the tightest pairs that share a layer (mm)"),
                  xaxis=dict(title=dict(text=f"input [{u.angle if rotary else u.length}]")),
                  yaxis=dict(title=dict(text="distance [mm]"), rangemode="tozero", automargin=True), height=420,
                  margin=dict(l=10, r=10, t=40, b=40))
    return dict(data=data, layout=layout)


def figure_html(fig: dict, include_plotlyjs) -> str:
    """A plotly figure (a dict) as an HTML ``<div>`` (plotly.js inlined when ``include_plotlyjs``)."""
    import plotly.io as pio
    return pio.to_html(fig, include_plotlyjs=include_plotlyjs, full_html=False, validate=False,
                       config={"displaylogo": False})


def _table(rows, header=True) -> str:
    out = ["<table class='parts'>"]
    for n, row in enumerate(rows):
        tag = "th" if header and n == 0 else "td"
        out.append("<tr>" + "".join(f"<{tag}>{html.escape(str(c))}</{tag}>" for c in row) + "</tr>")
    out.append("</table>")
    return "\n".join(out)


def certificate_html(result) -> str:
    c = result.certificate
    conf = result.conflicts
    rows = [("layers", c.layers), ("lower bound (maximum clique of the conflict graph)", c.bound),
            ("clique", "; ".join(" + ".join(g) for g in c.clique)),
            ("HiGHS status (fewest layers)", c.status), ("proven lower bound", f"{c.dual_bound:g}"),
            ("gap", f"{100 * c.gap:.1f} %"),
            ("no layout with one layer fewer (exhaustive search)",
             "not run" if c.exhaustive is None else ("verified" if c.exhaustive else "NOT verified")),
            ("proven minimal", "yes" if c.proven else "no"),
            ("pairs checked over the run", len(conf.all())), ("pairs in conflict", sum(v.conflict for v in conf.all())),
            ("intervals refined between samples", sum(v.refined for v in conf.all())),
            ("samples of the run", result.frames.n), ("clearance", f"{result.settings.clearance * MM:g} mm")]
    return _table([("", "")] + [(k, v) for k, v in rows], header=False)


def section_html(result, *, meshes: bool = True, include_plotlyjs=True) -> str:
    """The page's body: headings, figures and tables (an HTML fragment)."""
    from .bom import bom_rows
    figs = [("Layers", layer_chart(result)), ("Exploded assembly", exploded_view(result, meshes)),
            ("The assembly over the run", moving_assembly(result))]
    pairs = tightest_pairs(result)
    if pairs:
        figs.append(("Clearance", clearance_figure(result, pairs)))
    parts = []
    first = include_plotlyjs
    for title, fig in figs:
        parts.append(f"<h2>{html.escape(title)}</h2>")
        parts.append(figure_html(fig, first))
        first = False
    parts.append("<h2>Minimality certificate</h2>")
    parts.append(certificate_html(result))
    parts.append("<h2>Bill of materials</h2>")
    parts.append(_table(bom_rows(result, masses=meshes)))
    return "\n".join(parts)


STYLE = ("<style>body{font-family:sans-serif;margin:1.5em;max-width:1200px}table.parts{border-collapse:collapse;"
         "font-size:90%}table.parts td,table.parts th{border:1px solid #ccc;padding:2px 6px;text-align:left}</style>")


def write_page(result, path, *, meshes: bool = True) -> None:
    """The self-contained page (plotly.js inlined: it opens without network access)."""
    from pathlib import Path
    title = html.escape(f"{result.mechanism.name or 'mechanism'}: parts")
    body = section_html(result, meshes=meshes)
    Path(path).write_text(f"<!DOCTYPE html><html><head><meta charset='utf-8'><title>{title}</title>{STYLE}</head>"
                          f"<body><h1>{title}</h1>\n{body}\n</body></html>\n", encoding="utf-8")


def report_section(cycle, *, include_plotlyjs=True) -> str:
    """The parts section of ``assur report`` for a mechanism file with a ``[make]`` table: the HTML fragment of
    the page, from the solved ``cycle`` (solids and masses when build123d is installed, footprints otherwise)."""
    from .api import make_parts
    result = cycle.parts if hasattr(type(cycle), "parts") else make_parts(cycle)   # a Study keeps its parts
    try:
        from .solids import require_make
        require_make()
        meshes = True
    except ImportError:
        meshes = False
    head = "" if meshes else ("<p>Footprints only: install the CAD packages for solids and masses "
                              "(<code>pip install 'assur[make]'</code>).</p>")
    return head + section_html(result, meshes=meshes, include_plotlyjs=include_plotlyjs)


__all__ = ["clearance_figure", "exploded_view", "layer_chart", "moving_assembly", "prism", "report_section",
           "section_html", "tightest_pairs", "write_page"]
