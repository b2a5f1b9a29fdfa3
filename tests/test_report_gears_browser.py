"""The gear-pair report page renders in real headless Chromium (pattern of tests/test_report_browser.py).

Chromium comes from Debian (``.ci/run`` installs it); outside CI the test is skipped when it is missing.
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
    out = tmp_path_factory.mktemp("report") / "gears001"
    assert main(["report", str(ROOT / "examples" / "gears_001.toml"), "-o", str(out), "--frames", "6"]) == 0
    return out / "index.html"


def test_gear_report_renders_with_tables_plots_and_local_cad_links(report, tmp_path):
    screenshot_is_a_real_page(tmp_path, report.as_uri())
    dom = run_browser(tmp_path, "--dump-dom", "--virtual-time-budget=5000", report.as_uri()).stdout
    assert "Teeth and mesh check" in dom and "Paper sector scheme" in dom and "interferes" in dom
    assert "Table 1" in dom and "-84.19" in dom          # Table 1, row 2 as printed (docs/papers/001.md §E)
    assert dom.count("data:image/png;base64,") >= 4
    # nothing from the network: images inline, links are anchors or files written beside the page
    refs = re.findall(r'(?:src|href)="([^"]+)"', dom)
    local = [r for r in refs if not r.startswith(("data:", "#"))]
    assert any(r.endswith(".dxf") for r in local) and any(r.endswith(".svg") for r in local)
    for r in local:
        assert "://" not in r and (report.parent / r).is_file(), r
