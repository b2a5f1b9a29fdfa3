"""CAD and table outputs: closed outlines as DXF (ezdxf) and SVG, in millimetres; tables as CSV and JSON.

Outlines are (M, 2) closed polygons in metres (the first point not repeated); files carry them in mm. Each DXF holds
one closed LWPOLYLINE per outline on its own layer, a centre mark (cross and small circle) per outline, optional
reference curves (pitch curves, as open or closed polylines on the layer ``PITCH``), ``$INSUNITS`` = 4 (mm) and the
parameters as header custom properties. Each SVG is plain XML with a ``viewBox`` in mm, one ``<path>`` per outline
(``fill-rule="evenodd"``), centre marks, and the parameters in ``<metadata>`` (JSON). ezdxf is imported lazily.
All files are written through :func:`assur.io.output.atomic_file`.
"""
from __future__ import annotations

import json
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from ..errors import SpecError
from .output import atomic_file, json_text, write_csv

MM = 1e3


@dataclass(frozen=True)
class Shape:
    """One outline to export: name (layer), closed polygon xy (M, 2) in m, its centre (2,) in m, optional
    reference curves (each (K, 2), m, closed) and an optional bore diameter (m; a circle about the centre, on the
    layer ``BORE`` in DXF, a ``class="bore"`` circle in SVG)."""

    name: str
    xy: np.ndarray
    centre: tuple = (0.0, 0.0)
    references: tuple = field(default=())
    bore: float | None = None


def _check(shape: Shape) -> np.ndarray:
    xy = np.asarray(shape.xy, dtype=float)
    if xy.ndim != 2 or xy.shape[1] != 2 or xy.shape[0] < 3 or not np.all(np.isfinite(xy)):
        raise SpecError(f"outline {shape.name!r} must be a finite (M ≥ 3, 2) polygon: shape {xy.shape}")
    return xy


def _layer(name: str) -> str:
    return "".join(c if c.isalnum() or c in "_-" else "_" for c in name.upper()) or "OUTLINE"


def _fast_points_class():
    """An ezdxf LWPOLYLINE vertex array that exports its (x, y) vertices as one block of text (the plain
    per-vertex export of ezdxf costs ~30 µs a vertex: seconds for the gear outlines), or None when this ezdxf
    does not have the expected internals (then the plain export is used)."""
    global _FAST_POINTS
    if _FAST_POINTS is not False:
        return _FAST_POINTS
    try:
        from ezdxf.entities.lwpolyline import LWPolylinePoints

        class _Block:
            __slots__ = ("code", "value", "_text")

            def __init__(self, text):
                self.code, self.value, self._text = 10, None, text

            def dxfstr(self):
                return self._text

        class FastPoints(LWPolylinePoints):
            __slots__ = ()

            def dxftags(self):
                v = np.frombuffer(self.values, dtype=float).reshape(-1, 5)
                if np.any(v[:, 2:]):               # widths or bulges: the plain export
                    yield from super().dxftags()
                    return
                yield _Block((" 10\n%r\n 20\n%r\n" * v.shape[0]) % tuple(v[:, :2].ravel().tolist()))

        _FAST_POINTS = FastPoints
    except Exception:  # noqa: BLE001 - any other ezdxf: the plain export
        _FAST_POINTS = None
    return _FAST_POINTS


_FAST_POINTS = False


def _add_polyline(msp, xy, layer):
    """A closed LWPOLYLINE through xy (M, 2) (mm), all vertices set at once."""
    e = msp.add_lwpolyline([], format="xy", close=True, dxfattribs={"layer": layer})
    fast = _fast_points_class()
    if fast is None:
        e.set_points([tuple(p) for p in xy], format="xy")
        return e
    import array
    pts = fast()
    flat = np.zeros((xy.shape[0], 5))
    flat[:, :2] = xy
    pts.values = array.array("d")
    pts.values.frombytes(np.ascontiguousarray(flat).tobytes())
    e.lwpoints = pts
    return e


def write_dxf(path, shapes, *, metadata: dict | None = None, mark: float = 2.0) -> Path:
    """Write shapes to a DXF (R2010, mm): closed LWPOLYLINE per outline, centre marks of ``mark`` mm, the bore
    circle (when the shape has one) on the layer ``BORE``."""
    try:
        import ezdxf
    except ImportError as exc:  # pragma: no cover - ezdxf is an extra
        raise ImportError("DXF output needs ezdxf: pip install 'assur[cad]' (or pip install ezdxf)") from exc
    doc = ezdxf.new("R2010")
    doc.units = ezdxf.units.MM
    doc.header["$INSUNITS"] = 4
    msp = doc.modelspace()
    doc.layers.add("CENTRE", color=1)
    doc.layers.add("PITCH", color=8)
    for i, s in enumerate(shapes):
        xy = _check(s) * MM
        layer = _layer(s.name)
        if layer not in doc.layers:
            doc.layers.add(layer, color=(5 + 2 * i) % 255 or 7)
        _add_polyline(msp, xy, layer)
        cx, cy = (float(c) * MM for c in s.centre)
        msp.add_line((cx - mark, cy), (cx + mark, cy), dxfattribs={"layer": "CENTRE"})
        msp.add_line((cx, cy - mark), (cx, cy + mark), dxfattribs={"layer": "CENTRE"})
        msp.add_circle((cx, cy), mark / 4, dxfattribs={"layer": "CENTRE"})
        if s.bore:
            if "BORE" not in doc.layers:
                doc.layers.add("BORE", color=3)
            msp.add_circle((cx, cy), 0.5 * float(s.bore) * MM, dxfattribs={"layer": "BORE"})
        for ref in s.references:
            _add_polyline(msp, np.asarray(ref, dtype=float) * MM, "PITCH")
    for k, v in (metadata or {}).items():
        doc.header.custom_vars.append(str(k), str(v))
    path = Path(path)
    with atomic_file(path) as tmp:
        doc.saveas(tmp)
    return path


