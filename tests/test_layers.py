"""The layer rule of DESIGN.md: a module imports only from its own layer or below."""
import ast
from pathlib import Path

import pytest

SRC = Path(__file__).resolve().parents[1] / "src" / "assur"
LAYER = {"kernels": 0, "errors": 0, "tolerances": 0,
         "model": 1, "structure": 1,
         "compile": 2, "plan": 2, "solve": 2, "state": 2, "compiled_backend": 2, "spatial_plan": 2,
         "analysis": 3, "io": 3, "gears": 3, "wheelstep": 3,
         "synthesis": 4, "plot": 4, "report": 4, "cli": 4, "__main__": 4, "__root__": 4}


def top_of(path: Path) -> str:
    rel = path.relative_to(SRC)
    return rel.parts[0].removesuffix(".py")


def imported_tops(path: Path):
    tree = ast.parse(path.read_text(encoding="utf-8"))
    pkg = path.relative_to(SRC).parts[:-1]
    for node in ast.walk(tree):
        if isinstance(node, ast.ImportFrom):
            if node.level == 0:
                if node.module and node.module.startswith("assur."):
                    yield node.module.split(".")[1], node.lineno
                continue
            base = list(pkg[: len(pkg) - (node.level - 1)]) if node.level > 1 else list(pkg)
            parts = base + (node.module.split(".") if node.module else [])
            if parts:
                yield parts[0], node.lineno
            else:  # "from . import module", or a name of the package root (the public API, top layer only)
                for alias in node.names:
                    yield (alias.name if alias.name in LAYER else "__root__"), node.lineno
        elif isinstance(node, ast.Import):
            for alias in node.names:
                if alias.name.startswith("assur."):
                    yield alias.name.split(".")[1], node.lineno


MODULES = [p for p in SRC.rglob("*.py") if p.name != "__init__.py" or p.parent != SRC]


@pytest.mark.parametrize("path", MODULES, ids=lambda p: str(p.relative_to(SRC)))
def test_imports_go_downward(path):
    top = top_of(path)
    if top == "__init__":
        pytest.skip("package root re-exports the public API")
    mine = LAYER[top]
    for target, line in imported_tops(path):
        assert target in LAYER, f"{path.name}:{line} imports unknown module assur.{target}"
        assert LAYER[target] <= mine, (f"{path.relative_to(SRC)}:{line} (layer {mine}) imports "
                                       f"assur.{target} (layer {LAYER[target]})")


def test_core_import_is_light():
    """`import assur` must not import matplotlib or scipy.optimize (heavy deps load lazily)."""
    import subprocess
    import sys
    code = "import sys, assur; print(','.join(m for m in ('matplotlib', 'scipy.optimize') if m in sys.modules))"
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True).stdout.strip()
    assert out == ""
