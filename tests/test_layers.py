"""The import rules of src/assur, against the layer table declared in docs/architecture.md (see tests/layering.py).

The checker itself is tested on a small package written here: a copy that keeps its table passes, and each kind of
violation injected into a fresh copy is reported.
"""
from __future__ import annotations

import shutil
import subprocess
import sys
import textwrap
from pathlib import Path

import pytest

from layering import Tree, read_dynamic, read_table, strongly_connected_components, violations

ROOT = Path(__file__).resolve().parents[1]
SRC = ROOT / "src" / "assur"
DOC = ROOT / "docs" / "architecture.md"


def test_src_keeps_the_declared_layers():
    found = violations(Tree(SRC), read_table(DOC), read_dynamic(DOC))
    assert not found, f"{len(found)} import rule(s) broken in src/assur:\n" + "\n".join(sorted(set(found)))


def test_no_module_over_600_lines():
    long = [f"{p.relative_to(ROOT)}: {n}" for p in sorted(SRC.rglob("*.py"))
            if (n := len(p.read_text(encoding="utf-8").splitlines())) > 600]
    assert not long, "modules over 600 lines:\n" + "\n".join(long)


def test_core_import_is_light():
    """`import assur` must not import matplotlib or scipy.optimize (heavy deps load lazily)."""
    code = "import sys, assur; print(','.join(m for m in ('matplotlib', 'scipy.optimize') if m in sys.modules))"
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, encoding="utf-8", check=True).stdout.strip()
    assert out == ""


def test_tarjan_finds_the_cycles_of_a_small_graph():
    graph = {"a": ["b"], "b": ["c"], "c": ["a", "d"], "d": ["e"], "e": ["d"], "f": ["f", "a"], "g": ["outside"]}
    found = sorted(strongly_connected_components(graph))
    assert found == [["a", "b", "c"], ["d", "e"], ["f"], ["g"]]


# -- the checker on a small package ---------------------------------------------------------------------------
FAKE = {
    "__init__.py": '''
        """The public API, loaded lazily."""
        import importlib
        _LAZY = {"thing": "fake.top.api"}

        def __getattr__(name):
            return getattr(importlib.import_module(_LAZY[name]), name)
    ''',
    "errors.py": "class FakeError(Exception):\n    pass\n",
    "low/__init__.py": "",
    "low/core.py": "from ..errors import FakeError\n\ndef _hidden():\n    return 1\n\ndef shown():\n    return 2\n",
    "mid/__init__.py": "",
    "mid/a.py": "from ..low.core import shown\n",
    "mid/b.py": "from .a import shown\n",
    "side/__init__.py": "",
    "side/c.py": "from ..mid.a import shown\n",
    "top/__init__.py": "",
    "top/api.py": "from ..mid.b import shown\nfrom ..side.c import shown as also\n\ndef thing():\n    return shown()\n",
}
TABLE = """
# fake

<!-- layer table -->
| package | layer | may also import |
|---|---|---|
| `errors` | 0 | |
| `low` | 0 | `errors` |
| `mid` | 1 | |
| `side` | 1 | `mid` |
| `top` | 2 | |
"""


def fake_package(tmp_path: Path, changes: dict | None = None) -> tuple[Tree, dict, frozenset]:
    """A fresh copy of the fake package with ``changes`` ({file: source}) applied, and its table."""
    root = tmp_path / "fake"
    shutil.rmtree(root, ignore_errors=True)
    for name, text in {**FAKE, **(changes or {})}.items():
        path = root / name
        path.parent.mkdir(parents=True, exist_ok=True)
        path.write_text(textwrap.dedent(text), encoding="utf-8")
    doc = tmp_path / "layers.md"
    doc.write_text(TABLE, encoding="utf-8")
    return Tree(root), read_table(doc), read_dynamic(doc)


def test_the_fake_package_keeps_its_table(tmp_path):
    assert violations(*fake_package(tmp_path)) == []


@pytest.mark.parametrize("kind, changes", [
    ("cycle of modules", {"mid/a.py": "from ..low.core import shown\nfrom . import b\n"}),
    ("cycle of packages", {"side/c.py": "from ..mid.a import shown\n",
                           "mid/b.py": "from .a import shown\n\ndef f():\n    from ..side import c\n"}),
    ("not allowed", {"low/core.py": "from ..errors import FakeError\n\ndef g():\n    from ..mid import a\n"}),
    ("not allowed", {"mid/b.py": "from .a import shown\nfrom ..side.c import shown as s\n"}),
    ("not allowed", {"mid/b.py": "import importlib\nimportlib.import_module('fake.top.api')\n"}),
    ("dynamic", {"mid/b.py": "import importlib\nname = 'fake.low.core'\nimportlib.import_module(name)\n"}),
    ("dynamic", {"mid/b.py": "m = __import__('os' + '')\n"}),
    ("private", {"mid/b.py": "from ..low.core import _hidden\n"}),
    ("root", {"mid/b.py": "from .. import thing\n"}),
    ("root", {"side/c.py": "import fake\n"}),
    ("no layer", {"extra/__init__.py": ""}),
])
def test_each_kind_of_violation_is_reported(tmp_path, kind, changes):
    found = violations(*fake_package(tmp_path, changes))
    assert any(line.startswith(kind) for line in found), found