def svg_text(shapes, *, metadata: dict | None = None, margin: float = 5.0, mark: float = 2.0) -> str:
    """The SVG document (mm; y up in the drawing, i.e. flipped into SVG's y-down frame) as a string."""
    from xml.sax.saxutils import escape
    pts = [_check(s) * MM for s in shapes]
    allp = np.concatenate(pts + [np.asarray([s.centre], dtype=float) * MM for s in shapes])
    lo = allp.min(axis=0) - margin
    hi = allp.max(axis=0) + margin
    w, h = hi - lo

    def tr(p):      # drawing (x, y up) → SVG (x, y down)
        return p[:, 0] - lo[0], hi[1] - p[:, 1]

    out = ['<?xml version="1.0" encoding="UTF-8"?>',
           f'<svg xmlns="http://www.w3.org/2000/svg" width="{w:.4f}mm" height="{h:.4f}mm" '
           f'viewBox="0 0 {w:.6f} {h:.6f}">']
    out.append(f"<metadata>{escape(json.dumps(metadata or {}, ensure_ascii=False))}</metadata>")
    for s, p in zip(shapes, pts):
        x, y = tr(p)
        d = _svg_path(x, y)
        out.append(f'<path id="{escape(_layer(s.name).lower())}" d="{d}" fill="none" stroke="black" '
                   f'stroke-width="0.1" fill-rule="evenodd"/>')
        for j, ref in enumerate(s.references):
            rx, ry = tr(np.asarray(ref, dtype=float) * MM)
            d = _svg_path(rx, ry)
            out.append(f'<path class="pitch" d="{d}" fill="none" stroke="gray" stroke-width="0.05" '
                       f'stroke-dasharray="1,1"/>')
        cx, cy = tr(np.asarray([s.centre], dtype=float) * MM)
        cx, cy = float(cx[0]), float(cy[0])
        if s.bore:
            out.append(f'<circle class="bore" cx="{cx:.6f}" cy="{cy:.6f}" r="{0.5 * float(s.bore) * MM:.6f}" '
                       f'fill="none" stroke="blue" stroke-width="0.1"/>')
        out.append(f'<g class="centre" stroke="red" stroke-width="0.05"><line x1="{cx - mark:.4f}" y1="{cy:.4f}" '
                   f'x2="{cx + mark:.4f}" y2="{cy:.4f}"/><line x1="{cx:.4f}" y1="{cy - mark:.4f}" x2="{cx:.4f}" '
                   f'y2="{cy + mark:.4f}"/></g>')
    out.append("</svg>")
    return "\n".join(out) + "\n"


def _svg_path(x, y) -> str:
    """The SVG path data "M x,y L x,y … Z" of the closed polyline (x (K,), y (K,)), mm to 6 decimals."""
    xy = np.column_stack([x, y]).ravel().tolist()
    return "M " + " L ".join(["%.6f,%.6f"] * (len(xy) // 2)) % tuple(xy) + " Z"


def write_svg(path, shapes, *, metadata: dict | None = None) -> Path:
    path = Path(path)
    text = svg_text(shapes, metadata=metadata)
    with atomic_file(path) as tmp:
        tmp.write_text(text, encoding="utf-8")
    return path


def write_json(path, data) -> Path:
    path = Path(path)
    with atomic_file(path) as tmp:
        tmp.write_text(json_text(data) + "\n",
                       encoding="utf-8")
    return path


def write_outline_csv(path, xy, *, comments: dict | None = None) -> Path:
    """The closed outline xy (M, 2) (m) as CSV in mm: ``# key: value`` comment lines (``comments``, e.g. the face
    width and the bore), then the header ``x [mm],y [mm]`` and one row per vertex."""
    path = Path(path)
    xy = np.asarray(xy, dtype=float) * MM
    lines = [f"# {k}: {v}" for k, v in (comments or {}).items()]
    lines.append("x [mm],y [mm]")
    text = "".join(line + "\r\n" for line in lines) + ("%r,%r\r\n" * xy.shape[0]) % tuple(xy.ravel().tolist())
    with atomic_file(path) as tmp:
        with open(tmp, "w", encoding="utf-8", newline="") as fh:
            fh.write(text)
    return path


def write_table(base, header, rows, *, meta: dict | None = None) -> tuple[Path, Path]:
    """A table as ``base.csv`` and ``base.json`` (``{"columns": [...], "rows": [[...]], **meta}``)."""
    base = Path(base)
    a = write_csv(base.with_suffix(".csv"), header, rows)
    b = write_json(base.with_suffix(".json"), {**(meta or {}), "columns": list(header),
                                                "rows": [list(r) for r in rows]})
    return a, b


__all__ = ["Shape", "svg_text", "write_csv", "write_dxf", "write_json", "write_outline_csv", "write_svg",
           "write_table"]
