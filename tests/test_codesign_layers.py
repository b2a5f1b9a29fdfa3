"""The co-design package's place in the layers (issue 24 §3, §4), checked on its own while tests/test_layers.py
waits for an unrelated module cycle: no package cycle at all, gears below io, codesign above analysis, io, gears and
kinetostatics, and the atlas's mathematics importing nothing above the structure layer."""
from pathlib import Path

from layering import Tree, read_dynamic, read_table, violations

ROOT = Path(__file__).resolve().parents[1]
SRC = ROOT / "src" / "assur"
DOC = ROOT / "docs" / "architecture.md"


def test_gears_io_codesign_and_the_atlas_keep_their_layers():
    found = violations(Tree(SRC), read_table(DOC), read_dynamic(DOC))
    mine = [v for v in found if v.startswith("cycle of packages") or any(
        f"assur/{where}" in v or f"assur.{where.replace('/', '.')}" in v
        for where in ("gears", "io", "codesign", "structure/atlas", "wheelstep"))]
    assert not mine, "\n".join(mine)


def test_gears_imports_nothing_of_its_own_layer():
    tree = Tree(SRC)
    up = sorted({(m, target) for m in tree.paths if m.startswith("assur.gears")
                 for target, *_ in tree.imports[m]
                 if target.split(".")[1] in ("io", "analysis", "codesign", "kinetostatics", "engine")})
    assert not up, up
