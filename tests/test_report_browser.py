"""The report is a page people open in a browser: render it in real headless Chromium.

Chromium comes from Debian (``.ci/run`` installs it); outside CI the test is skipped when it is
missing, in CI its absence is a failure.
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
    out = tmp_path_factory.mktemp("report") / "walker000"
    assert main(["report", str(ROOT / "examples" / "walker_crank_slider.toml"), "-o", str(out), "--steps", "90"]) == 0
    return out / "index.html"


def run_browser(tmp_path, *args):
    return subprocess.run([BROWSER, *FLAGS, f"--user-data-dir={tmp_path / 'profile'}", *args],
                          capture_output=True, text=True, timeout=120, cwd=tmp_path)


def test_report_renders_in_chromium(report, tmp_path):
    shot = tmp_path / "page.png"
    run_browser(tmp_path, "--window-size=1280,3000", f"--screenshot={shot}", report.as_uri())
    assert shot.exists() and shot.stat().st_size > 10_000
    import matplotlib.image as mpimg
    img = mpimg.imread(shot)[..., :3]
    # a page with text, tables and plots, not a blank or error page: many distinct shades
    assert img.std() > 0.05
    assert len(np.unique((img[::7, ::7] * 255).astype(np.uint8).reshape(-1, 3), axis=0)) > 50


def test_report_dom_has_structure_and_loaded_images(report, tmp_path):
    dom = run_browser(tmp_path, "--dump-dom", "--virtual-time-budget=5000", report.as_uri()).stdout
    assert "I(frame, crank) → II(rod, slider.block)" in dom
    assert dom.count("<img") >= 1 and "data:image/png;base64," in dom
    # the page fetches nothing from the network: every src/href is inline data or an anchor
    for ref in re.findall(r'(?:src|href)="([^"]+)"', dom):
        assert ref.startswith(("data:", "#")), ref
