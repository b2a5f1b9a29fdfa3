"""Checks of the written meshes (trimesh, manifold3d) before an output is accepted:

- every STL is read back: it must be watertight with a positive volume equal to its B-rep's within
  :data:`VOLUME_TOLERANCE`;
- the assembly at the sketch pose: no two parts may share volume (a manifold3d boolean of every pair whose
  height ranges overlap) — pins sit in holes with their allowance, washers touch faces, blocks ride in slots with
  their play, gears mesh with their backlash.

A failure is a defect of ``assur make`` (RuntimeError), never the user's: the output is then not written.
"""
from __future__ import annotations

import numpy as np

#: the least relative agreement of an STL's volume with its solid's
VOLUME_TOLERANCE = 0.005
#: common volume below this fraction of the smaller part's volume is a numerical touch, not an overlap
OVERLAP_TOLERANCE = 1e-6


def _manifold(name, vertices, triangles):
    """The manifold3d solid of a closed mesh; RuntimeError when it is not one (a boolean of a broken mesh would
    report no common volume whatever the parts do)."""
    import manifold3d as mf
    mesh = mf.Mesh(vert_properties=np.asarray(vertices, dtype=np.float32), tri_verts=np.asarray(triangles,
                                                                                               dtype=np.uint32))
    out = mf.Manifold(mesh)
    if out.status() != mf.Error.NoError or not out.volume() > 0:
        raise RuntimeError(f"the mesh of part {name} is not a closed solid ({out.status()})")
    return out


def check_stl(path, brep_volume_mm3: float) -> dict:
    """{"watertight", "volume" (mm³), "mismatch"} of the STL at ``path``; RuntimeError when it is not watertight,
    not positive or off its B-rep's volume by more than :data:`VOLUME_TOLERANCE`."""
    import trimesh
    mesh = trimesh.load_mesh(str(path), file_type="stl")
    mismatch = abs(mesh.volume - brep_volume_mm3) / brep_volume_mm3
    if not mesh.is_watertight or not mesh.volume > 0 or mismatch > VOLUME_TOLERANCE:
        raise RuntimeError(f"{path}: the mesh is not a closed solid of the part's volume (watertight "
                           f"{mesh.is_watertight}, volume {mesh.volume:.6g} mm³ against {brep_volume_mm3:.6g})")
    return {"watertight": True, "volume": float(mesh.volume), "mismatch": float(mismatch)}


def assembly_overlaps(parts, meshes: dict) -> list:
    """[(a, b, common volume mm³)] of the pairs of ``parts`` whose meshes at the sketch pose (``meshes``: {name:
    (vertices (v, 3), triangles (t, 3))}, mm) share volume."""
    solids = {name: _manifold(name, v, t) for name, (v, t) in meshes.items()}
    volume = {name: m.volume() for name, m in solids.items()}
    out = []
    for i, a in enumerate(parts):
        for b in parts[i + 1:]:
            if min(a.z[1], b.z[1]) - max(a.z[0], b.z[0]) <= 0:
                continue
            common = (solids[a.name] ^ solids[b.name]).volume()
            if common > OVERLAP_TOLERANCE * min(volume[a.name], volume[b.name]):
                out.append((a.name, b.name, float(common)))
    return out


__all__ = ["OVERLAP_TOLERANCE", "VOLUME_TOLERANCE", "assembly_overlaps", "check_stl"]
