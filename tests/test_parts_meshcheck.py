"""The mesh checks ``assur make`` runs before it accepts an output can fail: a shared volume, an open mesh, an
STL off its solid's volume (trimesh boxes, no CAD kernel)."""
from types import SimpleNamespace

import numpy as np
import pytest

trimesh = pytest.importorskip("trimesh")
pytest.importorskip("manifold3d")

from assur.parts.meshcheck import assembly_overlaps, check_stl   # noqa: E402


def box(name, centre, size, z):
    mesh = trimesh.creation.box(extents=size)
    mesh.apply_translation(centre)
    return SimpleNamespace(name=name, z=z), (np.asarray(mesh.vertices), np.asarray(mesh.faces))


def test_overlapping_parts_are_found_with_their_common_volume():
    a, ma = box("a", (0, 0, 1), (10, 10, 2), (0, 2))
    b, mb = box("b", (8, 0, 1), (10, 10, 2), (0, 2))          # 2 × 10 × 2 = 40 mm³ in common
    c, mc = box("c", (0, 0, 3.5), (10, 10, 2), (2.5, 4.5))    # above a: its faces never meet a's
    out = assembly_overlaps([a, b, c], {"a": ma, "b": mb, "c": mc})
    assert len(out) == 1 and out[0][:2] == ("a", "b") and out[0][2] == pytest.approx(40.0, rel=1e-5)


def test_touching_faces_are_no_overlap():
    a, ma = box("a", (0, 0, 1), (10, 10, 2), (0, 2))
    b, mb = box("b", (10, 0, 1), (10, 10, 2), (0, 2))
    assert assembly_overlaps([a, b], {"a": ma, "b": mb}) == []


def test_an_open_mesh_is_refused_not_passed():
    a, (v, f) = box("a", (0, 0, 1), (10, 10, 2), (0, 2))
    b, mb = box("b", (8, 0, 1), (10, 10, 2), (0, 2))
    with pytest.raises(RuntimeError, match="not a closed solid"):
        assembly_overlaps([a, b], {"a": (v, f[:-2]), "b": mb})


def test_an_stl_must_be_closed_and_of_its_solids_volume(tmp_path):
    mesh = trimesh.creation.box(extents=(10, 10, 2))
    path = tmp_path / "a.stl"
    mesh.export(path)
    assert check_stl(path, 200.0)["mismatch"] == pytest.approx(0.0, abs=1e-9)
    with pytest.raises(RuntimeError, match="volume"):
        check_stl(path, 210.0)                                 # 5 % off
    open_mesh = trimesh.Trimesh(mesh.vertices, mesh.faces[:-1], process=False)
    open_mesh.export(tmp_path / "b.stl")
    with pytest.raises(RuntimeError, match="watertight False"):
        check_stl(tmp_path / "b.stl", 200.0)
