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

from pathlib import Path

import numpy as np

from .api import LAYERED
from .bom import write_bom

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
            flat = _centred(result.flat_meshes()[p.name])
            write_stl(flat, out / "stl" / f"{p.name}.stl")
            write_3mf(flat, out / "3mf" / f"{p.name}.3mf", p.name)
        log("writing the assembly (STEP)")
        write_step([placed(p, solids[p.name], result.frames) for p in result.parts], out / "assembly.step",
                   name=result.mechanism.name or "assembly")
        write_bom(result, out / "bom.csv")
        log("checking the meshes (watertight, volumes, no common volume in the assembly)")
        checks = mesh_checks(result, out)
    (out / "parts.json").write_text(json.dumps(parts_json(result, stl=not layers_only), indent=1) + "\n",
                                    encoding="utf-8")
    (out / "certificate.json").write_text(json.dumps(certificate_json(result), indent=1, allow_nan=False) + "\n",
                                          encoding="utf-8")
    from .page import write_page
    log("writing the page")
    write_page(result, out / "parts.html", meshes=not layers_only)
    out_summary = summary(result, masses=not layers_only)
    if not layers_only:
        out_summary["mesh_checks"] = checks
    return out_summary


def mesh_checks(result, out: Path) -> dict:
    """The checks of :mod:`assur.parts.meshcheck` on the written STL files and the assembly; RuntimeError (a
    defect) when one fails."""
    from .meshcheck import assembly_overlaps, check_stl
    mass = result.mass()
    worst = 0.0
    for p in result.parts:
        worst = max(worst, check_stl(out / "stl" / f"{p.name}.stl", mass[p.name].volume * MM ** 3)["mismatch"])
    overlaps = assembly_overlaps(result.parts, result.meshes())
    if overlaps:
        a, b, v = overlaps[0]
        raise RuntimeError(f"parts {a} and {b} share {v:.3g} mm³ in the assembly (a defect of assur make)")
    return {"stl_files": len(result.parts), "watertight": len(result.parts), "max_volume_mismatch": worst,
            "assembly_overlaps": 0}


def _centred(mesh):
    """A copy of ``mesh`` moved so its bounding box is centred on the origin in x, y and rests on z = 0."""
    lo, hi = mesh.bounds
    return mesh.copy().apply_translation([-0.5 * (lo[0] + hi[0]), -0.5 * (lo[1] + hi[1]), -lo[2]])


#: the print bed a part must fit for FDM (m): 250 mm square (the common 250–256 mm class of printers)
PRINT_BED = 0.250


def oversize(result, bed: float = PRINT_BED) -> list:
    """[(name, long side, short side)] (m) of the parts whose footprint does not fit a ``bed`` square in any
    orientation (its least-area enclosing rectangle is longer than the bed), largest first."""
    out = []
    for p in result.parts:
        rect = p.shape.region().minimum_rotated_rectangle
        xy = np.asarray(rect.exterior.coords)[:4]
        sides = sorted((float(np.hypot(*(xy[1] - xy[0]))), float(np.hypot(*(xy[2] - xy[1])))), reverse=True)
        if sides[0] > bed:
            out.append((p.name, sides[0], sides[1]))
    return sorted(out, key=lambda t: -t[1])


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
            "larger_than_print_bed": [{"name": n, "size": [a, b]} for n, a, b in oversize(result)]
            if result.settings.process == "fdm" else [],
            "kinds": sorted({p.kind for p in result.parts if p.kind in LAYERED})}


__all__ = ["certificate_json", "parts_json", "summary", "write_all"]
