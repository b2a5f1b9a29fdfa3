"""The bill of materials of made parts: each made part on its row (material, thickness, mass, size, file), dowel
pins and washers grouped by size, the motor."""
from __future__ import annotations

import csv
import math

import numpy as np

MM = 1000.0


def _round(x, digits=6):
    return float(round(float(x), digits))


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
    for _, _, d, flat in p.shape.flats:
        text += f"; D-bore ⌀{d * MM:g}, {(0.5 * d + flat) * MM:g} across the flat (the motor shaft)"
    return text


def write_bom(result, path, masses: bool = True) -> None:
    with open(path, "w", newline="", encoding="utf-8") as fh:
        csv.writer(fh).writerows(bom_rows(result, masses))


__all__ = ["bom_rows", "write_bom"]
