"""The spatial report and 3D view are pages people open in a browser: render them in real headless
Chromium (as tests/test_report_browser.py). The plotly 3D scene must draw (a WebGL canvas, the SVG
layers, the path colours on screen) with no JavaScript error and nothing fetched from the network.

Chromium comes from Debian (``.ci/run`` installs it); outside CI the test is skipped when it is
missing, in CI its absence is a failure.
"""
import re
from pathlib import Path

import numpy as np
import pytest

import browser
from assur.cli.main import main
from browser import needs_browser

ROOT = Path(__file__).resolve().parents[1]
JS_ERROR = re.compile(r"CONSOLE.*(Uncaught|TypeError|ReferenceError|SyntaxError|WebGL is not supported)")

pytestmark = [needs_browser, pytest.mark.slow]


@pytest.fixture(scope="module")
def pages(tmp_path_factory):
    base = tmp_path_factory.mktemp("spatial")
    rep = base / "rssr"
    assert main(["report", str(ROOT / "examples" / "rssr_tilted.toml"), "-o", str(rep), "--steps", "72",
                 "--frames", "8"]) == 0
    view = base / "view.html"
    assert main(["plot", str(ROOT / "examples" / "rssr_tilted.toml"), "-o", str(view), "--steps", "72"]) == 0
    return rep / "index.html", view


def run_browser(tmp_path, *args):
    return browser.run_browser(tmp_path, *args, webgl=True, timeout=180)


def test_spatial_report_dom_has_a_drawn_3d_scene_and_no_js_error(pages, tmp_path):
    report, _ = pages
    res = run_browser(tmp_path, "--dump-dom", "--virtual-time-budget=8000", report.as_uri())
    dom = res.stdout
    assert "js-plotly-plot" in dom                        # plotly ran and built the figure
    scene = dom[dom.index('class="gl-container"'):]
    assert re.match(r'class="gl-container"><div id="scene"[^>]*>(<svg[^>]*></svg>)?<canvas', scene)   # the WebGL 3D scene
    assert dom.count('class="main-svg"') >= 1             # the SVG layers (legend, slider, buttons)
    assert "play" in dom and "Somov–Malyshev" in dom
    assert not JS_ERROR.search(res.stderr), JS_ERROR.search(res.stderr).group(0)
    # the page fetches nothing from the network: every src/href is inline data or an anchor
    markup = re.sub(r"<script[^>]*>.*?</script>", "", dom, flags=re.S)      # plotly.js's own text aside
    for ref in re.findall(r'(?:src|href)="([^"]+)"', markup):
        assert ref.startswith(("data:", "#", "javascript:")), ref


def test_3d_view_paints_the_paths(pages, tmp_path):
    """A screenshot of the standalone view shows the paths' colours (P2 blue #1f77b4, P3 red #d62728)."""
    _, view = pages
    shot = tmp_path / "view.png"
    res = run_browser(tmp_path, "--window-size=1100,800", "--virtual-time-budget=8000", f"--screenshot={shot}",
                      view.as_uri())
    assert shot.exists(), res.stderr[-2000:]
    assert not JS_ERROR.search(res.stderr)
    import matplotlib.image as mpimg
    img = (mpimg.imread(shot)[..., :3] * 255).astype(int)
    for rgb in ((0x1f, 0x77, 0xb4), (0xd6, 0x27, 0x28)):
        near = np.all(np.abs(img - np.array(rgb)) < 30, axis=-1)
        assert near.sum() > 200, rgb
