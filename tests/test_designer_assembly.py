"""The designer's page module is joined from its parts by concern at import time (no Node for `pip install .`): the
parts join without a clash, each imports what it uses from the others, and the page and the widget get the joined
module. The browser tests (tests/test_designer_browser*.py, test_designer_widget.py) run it in Chromium."""
import re
import subprocess
from pathlib import Path

import pytest

from assur.designer.assembly import PARTS, AssemblyError, assemble, module_text, parts_dir

DECLARATION = re.compile(r"^(?:export\s+)?(?:const|let|function|class|async\s+function)\s+([A-Za-z_$][\w$]*)", re.M)


def test_the_parts_are_split_by_concern_and_each_is_under_600_lines():
    assert set(PARTS) == {"util.js", "channel.js", "canvas.js", "gestures.js", "panels.js", "synthesis.js",
                          "motor.js", "chooser.js", "designer.js"}
    assert sorted(p.name for p in parts_dir().glob("*.js")) == sorted(PARTS)
    for name in PARTS:
        assert len((parts_dir() / name).read_text().splitlines()) <= 600, name


def test_the_joined_module_has_every_part_once_and_only_the_entrys_exports():
    text = module_text()
    for name in PARTS:
        body = (parts_dir() / name).read_text()
        for symbol in DECLARATION.findall(body):
            assert len(re.findall(rf"^(?:export\s+)?(?:const|let|function|class|async\s+function)\s+{re.escape(symbol)}\b",
                                  text, re.M)) == 1, symbol
    assert not re.search(r'^import ', text, re.M)
    assert re.findall(r"^export .*$", text, re.M) == ["export default { render };",
                                                     "export { render, shareCodec, preferReadbackCanvases };"]


def test_every_name_a_part_takes_from_another_is_imported():
    """So the parts load natively as a module graph too (and the joined module does not depend on the order of
    anything but :data:`PARTS`)."""
    declared = {}
    for name in PARTS:
        for symbol in DECLARATION.findall((parts_dir() / name).read_text()):
            declared[symbol] = name
    for name in PARTS:
        text = (parts_dir() / name).read_text()
        imported = {s.strip() for m in re.finditer(r"^import\s*\{([^}]*)\}", text, re.M) for s in m.group(1).split(",")}
        code = re.sub(r"//.*", "", text)
        for symbol, home in declared.items():
            if home != name and re.search(rf"(?<![\w.$]){re.escape(symbol)}\b", code):
                assert symbol in imported, f"{name} uses {symbol} of {home} without importing it"


@pytest.mark.parametrize("parts, says", [
    ({"a.js": 'import { x } from "./b.js";\n', "b.js": "export const x = 1;\n"}, "not an earlier part"),
    ({"a.js": "export const x = 1;\n", "b.js": 'import { y } from "./a.js";\n'}, "does not export y"),
    ({"a.js": "export const x = 1;\n", "b.js": "const x = 2;\n"}, "declared in a.js already"),
    ({"a.js": "export default {};\n", "b.js": "const y = 2;\n"}, "exports declarations only"),
    ({"a.js": 'import {\n  x } from "./b.js";\n', "b.js": ""}, "one-line imports"),
])
def test_a_broken_part_is_refused_with_its_line(parts, says):
    with pytest.raises(AssemblyError, match=says):
        assemble(parts)


def test_the_server_serves_the_joined_module():
    pytest.importorskip("starlette")
    import urllib.request

    from assur.designer.server import start_server
    from assur.designer.session import Session
    srv = start_server(Session.of_file(Path(__file__).resolve().parents[1] / "examples" / "crank_rocker.toml"))
    try:
        url = f"http://127.0.0.1:{srv.port}/static/designer.js?token={srv.token}"
        with urllib.request.urlopen(url, timeout=10) as r:
            assert r.headers["Content-Type"].startswith("text/javascript")
            assert r.read().decode() == module_text()
    finally:
        srv.stop()


def test_node_if_present_parses_the_joined_module(tmp_path):
    """A syntax check by an independent parser where one is installed (Node is never needed to install)."""
    import shutil
    node = shutil.which("node")
    if node is None:
        pytest.skip("no node on this machine (the browser tests run the module in Chromium)")
    path = tmp_path / "designer.mjs"
    path.write_text(module_text())
    subprocess.run([node, "--check", str(path)], check=True, capture_output=True, timeout=60)
