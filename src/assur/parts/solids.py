"""The solids of the parts (build123d B-reps, millimetres): each part flat in its body's frame (z from 0 to its
thickness, the way it is printed or cut), and the same solid moved to its body's sketch pose and height for the
assembly. Holes are exact cylinders (so a STEP reader recovers the joint centres), bars and plates the exact
hulls of their bosses, gears the cut tooth outline.

Exports: one STL and one 3MF per part (flat), one STEP (AP214) of the assembly with every part named; mass
properties (mass, centre of mass in the body's frame, moment of inertia about the centre of mass) from the B-rep.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..errors import require

#: millimetres per metre: solids are built and exported in millimetres
MM = 1000.0
#: the STL and 3MF tessellation: linear deflection (mm) and angular deflection (rad)
STL_TOLERANCE = 0.002
STL_ANGULAR = 0.1
#: the package set of ``pip install 'assur[make]'``
EXTRA = ("build123d", "trimesh", "manifold3d")
INSTALL = "pip install 'assur[make]'"


def require_make() -> None:
    """MissingPackageError with the install command unless build123d, trimesh and manifold3d import."""
    for name in EXTRA:
        require(name, "assur make", INSTALL)


def _bd():
    import build123d
    return build123d


def face_of(shape):
    """The build123d face (mm) of a :class:`~assur.parts.shapes.Shape2D` (m): the union of its hulls and polygons
    minus its holes, D-bores and slots."""
    bd = _bd()
    faces = []
    for hull in shape.hulls:
        circles = [bd.Circle(r * MM).locate(bd.Location((x * MM, y * MM))) for x, y, r in hull]
        if len(circles) == 1:
            faces.append(circles[0].faces()[0])
        else:
            faces.append(bd.make_hull([e for c in circles for e in c.edges()]).faces()[0])
    for poly in shape.polygons:
        faces.append(bd.Face(bd.Wire.make_polygon([bd.Vector(x * MM, y * MM, 0) for x, y in poly], close=True)))
    face = faces[0]
    for f in faces[1:]:
        face = face + f
    for x, y, d in shape.holes:
        face = face - bd.Circle(0.5 * d * MM).locate(bd.Location((x * MM, y * MM)))
    for x, y, d, flat in shape.trim:                       # a D-shaft: the disc below its flat
        r, keep = 0.5 * d * MM, flat * MM
        face = face & bd.Rectangle(2 * r, r + keep).locate(bd.Location((x * MM, y * MM + 0.5 * (keep - r))))
    for x, y, d, flat in shape.flats:                      # a D-bore: the same cut out
        r, keep = 0.5 * d * MM, flat * MM
        face = face - (bd.Circle(r).locate(bd.Location((x * MM, y * MM)))
                       & bd.Rectangle(2 * r, r + keep).locate(bd.Location((x * MM, y * MM + 0.5 * (keep - r)))))
    for x0, y0, x1, y1, w in shape.slots:
        ends = [bd.Circle(0.5 * w * MM).locate(bd.Location((x * MM, y * MM))) for x, y in ((x0, y0), (x1, y1))]
        face = face - bd.make_hull([e for c in ends for e in c.edges()])
    return face


def flat_solid(part):
    """The part as printed: a build123d solid (mm) in its body's frame, z from 0 to its thickness."""
    bd = _bd()
    solid = bd.extrude(face_of(part.shape), amount=part.thickness * MM)
    solids = solid.solids()
    if len(solids) != 1:
        raise RuntimeError(f"the solid of part {part.name} has {len(solids)} pieces")
    out = solids[0]
    out.label = part.name
    return out


def placed(part, solid, frames):
    """``solid`` (the part's flat solid) moved to its body's sketch pose and the part's height (mm)."""
    bd = _bd()
    if part.body == 0:
        x, y, th = 0.0, 0.0, 0.0
    else:
        (x, y), th = frames.sketch_origin[part.body], float(frames.sketch_angle[part.body])
    out = solid.moved(bd.Location((x * MM, y * MM, part.z[0] * MM), (0, 0, 1), math.degrees(th)))
    out.label = part.name
    return out


