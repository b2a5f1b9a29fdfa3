"""Real headless Chromium for the tests of pages people open in a browser (reports, 3D views).

Chromium comes from Debian (``.ci/run`` installs it); outside CI a test module using ``needs_browser``
is skipped when it is missing, in CI its absence is a failure.
"""
import os
import shutil
import subprocess

import numpy as np
import pytest

BROWSER = shutil.which("chromium") or shutil.which("chromium-browser")
FLAGS = ["--headless", "--no-sandbox", "--disable-gpu", "--disable-quic", "--no-first-run",
         "--disable-background-networking", "--disable-component-update", "--disable-sync"]
#: what a WebGL page (plotly 3D) needs in headless Chromium, and console logging to catch JS errors
WEBGL_FLAGS = ["--enable-unsafe-swiftshader", "--enable-logging=stderr", "--v=0"]

if BROWSER is None and os.environ.get("CI"):
    raise RuntimeError("CI needs Debian's chromium for the browser tests (.ci/run installs it)")
needs_browser = pytest.mark.skipif(BROWSER is None, reason="headless Chromium not installed")


def run_browser(tmp_path, *args, webgl: bool = False, timeout: int = 120):
    """Run Chromium once with its own profile in ``tmp_path``; returns the CompletedProcess."""
    flags = FLAGS + (WEBGL_FLAGS if webgl else [])
    return subprocess.run([BROWSER, *flags, f"--user-data-dir={tmp_path / 'profile'}", *args],
                          capture_output=True, encoding="utf-8", timeout=timeout, cwd=tmp_path)


def screenshot_is_a_real_page(tmp_path, url, size="1280,3000"):
    """Screenshot ``url``; assert it is a page with text, tables and plots (many distinct shades), not a
    blank or error page. Returns the image (h, w, 3) floats."""
    import matplotlib.image as mpimg
    shot = tmp_path / "page.png"
    run_browser(tmp_path, f"--window-size={size}", f"--screenshot={shot}", url)
    assert shot.exists() and shot.stat().st_size > 10_000
    img = mpimg.imread(shot)[..., :3]
    assert img.std() > 0.05
    assert len(np.unique((img[::7, ::7] * 255).astype(np.uint8).reshape(-1, 3), axis=0)) > 50
    return img
