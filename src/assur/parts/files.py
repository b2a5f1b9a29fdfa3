"""The files ``assur make`` writes into its output directory (all in mm):

- ``stl/NAME.stl`` and ``3mf/NAME.3mf``: every part flat (as printed or cut), centred on the origin;
- ``assembly.step``: the assembly (STEP AP214), every part a named solid at its body's sketch pose and height;
- ``parts.json``: ``{"parts": [...]}``, each part with ``name``, ``link`` (the body it moves with, or ``frame``)
  or ``joint`` and ``holds`` (a pin and its washers and sleeves), ``layer``, ``z`` ([z_min, z_max]), ``stl`` and
  ``outline`` (its footprint at the sketch pose, sketch frame);
- ``certificate.json``: the settings, the layer count and why it is minimal, and every conflict verdict;
- ``bom.csv``: the bill of materials;
- ``parts.html``: the page (:mod:`assur.parts.page`).
"""
from __future__ import annotations

import csv
import math
from pathlib import Path

import numpy as np

from .api import LAYERED

MM = 1000.0


def _round(x, digits=6):
    return float(round(float(x), digits))


def parts_json(result, stl: bool = True) -> dict:
    """The ``parts.json`` document of ``result`` (:class:`~assur.parts.api.Parts`)."""
    out = []
    for p in result.parts:
        entry = {"name": p.name}
        if p.kind in ("pin", "washer"):
            entry["joint"] = p.joint
            entry["holds"] = list(p.holds)
        else:
            entry["link"] = p.body_name
        entry["layer"] = p.layer if isinstance(p.layer, int) else [int(v) for v in p.layer]
        entry["z"] = [_round(p.z[0] * MM), _round(p.z[1] * MM)]
        entry["stl"] = f"stl/{p.name}.stl" if stl else None
        ring = np.asarray(p.shape.region().exterior.coords)[:-1]
        entry["outline"] = [[_round(x * MM), _round(y * MM)] for x, y in result.frames.at_sketch(p.body, ring)]
        out.append(entry)
    return {"parts": out}


def certificate_json(result) -> dict:
    """The settings, the certificate and the conflict verdicts (SI)."""
    c = result.conflicts

    def verdicts(vs):
        return [{"a": v.a, "b": v.b, "conflict": bool(v.conflict), "certified_gap": float(v.gap),
                 "least_sampled_distance": float(v.sampled), "at_input": float(v.at),
                 "refined_intervals": int(v.refined)} for v in vs]
    return {"mechanism": result.mechanism.name, "units": "SI (m, kg)", "settings": result.settings.as_dict(),
            "layers": result.layers, "certificate": result.certificate.as_dict(),
            "samples": int(result.frames.n), "clearance": c.clearance,
            "layer_of": result.layer_of(),
            "conflicts": {"parts": verdicts(c.parts), "pin_parts": verdicts(c.pins), "pins": verdicts(c.pin_pairs)}}


def bom_rows(result, masses: bool = True) -> list[list]:
    """The bill of materials: made parts one row each, dowels and washers grouped by size, the motor."""
    s = result.settings
    mass = result.mass() if masses else {}
    header = ["part", "kind", "quantity", "material", "thickness [mm]", "mass [g]", "size", "file"]
    rows, groups = [header], {}
    for p in result.parts:
        g = mass[p.name].mass * 1e3 if p.name in mass else math.nan
        if p.kind == "pin":
            d = 2 * p.shape.hulls[0][0][2] - s.shaft_allowance
            label = "motor shaft (the motor's own)" if p.name.startswith("shaft_") else "dowel pin ISO 8734"
            key = (label, round(d * MM, 3), round(p.thickness * MM, 1))
            groups.setdefault(key, []).append((p, g))
            continue
        if p.kind == "washer" and p.material == "steel":
            key = ("washer DIN 125-A", round(s.pin * MM, 3), round(p.thickness * MM, 2))
            groups.setdefault(key, []).append((p, g))
            continue
        size = _size(p, s)
        rows.append([p.name, p.kind, 1, p.material, _round(p.thickness * MM, 3),
                     "" if math.isnan(g) else _round(g, 3), size, f"stl/{p.name}.stl"])
    for (label, d, length), members in groups.items():
        names = " ".join(p.name for p, _ in members)
        total = sum(g for _, g in members)
        size = f"⌀{d:g} × {length:g} mm" if "washer" not in label else f"M{d:g} ⌀{s.washer_od * MM:g} × {length:g} mm"
        rows.append([names, label, len(members), "steel", length, "" if math.isnan(total) else _round(total, 3),
                     size, ""])
    if result.design.driver is not None:
        rows.append(["motor", "NEMA 17 motor (bought)", 1, "", "", "", f"shaft ⌀{s.shaft * MM:g} mm", ""])
    return rows


