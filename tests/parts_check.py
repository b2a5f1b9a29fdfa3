"""An independent collision test of made parts (it uses no code of ``assur.parts``).

Each part is a mesh (re-imported from a STEP file and tessellated, at its sketch pose); its footprint is the union
of the mesh's upward-facing triangles projected on the sketch plane, and its height range is the mesh's z extent.
The part moves with a body of the mechanism: the engine's solved poses (a point the body carries and the body's
angle, ``assur.solve``) move the footprint rigidly from the sketch pose to each input. Two parts whose height
ranges overlap must then never intersect or come closer than the clearance, at any of the inputs, unless they
touch by design:

- parts on one body (fixed to each other) are checked once, at the sketch pose, by a mesh boolean (manifold3d):
  their common volume must be nil;
- a pin (or a washer on it) and a part of a body it joins whose footprint holds the pin's centre (the pin in its
  hole, the washer on its face);
- parts at one joint (a pin and its washers);
- a pair of meshing gears, and a slider block and the part on its guide body (the block in its slot).
"""
from __future__ import annotations

import numpy as np


def step_meshes(path) -> dict:
    """{name: trimesh.Trimesh (mm)} of the parts of a STEP file: each child of the assembly (its solids merged),
    by its name, or numbered s0, s1, … when the file gives no distinct names."""
    import build123d as bd
    import trimesh
    shape = bd.import_step(str(path))
    kids = list(shape.children) or [s for s in shape.solids()]
    labels = [c.label for c in kids]
    unique = all(labels) and len(set(labels)) == len(labels)        # else (pylinkage: all "COMPOUND") numbered
    items = [(c.label if unique else f"s{i}", c.solids()) for i, c in enumerate(kids)]
    out = {}
    for name, solids in items:
        meshes = []
        for solid in solids:
            verts, tris = solid.tessellate(0.002, 0.1)
            meshes.append(trimesh.Trimesh(np.array([[p.X, p.Y, p.Z] for p in verts]), np.asarray(tris)))
        out[name] = trimesh.util.concatenate(meshes) if len(meshes) > 1 else meshes[0]
    return out


def footprint(mesh):
    """The shapely polygon (with its holes) covered by ``mesh`` seen from above (mm)."""
    import shapely
    up = mesh.face_normals[:, 2] > 0.5
    tris = mesh.vertices[mesh.faces[up]][:, :, :2]
    polys = shapely.polygons(np.concatenate([tris, tris[:, :1]], axis=1))
    polys = polys[shapely.area(polys) > 0]
    # the triangles of a tessellated face meet edge to edge; closing the union by ±0.1 µm seals rounding slivers
    return shapely.union_all(polys).buffer(1e-4, join_style="mitre").buffer(-1e-4, join_style="mitre")


def body_poses(plan, q) -> tuple[np.ndarray, np.ndarray]:
    """(reference point positions (n, B, 2) in mm, body angles (n, B)) of the engine's solve at inputs q (n, k):
    each body's reference is the first point the mechanism gives it (a link's first point, a slider block's pin,
    an actuator cylinder's first hinge and its rod's second); the frame's is the origin."""
    import assur
    m = plan.mechanism
    st = assur.solve(plan, None, q)
    pos = np.asarray(st.pos) * 1e3
    ang = np.asarray(st.body_angle)
    ref = np.zeros(pos.shape[:-2] + (plan.n_bodies, 2))
    names = list(plan.body_names)
    owner = {lk.name: lk.points[0] for lk in m.links}
    owner |= {f"{pr.name}.block": pr.point for pr in m.prismatic if pr.point}
    owner |= {f"{a.name}.cylinder": a.between[0] for a in m.actuators}
    owner |= {f"{a.name}.rod": a.between[1] for a in m.actuators}
    for b, name in enumerate(names):
        if name == "frame":
            ang[..., b] = 0.0
            continue
        ref[..., b, :] = pos[..., plan.point_index(owner[name]), :]
    return ref, ang


def move(poly, ref0, ang0, ref, ang):
    """``poly`` at the body pose (ref0, ang0) moved rigidly to (ref, ang)."""
    import shapely
    c, s = np.cos(ang - ang0), np.sin(ang - ang0)

    def f(xy):
        d = xy - ref0
        return np.stack([ref[0] + c * d[:, 0] - s * d[:, 1], ref[1] + s * d[:, 0] + c * d[:, 1]], axis=-1)
    return shapely.transform(poly, f)


