"""The gear-pair report page renders in real headless Chromium (pattern of tests/test_report_browser.py).

Chromium comes from Debian (``.ci/run`` installs it); outside CI the test is skipped when it is missing.
"""
import os
import re
import shutil
import subprocess
from pathlib import Path

import numpy as np
import pytest

from assur.cli.main import main

ROOT = Path(__file__).resolve().parents[1]
BROWSER = shutil.which("chromium") or shutil.which("chromium-browser")
FLAGS = ["--headless", "--no-sandbox", "--disable-gpu", "--disable-quic", "--no-first-run",
         "--disable-background-networking", "--disable-component-update", "--disable-sync"]

if BROWSER is None and os.environ.get("CI"):
    raise RuntimeError("CI needs Debian's chromium for the browser test (.ci/run installs it)")
pytestmark = pytest.mark.skipif(BROWSER is None, reason="headless Chromium not installed")


@pytest.fixture(scope="module")
def report(tmp_path_factory):
    out = tmp_path_factory.mktemp("report") / "gears001"
    assert main(["report", str(ROOT / "examples" / "gears_001.toml"), "-o", str(out), "--frames", "6"]) == 0
    return out / "index.html"


def run_browser(tmp_path, *args):
    return subprocess.run([BROWSER, *FLAGS, f"--user-data-dir={tmp_path / 'profile'}", *args],
                          capture_output=True, text=True, timeout=120, cwd=tmp_path)


def test_gear_report_renders_with_tables_plots_and_local_cad_links(report, tmp_path):
    shot = tmp_path / "page.png"
    run_browser(tmp_path, "--window-size=1280,3000", f"--screenshot={shot}", report.as_uri())
    assert shot.exists() and shot.stat().st_size > 10_000
    import matplotlib.image as mpimg
    img = mpimg.imread(shot)[..., :3]
    assert img.std() > 0.05
    assert len(np.unique((img[::7, ::7] * 255).astype(np.uint8).reshape(-1, 3), axis=0)) > 50
    dom = run_browser(tmp_path, "--dump-dom", "--virtual-time-budget=5000", report.as_uri()).stdout
    assert "Teeth and mesh check" in dom and "Paper sector scheme" in dom and "interferes" in dom
    assert "Table 1" in dom and "-84.19" in dom          # Table 1, row 2 as printed (spec §E)
    assert dom.count("data:image/png;base64,") >= 4
    # nothing from the network: images inline, links are anchors or files written beside the page
    refs = re.findall(r'(?:src|href)="([^"]+)"', dom)
    local = [r for r in refs if not r.startswith(("data:", "#"))]
    assert any(r.endswith(".dxf") for r in local) and any(r.endswith(".svg") for r in local)
    for r in local:
        assert "://" not in r and (report.parent / r).is_file(), r