def _size(p, s) -> str:
    ring = np.asarray(p.shape.region().exterior.coords)
    span = ring.max(axis=0) - ring.min(axis=0)
    text = f"{span[0] * MM:.1f} × {span[1] * MM:.1f} mm"
    if p.shape.holes:
        ds = sorted({round(d * MM, 3) for _, _, d in p.shape.holes})
        text += "; holes ⌀" + ", ⌀".join(f"{d:g}" for d in ds)
    return text


def write_bom(result, path, masses: bool = True) -> None:
    with open(path, "w", newline="", encoding="utf-8") as fh:
        csv.writer(fh).writerows(bom_rows(result, masses))


def write_all(result, out: Path, *, layers_only: bool = False, log=lambda _: None) -> dict:
    """Write every file into the directory ``out`` (which the caller makes atomic); returns a summary."""
    import json
    out = Path(out)
    if not layers_only:
        from .solids import placed, require_make, write_3mf, write_step, write_stl
        require_make()
        solids = result.solids()
        (out / "stl").mkdir()
        (out / "3mf").mkdir()
        log(f"writing {len(solids)} parts (STL, 3MF)")
        for p in result.parts:
            flat = _centred(solids[p.name])
            write_stl(flat, out / "stl" / f"{p.name}.stl")
            write_3mf(flat, out / "3mf" / f"{p.name}.3mf", p.name)
        log("writing the assembly (STEP)")
        write_step([placed(p, solids[p.name], result.frames) for p in result.parts], out / "assembly.step",
                   name=result.mechanism.name or "assembly")
        write_bom(result, out / "bom.csv")
    (out / "parts.json").write_text(json.dumps(parts_json(result, stl=not layers_only), indent=1) + "\n",
                                    encoding="utf-8")
    (out / "certificate.json").write_text(json.dumps(certificate_json(result), indent=1, allow_nan=False) + "\n",
                                          encoding="utf-8")
    from .page import write_page
    log("writing the page")
    write_page(result, out / "parts.html", meshes=not layers_only)
    return summary(result, masses=not layers_only)


def _centred(solid):
    """``solid`` moved so its bounding box is centred on the origin in x, y and rests on z = 0 (for printing)."""
    import build123d as bd
    bb = solid.bounding_box()
    c = bb.center()
    out = solid.moved(bd.Location((-c.X, -c.Y, -bb.min.Z)))
    out.label = solid.label
    return out


def summary(result, masses: bool = True) -> dict:
    """A JSON-ready summary (SI): settings, layers and certificate, the parts with their layers and heights."""
    mass = result.mass() if masses else {}
    c = result.conflicts
    return {"mechanism": result.mechanism.name, "settings": result.settings.as_dict(), "layers": result.layers,
            "certificate": result.certificate.as_dict(),
            "pairs_checked": len(c.all()), "conflicts": sum(v.conflict for v in c.all()),
            "refined_intervals": sum(v.refined for v in c.all()),
            "parts": [{"name": p.name, "kind": p.kind, "body": p.body_name, "layer": p.layer,
                       "z": [float(p.z[0]), float(p.z[1])], **({"mass": mass[p.name].mass} if p.name in mass else {})}
                      for p in result.parts],
            "layered": sorted(result.layer_of().items(), key=lambda kv: (kv[1], kv[0])),
            "kinds": sorted({p.kind for p in result.parts if p.kind in LAYERED})}


__all__ = ["bom_rows", "certificate_json", "parts_json", "summary", "write_all", "write_bom"]