def find_collisions(parts: list, plan, q, clearance_mm: float, *, sketch_q, exclude=(), tolerance_mm=0.01):
    """Pairs of ``parts`` that come closer than the clearance at any of the inputs ``q`` (n, k).

    ``parts``: dicts with ``name``, ``body`` (body index), ``mesh`` (trimesh at the sketch pose, mm); ``sketch_q``
    (k,) the sketch inputs; ``exclude``: pairs of names that touch by design. Returns [(a, b, least distance (mm),
    index into q)] for the pairs whose height ranges overlap and whose least distance is below ``clearance_mm −
    tolerance_mm`` (the tolerance covers the tessellation of round edges)."""
    import shapely
    ref, ang = body_poses(plan, q)
    ref0, ang0 = body_poses(plan, np.asarray(sketch_q, dtype=float)[None])
    skip = {frozenset(p) for p in exclude}
    for p in parts:
        p["foot"] = footprint(p["mesh"])
        p["zr"] = (float(p["mesh"].bounds[0, 2]), float(p["mesh"].bounds[1, 2]))
    hits = []
    cache = {}

    def moved(p):
        if p["name"] not in cache:
            b = p["body"]
            cache[p["name"]] = [move(p["foot"], ref0[0, b], ang0[0, b], ref[i, b], ang[i, b]) for i in range(len(q))]
        return cache[p["name"]]
    for i, a in enumerate(parts):
        for b in parts[i + 1:]:
            if frozenset((a["name"], b["name"])) in skip or a["body"] == b["body"]:
                continue
            if min(a["zr"][1], b["zr"][1]) - max(a["zr"][0], b["zr"][0]) <= 1e-6:
                continue
            d = np.asarray(shapely.distance(np.array(moved(a), dtype=object), np.array(moved(b), dtype=object)))
            k = int(np.argmin(d))
            if d[k] < clearance_mm - tolerance_mm:
                hits.append((a["name"], b["name"], float(d[k]), k))
    return hits


def same_body_overlaps(parts: list, *, volume_mm3: float = 1e-3):
    """Pairs of parts on one body whose meshes share volume (manifold3d boolean): [(a, b, common volume)]."""
    import manifold3d as mf
    out = []

    def manifold(mesh):
        out = mf.Manifold(mf.Mesh(vert_properties=np.asarray(mesh.vertices, dtype=np.float32),
                                  tri_verts=np.asarray(mesh.faces, dtype=np.uint32)))
        assert out.status() == mf.Error.NoError and out.volume() > 0      # a closed solid, else nothing is tested
        return out
    for i, a in enumerate(parts):
        for b in parts[i + 1:]:
            if a["body"] != b["body"]:
                continue
            common = (manifold(a["mesh"]) ^ manifold(b["mesh"])).volume()
            if common > volume_mm3:
                out.append((a["name"], b["name"], common))
    return out


def designed_contacts(parts: list, mechanism, plan, sketch_q) -> list:
    """The pairs that touch by design (module docstring), from the parts' names, joints and bodies."""
    import shapely
    out = []
    names = list(plan.body_names)
    gear_bodies = [{names.index(gp.a), names.index(gp.b)} for gp in mechanism.gears]
    guide = {names.index(f"{pr.name}.block"): names.index(pr.guide) for pr in mechanism.prismatic if pr.point}
    for i, a in enumerate(parts):
        for b in parts[i + 1:]:
            pair = (a["name"], b["name"])
            if a.get("joint") is not None and a.get("joint") == b.get("joint"):
                out.append(pair)
                continue
            for pin, other in ((a, b), (b, a)):
                if pin.get("joint") is None or other.get("joint") is not None:
                    continue
                if other["body"] not in [names.index(h) for h in pin["holds"]]:
                    continue
                outer = shapely.union_all([shapely.Polygon(g.exterior) for g in shapely.get_parts(footprint(other["mesh"]))])
                if outer.contains(footprint(pin["mesh"]).centroid):
                    out.append(pair)
            if {a["body"], b["body"]} in gear_bodies and a["name"].startswith("gear") and b["name"].startswith("gear"):
                out.append(pair)
            for blk, other in ((a, b), (b, a)):
                if blk["body"] in guide and other["body"] == guide[blk["body"]]:
                    out.append(pair)
    return out