@dataclass(frozen=True)
class MassProperties:
    """A part's volume (m³), mass (kg), centre of mass (m, in its body's frame; z from its bottom face) and
    moment of inertia about the vertical axis through the centre of mass (kg·m²)."""
    volume: float
    mass: float
    com: tuple
    inertia: float


def mass_properties(part, solid) -> MassProperties:
    """The mass properties of ``part`` from its flat solid (density × the B-rep's volume integrals)."""
    bd = _bd()
    volume = solid.volume / MM ** 3
    c = solid.center(bd.CenterOf.MASS)
    izz = float(np.asarray(solid.matrix_of_inertia)[2][2]) / MM ** 5
    return MassProperties(volume, part.density * volume, (c.X / MM, c.Y / MM, c.Z / MM), part.density * izz)


def tessellation(solid):
    """The solid as a closed triangle mesh (trimesh, mm): OCCT's tessellation within :data:`STL_TOLERANCE`, its
    faces' shared vertices merged."""
    import trimesh
    verts, tris = solid.tessellate(STL_TOLERANCE, STL_ANGULAR)
    return trimesh.Trimesh(np.array([[v.X, v.Y, v.Z] for v in verts]), np.asarray(tris, dtype=np.int64), process=True)


def pose_matrix(part, frames) -> np.ndarray:
    """(4, 4) the rigid motion from the part's flat frame to its place in the assembly (mm)."""
    if part.body == 0:
        x, y, th = 0.0, 0.0, 0.0
    else:
        (x, y), th = frames.sketch_origin[part.body], float(frames.sketch_angle[part.body])
    c, s = math.cos(th), math.sin(th)
    return np.array([[c, -s, 0, x * MM], [s, c, 0, y * MM], [0, 0, 1, part.z[0] * MM], [0, 0, 0, 1.0]])


def write_stl(mesh, path) -> None:
    """A binary STL of ``mesh`` (trimesh, mm)."""
    mesh.export(str(path), file_type="stl")


def write_3mf(mesh, path, name: str) -> None:
    """A 3MF file (lib3mf, mm) of ``mesh`` as one object called ``name``."""
    import ctypes

    from lib3mf import Lib3MF
    import os
    wrapper = Lib3MF.Wrapper(os.path.join(os.path.dirname(Lib3MF.__file__), "lib3mf"))
    model = wrapper.CreateModel()
    model.SetUnit(Lib3MF.ModelUnit.MilliMeter)
    obj = model.AddMeshObject()
    obj.SetName(name)
    f3, u3 = ctypes.c_float * 3, ctypes.c_uint * 3
    obj.SetGeometry([Lib3MF.Position(f3(*v)) for v in np.asarray(mesh.vertices, dtype=float).tolist()],
                    [Lib3MF.Triangle(u3(*t)) for t in np.asarray(mesh.faces, dtype=int).tolist()])
    if not obj.IsManifoldAndOriented():
        raise RuntimeError(f"the 3MF mesh of {name} is not a closed oriented solid")
    model.AddBuildItem(obj, wrapper.GetIdentityTransform())
    model.QueryWriter("3mf").WriteToFile(str(path))


def write_step(solids, path, name: str) -> None:
    """One STEP file (AP214, mm) of the named ``solids`` as an assembly called ``name``."""
    bd = _bd()
    from OCP.Interface import Interface_Static
    from OCP.STEPControl import STEPControl_Controller
    STEPControl_Controller.Init_s()
    Interface_Static.SetCVal_s("write.step.schema", "AP214IS")
    assembly = bd.Compound(children=list(solids), label=name)
    bd.export_step(assembly, str(path), unit=bd.Unit.MM, timestamp="2000-01-01T00:00:00")


__all__ = ["EXTRA", "INSTALL", "MM", "MassProperties", "face_of", "flat_solid", "mass_properties", "placed",
           "pose_matrix", "require_make", "tessellation", "write_3mf", "write_stl", "write_step"]
