"""The report is a page people open in a browser: render it in real headless Chromium.

Chromium comes from Debian (``.ci/run`` installs it); outside CI the test is skipped when it is
missing, in CI its absence is a failure.
"""
import re
from pathlib import Path

import pytest

from assur.cli.main import main
from browser import needs_browser, run_browser, screenshot_is_a_real_page

ROOT = Path(__file__).resolve().parents[1]
pytestmark = [needs_browser, pytest.mark.slow]


@pytest.fixture(scope="module")
def report(tmp_path_factory):
    out = tmp_path_factory.mktemp("report") / "walker000"
    assert main(["report", str(ROOT / "examples" / "walker_crank_slider.toml"), "-o", str(out), "--steps", "90"]) == 0
    return out / "index.html"


def test_report_renders_in_chromium(report, tmp_path):
    screenshot_is_a_real_page(tmp_path, report.as_uri())


def test_report_dom_has_structure_and_loaded_images(report, tmp_path):
    dom = run_browser(tmp_path, "--dump-dom", "--virtual-time-budget=5000", report.as_uri()).stdout
    assert "I(frame, crank) → II(rod, slider.block)" in dom
    assert dom.count("<img") >= 1 and "data:image/png;base64," in dom
    # the page fetches nothing from the network: every src/href is inline data or an anchor
    for ref in re.findall(r'(?:src|href)="([^"]+)"', dom):
        assert ref.startswith(("data:", "#")), ref
